// The `climbsim bench` verbs as the command runs them: output folder, runs, files, and the
// text the command prints. Library functions, so that a binding runs a verb the same way.
//
//   std::fputs(climbsim::optimise::RunBenchSpeed("examples/gecko_wall.yaml", 5, 5, 0).c_str(),
//              stdout);
#ifndef CLIMBSIM_EXPERIMENTS_BENCH_VERBS_H_
#define CLIMBSIM_EXPERIMENTS_BENCH_VERBS_H_

#include <functional>
#include <string>
#include <vector>

#include "experiments/experiments.h"

namespace climbsim::optimise {

// `bench speed`: steps per second of bare mj_step and of each cumulative effect variant,
// then the full scenario's profile from profile_from_s (< duration_s, else InputError).
std::string RunBenchSpeed(const std::string& file, double duration_s, int repetitions,
                          double profile_from_s);

// `bench speed --versus KEY=VALUE ...`: the scenario as written (A) against the same scenario
// with those keys changed (B), every effect on, interleaved. InputError names a bad KEY=VALUE.
std::string RunBenchSpeedVersus(const std::string& file, const std::vector<std::string>& versus,
                                double duration_s, int repetitions);

// `bench accuracy`: BenchAccuracy written to the run folder `out` (an earlier bench accuracy
// folder there is replaced).
std::string RunBenchAccuracy(const std::string& file, double duration_s, int threads,
                             const std::string& out);

// `bench optimise`: evaluations per second of `climbsim optimise` with 1 and 2 threads on a
// short budget (only "all" or "threads"), and with 1 and 2 MPI ranks of one thread each
// (only "all" or "mpi"; when built with MPI and mpirun is on the PATH), each run in its
// folder under `out`. `climbsim_exe` is the executable mpirun starts. Each run also reports
// the CPU seconds it took (all threads, or all ranks) and the load average when it ended: on
// a shared machine the wall time says little without them. The thread runs also report each
// worker thread's busy share (time in rollouts / the time the workers ran) and, from the
// 1-thread run's recorded rollout times, the speed-up on 2, 4, 8 and 16 cores predicted by
// the schedule simulation (optimise/schedule.h) for the queue order as run, candidate order,
// longest first by the recorded times, and without the generation barrier. `print` gets
// each line as its run ends.
void RunBenchOptimise(const std::string& file, int evaluations, const std::string& out,
                      const std::string& only, const std::string& climbsim_exe,
                      const std::function<void(const std::string&)>& print);

// `bench robustness`: BenchRobustness written to the run folder `out` (an earlier bench
// robustness folder there is replaced); returns the table, the outputs line, each worker
// thread's busy share and the speed-up on 2 to 16 cores predicted from this run's recorded
// case times (the table and robustness.csv do not depend on the thread count; these lines do).
std::string RunBenchRobustness(const std::string& file, const RobustnessOptions& options,
                               const std::string& out,
                               const std::function<void(double)>& progress = {});

}  // namespace climbsim::optimise

#endif  // CLIMBSIM_EXPERIMENTS_BENCH_VERBS_H_
