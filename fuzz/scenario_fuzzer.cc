// libFuzzer target: any bytes as a scenario file (fuzz/scenario_check.h says what must hold).
// Built by fuzz/CMakeLists.txt with clang++ -fsanitize=fuzzer,address,undefined; run by the
// CTest test fuzz_scenario_loader (tests/sanitize/run_fuzz.sh), or by hand:
//
//   cmake -S fuzz -B build-fuzz -DCMAKE_CXX_COMPILER=clang++-14 && cmake --build build-fuzz
//   mkdir -p /tmp/corpus && cp examples/*.yaml fuzz/regressions/* /tmp/corpus/
//   build-fuzz/scenario_fuzzer -dict=fuzz/scenario.dict -max_total_time=600 /tmp/corpus
//
// A finding aborts with its description; libFuzzer writes the input as crash-<sha1>: copy it
// to fuzz/regressions/ (the unit test FuzzRegressions.* replays every file there).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "fuzz/scenario_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  // A file in examples/, so that relative robot and scene paths can reach mjcf/.
  static const std::string file = std::string(CLIMBSIM_SOURCE_DIR) + "/examples/fuzz_input.yaml";
  const climbsim::fuzz::Check c = climbsim::fuzz::CheckScenarioText(text, file);
  if (!c.finding.empty()) {
    std::fprintf(stderr, "scenario loader finding: %s\n", c.finding.c_str());
    std::abort();
  }
  // CLIMBSIM_FUZZ_STRICT=1: yaml-cpp exceptions that escape ParseScenario count as findings
  // too (the loader promises an InputError with the place for every bad input).
  static const bool strict = std::getenv("CLIMBSIM_FUZZ_STRICT") != nullptr;
  if (strict && c.outcome == climbsim::fuzz::Outcome::kLoaderYamlError) {
    std::fprintf(stderr, "scenario loader finding: a YAML::Exception escaped ParseScenario: %s\n",
                 c.detail.c_str());
    std::abort();
  }
  return 0;
}
