# climbsim::reflex micro benchmarks: ns per leg update (and per law update).
climbsim_bench(reflex_update_bench SOURCES reflex_update_bench.cc LIBS climbsim::reflex)
