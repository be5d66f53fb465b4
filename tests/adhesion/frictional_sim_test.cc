// The directional law through a scenario (adhesion.law: frictional): the gecko placed on the
// wall hangs on pads that grip down the wall and lets go of pads that grip up it (the same
// robot, pose and seed); bad keys of the law are named with their file place. α* = 40°: the
// bundled gecko's front pads see F_n/F_t ≈ 0.6 when it hangs, so at 30° and 35° they let go
// at 7 ms and it slides 4 cm onto its hind pads (docs/climbing.md).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "sim/adhesion_effect.h"
#include "sim/sim.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::WriteFile;

std::string Wall(double grip_x) {
  return "robot: gecko\nscene: wall\nduration_s: 5\nadhesion:\n  start_attached: true\n"
         "  law: frictional\n  frictional:\n    moment_share: 0\n    critical_angle_deg: 40\n"
         "    grip_x: " +
         std::to_string(grip_x) + "\n    grip_y: 0\n";
}

TEST(FrictionalSim, GeckoHangsOnPadsGrippingDownTheWallAndNotOnPadsGrippingUp) {
  {
    const Scenario s = LoadScenario(WriteFile("frictional_down.yaml", Wall(-1.0)));
    auto model = CompileScenario(s);
    Simulation sim(s, *model);
    const AdhesionEffect* a = FindAdhesion(sim.effects());
    ASSERT_NE(a, nullptr);
    ASSERT_EQ(a->pad(0).params().law, adhesion::PadLaw::kFrictional);
    const RunResult r = sim.Run();
    EXPECT_FALSE(r.fell);
    EXPECT_LT(std::abs(r.distance_m), 0.005);
    for (int i = 0; i < a->pad_count(); ++i) {
      EXPECT_TRUE(a->pad(i).attached()) << a->pad_name(i);
      EXPECT_EQ(a->pad(i).bonded_fraction(), 1.0) << a->pad_name(i);
      // Shear along the grip (pad −x) carries the weight.
      EXPECT_LT(a->pad(i).load().fx_n, 0.0) << a->pad_name(i);
      EXPECT_LT(a->pad(i).frictional_utilisation(), 1.0) << a->pad_name(i);
    }
  }
  {
    const Scenario s = LoadScenario(WriteFile("frictional_up.yaml", Wall(1.0)));
    auto model = CompileScenario(s);
    Simulation sim(s, *model);
    const AdhesionEffect* a = FindAdhesion(sim.effects());
    const RunResult r = sim.Run();
    EXPECT_TRUE(r.fell);
    long detached = 0;
    for (int i = 0; i < a->pad_count(); ++i) detached += a->pad(i).counts().detach_overload;
    EXPECT_GE(detached, 2) << "pads let go all at once under reversed shear";
  }
}

std::string ErrorOf(const std::string& name, const std::string& text) {
  try {
    const Scenario s = LoadScenario(WriteFile(name, text));
    auto model = CompileScenario(s);
    Simulation sim(s, *model);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(FrictionalSim, BadKeysAreNamedWithTheirPlace) {
  const std::string base =
      "robot: gecko\nscene: wall\nduration_s: 1\nadhesion:\n  law: frictional\n";
  std::string e = ErrorOf("bad_angle.yaml", base + "  frictional:\n    critical_angle_deg: 95\n");
  EXPECT_NE(e.find("bad_angle.yaml:7"), std::string::npos) << e;
  EXPECT_NE(e.find("critical_angle_deg"), std::string::npos) << e;
  e = ErrorOf("bad_grip.yaml", base + "  frictional:\n    grip_x: 0\n    grip_y: 0\n");
  EXPECT_NE(e.find("grip_x"), std::string::npos) << e;
  e = ErrorOf("bad_law.yaml",
              "robot: gecko\nscene: wall\nduration_s: 1\nadhesion:\n  law: sticky\n");
  EXPECT_NE(e.find("bad_law.yaml:5"), std::string::npos) << e;
  EXPECT_EQ(ErrorOf("good.yaml", base), "");
}

}  // namespace
}  // namespace climbsim::sim
