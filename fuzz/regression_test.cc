// Every input the scenario fuzzer ever flagged (fuzz/regressions/), replayed through the
// loader in the main build, with the same check as the fuzzer (fuzz/scenario_check.h): an
// InputError or a valid scenario that reads back to itself, never a crash or another
// exception. The examples go through the same check: each must be valid. Likewise the run-
// folder readers (fuzz/run_files_check.h): every input of fuzz/run_files_regressions/ is read
// or rejected with an InputError naming its file, and every seed (fuzz/run_files_seeds/, files
// of a real run) is read.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "fuzz/run_files_check.h"
#include "fuzz/scenario_check.h"
#include "tests/common/test_util.h"

namespace climbsim::fuzz {
namespace {

namespace fs = std::filesystem;

std::string Read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<fs::path> FilesIn(const std::string& dir, const std::string& extension = "") {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_regular_file() && (extension.empty() || e.path().extension() == extension)) {
      files.push_back(e.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

// The name the fuzzer gives every input (relative model paths resolve from examples/).
const std::string kFile = std::string(CLIMBSIM_SOURCE_DIR) + "/examples/fuzz_input.yaml";

TEST(FuzzRegressions, EveryFlaggedInputIsRejectedOrValidAndNeverCrashes) {
  const std::vector<fs::path> files =
      FilesIn(std::string(CLIMBSIM_SOURCE_DIR) + "/fuzz/regressions");
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.filename().string());
    const Check c = CheckScenarioText(Read(f), kFile);
    EXPECT_EQ(c.finding, "");
  }
  std::printf("%zu regression inputs replayed\n", files.size());
}

// What the loader does with the findings it was fixed for: the outcome, and for a rejection
// a piece of its message (after the place).
TEST(FuzzRegressions, FixedFindingsHaveTheirFixedOutcome) {
  const struct {
    const char* file;
    Outcome outcome;
    const char* message;
  } kFixed[] = {
      // duration_s is required; "duration_s:" alone is null, which read as 0, outside its
      // range (0, 1e6], and the resolved scenario.yaml then did not read back.
      {"required_duration_given_as_null.yaml", Outcome::kInputError,
       "duration_s: is required, got nothing"},
      // A carriage return inside a name: accepted, and written back unquoted by yaml-cpp, so
      // scenario.yaml read back a different name.
      {"carriage_return_in_a_name.yaml", Outcome::kInputError,
       "cpg.gait: must not contain control characters (0x0d at 15)"},
      // A robot name longer than the file system takes: std::filesystem::exists threw
      // filesystem_error ("File name too long") out of the loader (exit code 1, no place).
      {"robot_name_too_long_for_the_file_system.yaml", Outcome::kInputError,
       "robot: no bundled robot '"},
      {"robot_name_too_long_for_the_file_system_2.yaml", Outcome::kInputError,
       "robot: no bundled robot '"},
      // An optional number given as null ("stride_m:" alone) read as 0, outside its range
      // (0, 0.2]; now null means absent, as for every other key.
      {"optional_stride_m_given_as_null.yaml", Outcome::kValid, ""},
  };
  for (const auto& f : kFixed) {
    SCOPED_TRACE(f.file);
    const fs::path path = fs::path(CLIMBSIM_SOURCE_DIR) / "fuzz" / "regressions" / f.file;
    ASSERT_TRUE(fs::exists(path));
    const Check c = CheckScenarioText(Read(path), kFile);
    EXPECT_EQ(c.finding, "");
    EXPECT_EQ(c.outcome, f.outcome) << c.detail;
    EXPECT_NE(c.detail.find(f.message), std::string::npos) << c.detail;
  }
}

TEST(FuzzRegressions, EveryExampleIsValidUnderTheFuzzersCheck) {
  for (const fs::path& f : FilesIn(std::string(CLIMBSIM_SOURCE_DIR) + "/examples", ".yaml")) {
    SCOPED_TRACE(f.filename().string());
    const Check c = CheckScenarioText(Read(f), f.string());
    EXPECT_EQ(c.finding, "");
    EXPECT_EQ(c.outcome, Outcome::kValid) << c.detail;
  }
}

RunFileCheck CheckRunFile(const fs::path& input) {
  const std::string bytes = Read(input);
  const std::string dir = climbsim::testing::TempDir();
  return CheckRunFileInput(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), dir);
}

TEST(FuzzRegressions, EveryRunFileSeedIsRead) {
  const std::vector<fs::path> files =
      FilesIn(std::string(CLIMBSIM_SOURCE_DIR) + "/fuzz/run_files_seeds");
  EXPECT_EQ(files.size(), 5u) << "one seed per reader";
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.filename().string());
    const RunFileCheck c = CheckRunFile(f);
    EXPECT_EQ(c.finding, "");
    EXPECT_FALSE(c.rejected) << c.detail;
  }
}

TEST(FuzzRegressions, EveryFlaggedRunFileIsRejectedWithItsFileAndNeverCrashes) {
  const std::string dir = std::string(CLIMBSIM_SOURCE_DIR) + "/fuzz/run_files_regressions";
  for (const fs::path& f : FilesIn(dir)) {
    SCOPED_TRACE(f.filename().string());
    const RunFileCheck c = CheckRunFile(f);
    EXPECT_EQ(c.finding, "");
  }
}

// What the readers do with the findings they were fixed for: a rejection, and a piece of its
// message (after the place).
TEST(FuzzRegressions, FixedRunFileFindingsAreRejectedWithTheirKey) {
  const struct {
    const char* file;
    const char* message;
  } kFixed[] = {
      // failed_runs read with get<int>: 1e300 is undefined behaviour (UBSan stopped the
      // fuzzer), and a whole number beyond INT_MAX wrapped to another count.
      {"checkpoint_failed_runs_1e300.json",
       "starts[0][0]: wrong value: expected a whole number >= 0, got 1e+300"},
      {"checkpoint_failed_runs_beyond_int.json",
       "starts[0][0]: wrong value: expected a whole number >= 0, got 99999999999"},
  };
  for (const auto& f : kFixed) {
    SCOPED_TRACE(f.file);
    const fs::path path = fs::path(CLIMBSIM_SOURCE_DIR) / "fuzz" / "run_files_regressions" / f.file;
    ASSERT_TRUE(fs::exists(path));
    const RunFileCheck c = CheckRunFile(path);
    EXPECT_EQ(c.finding, "");
    EXPECT_TRUE(c.rejected);
    EXPECT_NE(c.detail.find(f.message), std::string::npos) << c.detail;
  }
}

}  // namespace
}  // namespace climbsim::fuzz
