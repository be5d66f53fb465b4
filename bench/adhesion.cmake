# climbsim::adhesion micro benchmarks: ns per BondGrid::Update of one pad, by grid size.
climbsim_bench(adhesion_grid_bench SOURCES adhesion_grid_bench.cc LIBS climbsim::adhesion)
