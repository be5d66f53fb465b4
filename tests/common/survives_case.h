// Whether a scenario survives one bench robustness case, by the bench's own rule: for tests
// that link climbsim::optimise.
#ifndef CLIMBSIM_TESTS_COMMON_SURVIVES_CASE_H_
#define CLIMBSIM_TESTS_COMMON_SURVIVES_CASE_H_

#include <string>

#include "optimise/disturbance.h"
#include "tests/common/run_scenario.h"

namespace climbsim::testing {

// `base` survives `family` at `magnitude` on seed case `seed`, push phase `phase`: stable, not
// fallen, and at least half the same case undisturbed; `how` (may be null) says why not.
inline bool SurvivesCase(const sim::Scenario& base, const char* family, double magnitude, int seed,
                         int phase, std::string* how) {
  const optimise::DisturbanceSetup u =
      optimise::MakeDisturbanceSetup(base, optimise::RobustnessOptions{});
  const sim::RunResult calm =
      RunScenario(optimise::DisturbanceCase(u, family, 0.0, 0, seed, phase));
  const sim::RunResult hit =
      RunScenario(optimise::DisturbanceCase(u, family, magnitude, 0, seed, phase));
  return optimise::SurvivedRun(hit, calm.distance_m, how);
}

}  // namespace climbsim::testing

#endif  // CLIMBSIM_TESTS_COMMON_SURVIVES_CASE_H_
