// `climbsim bench robustness` says before any run when its runs are too short to show a fall
// (a 3 s run let the gecko "survive" a payload that fells it at 3.45 s in a 20 s run), prints
// each push's time, and refuses pushes that would land after the run and families whose key
// the scenario already sets (the search would replace it silently).
#include <gtest/gtest.h>

#include <filesystem>

#include "experiments/experiments.h"
#include "scenario/scenario.h"
#include "tests/common/test_util.h"

namespace climbsim::optimise {
namespace {

using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsim;
using climbsim::testing::Source;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

sim::Scenario Gecko() { return sim::LoadScenario(Source("examples/gecko_wall.yaml")); }

TEST(RobustnessPlan, WarnsWhenTheRunsEndTooSoonAfterTheLastPush) {
  RobustnessOptions o;
  o.duration_s = 3.0;
  o.families = {"push_down"};
  o.phases = 4;
  const RobustnessPlan plan = PlanRobustness(Gecko(), o);
  const double f = 0.6;  // examples/gecko_wall.yaml's cpg.frequency_hz
  ASSERT_EQ(plan.push_times_s.size(), 4u);
  for (int j = 0; j < 4; ++j) {
    EXPECT_NEAR(plan.push_times_s[j], 1.0 + j / (4 * f), 1e-12);  // a third of 3 s, phase j/4
  }
  // 3 − 2.25 s after the last push = 0.45 cycles at 0.6 Hz.
  EXPECT_NEAR(plan.cycles_left, (3.0 - 2.25) * f, 1e-12);
  EXPECT_NE(plan.warning.find("leave 0.45 gait cycles"), std::string::npos) << plan.warning;
  // The shortest duration with 3 cycles after the last push, the first push at a third of it:
  // D − D/3 − 3/(4 f) = 3/f.
  const double want = 1.5 * (3 / (4 * f) + 3 / f);
  EXPECT_NEAR(plan.suggested_duration_s, want, 1e-12);
  EXPECT_NE(plan.warning.find("--duration 9.38 would leave 3"), std::string::npos) << plan.warning;
  // That duration gives no warning.
  o.duration_s = want;
  const RobustnessPlan enough = PlanRobustness(Gecko(), o);
  EXPECT_TRUE(enough.warning.empty()) << enough.warning;
  EXPECT_NEAR(enough.cycles_left, 3.0, 1e-9);
}

TEST(RobustnessPlan, CountsTheWholeRunForDisturbancesPresentFromTheStart) {
  RobustnessOptions o;
  o.duration_s = 3.0;
  o.families = {"payload"};
  const RobustnessPlan plan = PlanRobustness(Gecko(), o);
  EXPECT_TRUE(plan.push_times_s.empty());
  EXPECT_NEAR(plan.cycles_left, 1.8, 1e-12);
  EXPECT_NEAR(plan.suggested_duration_s, 5.0, 1e-12);
  EXPECT_NE(plan.warning.find("in the whole run"), std::string::npos) << plan.warning;
  o.duration_s = 20.0;
  EXPECT_TRUE(PlanRobustness(Gecko(), o).warning.empty());
}

TEST(RobustnessPlan, NamesTheFamiliesLeftOut) {
  RobustnessOptions o;
  const RobustnessPlan plan =
      PlanRobustness(sim::LoadScenario(Source("examples/gecko_ceiling_mujoco.yaml")), o);
  bool said = false;
  for (const auto& s : plan.skipped)
    said = said || s.rfind("weak_patch: its adhesion.model", 0) == 0;
  EXPECT_TRUE(said);
  EXPECT_NE(RobustnessPlanText(plan).find("left out: weak_patch"), std::string::npos);
}

// Through the executable: the push times and the warning on stderr before the runs.
TEST(RobustnessPlan, TheVerbPrintsThePushTimesAndTheWarning) {
  const auto r = RunClimbsim("bench robustness " + Source("examples/gecko_wall.yaml") +
                             " --duration 0.3 --seeds 1 --phases 1 --families push_down --out " +
                             TempDir() + "/robustness_plan_printed");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("pushes at 0.100 s"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("warning: the 0.3 s runs leave 0.12 gait cycles"), std::string::npos)
      << r.err;
  EXPECT_NE(r.out.find("pushes at 0.100 s"), std::string::npos) << r.out;  // and in the table
}

TEST(RobustnessPlan, RefusesPushesAfterTheRunAndKeysTheSearchWouldReplace) {
  const std::string late = TempDir() + "/robustness_plan_late";
  const auto r = RunClimbsim("bench robustness " + Source("examples/gecko_wall.yaml") +
                             " --duration 0.6 --phases 2 --families push_down --out " + late);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--phases: the last of 2 push phases, at 1.033 s, ends after the 0.6 s run"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(late));

  const std::string yaml = TempDir() + "/robustness_plan_rough.yaml";
  sim::Scenario s = Gecko();
  s.scene.roughness = sim::RoughnessParams{};
  WriteFile(yaml, sim::ScenarioToYamlText(s));
  const auto rough = RunClimbsim("bench robustness " + yaml +
                                 " --duration 0.3 --phases 1 --families roughness --out " +
                                 TempDir() + "/robustness_plan_rough");
  EXPECT_EQ(rough.code, 2) << rough.err;
  EXPECT_NE(rough.err.find("cannot take family 'roughness': it sets scene.roughness itself"),
            std::string::npos)
      << rough.err;
}

}  // namespace
}  // namespace climbsim::optimise
