// A sweep whose swept value the scenario reader takes but sim::Simulation's constructor
// refuses, through another module's key, ends as bad input (exit code 2) naming the swept
// key, its value and the key refused, before any run, never with a signal. (The refusal at
// the swept key itself, cpg.control_period_s, is SweepFailure.* in tests/optimise.)
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

// The reflexes' GTO hold delay (10 ms by default) fits in at most 10000 control periods:
// the reflex effect refuses a 0.1 µs time step, the first value of the sweep.
const char* kScenario =
    "robot: gecko\nscene: floor\nduration_s: 0.05\n"
    "cpg:\n  gait: trot\n  frequency_hz: 1.0\nreflex: {}\n"
    "outputs:\n  trajectory_rate_hz: 0\n";

TEST(SweepRefused, AValueAnotherModuleRefusesIsBadInputNamingTheValueAndTheKey) {
  const std::string scenario = WriteFile("sweep_refused.yaml", kScenario);
  std::string first;
  for (const char* threads : {"1", "2"}) {
    const std::string out = TempDir() + "/sweep_refused_" + threads;
    std::filesystem::remove_all(out);
    const CliResult r = RunClimbsimArgs({"sweep", scenario, "--key", "physics.timestep_s",
                                         "--from", "0.0000001", "--to", "0.001", "--step",
                                         "0.0009999", "--threads", threads, "--out", out});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_TRUE(Has(r.err, "physics.timestep_s = 1e-07 gives an invalid scenario")) << r.err;
    EXPECT_TRUE(Has(r.err, "reflex.gto.hold_delay_s")) << r.err;
    EXPECT_FALSE(std::filesystem::exists(out));
    if (first.empty()) first = r.err;
    EXPECT_EQ(r.err, first);
  }
}

}  // namespace
