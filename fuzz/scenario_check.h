// What the scenario loader must do with any bytes (issue 7 item 4), shared by the libFuzzer
// target (fuzz/scenario_fuzzer.cc) and the replay of every input the fuzzer ever flagged
// (fuzz/regression_test.cc, in the main build):
//
//   1. YAML::Load the bytes; a YAML::Exception is fine (LoadYamlFile turns the parser's into
//      an InputError with the place).
//   2. sim::ParseScenario the tree; climbsim::InputError is fine (bad input, exit code 2), and
//      so is a YAML::Exception (yaml-cpp's own conversion errors; the CLI still reports them).
//      Any other exception is a finding: the CLI would report bad input as a failed run.
//   3. A scenario that parses must write its resolved form (ScenarioToYamlText, the run
//      directory's scenario.yaml) so that it reads back, and reads back to the same text
//      (docs/scenario.md: "Running it again gives the same trajectory, bit for bit").
//
// Crashes, leaks and undefined behaviour are the sanitizers' to find (scenario_fuzzer is
// built with -fsanitize=fuzzer,address,undefined).
#ifndef CLIMBSIM_FUZZ_SCENARIO_CHECK_H_
#define CLIMBSIM_FUZZ_SCENARIO_CHECK_H_

#include <yaml-cpp/yaml.h>

#include <exception>
#include <string>

#include "common/common.h"
#include "scenario/scenario.h"

namespace climbsim::fuzz {

enum class Outcome { kYamlError, kInputError, kLoaderYamlError, kValid };

struct Check {
  Outcome outcome = Outcome::kYamlError;
  std::string finding;  // empty: the loader behaved; else what went wrong
  std::string detail;   // the message of the exception that was fine
};

// `file` is the name the scenario claims to have been read from: relative model paths are
// resolved against its folder.
inline Check CheckScenarioText(const std::string& text, const std::string& file) {
  Check c;
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    c.outcome = Outcome::kYamlError;
    c.detail = e.what();
    return c;
  }
  sim::Scenario scenario;
  try {
    scenario = sim::ParseScenario(root, file);
  } catch (const climbsim::InputError& e) {
    c.outcome = Outcome::kInputError;
    c.detail = e.what();
    return c;
  } catch (const YAML::Exception& e) {
    c.outcome = Outcome::kLoaderYamlError;
    c.detail = e.what();
    return c;
  } catch (const std::exception& e) {
    c.finding = std::string("ParseScenario threw a non-InputError exception: ") + e.what();
    return c;
  }
  c.outcome = Outcome::kValid;
  // The resolved scenario reads back, to itself.
  std::string resolved, again;
  try {
    resolved = sim::ScenarioToYamlText(scenario);
    again = sim::ScenarioToYamlText(sim::ParseScenario(YAML::Load(resolved), file));
  } catch (const std::exception& e) {
    c.finding = std::string("the resolved scenario does not read back: ") + e.what() +
                "\n--- resolved:\n" + resolved;
    return c;
  }
  if (again != resolved) {
    c.finding = "the resolved scenario reads back to a different one:\n--- first:\n" + resolved +
                "\n--- read back:\n" + again;
  }
  return c;
}

}  // namespace climbsim::fuzz

#endif  // CLIMBSIM_FUZZ_SCENARIO_CHECK_H_
