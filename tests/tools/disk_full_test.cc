// A write that fails (a full disk; here a file-size limit on the child, which fails a write
// with EFBIG as a full disk fails it with ENOSPC) is reported with the file's name and the
// cause, exits non-zero, and leaves no partial file, no staging folder, and the old run as it
// was. And bench robustness's folder is a run folder: checked and locked before the work.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <string>

#include "tests/common/test_util.h"

namespace {

namespace fs = std::filesystem;
using climbsim::testing::CliResult;
using climbsim::testing::Has;
using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsimArgs;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

// A short floor walk: runs in well under a second.
const char* kWalk = "robot: gecko\nscene: floor\nduration_s: 0.2\ncpg:\n  gait: trot\n";

// Names under `dir` (recursively, hidden ones included) that a failed write must not leave:
// temporaries of common::WriteFileAtomic and staging folders of sim::RunFolder.
std::vector<std::string> Leftovers(const std::string& dir) {
  std::vector<std::string> found;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (Has(name, ".tmp.") || Has(name, ".climbsim-new.")) found.push_back(e.path().string());
  }
  return found;
}

// model.xml (the composed MJCF, several kB) is the first file past the 4 kB limit.
constexpr long kLimitBytes = 4096;

TEST(DiskFull, AFailedWriteNamesTheFileAndItsCauseAndLeavesTheOldRun) {
  const std::string root = TempDir() + "/df_old";
  fs::create_directories(root);
  const std::string scenario = WriteFile(root + "/walk.yaml", kWalk);
  const std::string dir = root + "/run";
  ASSERT_EQ(RunClimbsimArgs({"simulate", scenario, "--out", dir, "--quiet"}).code, 0);
  const std::string before = ReadFile(dir + "/summary.json");
  const CliResult r =
      RunClimbsimArgs({"simulate", scenario, "--out", dir, "--force", "--quiet"}, "", kLimitBytes);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_TRUE(Has(r.err, "cannot write ")) << r.err;
  EXPECT_TRUE(Has(r.err, "model.xml: " + std::string(std::strerror(EFBIG)))) << r.err;
  EXPECT_EQ(ReadFile(dir + "/summary.json"), before) << "the old run is intact";
  EXPECT_TRUE(Leftovers(root).empty()) << Leftovers(root).front();
}

TEST(DiskFull, ANewRunThatCannotBeWrittenLeavesNothing) {
  const std::string root = TempDir() + "/df_new";
  fs::create_directories(root);
  const std::string scenario = WriteFile(root + "/walk.yaml", kWalk);
  const CliResult r =
      RunClimbsimArgs({"simulate", scenario, "--out", root + "/run", "--quiet"}, "", kLimitBytes);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_TRUE(Has(r.err, std::strerror(EFBIG))) << r.err;
  EXPECT_FALSE(fs::exists(root + "/run"));
  EXPECT_TRUE(Leftovers(root).empty()) << Leftovers(root).front();
}

TEST(BenchRobustness, AnEmptyOutIsRefusedBeforeTheWork) {
  const std::string scenario = WriteFile("df_bench.yaml", kWalk);
  const CliResult r =
      RunClimbsimArgs({"bench", "robustness", scenario, "--out", "", "--duration", "0.2", "--seeds",
                       "1", "--phases", "1", "--families", "push_down", "--threads", "1"});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(Has(r.err, "--out: must not be empty")) << r.err;
  EXPECT_TRUE(r.out.empty()) << "no table: the work must not run: " << r.out;
}

TEST(BenchRobustness, ASecondWriterOfTheFolderIsRefusedByTheLock) {
  const std::string scenario = WriteFile("df_bench_lock.yaml", kWalk);
  const std::string dir = TempDir() + "/df_robust";
  const int fd =
      ::open((TempDir() + "/.df_robust.climbsim-lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);  // as a first bench robustness would
  const CliResult r = RunClimbsimArgs({"bench", "robustness", scenario, "--out", dir, "--duration",
                                       "0.2", "--seeds", "1", "--phases", "1", "--families",
                                       "push_down", "--threads", "1"});
  ::close(fd);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(Has(r.err, "is being written by another climbsim")) << r.err;
  EXPECT_FALSE(fs::exists(dir));
}

// bench accuracy and bench robustness each replace only their own earlier folder: one never
// takes the other's report for its own.
TEST(BenchRobustness, AnotherBenchsFolderIsRefusedNotReplaced) {
  const std::string scenario = WriteFile("df_bench_mix.yaml", kWalk);
  const std::string dir = TempDir() + "/df_mix";
  const CliResult first = RunClimbsimArgs({"bench", "robustness", scenario, "--out", dir,
                                           "--duration", "0.2", "--seeds", "1", "--phases", "1",
                                           "--families", "push_down", "--threads", "1"});
  ASSERT_EQ(first.code, 0) << first.err;
  const CliResult second = RunClimbsimArgs(
      {"bench", "accuracy", scenario, "--duration", "0.1", "--threads", "1", "--out", dir});
  EXPECT_EQ(second.code, 2) << second.err;
  EXPECT_TRUE(Has(second.err, "bench robustness")) << second.err;
  EXPECT_TRUE(fs::exists(dir + "/robustness.csv"));
  EXPECT_FALSE(fs::exists(dir + "/accuracy.csv"));
}

}  // namespace
