// The directional law through a scenario (adhesion.law: frictional): the gecko placed on the
// wall hangs on pads that grip down the wall and lets go of pads that grip up it (the same
// robot, pose and seed); bad keys of the law are named with their file place. α* = 40°: the
// bundled gecko's front pads see F_n/F_t ≈ 0.6 when it hangs, so at 30° and 35° they let go
// at 7 ms and it slides 4 cm onto its hind pads (docs/climbing.md).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "sim/adhesion_effect.h"
#include "sim/cpg_effect.h"
#include "sim/reflex_effect.h"
#include "sim/sim.h"
#include "tests/common/scenario_error.h"
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
  return climbsim::testing::ScenarioErrorOf(name, text);
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

// adhesion.pad_overrides[].grip_x/grip_y: each pad its own gripping direction (hind feet
// opposed to the front ones, splayed toes). Every pad overridden to grip up the wall falls as
// the law-wide grip up does; one pad overridden keeps the others' direction.
TEST(FrictionalSim, PadOverridesGiveEachPadItsGrippingDirection) {
  const std::string all_up = Wall(-1.0) +
                             "  pad_overrides:\n    - {pad: LF_pad, grip_x: 1}\n"
                             "    - {pad: RF_pad, grip_x: 1}\n    - {pad: LH_pad, grip_x: 1}\n"
                             "    - {pad: RH_pad, grip_x: 1}\n";
  {
    const Scenario s = LoadScenario(WriteFile("frictional_override_up.yaml", all_up));
    auto model = CompileScenario(s);
    Simulation sim(s, *model);
    const RunResult r = sim.Run();
    EXPECT_TRUE(r.fell);
  }
  const std::string hind_up = Wall(-1.0) +
                              "  pad_overrides:\n    - {pad: LH_pad, grip_x: 1}\n"
                              "    - {pad: RH_pad, grip_x: 0.6, grip_y: 0.8}\n";
  const Scenario s = LoadScenario(WriteFile("frictional_override_hind.yaml", hind_up));
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  const AdhesionEffect* a = FindAdhesion(sim.effects());
  ASSERT_NE(a, nullptr);
  for (int i = 0; i < a->pad_count(); ++i) {
    const adhesion::FrictionalParams& f = a->pad(i).params().frictional;
    if (a->pad_name(i) == "LH_pad") {
      EXPECT_EQ(f.grip_x, 1.0);
      EXPECT_EQ(f.grip_y, 0.0);
    } else if (a->pad_name(i) == "RH_pad") {
      EXPECT_EQ(f.grip_x, 0.6);
      EXPECT_EQ(f.grip_y, 0.8);
    } else {
      EXPECT_EQ(f.grip_x, -1.0) << a->pad_name(i);
    }
  }
}

// reflex.peel.against_grip: the release moves each foot against its own pad's gripping
// direction (forward for a pad gripping back, back for one gripping forward); off, every leg
// keeps the signed hip_yaw_rad.
TEST(FrictionalSim, PeelAgainstGripSignsEachLegsReleaseByItsPad) {
  const std::string base =
      Wall(-1.0) + "  pad_overrides: [{pad: LH_pad, grip_x: 1}, {pad: RH_pad, grip_x: 1}]\n" +
      "cpg: {gait: lateral_sequence, stride_m: 0.03}\n";
  for (const bool against : {true, false}) {
    const std::string text =
        base + "reflex: {peel: {hip_yaw_rad: -0.1, against_grip: " + (against ? "true" : "false") +
        "}}\n";
    const Scenario s = LoadScenario(WriteFile("frictional_peel_against.yaml", text));
    auto model = CompileScenario(s);
    Simulation sim(s, *model);
    // The reflex block as the simulation composes it, on the same world and pads.
    const CpgEffect cpg(s, *s.cpg, sim.world());
    const auto rx = std::make_unique<ReflexEffect>(
        s, *s.reflex, sim.world(), cpg, FindAdhesion(sim.effects()), std::vector<int>{0, 1, 2, 3});
    ASSERT_EQ(rx->leg_count(), 4);
    // Legs LF, RF, LH, RH: front pads grip back (-x), hind pads forward (+x).
    const double front = against ? 0.1 : -0.1, hind = -0.1;
    EXPECT_EQ(rx->leg(0).params().peel.hip_yaw_rad, front);
    EXPECT_EQ(rx->leg(1).params().peel.hip_yaw_rad, front);
    EXPECT_EQ(rx->leg(2).params().peel.hip_yaw_rad, hind);
    EXPECT_EQ(rx->leg(3).params().peel.hip_yaw_rad, hind);
  }
}

// cpg.squeeze_m: stance feet aimed towards the middle of the body make the welded stance a
// grasp. The gecko hangs 1 s on its (isotropic) pads with the gait all but stopped (0.01 Hz):
// a 2 mm squeeze drags each front pad down the wall and each hind pad up it by about 0.5 N
// more than without (measured 0.35/0.25 -> 0.89/0.64 N front, 0.11/0.27 -> -0.26/-0.30 N
// hind), the weight they carry together unchanged.
TEST(FrictionalSim, SqueezeDragsTheFrontPadsDownAndTheHindPadsUp) {
  std::array<std::array<double, 4>, 2> down{};  // [squeeze][LF, RF, LH, RH]: -fx, N
  for (int k = 0; k < 2; ++k) {
    const std::string text =
        std::string(
            "robot: gecko\nscene: wall\nduration_s: 1\nadhesion: {start_attached: "
            "true}\ncpg: {gait: lateral_sequence, frequency_hz: 0.01, start_amplitude: 1, "
            "stride_m: 0.03, lift_m: 0.012, crouch_m: 0.01, squeeze_m: ") +
        (k == 0 ? "0" : "0.002") + "}\n";
    const Scenario s = LoadScenario(WriteFile("squeeze.yaml", text));
    auto model = CompileScenario(s);
    Simulation sim(s, *model);
    const AdhesionEffect* a = FindAdhesion(sim.effects());
    const RunResult r = sim.Run();
    ASSERT_FALSE(r.fell);
    for (int i = 0; i < 4; ++i) {
      ASSERT_TRUE(a->pad(i).attached()) << a->pad_name(i);
      down[k][i] = -a->pad(i).load().fx_n;
    }
  }
  for (int i = 0; i < 2; ++i) EXPECT_GT(down[1][i] - down[0][i], 0.3) << "front pad " << i;
  for (int i = 2; i < 4; ++i) EXPECT_LT(down[1][i] - down[0][i], -0.3) << "hind pad " << i;
  double total[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    for (int i = 0; i < 4; ++i) total[k] += down[k][i];
  }
  EXPECT_NEAR(total[1], total[0], 0.1) << "an internal force: the weight's share is unchanged";
}

TEST(FrictionalSim, AZeroGrippingDirectionInAnOverrideIsNamed) {
  const std::string text =
      "robot: gecko\nscene: wall\nduration_s: 1\nadhesion:\n  law: frictional\n"
      "  pad_overrides:\n    - {pad: LH_pad, grip_x: 0, grip_y: 0}\n";
  const std::string e = ErrorOf("bad_override_grip.yaml", text);
  EXPECT_NE(e.find("bad_override_grip.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("pad_overrides"), std::string::npos) << e;
  EXPECT_NE(e.find("LH_pad"), std::string::npos) << e;
}

}  // namespace
}  // namespace climbsim::sim
