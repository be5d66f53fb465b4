// The error a scenario text gets from climbsim before anything runs (shared by the tests that
// check bad input is named at its file, line and key).
#ifndef CLIMBSIM_TESTS_COMMON_SCENARIO_ERROR_H_
#define CLIMBSIM_TESTS_COMMON_SCENARIO_ERROR_H_

#include <string>

#include "sim/sim.h"
#include "tests/common/test_util.h"

namespace climbsim::testing {

// Writes `text` as `name` in the test's folder, then loads, compiles and constructs its
// simulation as `climbsim simulate` does; the InputError's message without the folder ("name:
// line:col: key: ..."), or "" when the scenario is accepted.
inline std::string ScenarioErrorOf(const std::string& name, const std::string& text) {
  try {
    const sim::Scenario s = sim::LoadScenario(WriteFile(name, text));
    auto model = sim::CompileScenario(s);
    sim::Simulation simulation(s, *model);
  } catch (const climbsim::InputError& e) {
    const std::string msg = e.what();
    const std::string prefix = TempDir() + "/";
    return msg.rfind(prefix, 0) == 0 ? msg.substr(prefix.size()) : msg;
  }
  return "";
}

}  // namespace climbsim::testing

#endif  // CLIMBSIM_TESTS_COMMON_SCENARIO_ERROR_H_
