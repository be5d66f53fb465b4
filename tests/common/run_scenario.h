// Compile a scenario's model and run it to its end: what most simulation tests do first. Apart
// from test_util.h, which tests without the sim module include too.
#ifndef CLIMBSIM_TESTS_COMMON_RUN_SCENARIO_H_
#define CLIMBSIM_TESTS_COMMON_RUN_SCENARIO_H_

#include <string>

#include "sim/sim.h"

namespace climbsim::testing {

// `events` (may be null) receives the run's events.csv text.
inline sim::RunResult RunScenario(const sim::Scenario& s, std::string* events = nullptr) {
  auto model = sim::CompileScenario(s);
  sim::Simulation sim(s, *model);
  const sim::RunResult r = sim.Run();
  if (events != nullptr) *events = sim.EventsCsv();
  return r;
}

}  // namespace climbsim::testing

#endif  // CLIMBSIM_TESTS_COMMON_RUN_SCENARIO_H_
