// One sticky pad in MuJoCo with the directional law (adhesion.law: frictional): a block
// welded under an inclined ceiling, its weight pulling at θ from the surface normal, holds
// iff the pull is shallow enough (θ ≥ 90° − α*) AND along the gripping direction; the same
// block with the von Mises law holds at every angle (on-vs-off on the same rig).
#include <gtest/gtest.h>

#include <cmath>

#include "adhesion/adhesion.h"
#include "tests/adhesion/closed_forms.h"
#include "tests/adhesion/mujoco_rig.h"

namespace climbsim::adhesion {
namespace {

using testing::BlockRig;
using testing::BlockSpec;
using testing::kDeg;
using testing::kG;

constexpr double kAreaM2 = 0.025 * 0.025;

// Weight 0.4·τ_max·A pulling at `theta_deg` from the normal, in the x–z plane (+x in-plane).
BlockSpec Inclined(double theta_deg, PadLaw law, double grip_x) {
  BlockSpec s;
  s.gravity = {kG * std::sin(theta_deg * kDeg), 0.0, kG * std::cos(theta_deg * kDeg)};
  s.pad.law = law;
  s.pad.frictional.critical_angle_deg = 30.0;
  s.pad.frictional.shear_limit_pa = 10e3;
  s.pad.frictional.grip_x = grip_x;
  s.pad.frictional.grip_y = 0.0;
  s.mass_kg = 0.4 * s.pad.frictional.shear_limit_pa * kAreaM2 / kG;
  s.start_attached = true;
  return s;
}

// Seconds until the pad lets go (−1: held for `seconds`).
double LetGoAfter(BlockRig* rig, double seconds) {
  const long n = std::lround(seconds / rig->m()->opt.timestep);
  for (long i = 0; i < n; ++i) {
    rig->Step();
    if (!rig->pad().attached()) return rig->d()->time;
  }
  return -1.0;
}

TEST(FrictionalPad, HoldsAShallowPullAlongTheGripAndNothingElse) {
  // θ = 75° along the grip: inside the limit (also with the 1 mm lever of the block's
  // centre: cos θ + 6(L/b) sin θ = 0.49 ≤ sin θ tan α* = 0.56).
  {
    BlockRig rig(Inclined(75.0, PadLaw::kFrictional, 1.0));
    ASSERT_TRUE(rig.pad().attached());
    EXPECT_LT(LetGoAfter(&rig, 2.0), 0.0);
    EXPECT_NEAR(rig.BlockPos().z(), 0.001, 1e-4);
    EXPECT_GT(rig.pad().frictional_utilisation(), 0.0);
    EXPECT_LT(rig.pad().frictional_utilisation(), 1.0);
    EXPECT_GT(rig.pad().load().fx_n, 0.0);  // the weight shears along +x
  }
  // Too steep (θ = 45° < 90° − α*), straight off (a ceiling, no shear), reversed grip: let go
  // within a few steps, all at once.
  for (auto [theta, grip] : {std::pair{45.0, 1.0}, std::pair{0.0, 1.0}, std::pair{75.0, -1.0}}) {
    SCOPED_TRACE(::testing::Message() << "theta " << theta << " grip_x " << grip);
    BlockRig rig(Inclined(theta, PadLaw::kFrictional, grip));
    const double t = LetGoAfter(&rig, 2.0);
    EXPECT_GT(t, 0.0);
    EXPECT_LT(t, 0.02);
    EXPECT_EQ(rig.pad().counts().detach_overload, 1);
  }
  // The von Mises pad under the same loads holds at every one of these angles (0.4 of its
  // capacity at 0°, 0.4/0.385 > 1 would not hold at 90°: these stay below).
  for (double theta : {0.0, 45.0, 75.0}) {
    SCOPED_TRACE(::testing::Message() << "von Mises theta " << theta);
    BlockSpec s = Inclined(theta, PadLaw::kVonMises, 1.0);
    s.mass_kg *= 0.8;  // 0.32 σ_T·A: below the 0.385 shear-limited minimum
    BlockRig rig(s);
    EXPECT_LT(LetGoAfter(&rig, 1.0), 0.0);
  }
}

// Release by unloading: a block held by shear along the grip (θ = 75°) lets go as soon as
// the shear is turned off while it still pulls (gravity switched to straight off the surface).
TEST(FrictionalPad, ReleasesWhenTheShearIsTakenOff) {
  BlockRig rig(Inclined(75.0, PadLaw::kFrictional, 1.0));
  EXPECT_LT(LetGoAfter(&rig, 0.5), 0.0);
  rig.m()->opt.gravity[0] = 0.0;
  rig.m()->opt.gravity[2] = 0.2 * kG;  // a pull of 0.08 τ_max·A, straight off
  const double t = LetGoAfter(&rig, 0.5);
  EXPECT_GT(t, 0.0);
  EXPECT_LT(t, 0.55);
}

// A bad key of the law is named when the pad is built.
TEST(FrictionalPad, BadParametersAreRejectedWithTheirKey) {
  StickyPadParams p;
  p.law = PadLaw::kFrictional;
  p.frictional.critical_angle_deg = 95.0;
  try {
    ValidateStickyPadParams(p);
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("adhesion.frictional.critical_angle_deg"),
              std::string::npos)
        << e.what();
  }
  p.law = PadLaw::kVonMises;  // not the law: not checked
  EXPECT_NO_THROW(ValidateStickyPadParams(p));
}

}  // namespace
}  // namespace climbsim::adhesion
