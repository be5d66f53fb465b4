// libFuzzer target: any bytes as a file of a run folder (events.csv, trajectory.csv,
// summary.json, checkpoint.json, pulloff.csv; the first byte picks which:
// fuzz/run_files_check.h says what must hold). Built by fuzz/CMakeLists.txt; run by the CTest
// test fuzz_run_files (tests/sanitize/run_fuzz.sh), or by hand:
//
//   cmake -S fuzz -B build-fuzz -DCMAKE_CXX_COMPILER=clang++-14 && cmake --build build-fuzz
//   mkdir -p /tmp/corpus && cp fuzz/run_files_seeds/* fuzz/run_files_regressions/* /tmp/corpus/
//   build-fuzz/run_files_fuzzer -dict=fuzz/run_files.dict -max_total_time=600 /tmp/corpus
//
// A finding aborts with its description; copy the crash-<sha1> file to
// fuzz/run_files_regressions/ (FuzzRegressions.* replays every file there).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "fuzz/run_files_check.h"

namespace {

// A folder of this process for the one file each input is written to.
const std::string& WorkDir() {
  static const std::string dir = [] {
    const auto d = std::filesystem::temp_directory_path() /
                   ("climbsim_run_files_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d.string();
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const climbsim::fuzz::RunFileCheck c = climbsim::fuzz::CheckRunFileInput(data, size, WorkDir());
  if (!c.finding.empty()) {
    std::fprintf(stderr, "run-folder reader finding (%s): %s\n", c.file.c_str(), c.finding.c_str());
    std::abort();
  }
  return 0;
}
