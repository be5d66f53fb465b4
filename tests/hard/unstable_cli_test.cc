// A model that MuJoCo flags, through the executable: a robot with an absurdly stiff explicit
// spring at a large Euler step diverges; `climbsim simulate` must stop at the step MuJoCo
// flags (mjWARN_BADQACC and friends), say the step, the time and the cause, exit with code 1,
// and still write the run directory with summary.json saying stable: false.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <regex>
#include <string>

#include "tests/common/test_util.h"

namespace {

using climbsim::testing::CliResult;
using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsim;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

TEST(HardUnstableCli, SimulateStopsWithStepTimeAndCauseExitsOneAndWritesTheRun) {
  WriteFile("hard_models/unstable.xml", climbsim::testing::kUnstableRobotMjcf);
  const std::string scenario =
      WriteFile("hard_unstable.yaml",
                "robot: hard_models/unstable.xml\nscene: floor\nduration_s: 1\n"
                "physics:\n  integrator: euler\n  timestep_s: 0.01\n");
  const std::string dir = TempDir() + "/hard_unstable_run";
  const CliResult r = RunClimbsim("simulate " + scenario + " --out " + dir + " --quiet");
  EXPECT_EQ(r.code, 1) << r.out << r.err;
  // "climbsim simulate: the run went numerically bad: step N, t = T s: mjWARN_BAD... at index I
  // (MuJoCo: its own warning text)"
  const std::regex message(
      "climbsim simulate: the run went numerically bad: step ([0-9]+), t = ([0-9.]+) s: "
      "(mjWARN_BAD[A-Z]+) \\(bad number in [a-z]+\\) at index -?[0-9]+ \\(MuJoCo: [^\n]+\\)\n");
  std::smatch m;
  ASSERT_TRUE(std::regex_match(r.err, m, message)) << r.err;
  const long step = std::stol(m[1]);
  const double t = std::stod(m[2]);
  EXPECT_GT(step, 0);
  EXPECT_LT(step, 100) << "stopped early, not at the end (100 steps)";
  EXPECT_NEAR(t, step * 0.01, 1e-9) << "the time is the step's end";

  // The run directory is complete and says why it stopped.
  for (const char* f : {"scenario.yaml", "model.xml", "events.csv", "trajectory.csv"}) {
    EXPECT_TRUE(std::filesystem::exists(dir + "/" + f)) << f;
  }
  const auto summary = nlohmann::json::parse(ReadFile(dir + "/summary.json"));
  EXPECT_EQ(summary["stable"], false);
  EXPECT_EQ(summary["steps"], step);
  const std::string failure = summary["failure"];
  EXPECT_EQ(failure.rfind("step " + std::to_string(step) + ", t = ", 0), 0u) << failure;
  EXPECT_NE(failure.find(std::string(m[3])), std::string::npos) << failure;
}

}  // namespace
