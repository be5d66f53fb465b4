// The reflexes for feet welded to a surface (docs/control.md, "Reflexes on a closed chain"): stance
// compliance, GTO unloading and support holding on the pad's utilisation, the hold channel that
// presses only a foot that can move, and spindles that give a welded foot no offset but hold
// the gait when the body is pushed. Closed forms at dt = 10 ms, delays of one period.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "reflex/reflex.h"
#include "tests/reflex/test_util.h"

namespace climbsim::reflex {
namespace {

using testing_util::AllOff;
using testing_util::At;
using testing_util::Attached;
using testing_util::Recorder;
using testing_util::Stance;
using testing_util::Swing;
using testing_util::TimedEvent;
using testing_util::Touching;
using testing_util::kDt;
using Events = std::vector<TimedEvent>;
using E = LegEventType;
using R = LegEventReason;

// ---------------------------------------------------------------------------------------------
// Compliance
// ---------------------------------------------------------------------------------------------

LegReflexParams ComplianceOnly() {
  LegReflexParams p = AllOff();
  p.compliance.enabled = true;
  p.compliance.stance_kp_fraction = 0.5;
  p.compliance.ramp_s = 0.04;  // 0.25 of full kp per period
  return p;
}

// Attached in stance the stiffness falls to the stance fraction at 1/ramp_s; in swing (or
// detached) it rises back to full. No offsets, no events.
TEST(ReflexCompliance, StiffnessRampsDownInAttachedStanceAndBackInSwing) {
  LegReflex leg(ComplianceOnly(), kDt);
  Recorder rec(&leg);
  rec.Step(Touching(Stance()));              // #0: not attached: full
  rec.Repeat(Attached(Stance()), 3);         // #1..#3
  rec.Repeat(Attached(Swing()), 1);          // #4 (a peel: attached but in swing)
  rec.Repeat(Swing(), 2);                    // #5, #6
  const double expected[] = {1.0, 0.75, 0.5, 0.5, 0.75, 1.0, 1.0};
  for (int k = 0; k < 7; ++k) {
    EXPECT_EQ(rec.output(k).kp_fraction, Eigen::Vector3d::Constant(expected[k])) << k;
    EXPECT_EQ(rec.output(k).target_offset_rad, Eigen::Vector3d::Zero()) << k;
    EXPECT_EQ(rec.output(k).Fired(Reflex::kCompliance), expected[k] < 1.0) << k;
  }
  EXPECT_TRUE(rec.events().empty());
}

TEST(ReflexCompliance, FullStiffnessWhenSwitchedOff) {
  LegReflexParams p = ComplianceOnly();
  p.compliance.enabled = false;
  LegReflex leg(p, kDt);
  EXPECT_EQ(Recorder(&leg).Repeat(Attached(Stance()), 5).kp_fraction, Eigen::Vector3d::Ones());
}

// ---------------------------------------------------------------------------------------------
// GTO on the pad's utilisation
// ---------------------------------------------------------------------------------------------

LegReflexParams UnloadOnly() {
  LegReflexParams p = AllOff();
  p.gto.enabled = true;
  p.gto.require_partner_attached = false;
  p.gto.hold.threshold = 1e9;  // the load channel never holds here
  p.gto.unload = {.gain = 2.0, .threshold = 0.5, .delay_s = 0.01};
  p.gto.unload_min_kp_fraction = 0.25;
  p.gto.support.threshold = 1e9;
  return p;
}

// kp_fraction = max(min, 1 − K_U·[U(t−Δ) − U0]₊) while attached in stance.
TEST(ReflexGtoUnload, PadNearItsLimitLowersItsLegsStiffnessAfterTheDelay) {
  LegReflex leg(UnloadOnly(), kDt);
  Recorder rec(&leg);
  LegSensing s = Attached(Stance());
  s.utilisation = 0.5;  // exactly U0: nothing
  rec.Repeat(s, 2);     // #0, #1
  s.utilisation = 0.75;
  rec.Repeat(s, 2);  // #2, #3
  s.utilisation = 2.0;
  rec.Repeat(s, 2);  // #4, #5
  s.utilisation = 0.25;
  rec.Repeat(s, 2);  // #6, #7
  const double expected[] = {1.0, 1.0, 1.0, 0.5, 0.5, 0.25, 0.25, 1.0};
  for (int k = 0; k < 8; ++k) {
    EXPECT_EQ(rec.output(k).kp_fraction, Eigen::Vector3d::Constant(expected[k])) << k;
    EXPECT_EQ(rec.output(k).Fired(Reflex::kGtoUnload), expected[k] < 1.0) << k;
    EXPECT_EQ(rec.output(k).target_offset_rad, Eigen::Vector3d::Zero()) << k;
  }
  EXPECT_EQ(rec.events(), (Events{At(3, E::kGtoUnload)}));  // one event at onset
}

// Unloading multiplies the stance compliance: 0.5 · 0.5.
TEST(ReflexGtoUnload, ActsOnTopOfTheStanceCompliance) {
  LegReflexParams p = UnloadOnly();
  p.compliance = {.enabled = true, .stance_kp_fraction = 0.5, .ramp_s = 0.0};
  LegReflex leg(p, kDt);
  LegSensing s = Attached(Stance());
  s.utilisation = 0.75;
  EXPECT_EQ(Recorder(&leg).Repeat(s, 3).kp_fraction, Eigen::Vector3d::Constant(0.25));
}

TEST(ReflexGtoUnload, NotInSwingNorOnADetachedPad) {
  LegReflex leg(UnloadOnly(), kDt);
  Recorder rec(&leg);
  LegSensing swing = Attached(Swing());
  swing.utilisation = 2.0;
  EXPECT_EQ(rec.Repeat(swing, 3).kp_fraction, Eigen::Vector3d::Ones());
  LegSensing touching = Touching(Stance());
  touching.utilisation = 2.0;
  EXPECT_EQ(rec.Repeat(touching, 3).kp_fraction, Eigen::Vector3d::Ones());
  EXPECT_TRUE(rec.events().empty());
}

// A stance leg holds stance while the pads that carry its swing are near their limit.
TEST(ReflexGtoSupport, SupportPadsNearTheirLimitHoldStance) {
  LegReflexParams p = UnloadOnly();
  p.gto.support = {.gain = 1.0, .threshold = 0.75, .delay_s = 0.01};
  LegReflex leg(p, kDt);
  Recorder rec(&leg);
  LegSensing s = Attached(Stance());
  s.support_utilisation = 0.75;  // at the threshold: free
  rec.Repeat(s, 2);              // #0, #1
  s.support_utilisation = 0.875;
  rec.Repeat(s, 3);  // #2..#4
  s.support_utilisation = 0.5;
  rec.Repeat(s, 2);  // #5, #6
  for (int k = 0; k < 7; ++k) {
    EXPECT_EQ(rec.output(k).hold_stance, k >= 3 && k <= 5) << k;
    EXPECT_EQ(rec.output(k).target_offset_rad, Eigen::Vector3d::Zero()) << k;
  }
  EXPECT_EQ(rec.events(), (Events{At(3, E::kGtoHold, R::kSupport)}));
  LegSensing swing = Attached(Swing());
  swing.support_utilisation = 2.0;
  EXPECT_FALSE(rec.Repeat(swing, 3).hold_stance);  // only ever in stance
}

// The load channel holds and presses a loaded foot that can move, not a welded one (unless
// load_attached): on a wall the front pads hang loaded all the time.
TEST(ReflexGtoHold, LoadChannelActsOnAFreeFootNotOnAWeldedOne) {
  LegReflexParams p = AllOff();
  p.gto.enabled = true;
  p.gto.require_partner_attached = false;
  p.gto.hold = {.gain = 0.25, .threshold = 0.25, .delay_s = 0.01};
  LegSensing welded = Attached(Stance());
  welded.normal_load_n = 0.75;
  LegSensing free = Touching(Stance());
  free.normal_load_n = 0.75;
  {
    LegReflex leg(p, kDt);
    Recorder rec(&leg);
    const LegReflexOutput& a = rec.Repeat(welded, 3);
    EXPECT_FALSE(a.hold_stance);
    EXPECT_EQ(a.target_offset_rad, Eigen::Vector3d::Zero());
    const LegReflexOutput& b = rec.Repeat(free, 2);
    EXPECT_TRUE(b.hold_stance);
    EXPECT_EQ(b.target_offset_rad[kHipPitch], -0.125);  // 0.25·(0.75 − 0.25)
  }
  p.gto.load_attached = true;
  {
    LegReflex leg(p, kDt);
    Recorder rec(&leg);  // Repeat returns a reference into the recorder: keep it alive
    const LegReflexOutput& a = rec.Repeat(welded, 3);
    EXPECT_TRUE(a.hold_stance);
    EXPECT_EQ(a.target_offset_rad[kHipPitch], -0.125);
  }
}

// ---------------------------------------------------------------------------------------------
// Spindles on a welded foot
// ---------------------------------------------------------------------------------------------

LegReflexParams WeldedSpindleOnly() {
  LegReflexParams p = AllOff();
  p.spindle.enabled = true;
  p.spindle.resist = true;
  for (SpindleParams& j : p.spindle.joints) {
    j = {.length_gain = 0.5,
         .velocity_gain_s = 0.0,
         .length_threshold_rad = 0.0625,
         .velocity_threshold_rad_per_s = 0.0,
         .delay_s = 0.01};
  }
  p.spindle.stance_band_rad = 0.25;
  p.spindle.hold_s = 0.03;  // 3 periods
  return p;
}

// Attached: no offset whatever the stretch. In stance, a delayed stretch beyond the band holds
// every leg (hold_others) while it lasts and hold_s after; one event spindle(pushed).
TEST(ReflexLegSpindle, WeldedFootGetsNoOffsetAndAPushHoldsEveryLeg) {
  LegReflex leg(WeldedSpindleOnly(), kDt);
  Recorder rec(&leg);
  LegSensing s = Attached(Stance());
  s.stretch_rad = {0.0, 0.25, 0.0};  // at the band: inside
  rec.Repeat(s, 2);                  // #0, #1
  s.stretch_rad = {0.0, -0.3, 0.0};
  rec.Repeat(s, 2);  // #2, #3
  s.stretch_rad.setZero();
  rec.Repeat(s, 6);  // #4..#9
  for (int k = 0; k < 10; ++k) {
    EXPECT_EQ(rec.output(k).target_offset_rad, Eigen::Vector3d::Zero()) << k;
    // Stretched at #3 and #4 (one period late), then 3 periods more.
    EXPECT_EQ(rec.output(k).hold_others(), k >= 3 && k <= 7) << k;
  }
  EXPECT_EQ(rec.events(), (Events{At(3, E::kSpindle, R::kPushed)}));
}

// A stretch that outlasts max_hold_s is the leg's posture (its welded foot where the gait would
// not put it), not a push: the hold lets go after max_hold_s of it, and holds again only for a
// stretch that starts after one inside the band.
TEST(ReflexLegSpindle, AStretchThatOutlastsMaxHoldIsPostureAndLetsTheGaitGo) {
  LegReflexParams p = WeldedSpindleOnly();
  p.spindle.max_hold_s = 0.05;  // 5 periods
  LegReflex leg(p, kDt);
  Recorder rec(&leg);
  LegSensing s = Attached(Stance());
  s.stretch_rad = {0.0, 0.25, 0.0};  // at the band: inside
  rec.Repeat(s, 2);                  // #0, #1
  s.stretch_rad = {0.0, -0.3, 0.0};
  rec.Repeat(s, 14);  // #2..#15
  s.stretch_rad.setZero();
  rec.Repeat(s, 1);  // #16
  s.stretch_rad = {0.0, -0.3, 0.0};
  rec.Repeat(s, 3);  // #17..#19
  for (int k = 0; k < 20; ++k) {
    // Stretched from #3 (one period late): pushed #3..#7, posture from #8, the hold's hold_s
    // (3 periods) to #10; inside at #17; stretched again from #18.
    EXPECT_EQ(rec.output(k).hold_others(), (k >= 3 && k <= 10) || k >= 18) << k;
  }
  EXPECT_EQ(rec.events(),
            (Events{At(3, E::kSpindle, R::kPushed), At(18, E::kSpindle, R::kPushed)}));
}

// A free swing leg stretched beyond the swing threshold lifts its foot by K_L times the
// largest excess, on hip pitch and knee (stumbling correction); below it, nothing.
TEST(ReflexLegSpindle, BlockedSwingLegLiftsItsFoot) {
  LegReflexParams p = WeldedSpindleOnly();
  p.spindle.swing_threshold_rad = 0.25;
  p.spindle.joints[kKnee].length_gain = 0.25;
  LegReflex leg(p, kDt);
  Recorder rec(&leg);
  LegSensing s = Swing();
  s.stretch_rad = {-0.25, 0.125, 0.0};  // at the threshold: nothing
  rec.Repeat(s, 2);                      // #0, #1
  s.stretch_rad = {-0.5, 0.375, 0.0};    // excess 0.25 on hip yaw
  rec.Repeat(s, 2);                      // #2, #3
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(rec.output(k).target_offset_rad, Eigen::Vector3d::Zero()) << k;
  }
  EXPECT_EQ(rec.output(3).target_offset_rad, Eigen::Vector3d(0.0, 0.125, 0.0625));
  EXPECT_EQ(rec.events(), (Events{At(3, E::kSpindle, R::kStumble)}));
}

// With resist, the same stretch on a stance foot in the air is resisted, as before; on a foot
// that touches without a bond it is left to the preload; without resist a stance foot in the
// air only lifts when blocked, like a swing leg.
TEST(ReflexLegSpindle, FootInTheAirResistsTheSameStretch) {
  {
    LegReflexParams p = WeldedSpindleOnly();
    p.spindle.resist = false;
    p.spindle.swing_threshold_rad = 0.5;
    LegReflex leg(p, kDt);
    LegSensing s = Stance();
    s.stretch_rad = {0.0, -0.3125, 0.0};
    EXPECT_EQ(Recorder(&leg).Repeat(s, 3).target_offset_rad, Eigen::Vector3d::Zero());
  }
  {
    LegReflex leg(WeldedSpindleOnly(), kDt);
    LegSensing s = Touching(Stance());
    s.stretch_rad = {0.0, -0.3125, 0.0};
    EXPECT_EQ(Recorder(&leg).Repeat(s, 3).target_offset_rad, Eigen::Vector3d::Zero());
  }
  LegReflex leg(WeldedSpindleOnly(), kDt);
  Recorder rec(&leg);
  LegSensing s = Stance();
  s.stretch_rad = {0.0, -0.3125, 0.0};
  const LegReflexOutput& out = rec.Repeat(s, 2);
  EXPECT_EQ(out.target_offset_rad, Eigen::Vector3d(0.0, 0.125, 0.0));
  EXPECT_FALSE(out.hold_others());
  EXPECT_EQ(rec.events(), (Events{At(1, E::kSpindle)}));
}

// The spindles measure the stretch from the target the leg was given: a leg in a search (its
// foot in the air, where the law acts) that follows the search's reach exactly is not
// stretched. (Measured from the CPG's target alone, the spindle undid the reflexes' own
// offsets: on the wall it fought the peel.)
TEST(ReflexLegSpindle, StretchIsMeasuredFromTheCommandedTarget) {
  LegReflexParams p = WeldedSpindleOnly();
  p.search.enabled = true;
  p.search.attempt_duration_s = 0.1;  // 10 periods
  p.search.max_attempts = 3;
  LegReflex leg(p, kDt);
  Recorder rec(&leg);
  rec.Step(Swing());  // #0
  LegSensing s = Stance();
  Eigen::Vector3d commanded = rec.Step(s).target_offset_rad;  // #1: the search starts
  double largest = 0.0;
  for (int k = 2; k < 25; ++k) {
    s.stretch_rad = commanded;  // the joints followed last period's command
    const LegReflexOutput& out = rec.Step(s);
    EXPECT_FALSE(out.Fired(Reflex::kSpindle)) << k;
    EXPECT_TRUE(out.Fired(Reflex::kSearch)) << k;
    commanded = out.target_offset_rad;
    largest = std::max(largest, commanded.cwiseAbs().maxCoeff());
  }
  EXPECT_GT(largest, 0.1);  // well past the spindle's 0.0625 rad dead zone
}

}  // namespace
}  // namespace climbsim::reflex
