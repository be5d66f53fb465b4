// `climbsim bench speed`: what each effect costs over bare MuJoCo on one scenario's model.
//
// Variants, all on the scenario's own compiled model (its welds present, switched off unless
// the adhesion effect switches them on), interleaved over several repetitions in one process:
//   bare         a loop of mj_step on a World: the reference
//   no effects   a Simulation with no effect: the step loop and its monitor only
//   +adhesion, +cpg, +reflex, +perturbation, +trajectory   the effects of the scenario added
//                in pipeline order (each variant keeps the ones before it)
// A variant's physics can differ from bare (a robot that climbs touches more than one that
// hangs), so the full variant is also profiled: time in mj_step against time in each effect's
// hooks within the same run, which the physics cannot blur.
#ifndef CLIMBSIM_SIM_BENCH_SPEED_H_
#define CLIMBSIM_SIM_BENCH_SPEED_H_

#include <string>
#include <vector>

#include "sim/scenario.h"

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
  // Profile of the full scenario: seconds in mj_step, in each effect, in the monitor.
  double mj_step_s = 0.0;
  std::vector<std::pair<std::string, double>> effect_s;
  double monitor_s = 0.0;
};

SpeedReport BenchSpeed(const Scenario& scenario, double duration_s, int repetitions);

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_BENCH_SPEED_H_
