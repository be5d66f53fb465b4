// Helpers of the inspect tests, beside tests/common/test_util.h: real runs simulated once per
// build and shared by the test processes.
#ifndef CLIMBSIM_TESTS_INSPECT_INSPECT_TEST_UTIL_H_
#define CLIMBSIM_TESTS_INSPECT_INSPECT_TEST_UTIL_H_

#include <unistd.h>

#include <filesystem>
#include <string>

#include "tests/common/test_util.h"

namespace climbsim::testing {

// A real run of `scenario` (a path), simulated by the climbsim executable into the build tree
// once per build: redone when its summary.json is missing or older than the executable.
// Test processes run in parallel: each simulates into its own folder and renames it into
// place, so a reader sees a complete run or none.
inline std::string SharedRun(const std::string& name, const std::string& scenario) {
  namespace fs = std::filesystem;
  const fs::path root = fs::path(CLIMBSIM_BINARY_DIR) / "tests" / "inspect_runs";
  const fs::path dir = root / name;
  std::error_code ec;
  const auto exe_time = fs::last_write_time(Climbsim(), ec);
  auto fresh = [&] {
    std::error_code e;
    return fs::exists(dir / "summary.json", e) &&
           fs::last_write_time(dir / "summary.json", e) >= exe_time;
  };
  if (fresh()) return dir.string();
  const fs::path mine = root / (name + ".tmp." + std::to_string(::getpid()));
  fs::remove_all(mine, ec);
  const CliResult r = RunClimbsim("simulate " + scenario + " --out " + mine.string() + " --quiet");
  if (r.code != 0) return "simulate failed: " + r.err;
  if (!fresh()) {  // else another process finished first: its run is as good
    fs::remove_all(dir, ec);
    fs::rename(mine, dir, ec);
  }
  fs::remove_all(mine, ec);
  return dir.string();
}

// Copies a run directory to a fresh folder under TempDir().
inline std::string CopyRun(const std::string& from, const std::string& name) {
  const std::string to = TempDir() + "/" + name;
  std::filesystem::remove_all(to);
  std::filesystem::copy(from, to, std::filesystem::copy_options::recursive);
  return to;
}

}  // namespace climbsim::testing

#endif  // CLIMBSIM_TESTS_INSPECT_INSPECT_TEST_UTIL_H_
