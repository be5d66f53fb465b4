# sim: generating and compiling one designed robot's model against one 20 s rollout.
climbsim_bench(model_build_bench SOURCES model_build_bench.cc LIBS climbsim::sim)
