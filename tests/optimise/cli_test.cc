// `climbsim optimise` killed with SIGKILL mid-run and resumed ends exactly where an
// uninterrupted run ends: same best.yaml, same history (but for wall times).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "experiments/experiments.h"
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
    setpgid(0, 0);  // its own process group, so that a kill reaches mpirun's ranks too
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

// The parent of process `pid` from /proc (0 when it is gone).
pid_t ParentOf(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat;
  std::getline(in, stat);
  const size_t close = stat.rfind(')');
  if (close == std::string::npos) return 0;
  std::istringstream rest(stat.substr(close + 2));
  char state = 0;
  pid_t parent = 0;
  rest >> state >> parent;
  return parent;
}

bool IsZombie(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat;
  std::getline(in, stat);
  const size_t close = stat.rfind(')');
  return close == std::string::npos || stat.substr(close + 2, 1) == "Z";
}

// Every process below `root` (children, their children, ...).
std::vector<pid_t> Descendants(pid_t root) {
  std::vector<pid_t> found{root};
  for (size_t i = 0; i < found.size(); ++i) {
    for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
      const std::string name = entry.path().filename().string();
      if (name.find_first_not_of("0123456789") != std::string::npos) continue;
      const pid_t p = std::stoi(name);
      if (ParentOf(p) == found[i]) found.push_back(p);
    }
  }
  return std::vector<pid_t>(found.begin() + 1, found.end());
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

// CMA-ES killed mid-run and resumed: pagmo's cmaes is run again from its seed and served
// the recorded generations, so it ends exactly where an uninterrupted run ends.
const char* kCmaes =
    "robot: gecko\nscene: floor\nduration_s: 1\n"
    "cpg:\n  gait: trot\n  frequency_hz: 1.0\n  stride_rad: [0.35, 0.0, 0.0]\n"
    "  lift_rad: [0.0, 0.4, 0.3]\n"
    "outputs:\n  trajectory_rate_hz: 0\n"
    "optimise:\n  parameters:\n"
    "    - {key: cpg.frequency_hz, start: 1.0, min: 0.5, max: 2.5}\n"
    "    - {key: \"cpg.stride_rad[0]\", start: 0.35, min: 0.1, max: 0.45}\n"
    "  algorithm: cmaes\n  population: 5\n  max_evaluations: 16\n  starts: 1\n";

// Runs `args` (a climbsim command after the executable) to the end, killed with SIGKILL
// (the whole process group: mpirun and its ranks) once `kill_after` evaluations are in the
// checkpoint; then resumes it and checks it ends like an uninterrupted run of `full_args`.
void KillResumeAndCompare(const std::vector<std::string>& prefix, const std::string& scenario,
                          const std::string& name, int total, int kill_after) {
  const std::string exe = std::string(CLIMBSIM_BINARY_DIR) + "/climbsim";
  const std::string full = TempDir() + "/" + name + "_full",
                    killed = TempDir() + "/" + name + "_killed";
  std::filesystem::remove_all(full);
  std::filesystem::remove_all(killed);
  ASSERT_EQ(Wait(Spawn({exe, "optimise", scenario, "--out", full, "--quiet"})), 0);

  auto command = [&](bool resume) {
    std::vector<std::string> args = prefix;
    for (const std::string& a :
         {exe, std::string("optimise"), scenario, std::string("--out"), killed,
          std::string("--quiet"), std::string("--threads"), std::string("1")}) {
      args.push_back(a);
    }
    if (resume) args.push_back("--resume");
    return args;
  };
  const pid_t pid = Spawn(command(false));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (CheckpointEvaluations(killed + "/checkpoint.json") < kill_after &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  // SIGKILL reaches neither mpirun's ranks (they run in process groups of their own) nor
  // lets mpirun stop them: kill the descendants first, by their ids, then the command.
  const std::vector<pid_t> tree = Descendants(pid);
  for (pid_t p : tree) kill(p, SIGKILL);
  kill(pid, SIGKILL);
  const int status = Wait(pid);
  ASSERT_TRUE(WIFSIGNALED(status)) << "finished before the kill: make the run longer";
  for (pid_t p : tree) {
    while (kill(p, 0) == 0 && !IsZombie(p)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  const int before = CheckpointEvaluations(killed + "/checkpoint.json");
  ASSERT_GE(before, kill_after);
  ASSERT_LT(before, total);
  EXPECT_FALSE(std::filesystem::exists(killed + "/best.yaml"));

  ASSERT_EQ(Wait(Spawn(command(true))), 0);
  EXPECT_EQ(ReadFile(killed + "/best.yaml"), ReadFile(full + "/best.yaml"));
  EXPECT_EQ(WithoutWallTime(ReadFile(killed + "/history.csv")),
            WithoutWallTime(ReadFile(full + "/history.csv")));
  const auto summary = nlohmann::json::parse(ReadFile(killed + "/summary.json"));
  EXPECT_EQ(summary["evaluations_computed"].get<int>(), total - before);  // the rest replayed
}

TEST(OptimiseCli, CmaesKillAndResumeEndsLikeAnUninterruptedRun) {
  KillResumeAndCompare({}, WriteFile("resume_cmaes.yaml", kCmaes), "resume_cmaes", 16, 6);
}

// The objective's robustness term: a side push at two phases and a payload, each rollout
// scheduled on the same queue as the nominal one.
std::string WithRobustness(std::string text) {
  text.replace(text.find("duration_s: 1"), 13, "duration_s: 0.6");
  return text +
         "  objective:\n    robustness:\n"
         "      - {family: push_side, magnitude: 0.3, seeds: 1, phases: 2}\n"
         "      - {family: payload, magnitude: 0.05, seeds: 1, first_seed: 3}\n";
}

TEST(OptimiseCli, RobustnessTermKillAndResumeEndsLikeAnUninterruptedRun) {
  KillResumeAndCompare({}, WriteFile("resume_robust.yaml", WithRobustness(kCmaes)),
                       "resume_robust", 16, 6);
}

#ifdef CLIMBSIM_TEST_MPIEXEC
// mpirun as CI runs it: as root, two ranks on whatever cores there are.
std::vector<std::string> Mpirun(int ranks) {
  setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
  setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
  setenv("OMPI_MCA_btl", "self,vader", 1);  // one machine: shared memory, no network probing
  return {CLIMBSIM_TEST_MPIEXEC, "-np", std::to_string(ranks), "--oversubscribe",
          "--allow-run-as-root"};
}

std::vector<std::string> Concat(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

TEST(OptimiseMpi, TwoRanksWriteTheSameBestAsOneProcess) {
  const std::string exe = std::string(CLIMBSIM_BINARY_DIR) + "/climbsim";
  // NLopt starts (a round holds one evaluation per start) and CMA-ES with perturbed runs (a
  // round holds a generation's rollouts).
  std::string robust = kCmaes;
  robust.replace(robust.find("max_evaluations: 16"), 19, "max_evaluations: 11");
  robust += "  objective: {runs: 2, aggregate: worst}\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"mpi_nlopt", kScenario}, {"mpi_cmaes", robust}, {"mpi_robust", WithRobustness(kCmaes)}};
  for (const auto& [name, text] : cases) {
    const std::string scenario = WriteFile(name + ".yaml", text);
    const std::string one = TempDir() + "/" + name + "_1", two = TempDir() + "/" + name + "_2";
    std::filesystem::remove_all(one);
    std::filesystem::remove_all(two);
    ASSERT_EQ(Wait(Spawn({exe, "optimise", scenario, "--out", one, "--quiet"})), 0);
    ASSERT_EQ(Wait(Spawn(Concat(Mpirun(2), {exe, "optimise", scenario, "--out", two, "--quiet",
                                            "--threads", "1"}))),
              0);
    EXPECT_EQ(ReadFile(two + "/best.yaml"), ReadFile(one + "/best.yaml")) << name;
    EXPECT_EQ(WithoutWallTime(ReadFile(two + "/history.csv")),
              WithoutWallTime(ReadFile(one + "/history.csv")))
        << name;
    const auto summary = nlohmann::json::parse(ReadFile(two + "/summary.json"));
    EXPECT_EQ(summary["processes"].get<int>(), 2);
  }
}

TEST(OptimiseMpi, KillAndResumeUnderMpiEndsLikeAnUninterruptedRun) {
  KillResumeAndCompare(Mpirun(2), WriteFile("mpi_resume.yaml", kCmaes), "mpi_resume", 16, 6);
}

TEST(OptimiseMpi, SweepOverTwoRanksWritesTheSameTable) {
  const std::string exe = std::string(CLIMBSIM_BINARY_DIR) + "/climbsim";
  const std::string scenario = WriteFile("mpi_sweep.yaml",
                                         "robot: gecko\nscene: floor\nduration_s: 0.5\n"
                                         "cpg:\n  gait: trot\n  frequency_hz: 1.0\n"
                                         "outputs:\n  trajectory_rate_hz: 0\n");
  const std::vector<std::string> sweep = {exe,      "sweep", scenario, "--key", "cpg.frequency_hz",
                                          "--from", "0.5",   "--to",   "1.5",   "--step",
                                          "0.5"};
  const std::string one = TempDir() + "/mpi_sweep_1", two = TempDir() + "/mpi_sweep_2";
  ASSERT_EQ(Wait(Spawn(Concat(sweep, {"--out", one}))), 0);
  ASSERT_EQ(Wait(Spawn(Concat(Mpirun(2), Concat(sweep, {"--out", two, "--threads", "1"})))), 0);
  const std::string table = ReadFile(one + "/sweep.csv");
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 4);  // header and 3 values
  EXPECT_EQ(ReadFile(two + "/sweep.csv"), table);
}
#endif  // CLIMBSIM_TEST_MPIEXEC

}  // namespace
