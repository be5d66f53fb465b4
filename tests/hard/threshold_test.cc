// Loads exactly at the rupture threshold, and the extreme bond grids (1×1 and 128×128) in a
// MuJoCo run. The rule (adhesion/README.md, seed eqs. 6–8): a bond in tension breaks when
// σ_vM ≥ σ_T, compared in squares; "≥" puts a load exactly at the threshold on the breaking side.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "adhesion/adhesion.h"
#include "tests/adhesion/mujoco_rig.h"
#include "tests/hard/hard_util.h"

namespace climbsim::adhesion {
namespace {

using climbsim::testing::StateFinite;
using climbsim::testing::WarningsRaised;
using testing::BlockRig;
using testing::BlockSpec;
using testing::kG;

// A pad whose every number is a power of two: b = h = 0.5 m, 4×4 bonds, σ_T = 1024 Pa. Then
// A = 0.25 m², dA = 2⁻⁶ m², σ_T·A = 256 N, the bonded centroid is 0 exactly (integer moment
// sums) and a straight pull F gives σ = F/(16·dA) with no rounding at all: F = σ_T·A is
// σ = σ_T to the last bit, the case the rule has to decide.
PadParams ExactPad() {
  return PadParams{.width_m = 0.5, .length_m = 0.5, .grid_x = 4, .grid_y = 4, .sigma_t_pa = 1024.0};
}

struct GridOutcome {
  BondGrid::UpdateResult result;
  std::vector<BrokenBond> broken;
  StressSummary summary;
};

GridOutcome PullStraightOff(double fn_n) {
  BondGrid g(ExactPad());
  g.BondAll();
  GridOutcome o;
  o.summary = g.Evaluate(PadLoad{.fn_n = fn_n});
  o.result = g.Update(PadLoad{.fn_n = fn_n});
  o.broken.assign(g.last_broken().begin(), g.last_broken().end());
  return o;
}

TEST(HardThreshold, BondGridPullExactlyAtSigmaTTimesAreaBreaksAndIsDeterministic) {
  const double capacity_n = 1024.0 * 0.25;  // 256 N exactly
  const GridOutcome a = PullStraightOff(capacity_n);
  const GridOutcome b = PullStraightOff(capacity_n);
  // σ is σ_T exactly, utilisation exactly 1.
  EXPECT_EQ(a.summary.peak_sigma_pa, 1024.0);
  EXPECT_EQ(a.summary.peak_utilisation, 1.0);
  EXPECT_EQ(a.summary.over_threshold, 16) << "every bond is at its threshold";
  // The documented side: σ_vM ≥ σ_T breaks. All 16 bonds in one round: overload.
  EXPECT_EQ(a.result.broken, 16);
  EXPECT_EQ(a.result.rounds, 1);
  EXPECT_TRUE(a.result.detached);
  // Deterministic: the same result twice, bit for bit (the broken-bond log in order).
  EXPECT_EQ(a.result.broken, b.result.broken);
  EXPECT_EQ(a.result.rounds, b.result.rounds);
  ASSERT_EQ(a.broken.size(), b.broken.size());
  for (size_t k = 0; k < a.broken.size(); ++k) {
    EXPECT_EQ(a.broken[k].index, b.broken[k].index);
    EXPECT_EQ(a.broken[k].round, b.broken[k].round);
  }
  EXPECT_EQ(0, std::memcmp(&a.summary, &b.summary, sizeof(StressSummary)));

  // One ulp below the capacity holds, untouched.
  const GridOutcome below = PullStraightOff(std::nextafter(capacity_n, 0.0));
  EXPECT_EQ(below.result.broken, 0);
  EXPECT_FALSE(below.result.detached);
  EXPECT_LT(below.summary.peak_utilisation, 1.0);
}

// The pull-off experiment in MuJoCo (adhesion/pulloff_rig.h) at exactly σ_T·A straight off:
// the weld's force is σ_T·A only to the solver's tolerance, and a pull applied all at once
// is met by a weld force that rises through it while the block settles into the weld, so
// which side it lands on is MuJoCo's business (measured: it lets go, overload, in the first
// steps). What must hold is that two runs give the same bits, held or ramped.
TEST(HardThreshold, PulloffRigHoldAtSigmaTTimesAreaIsTheSameTwice) {
  PulloffRigParams p;
  p.pad.grid_x = p.pad.grid_y = 16;
  struct Snapshot {
    bool attached;
    int bonded;
    PadLoad load;
    long detach_overload;
  };
  Snapshot shot[2];
  for (int run = 0; run < 2; ++run) {
    PulloffRig rig(AdhesionModel::kBonds, p);  // a fresh rig each time
    const StickyPad& pad = rig.Hold(/*angle_rad=*/0.0, rig.capacity_n(), /*duration_s=*/0.2);
    shot[run] = {pad.attached(), pad.grid().bonded_count(), pad.load(),
                 pad.counts().detach_overload};
  }
  EXPECT_EQ(shot[0].attached, shot[1].attached);
  EXPECT_EQ(shot[0].bonded, shot[1].bonded);
  EXPECT_EQ(shot[0].detach_overload, shot[1].detach_overload);
  EXPECT_EQ(0, std::memcmp(&shot[0].load, &shot[1].load, sizeof(PadLoad)));
  std::printf("pull-off rig held at sigma_T*A for 0.2 s: %s, %d bonds, overload detaches %ld\n",
              shot[0].attached ? "attached" : "let go", shot[0].bonded, shot[0].detach_overload);
  // And the ramp finds the same pull-off force twice, to the bit.
  PulloffRig r1(AdhesionModel::kBonds, p), r2(AdhesionModel::kBonds, p);
  const PulloffRun a = r1.Run(0.0), b = r2.Run(0.0);
  EXPECT_EQ(a.force_n, b.force_n);
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_STREQ(a.cause, b.cause);
}

// A block hanging from one fully bonded pad under a ceiling (gravity pulls it off the plane;
// a centred, uniform pull m·g), with a 1×1 and a 128×128 grid: it holds 2 s at 0.9·σ_T·A
// and lets go at 1.1·σ_T·A, whatever the grid, since a uniform pull loads every bond
// equally and σ = m·g/A. 1×1 is one bond, a hinge about every axis: the pull must be centred
// within kHingeMomentTolerance, which the weld's couple under a centred block is.
TEST(HardThreshold, OneByOneAndHundredTwentyEightSquaredGridsHoldAndFallAsSigmaTTimesAreaSays) {
  for (int n : {1, 128}) {
    for (double factor : {0.9, 1.1}) {
      SCOPED_TRACE("grid " + std::to_string(n) + ", load " + std::to_string(factor));
      BlockSpec s;
      s.gravity = {0, 0, kG};  // away from the plane: hanging under a ceiling
      s.pad.bonds.grid_x = s.pad.bonds.grid_y = n;
      const double capacity_n = s.pad.bonds.sigma_t_pa * 0.025 * 0.025;  // 6.25 N
      s.mass_kg = factor * capacity_n / kG;
      s.start_attached = true;
      BlockRig rig(s);
      ASSERT_TRUE(rig.pad().attached());
      double let_go_s = -1;
      bool finite = true;
      for (int i = 0; i < 2000; ++i) {
        rig.Step();
        finite = finite && StateFinite(rig.m(), rig.d());
        if (let_go_s < 0 && !rig.pad().attached()) let_go_s = rig.d()->time;
      }
      EXPECT_TRUE(finite);
      EXPECT_EQ(WarningsRaised(rig.d()), "");
      if (factor < 1) {
        EXPECT_LT(let_go_s, 0) << "let go at " << let_go_s << " s";
        EXPECT_TRUE(rig.pad().attached());
        EXPECT_EQ(rig.pad().grid().bonded_count(), n * n);
        mj_kinematics(rig.m(), rig.d());
        EXPECT_NEAR(rig.BlockPos().z(), 0.001, 1e-4) << "hangs where it was";
      } else {
        // In the first step the weld carries the weight: every bond at 1.1·σ_T, all at once.
        EXPECT_GT(let_go_s, 0);
        EXPECT_LE(let_go_s, 0.002 + 1e-12);
        EXPECT_EQ(rig.pad().counts().detach_overload, 1);
        EXPECT_EQ(rig.pad().grid().bonded_count(), 0);
      }
    }
  }
}

}  // namespace
}  // namespace climbsim::adhesion
