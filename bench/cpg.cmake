# cpg: ns per OscillatorNetwork::Step, 4 and 6 oscillators, each stepper, both networks.
climbsim_bench(cpg_step_bench SOURCES cpg_step_bench.cc LIBS climbsim::cpg)
