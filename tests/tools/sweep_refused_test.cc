// A sweep whose swept value the scenario reader takes but sim::Simulation's constructor
// refuses ends as bad input (exit code 2) naming the key and the value, before any run,
// never with a signal.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tests/common/test_util.h"

namespace {

using climbsim::testing::CliResult;
using climbsim::testing::Has;
using climbsim::testing::RunClimbsimArgs;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

// cpg.control_period_s must be a whole multiple of the time step (1 ms here): the reader
// cannot know the scene's step, the Simulation constructor refuses 2.5 ms.
const char* kScenario =
    "robot: gecko\nscene: floor\nduration_s: 0.2\nphysics: {timestep_s: 0.001}\n"
    "cpg:\n  gait: trot\n  frequency_hz: 1.0\n  control_period_s: 0.002\n"
    "outputs:\n  trajectory_rate_hz: 0\n";

TEST(SweepRefused, AValueTheSimulationRefusesIsBadInputNamingKeyAndValue) {
  const std::string scenario = WriteFile("sweep_refused.yaml", kScenario);
  const std::string out = TempDir() + "/sweep_refused";
  std::filesystem::remove_all(out);
  for (const char* threads : {"1", "2"}) {
    const CliResult r = RunClimbsimArgs({"sweep", scenario, "--key", "cpg.control_period_s",
                                         "--from", "0.002", "--to", "0.003", "--step", "0.0005",
                                         "--threads", threads, "--out", out});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_TRUE(Has(r.err, "cpg.control_period_s = 0.0025")) << r.err;
    EXPECT_TRUE(Has(r.err, "whole multiple of physics.timestep_s")) << r.err;
    EXPECT_FALSE(std::filesystem::exists(out + "/sweep.csv"));
  }
}

}  // namespace
