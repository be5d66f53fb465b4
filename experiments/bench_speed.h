// `climbsim bench speed`: what each effect costs over bare MuJoCo on one scenario's model.
//
// Variants, all on the scenario's own compiled model (its welds present, switched off unless
// the adhesion effect switches them on), interleaved over several repetitions in one process:
//   bare         a loop of mj_step on a World: the reference
//   no effects   a Simulation with no effect: the step loop and its monitor only
//   +adhesion, +cpg, +reflex, +perturbation, +trajectory   the effects of the scenario added
//                in pipeline order (each variant keeps the ones before it)
// Steps per second count the CPU time of the thread that steps (clock_gettime with
// CLOCK_THREAD_CPUTIME_ID): equal to wall time on an idle machine, and not inflated by other
// processes on a busy one.
// A variant's physics can differ from bare (a robot that climbs touches more than one that
// hangs), so the full variant is also profiled: time in mj_step against time in each effect's
// hooks within the same run, which the physics cannot blur.
#ifndef CLIMBSIM_EXPERIMENTS_BENCH_SPEED_H_
#define CLIMBSIM_EXPERIMENTS_BENCH_SPEED_H_

#include <string>
#include <vector>

#include "scenario/scenario.h"

namespace climbsim::sim {

struct SpeedVariant {
  std::string name;
  std::vector<double> steps_per_s;  // one per repetition
  double median_steps_per_s = 0.0;
  double overhead = 0.0;            // bare median / this median − 1
};

struct SpeedReport {
  long steps = 0;                   // per run
  int repetitions = 0;
  std::vector<SpeedVariant> variants;
  // Profile of the full scenario: seconds in mj_step, in each effect, in the monitor, over the
  // steps from profile_from_s on (e.g. a corner's manoeuvre; those before run unprofiled),
  // each less the profile's own clock: clock_lap_s (Simulation::Profile::LapSeconds) per lap.
  double profile_from_s = 0.0;
  long profiled_steps = 0;
  double mj_step_s = 0.0;
  std::vector<std::pair<std::string, double>> effect_s;
  double monitor_s = 0.0;
  double clock_lap_s = 0.0;
  double effects_with_clock_s = 0.0;  // every effect, the clock left in
  double mj_step_with_clock_s = 0.0;
};

// profile_from_s in [0, duration_s): where the profile of the full scenario starts.
SpeedReport BenchSpeed(const Scenario& scenario, double duration_s, int repetitions,
                       double profile_from_s = 0.0);

// Two settings of the same scenario (e.g. two physics options), every effect on, run
// alternately A, B, A, B, ... in one process so that the load of the machine falls on both
// alike. `ratio` = median steps/s of A over that of B: A is that many times faster.
struct SpeedComparison {
  struct Side {
    std::vector<double> steps_per_s;  // one per repetition
    double median_steps_per_s = 0.0;
    long steps = 0;
    double distance_m = 0.0;          // of the last repetition (all are the same run)
    bool fell = false;
    bool stable = true;
  };
  Side a, b;
  double ratio = 0.0;
};

SpeedComparison BenchSpeedCompare(const Scenario& a, const Scenario& b, double duration_s,
                                  int repetitions);

}  // namespace climbsim::sim

#endif  // CLIMBSIM_EXPERIMENTS_BENCH_SPEED_H_
