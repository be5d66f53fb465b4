// A model that MuJoCo flags, through the executable: a robot with an absurdly stiff explicit
// spring at a large Euler step diverges; `climbsim simulate` must stop at the step MuJoCo
// flags (mjWARN_BADQACC and friends), say the step, the time and the cause, exit with code 1,
// and still write the run directory with summary.json saying stable: false.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>

#include "tests/sim/test_util.h"

namespace {

using climbsim::testing::ReadFile;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

struct Result {
  int code;
  std::string out, err;
};

Result RunClimbsim(const std::string& args) {
  const std::string out = TempDir() + "/hard_cli_stdout", err = TempDir() + "/hard_cli_stderr";
  const std::string cmd =
      std::string(CLIMBSIM_BINARY_DIR) + "/climbsim " + args + " >" + out + " 2>" + err;
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, ReadFile(out), ReadFile(err)};
}

// The robot of Simulation.UnstableRunStopsWithStepTimeAndCause (tests/sim): a 1e9 N·m/rad
// spring on a 1 g link, integrated by explicit Euler at 10 ms. Its frequency sqrt(k/I) is
// ~1e8 rad/s against a stability limit of 2/dt = 200 rad/s: it blows up within a few steps.
constexpr const char* kUnstableRobot = R"(<mujoco>
  <compiler autolimits="true"/>
  <worldbody>
    <body name="base" pos="0 0 0.5"><freejoint name="root"/>
      <geom type="box" size="0.05 0.05 0.01" mass="0.1"/>
      <body pos="0.1 0 0"><joint name="spring" type="hinge" axis="0 1 0" stiffness="1e9"
        springref="1"/><geom type="capsule" fromto="0 0 0 0.05 0 0" size="0.005" mass="0.001"/>
      </body>
    </body>
  </worldbody>
</mujoco>)";

TEST(HardUnstableCli, SimulateStopsWithStepTimeAndCauseExitsOneAndWritesTheRun) {
  WriteFile("hard_models/unstable.xml", kUnstableRobot);
  const std::string scenario =
      WriteFile("hard_unstable.yaml",
                "robot: hard_models/unstable.xml\nscene: floor\nduration_s: 1\n"
                "physics:\n  integrator: euler\n  timestep_s: 0.01\n");
  const std::string dir = TempDir() + "/hard_unstable_run";
  const Result r = RunClimbsim("simulate " + scenario + " --out " + dir + " --quiet");
  EXPECT_EQ(r.code, 1) << r.out << r.err;
  // "climbsim simulate: the run went numerically bad: step N, t = T s: mjWARN_BAD... at index I"
  const std::regex message(
      "climbsim simulate: the run went numerically bad: step ([0-9]+), t = ([0-9.]+) s: "
      "(mjWARN_BAD[A-Z]+) \\(bad number in [a-z]+\\) at index -?[0-9]+\n");
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
