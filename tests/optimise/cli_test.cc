// `climbsim optimise` killed with SIGKILL mid-run and resumed ends exactly where an
// uninterrupted run ends: same best.yaml, same history (but for wall times).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "optimise/optimise.h"
#include "tests/common/test_util.h"

namespace {

using climbsim::testing::ReadFile;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

const char* kScenario =
    "robot: gecko\nscene: floor\nduration_s: 1\n"
    "cpg:\n  gait: trot\n  frequency_hz: 1.0\n  stride_rad: [0.35, 0.0, 0.0]\n"
    "  lift_rad: [0.0, 0.4, 0.3]\n"
    "outputs:\n  trajectory_rate_hz: 0\n"
    "optimise:\n  parameters:\n"
    "    - {key: cpg.frequency_hz, start: 1.0, min: 0.5, max: 2.5}\n"
    "    - {key: \"cpg.stride_rad[0]\", start: 0.35, min: 0.1, max: 0.45}\n"
    "  algorithm: chain\n  max_evaluations: 16\n  starts: 2\n";

pid_t Spawn(const std::vector<std::string>& args) {
  const pid_t pid = fork();
  if (pid == 0) {
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    freopen("/dev/null", "w", stdout);
    freopen("/dev/null", "w", stderr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

int Wait(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return status;
}

// Everything but the last column (wall_time_s), which no two runs share.
std::string WithoutWallTime(const std::string& csv) {
  std::string out, line;
  std::istringstream in(csv);
  while (std::getline(in, line)) out += line.substr(0, line.rfind(',')) + "\n";
  return out;
}

int CheckpointEvaluations(const std::string& path) {
  try {
    const auto j = nlohmann::json::parse(ReadFile(path));
    int n = 0;
    for (const auto& s : j["starts"]) n += static_cast<int>(s.size());
    return n;
  } catch (...) {
    return 0;  // not written yet
  }
}

TEST(OptimiseCli, KillAndResumeEndsLikeAnUninterruptedRun) {
  const std::string exe = std::string(CLIMBSIM_BINARY_DIR) + "/climbsim";
  const std::string scenario = WriteFile("resume.yaml", kScenario);
  const std::string full = TempDir() + "/resume_full", killed = TempDir() + "/resume_killed";

  ASSERT_EQ(Wait(Spawn({exe, "optimise", scenario, "--out", full, "--quiet"})), 0);

  const pid_t pid = Spawn({exe, "optimise", scenario, "--out", killed, "--quiet"});
  // Kill once some but not all evaluations are checkpointed.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (CheckpointEvaluations(killed + "/checkpoint.json") < 5 &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  kill(pid, SIGKILL);
  const int status = Wait(pid);
  ASSERT_TRUE(WIFSIGNALED(status)) << "finished before the kill: make the run longer";
  const int before = CheckpointEvaluations(killed + "/checkpoint.json");
  ASSERT_GE(before, 5);
  ASSERT_LT(before, 16);
  EXPECT_FALSE(std::filesystem::exists(killed + "/best.yaml"));

  ASSERT_EQ(Wait(Spawn({exe, "optimise", scenario, "--out", killed, "--resume", "--quiet"})), 0);
  EXPECT_EQ(ReadFile(killed + "/best.yaml"), ReadFile(full + "/best.yaml"));
  EXPECT_EQ(WithoutWallTime(ReadFile(killed + "/history.csv")),
            WithoutWallTime(ReadFile(full + "/history.csv")));
  const auto summary = nlohmann::json::parse(ReadFile(killed + "/summary.json"));
  EXPECT_EQ(summary["evaluations_computed"].get<int>(), 16 - before);  // the rest replayed
}

TEST(OptimiseCli, ResumeRefusesAnotherScenariosCheckpoint) {
  const std::string exe = std::string(CLIMBSIM_BINARY_DIR) + "/climbsim";
  const std::string a = WriteFile("resume_a.yaml", kScenario);
  std::string other = kScenario;
  other.replace(other.find("max_evaluations: 16"), 19, "max_evaluations: 4");
  const std::string b = WriteFile("resume_b.yaml", other);
  const std::string dir = TempDir() + "/resume_mixed";
  ASSERT_EQ(Wait(Spawn({exe, "optimise", b, "--out", dir, "--quiet"})), 0);
  const int status = Wait(Spawn({exe, "optimise", a, "--out", dir, "--resume", "--quiet"}));
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
}

}  // namespace
