// The gecko on directional pads (issue 18: examples/gecko_wall_directional.yaml): it climbs
// 0.3 m up the wall in 20 s with spindle and GTO on, and each piece the directional gait adds
// is needed, shown on the same scenario with that piece taken out (10 s runs): force tracking
// of each pad's gripping shear (reflex.gto.share.mode), the landing's settle and drag
// (reflex.landing), and the release without the contact's kick
// (adhesion.release_contact_delay_s). Under the ceiling (examples/gecko_ceiling_directional.yaml)
// the pads are opposed in pairs and it walks 20 s without falling; the least grasp
// (min_grip_n), the landing's drag and the pairs' diagonal directions are each needed. Keys
// that need directional pads say so, at their line.
#include <gtest/gtest.h>

#include <string>

#include "sim/sim.h"
#include "tests/common/scenario_error.h"
#include "tests/common/run_scenario.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::ReadFile;
using climbsim::testing::RunScenario;
using climbsim::testing::Source;
using climbsim::testing::WriteFile;

// The example's text with `from` replaced by `to` (which must occur) and a 10 s duration.
std::string Variant(const std::string& from, const std::string& to,
                    const char* example = "examples/gecko_wall_directional.yaml") {
  std::string text = ReadFile(Source(example));
  const size_t d = text.find("duration_s: 20");
  EXPECT_NE(d, std::string::npos);
  text.replace(d, 14, "duration_s: 10");
  if (!from.empty()) {
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  }
  return text;
}

// The example as shipped, 20 s, on directional pads with spindle and GTO on: its distance,
// after checking that it did not fall.
double DirectionalExampleDistance(const char* example) {
  const Scenario s = LoadScenario(Source(example));
  EXPECT_EQ(s.duration_s, 20.0);
  EXPECT_TRUE(s.adhesion.has_value() && s.adhesion->law == "frictional");
  EXPECT_TRUE(s.reflex.has_value() && s.reflex->spindle.enabled && s.reflex->gto.enabled);
  const RunResult r = RunScenario(s);
  EXPECT_TRUE(r.stable) << r.failure;
  EXPECT_FALSE(r.fell) << r.fall_time_s;
  return r.distance_m;
}

TEST(DirectionalClimb, GeckoClimbsThirtyCentimetresUpTheWallIn20s) {
  EXPECT_GE(DirectionalExampleDistance("examples/gecko_wall_directional.yaml"), 0.3);  // issue 18
}

// Each piece out, on the same scenario: the gecko falls, or climbs less than half as far.
TEST(DirectionalClimb, EachPieceOfTheDirectionalGaitIsNeeded) {
  const RunResult full = RunScenario(LoadScenario(WriteFile("directional_full.yaml", Variant("", ""))));
  ASSERT_FALSE(full.fell);
  ASSERT_GT(full.distance_m, 0.15);
  const struct {
    const char* name;
    const char* from;
    const char* to;
  } pieces[] = {
      {"utilisation_sharing", "mode: force_tracking", "mode: utilisation"},
      {"no_landing", "landing: {settle_s: 0.03, drag_n: 0.2}", "landing: {settle_s: 0}"},
      {"no_drag", "drag_n: 0.2", "drag_n: 0"},
      {"no_release_delay", "release_contact_delay_s: 0.01", "release_contact_delay_s: 0"},
  };
  for (const auto& p : pieces) {
    SCOPED_TRACE(p.name);
    const RunResult r = RunScenario(
        LoadScenario(WriteFile(std::string(p.name) + ".yaml", Variant(p.from, p.to))));
    ASSERT_TRUE(r.stable) << r.failure;
    EXPECT_TRUE(r.fell || r.distance_m < 0.5 * full.distance_m)
        << r.distance_m << " m against " << full.distance_m;
  }
}

std::string ErrorOf(const std::string& name, const std::string& text) {
  return climbsim::testing::ScenarioErrorOf(name, text);
}

// Force tracking and the landing's drag steer directional pads: on von Mises pads they are an
// error at their key's line; an unknown mode names the modes.
TEST(DirectionalClimb, KeysForDirectionalPadsAreRefusedOnVonMisesPads) {
  const std::string vm = Variant("\n  law: frictional\n", "\n  law: von_mises\n");
  std::string e = ErrorOf("tracking_vm.yaml", vm);
  EXPECT_NE(e.find("tracking_vm.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("reflex.gto.share.mode"), std::string::npos) << e;
  EXPECT_NE(e.find("adhesion.law: frictional"), std::string::npos) << e;

  std::string drag_only = vm;
  const size_t at = drag_only.find("mode: force_tracking");
  ASSERT_NE(at, std::string::npos);
  drag_only.replace(at, 20, "mode: utilisation");
  e = ErrorOf("drag_vm.yaml", drag_only);
  EXPECT_NE(e.find("reflex.landing.drag_n"), std::string::npos) << e;

  e = ErrorOf("bad_mode.yaml", Variant("mode: force_tracking", "mode: tracking"));
  EXPECT_NE(e.find("bad_mode.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("force_tracking"), std::string::npos) << e;
  EXPECT_EQ(ErrorOf("good.yaml", Variant("", "")), "");
}

TEST(DirectionalClimb, GeckoWalksUnderTheCeilingOnOpposedPadsFor20s) {
  // 0.085 m measured (docs/climbing.md).
  EXPECT_GE(DirectionalExampleDistance("examples/gecko_ceiling_directional.yaml"), 0.07);
}

// Under the ceiling, each piece out (10 s runs of the example): the gecko falls or does not
// walk a third of the way.
TEST(DirectionalClimb, EachPieceOfTheCeilingGaitIsNeeded) {
  constexpr const char* kCeiling = "examples/gecko_ceiling_directional.yaml";
  const RunResult full =
      RunScenario(LoadScenario(WriteFile("ceiling_full.yaml", Variant("", "", kCeiling))));
  ASSERT_TRUE(full.stable) << full.failure;
  ASSERT_FALSE(full.fell);
  ASSERT_GT(full.distance_m, 0.05);
  const struct {
    const char* name;
    const char* from;
    const char* to;
  } pieces[] = {
      {"no_least_grasp", "min_grip_n: 1.5", "min_grip_n: 0"},
      {"no_drag", "drag_n: 0.4", "drag_n: 0"},
      // Front and hind opposed along x alone, no left-right grasp.
      {"along_x", "grip_x: -0.39, grip_y: -0.92}\n    - {pad: RF_pad, grip_x: -0.39, grip_y: 0.92}"
                  "\n    - {pad: LH_pad, grip_x: 0.39, grip_y: -0.92}"
                  "\n    - {pad: RH_pad, grip_x: 0.39, grip_y: 0.92}",
       "grip_x: -1, grip_y: 0}\n    - {pad: RF_pad, grip_x: -1, grip_y: 0}"
       "\n    - {pad: LH_pad, grip_x: 1, grip_y: 0}\n    - {pad: RH_pad, grip_x: 1, grip_y: 0}"},
  };
  for (const auto& p : pieces) {
    SCOPED_TRACE(p.name);
    const RunResult r = RunScenario(LoadScenario(
        WriteFile(std::string("ceiling_") + p.name + ".yaml", Variant(p.from, p.to, kCeiling))));
    ASSERT_TRUE(r.stable) << r.failure;
    EXPECT_TRUE(r.fell || r.distance_m < full.distance_m / 3)
        << r.distance_m << " m against " << full.distance_m;
  }
}

// min_grip_n is force tracking's: refused at its line with the utilisation mode; a file that
// sets it still loads and runs with GTO off (bench robustness's second column switches GTO
// off, and with it the tracking).
TEST(DirectionalClimb, LeastGraspNeedsForceTrackingButLoadsWithGtoOff) {
  constexpr const char* kCeiling = "examples/gecko_ceiling_directional.yaml";
  const std::string e = ErrorOf(
      "grasp_util.yaml", Variant("mode: force_tracking", "mode: utilisation", kCeiling));
  EXPECT_NE(e.find("grasp_util.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("reflex.gto.share.min_grip_n"), std::string::npos) << e;
  Scenario off = LoadScenario(WriteFile("grasp_off.yaml", Variant("", "", kCeiling)));
  ASSERT_TRUE(off.reflex.has_value());
  off.reflex->gto.enabled = false;
  off.reflex->spindle.enabled = false;
  off.duration_s = 0.05;
  EXPECT_NO_THROW(RunScenario(off));
}

}  // namespace
}  // namespace climbsim::sim
