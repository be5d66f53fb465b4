// The gecko on directional pads (issue 18: examples/gecko_wall_directional.yaml): it climbs
// 0.3 m up the wall in 20 s with spindle and GTO on, and each piece the directional gait adds
// is needed, shown on the same scenario with that piece taken out (10 s runs): force tracking
// of each pad's gripping shear (reflex.gto.share.mode), the landing's settle and drag
// (reflex.landing), and the release without the contact's kick
// (adhesion.release_contact_delay_s). Keys that need directional pads say so, at their line.
#include <gtest/gtest.h>

#include <string>

#include "sim/sim.h"
#include "tests/common/scenario_error.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::ReadFile;
using climbsim::testing::Source;
using climbsim::testing::WriteFile;

RunResult RunScenario(const Scenario& s) {
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  return sim.Run();
}

// The example's text with `from` replaced by `to` (which must occur) and a 10 s duration.
std::string Variant(const std::string& from, const std::string& to) {
  std::string text = ReadFile(Source("examples/gecko_wall_directional.yaml"));
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

TEST(DirectionalClimb, GeckoClimbsThirtyCentimetresUpTheWallIn20s) {
  const Scenario s = LoadScenario(Source("examples/gecko_wall_directional.yaml"));
  ASSERT_EQ(s.duration_s, 20.0);
  ASSERT_TRUE(s.adhesion.has_value());
  EXPECT_EQ(s.adhesion->law, "frictional");
  ASSERT_TRUE(s.reflex.has_value());
  EXPECT_TRUE(s.reflex->spindle.enabled);
  EXPECT_TRUE(s.reflex->gto.enabled);
  const RunResult r = RunScenario(s);
  ASSERT_TRUE(r.stable) << r.failure;
  EXPECT_FALSE(r.fell) << r.fall_time_s;
  EXPECT_GE(r.distance_m, 0.3);  // issue 18
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

}  // namespace
}  // namespace climbsim::sim
