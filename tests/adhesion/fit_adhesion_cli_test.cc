// climbsim fit-adhesion as a user meets it: the run folder's files, fitted.yaml pasted into a
// gecko scenario that then runs with the tabulated law, and bad input refused with exit 2
// before any folder is made.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "sim/adhesion_effect.h"
#include "sim/sim.h"
#include "tests/common/test_util.h"

namespace {

using climbsim::testing::CliResult;
using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsim;
using climbsim::testing::Source;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

TEST(FitAdhesionCli, DesignersTableGivesABlockAGeckoRunsOn) {
  const std::string dir = TempDir() + "/fit_tab";
  const CliResult r = RunClimbsim("fit-adhesion " + Source("examples/pad_pulloff.csv") +
                                  " --law tabulated --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("fit-adhesion: tabulated fitted"), std::string::npos);  // progress
  for (const char* f : {"parameters.csv", "residuals.csv", "curves.csv", "fitted.yaml",
                        "verdict.txt", "fit.gp"}) {
    EXPECT_TRUE(std::filesystem::exists(dir + "/" + f)) << f;
  }
  const std::string verdict = ReadFile(dir + "/verdict.txt");
  EXPECT_EQ(verdict.rfind("tabulated: ", 0), 0u) << verdict;
  EXPECT_NE(verdict.find("the law represents your data"), std::string::npos);
  EXPECT_NE(verdict.find("von_mises: "), std::string::npos);
  const std::string fitted = ReadFile(dir + "/fitted.yaml");
  EXPECT_NE(fitted.find("pulloff_n: [2.1, 2.4, 3.3, 1.2]"), std::string::npos) << fitted;

  // The block pasted under a short gecko scenario on the wall: the keys load, the pads use
  // the table, and it runs.
  std::string block = fitted.substr(fitted.find("adhesion:"));
  block.insert(block.find("  law:"), "  start_attached: true\n");
  const std::string scenario =
      WriteFile("fit_gecko.yaml", "robot: gecko\nscene: wall\nduration_s: 0.3\n" + block);
  using namespace climbsim::sim;
  const Scenario s = LoadScenario(scenario);
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  const AdhesionEffect* a = FindAdhesion(sim.effects());
  ASSERT_NE(a, nullptr);
  ASSERT_EQ(a->pad(0).params().law, climbsim::adhesion::PadLaw::kTabulated);
  const RunResult run = sim.Run();
  EXPECT_GT(run.steps, 0);
  int attached = 0;
  for (int i = 0; i < a->pad_count(); ++i) attached += a->pad(i).attached() ? 1 : 0;
  EXPECT_GT(attached, 0);
}

TEST(FitAdhesionCli, BadDataExitsTwoWithFileLineAndColumnAndMakesNoFolder) {
  const std::string csv = WriteFile("bare_angle.csv", "angle,force_n\n0,2\n");
  const std::string dir = TempDir() + "/fit_bad";
  const CliResult r = RunClimbsim("fit-adhesion " + csv + " --law von_mises --out " + dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("bare_angle.csv:1:1"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("angle_from_normal_deg"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir));
  const CliResult push = RunClimbsim(
      "fit-adhesion " +
      WriteFile("push.csv", "angle_from_normal_deg,force_n,pad_width_m\n0,2,0.02\n120,3,0.02\n") +
      " --law tabulated --out " + dir);
  EXPECT_EQ(push.code, 2);
  EXPECT_NE(push.err.find("push.csv:3"), std::string::npos) << push.err;
  EXPECT_FALSE(std::filesystem::exists(dir));
  EXPECT_EQ(RunClimbsim("fit-adhesion " + csv + " --law glue --out " + dir).code, 2);
}

}  // namespace
