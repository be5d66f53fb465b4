// LegReflex: each climbing reflex fires in its scripted situation, with its exact event
// sequence and offsets, stays silent otherwise and when switched off.
// dt = 10 ms so that every duration below is a round number of control periods.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
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
// Preload
// ---------------------------------------------------------------------------------------------

LegReflexParams PreloadOnly() {
  LegReflexParams p = AllOff();
  p.preload.enabled = true;
  p.preload.hip_pitch_press_rad = 0.15;
  p.preload.knee_press_rad = 0.10;
  p.preload.ramp_s = 0.05;  // 5 periods
  p.preload.force_limit_n = 1.0;
  p.preload.max_duration_s = 0.2;  // 20 periods
  return p;
}

// Touchdown -> preload_start; the press ramps up; attach -> preload_end(attached).
TEST(ReflexPreload, TouchdownPressesUntilAttached) {
  LegReflex leg(PreloadOnly(), kDt);
  Recorder rec(&leg);
  rec.Step(Swing());             // #0
  for (int m = 0; m < 7; ++m) {  // #1..#7: touching, not attached
    const LegReflexOutput& out = rec.Step(Touching(Stance()));
    const double ramp = std::min(1.0, (m + 1.0) / 5.0);
    EXPECT_EQ(out.target_offset_rad[kHipPitch], -(0.15 * ramp)) << m;
    EXPECT_EQ(out.target_offset_rad[kKnee], -(0.10 * ramp)) << m;
    EXPECT_EQ(out.target_offset_rad[kHipYaw], 0.0);
    EXPECT_TRUE(out.hold_stance) << m;
    EXPECT_TRUE(out.Fired(Reflex::kPreload));
  }
  const LegReflexOutput& attached = rec.Step(Attached(Stance(), 0.1));  // #8
  EXPECT_EQ(attached.target_offset_rad, Eigen::Vector3d::Zero());
  EXPECT_FALSE(attached.hold_stance);
  rec.Repeat(Attached(Stance(), 0.2), 10);
  EXPECT_EQ(rec.events(),
            (Events{At(1, E::kPreloadStart, R::kTouchdown), At(8, E::kPreloadEnd, R::kAttached)}));
}

// With release_s the press fades after the attach instead of dropping at once: linearly, by
// 1/(n + 1) of the press it had a period, n = release_s/dt (a directional pad holds no pull
// before its shear builds).
TEST(ReflexPreload, PressFadesOverReleaseAfterTheAttach) {
  LegReflexParams p = PreloadOnly();
  p.preload.release_s = 0.03;  // 3 periods
  LegReflex leg(p, kDt);
  Recorder rec(&leg);
  rec.Step(Swing());                               // #0
  rec.Repeat(Touching(Stance()), 5);               // #1..#5: full press at #5
  rec.Repeat(Attached(Stance(), 0.9), 5);          // #6..#10
  const Eigen::Vector3d full(0.0, -0.15, -0.10);
  EXPECT_EQ(rec.output(5).target_offset_rad, full);
  for (int k = 6; k <= 10; ++k) {
    const double share = k <= 8 ? (9 - k) / 4.0 : 0.0;  // 3/4, 2/4, 1/4, then none
    EXPECT_LT((rec.output(k).target_offset_rad - share * full).norm(), 1e-15) << k;
    EXPECT_EQ(rec.output(k).Fired(Reflex::kPreload), share > 0.0) << k;
    EXPECT_FALSE(rec.output(k).hold_stance) << k;
  }
  EXPECT_EQ(rec.events(),
            (Events{At(1, E::kPreloadStart, R::kTouchdown), At(6, E::kPreloadEnd, R::kAttached)}));
}

TEST(ReflexPreload, ForceLimitEndsThePress) {
  LegReflex leg(PreloadOnly(), kDt);
  Recorder rec(&leg);
  rec.Step(Swing());  // #0
  LegSensing pressing = Touching(Stance());
  pressing.preload_n = 0.5;
  rec.Repeat(pressing, 3);                          // #1..#3
  pressing.preload_n = 1.0;                         // reaches force_limit_n exactly
  const LegReflexOutput& out = rec.Step(pressing);  // #4
  EXPECT_EQ(out.target_offset_rad, Eigen::Vector3d::Zero());
  EXPECT_FALSE(out.hold_stance);
  rec.Repeat(pressing, 30);  // still touching: no new preload
  EXPECT_EQ(rec.events(), (Events{At(1, E::kPreloadStart, R::kTouchdown),
                                  At(4, E::kPreloadEnd, R::kForceLimit)}));
}

// max_duration_s = 20 periods of press exactly, then preload_end(time_limit).
TEST(ReflexPreload, TimeLimitEndsThePressAfterExactlyMaxDuration) {
  LegReflex leg(PreloadOnly(), kDt);
  Recorder rec(&leg);
  rec.Step(Swing());                   // #0
  rec.Repeat(Touching(Stance()), 60);  // #1..#60
  EXPECT_EQ(rec.events(), (Events{At(1, E::kPreloadStart, R::kTouchdown),
                                  At(21, E::kPreloadEnd, R::kTimeLimit)}));
  for (int k = 1; k <= 60; ++k) {
    EXPECT_EQ(rec.output(k).hold_stance, k <= 20) << k;
    EXPECT_EQ(rec.output(k).target_offset_rad[kHipPitch] < 0.0, k <= 20) << k;
  }
}

// press_awaited_bond: an attached stance pad that the gait waits for is pressed as at touchdown
// (the same ramp and limits), again each time a press ends while the wait lasts; without the
// key, or once the wait ends, nothing.
TEST(ReflexPreload, PressesAnAttachedPadTheGaitWaitsForToBond) {
  LegSensing awaited = Attached(Stance(), 0.8);
  awaited.bond_awaited = true;
  awaited.preload_n = 0.5;
  for (const bool on : {false, true}) {
    LegReflexParams p = PreloadOnly();
    p.preload.press_awaited_bond = on;
    LegReflex leg(p, kDt);
    Recorder rec(&leg);
    rec.Step(Swing());                   // #0
    rec.Repeat(Attached(Stance()), 2);   // #1..#2: attached, nobody waits
    rec.Repeat(awaited, 3);              // #3..#5: the ramp, 1/5 .. 3/5 of full
    LegSensing pressed = awaited;
    pressed.preload_n = 1.0;             // the force limit
    rec.Step(pressed);                   // #6: ends
    rec.Step(awaited);                   // #7: the wait goes on: pressed again
    rec.Repeat(Attached(Stance()), 25);  // #8..#32: bonded, the wait over; time limit at #27
    if (!on) {
      EXPECT_TRUE(rec.events().empty());
      continue;
    }
    EXPECT_NEAR(rec.output(5).target_offset_rad[kHipPitch], -0.15 * 3 / 5, 1e-12);
    EXPECT_TRUE(rec.output(5).hold_stance);
    EXPECT_EQ(rec.events(), (Events{At(3, E::kPreloadStart, R::kBondAwaited),
                                    At(6, E::kPreloadEnd, R::kForceLimit),
                                    At(7, E::kPreloadStart, R::kBondAwaited),
                                    At(27, E::kPreloadEnd, R::kTimeLimit)}));
  }
}

TEST(ReflexPreload, SwingOnsetAbortsThePress) {
  LegReflex leg(PreloadOnly(), kDt);
  Recorder rec(&leg);
  rec.Step(Swing());
  rec.Repeat(Touching(Stance()), 3);                            // #1..#3
  const LegReflexOutput& out = rec.Step(Touching(Swing(0.0)));  // #4
  EXPECT_EQ(out.target_offset_rad, Eigen::Vector3d::Zero());
  EXPECT_EQ(rec.events(), (Events{At(1, E::kPreloadStart, R::kTouchdown),
                                  At(4, E::kPreloadEnd, R::kSwingStarted)}));
}

// A touchdown late in a swing counts at the stance onset.
TEST(ReflexPreload, TouchingBeforeStanceStartsAtStanceOnset) {
  LegReflex leg(PreloadOnly(), kDt);
  Recorder rec(&leg);
  rec.Repeat(Touching(Swing()), 3);  // #0..#2
  rec.Step(Touching(Stance(0.0)));   // #3
  EXPECT_EQ(rec.events(), (Events{At(3, E::kPreloadStart, R::kTouchdown)}));
}

TEST(ReflexPreload, SilentWhenAttachedOnTouchdownInSwingOrSwitchedOff) {
  {
    LegReflex leg(PreloadOnly(), kDt);
    Recorder rec(&leg);
    rec.Step(Swing());
    rec.Repeat(Attached(Stance()), 10);  // attached at touchdown: nothing to do
    rec.Repeat(Touching(Swing()), 10);   // touching in swing: not a touchdown
    EXPECT_TRUE(rec.events().empty());
  }
  {
    LegReflexParams p = PreloadOnly();
    p.preload.enabled = false;
    LegReflex leg(p, kDt);
    Recorder rec(&leg);
    rec.Step(Swing());
    const LegReflexOutput& out = rec.Repeat(Touching(Stance()), 30);
    EXPECT_TRUE(rec.events().empty());
    EXPECT_EQ(out.target_offset_rad, Eigen::Vector3d::Zero());
    EXPECT_FALSE(out.hold_stance);
  }
}

// ---------------------------------------------------------------------------------------------
// Search
// ---------------------------------------------------------------------------------------------

LegReflexParams SearchOnly() {
  LegReflexParams p = AllOff();
  p.search.enabled = true;
  p.search.reach_yaw_rad = 0.10;
  p.search.reach_pitch_rad = 0.20;
  p.search.reach_knee_rad = 0.10;
  p.search.lift_rad = 0.08;
  p.search.attempt_duration_s = 0.1;  // 10 periods
  p.search.max_attempts = 3;
  p.search.release_s = 0.05;  // 5 periods
  return p;
}

// Closed form of reflex.h at the m-th period of the search (10 periods per attempt, 3 attempts).
Eigen::Vector3d SearchOffset(const SearchParams& p, int m) {
  const double rho = m / 30.0;
  const double lift = p.lift_rad * std::sin(std::numbers::pi * (m % 10) / 10.0);
  return {p.reach_yaw_rad * rho, lift - p.reach_pitch_rad * rho, lift - p.reach_knee_rad * rho};
}

// A swing that ends without touchdown: search_start, reach and lift, search_end after exactly
// max_attempts attempts; the reached offset then fades out over release_s.
TEST(ReflexSearch, NoTouchdownSearchesForExactlyMaxAttempts) {
  const LegReflexParams p = SearchOnly();
  LegReflex leg(p, kDt);
  Recorder rec(&leg);
  rec.Step(Swing());              // #0
  for (int m = 0; m < 30; ++m) {  // #1..#30
    const LegReflexOutput& out = rec.Step(Stance());
    // Same formula, evaluated in a different order: rounding only.
    EXPECT_TRUE(out.target_offset_rad.isApprox(SearchOffset(p.search, m), 1e-12) || m == 0)
        << m << ": " << out.target_offset_rad.transpose();
    EXPECT_TRUE(out.hold_stance) << m;
  }
  EXPECT_EQ(rec.output(1).target_offset_rad, Eigen::Vector3d::Zero());  // m = 0: ρ = 0, s = 0
  const Eigen::Vector3d reached = rec.output(30).target_offset_rad;
  for (int r = 1; r <= 6; ++r) {  // #31..#36: released over 5 periods
    const LegReflexOutput& out = rec.Step(Stance());
    EXPECT_FALSE(out.hold_stance);
    const double left = std::max(0, 5 - r) / 5.0;
    EXPECT_TRUE(out.target_offset_rad.isApprox(reached * left, 1e-12) ||
                (left == 0.0 && out.target_offset_rad.isZero(0.0)))
        << r;
  }
  EXPECT_EQ(rec.events(),
            (Events{At(1, E::kSearchStart), At(31, E::kSearchEnd, R::kAttemptsExhausted)}));
}

// Touching during the search: search_end(found), then the touchdown preload at once; the
// reached offset is held through stance and released after the swing starts.
TEST(ReflexSearch, FoundThenPreloadAndTheReachIsHeldUntilSwing) {
  LegReflexParams p = SearchOnly();
  p.preload.enabled = true;
  LegReflex leg(p, kDt);
  Recorder rec(&leg);
  rec.Step(Swing());         // #0
  rec.Repeat(Stance(), 13);  // #1..#13: m = 0..12
  const Eigen::Vector3d reached = rec.output(13).target_offset_rad;
  EXPECT_TRUE(reached.isApprox(SearchOffset(p.search, 12), 1e-12));
  const LegReflexOutput& found = rec.Step(Touching(Stance()));  // #14
  EXPECT_TRUE(found.hold_stance);                               // preloading now
  rec.Repeat(Attached(Stance()), 5);                            // #15..#19
  EXPECT_EQ(rec.output(19).target_offset_rad, reached);         // preload over: the reach alone
  EXPECT_FALSE(rec.output(19).hold_stance);
  rec.Step(Attached(Swing(0.0)));  // #20: release starts
  EXPECT_TRUE(rec.output(20).target_offset_rad.isApprox(reached * 0.8, 1e-12));
  rec.Repeat(Swing(), 4);  // #21..#24
  EXPECT_EQ(rec.output(24).target_offset_rad, Eigen::Vector3d::Zero());
  EXPECT_EQ(rec.events(), (Events{At(1, E::kSearchStart), At(14, E::kSearchEnd, R::kFound),
                                  At(14, E::kPreloadStart, R::kTouchdown),
                                  At(15, E::kPreloadEnd, R::kAttached)}));
}

TEST(ReflexSearch, SwingOnsetAbortsTheSearch) {
  LegReflex leg(SearchOnly(), kDt);
  Recorder rec(&leg);
  rec.Step(Swing());
  rec.Repeat(Stance(), 4);  // #1..#4
  rec.Step(Swing(0.0));     // #5
  EXPECT_EQ(rec.events(), (Events{At(1, E::kSearchStart), At(5, E::kSearchEnd, R::kSwingStarted)}));
}

// A search that ran out while a peel waits for this pad starts again at once, and again; one
// that ran out with nobody waiting stays given up.
TEST(ReflexSearch, RunsAgainWhileAPeelWaitsForThePad) {
  LegSensing waited = Stance();
  waited.waited_on = true;
  LegReflex leg(SearchOnly(), kDt);
  Recorder rec(&leg);
  rec.Step(Swing());         // #0
  rec.Repeat(Stance(), 30);  // #1..#30: m = 0..29, nobody waits
  rec.Repeat(Stance(), 10);  // #31..#40: ran out at #31, stays given up
  rec.Step(waited);          // #41: a peel now waits: a second search
  rec.Repeat(waited, 29);    // #42..#70
  rec.Step(waited);          // #71: out again, and a third at once
  // The second search reached as the first did.
  EXPECT_TRUE(rec.output(70).target_offset_rad.isApprox(SearchOffset(SearchOnly().search, 29),
                                                        1e-12));
  EXPECT_FALSE(rec.output(70).target_offset_rad.isZero(1e-6));
  rec.Repeat(Touching(waited), 1);  // #72: found
  EXPECT_EQ(rec.events(),
            (Events{At(1, E::kSearchStart), At(31, E::kSearchEnd, R::kAttemptsExhausted),
                    At(41, E::kSearchStart), At(71, E::kSearchEnd, R::kAttemptsExhausted),
                    At(71, E::kSearchStart), At(72, E::kSearchEnd, R::kFound)}));
}

TEST(ReflexSearch, SilentWhenTouchingAtStanceOnsetOrSwitchedOff) {
  {
    LegReflex leg(SearchOnly(), kDt);
    Recorder rec(&leg);
    rec.Step(Swing());
    rec.Repeat(Touching(Stance()), 10);
    rec.Repeat(Swing(), 5);
    rec.Repeat(Attached(Stance()), 10);
    EXPECT_TRUE(rec.events().empty());
  }
  {
    LegReflexParams p = SearchOnly();
    p.search.enabled = false;
    LegReflex leg(p, kDt);
    Recorder rec(&leg);
    rec.Step(Swing());
    const LegReflexOutput& out = rec.Repeat(Stance(), 40);
    EXPECT_TRUE(rec.events().empty());
    EXPECT_FALSE(out.hold_stance);
    EXPECT_EQ(out.target_offset_rad, Eigen::Vector3d::Zero());
  }
}

// ---------------------------------------------------------------------------------------------
// Peel
// ---------------------------------------------------------------------------------------------

LegReflexParams PeelOnly() {
  LegReflexParams p = AllOff();
  p.peel.enabled = true;
  p.peel.hip_yaw_rad = -0.2;
  p.peel.hip_pitch_lift_rad = 0.05;
  p.peel.knee_lift_rad = 0.04;
  p.peel.ramp_s = 0.05;          // 5 periods of kDt
  p.peel.max_duration_s = 0.2;   // 20 periods
  p.peel.release_s = 0.03;       // 3 periods
  return p;
}

// r(u) = 3u² − 2u³, u = periods since onset · kDt / ramp_s.
double SmoothStep(int periods) {
  const double u = std::min(1.0, periods * kDt / 0.05);
  return u * u * (3.0 - 2.0 * u);
}

// Swing onset while attached: one peel event; the phase is held and the foot is drawn back
// and lifted along the smooth step, exactly, until the ramp is done.
TEST(ReflexPeel, SwingOnsetWhileAttachedPullsBackAlongASmoothStepAndHoldsThePhase) {
  LegReflex leg(PeelOnly(), kDt);
  Recorder rec(&leg);
  rec.Repeat(Attached(Stance()), 3);  // #0..#2
  for (int k = 0; k <= 8; ++k) {      // #3..#11, the phase held at the swing's start
    const LegReflexOutput& out = rec.Step(Attached(Swing(0.0)));
    const double r = SmoothStep(k);
    EXPECT_TRUE(out.hold_phase) << k;
    EXPECT_FALSE(out.hold_stance) << k;
    EXPECT_TRUE(out.Fired(Reflex::kPeel)) << k;
    EXPECT_NEAR(out.target_offset_rad[kHipYaw], -0.2 * r, 1e-15) << k;
    EXPECT_NEAR(out.target_offset_rad[kHipPitch], 0.05 * r, 1e-15) << k;
    EXPECT_NEAR(out.target_offset_rad[kKnee], 0.04 * r, 1e-15) << k;
  }
  EXPECT_EQ(rec.events(), (Events{At(3, E::kPeel)}));
}

// The pad lets go: peel_end (detached), the phase is free, the offsets fade linearly to zero
// over release_s (3/4, 2/4, 1/4 of the last offset, then nothing).
TEST(ReflexPeel, EndsWhenThePadLetsGoAndFadesOut) {
  LegReflex leg(PeelOnly(), kDt);
  Recorder rec(&leg);
  rec.Repeat(Attached(Stance()), 3);        // #0..#2
  rec.Repeat(Attached(Swing(0.0)), 3);      // #3..#5: peel periods 0, 1, 2
  const Eigen::Vector3d last = Eigen::Vector3d(-0.2, 0.05, 0.04) * SmoothStep(3);
  for (int k = 3; k >= 0; --k) {            // #6..#9
    const LegReflexOutput& out = rec.Step(Swing(0.05));
    EXPECT_FALSE(out.hold_phase) << k;
    const Eigen::Vector3d want = last * (k / 4.0);
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(out.target_offset_rad[j], want[j], 1e-15) << k;
  }
  EXPECT_EQ(rec.events(), (Events{At(3, E::kPeel), At(6, E::kPeelEnd, R::kDetached)}));
}

// A pad that will not let go: after max_duration_s the peel gives up and frees the phase.
TEST(ReflexPeel, GivesUpAfterItsMaximumDuration) {
  LegReflex leg(PeelOnly(), kDt);
  Recorder rec(&leg);
  rec.Repeat(Attached(Stance()), 3);                           // #0..#2
  const LegReflexOutput& held = rec.Repeat(Attached(Swing(0.0)), 20);  // #3..#22
  EXPECT_TRUE(held.hold_phase);
  const LegReflexOutput& gave_up = rec.Step(Attached(Swing(0.0)));     // #23: 20 periods
  EXPECT_FALSE(gave_up.hold_phase);
  EXPECT_EQ(rec.events(), (Events{At(3, E::kPeel), At(23, E::kPeelEnd, R::kTimeLimit)}));
}

// An active release: the peel asks the others to take the pad's load (unload_pad) from the
// swing onset; the pad is let go (release_pad) at the first period after the onset in which it
// carries at most release_load_n, and kept disengaged (disengage_pad) until the next stance.
TEST(ReflexPeel, ActiveReleaseUnloadsThenLetsGoAndKeepsThePadDisengagedThroughTheSwing) {
  LegReflexParams p = PeelOnly();
  p.peel.active_release = true;
  p.peel.release_load_n = 0.2;
  LegReflex leg(p, kDt);
  Recorder rec(&leg);
  rec.Repeat(Attached(Stance()), 2);  // #0, #1
  LegSensing loaded = Attached(Swing(0.0));
  for (const double load : {0.1, 0.8, 0.5, 0.25}) {  // #2..#5: onset (too early), loaded
    loaded.load_n = load;
    rec.Step(loaded);
  }
  loaded.load_n = 0.15;
  rec.Step(loaded);          // #6: light enough: let go
  rec.Step(Swing(0.1));      // #7: detached
  rec.Repeat(Swing(0.5), 2);  // #8, #9
  rec.Step(Touching(Stance()));  // #10: the next stance
  for (int k = 2; k <= 6; ++k) {
    EXPECT_TRUE(rec.output(k).unload_pad) << k;
    EXPECT_TRUE(rec.output(k).hold_phase) << k;
    EXPECT_EQ(rec.output(k).release_pad, k == 6) << k;
  }
  for (int k = 6; k <= 9; ++k) EXPECT_TRUE(rec.output(k).disengage_pad) << k;
  EXPECT_FALSE(rec.output(10).disengage_pad);
  EXPECT_FALSE(rec.output(7).unload_pad);
  EXPECT_EQ(rec.events(), (Events{At(2, E::kPeel), At(7, E::kPeelEnd, R::kDetached)}));
}

// A pad that stays loaded is let go at the peel's time limit (the period before it).
TEST(ReflexPeel, ActiveReleaseLetsGoAtTheTimeLimitWhateverTheLoad) {
  LegReflexParams p = PeelOnly();
  p.peel.active_release = true;
  LegReflex leg(p, kDt);
  Recorder rec(&leg);
  rec.Repeat(Attached(Stance()), 2);  // #0, #1
  LegSensing loaded = Attached(Swing(0.0));
  loaded.load_n = 2.0;
  rec.Repeat(loaded, 20);  // #2..#21: peel periods 0..19 (max 20)
  for (int k = 2; k <= 21; ++k) EXPECT_EQ(rec.output(k).release_pad, k == 21) << k;
  EXPECT_FALSE(PeelOnly().peel.active_release);  // off by default: the leg peels its pad
}

// With wait_for_support, a support leg's pad that is not attached makes the peeling pad a
// support again: while it lasts the pad is neither unloaded nor let go, light or not, and the
// time limit waits (the release comes max_duration_s of peeling without the wait); the phase
// stays held. Without it the same sensing lets the light pad go at once.
TEST(ReflexPeel, AnActiveReleaseWaitsWhileASupportPadIsDetached) {
  LegReflexParams p = PeelOnly();
  p.peel.active_release = true;
  p.peel.release_load_n = 0.2;
  // The outputs of one run (copied: the leg and its recorder end with the call).
  const auto run = [&](bool wait_for_support) {
    p.peel.wait_for_support = wait_for_support;
    LegReflex leg(p, kDt);
    Recorder rec(&leg);
    rec.Repeat(Attached(Stance()), 2);  // #0, #1
    LegSensing peeling = Attached(Swing(0.0));
    peeling.load_n = 2.0;
    rec.Repeat(peeling, 3);             // #2..#4: peel periods 0..2, loaded
    LegSensing alone = peeling;
    alone.partner_attached = false;
    alone.load_n = 0.1;                 // light: the release's load test would pass
    rec.Repeat(alone, 30);              // #5..#34: the support pad is gone
    rec.Repeat(peeling, 17);            // #35..#51: back; periods 3..19, the time limit's
    std::vector<LegReflexOutput> outputs;
    for (int k = 0; k < rec.updates(); ++k) outputs.push_back(rec.output(k));
    return outputs;
  };
  const std::vector<LegReflexOutput> waited = run(true);
  for (int k = 2; k <= 51; ++k) {
    const bool waiting = k >= 5 && k <= 34;
    EXPECT_TRUE(waited[k].hold_phase) << k;
    EXPECT_EQ(waited[k].unload_pad, !waiting) << k;
    // 20 periods of peeling: #2..#4, #35..#51.
    EXPECT_EQ(waited[k].release_pad, k == 51) << k;
  }
  EXPECT_TRUE(run(false)[5].release_pad);  // without the wait the light pad goes at once
  EXPECT_FALSE(PeelOnly().peel.wait_for_support);  // off by default
}

TEST(ReflexPeel, SilentWhenDetachedAtSwingOnsetOrSwitchedOff) {
  {
    LegReflex leg(PeelOnly(), kDt);
    Recorder rec(&leg);
    rec.Repeat(Touching(Stance()), 3);
    const LegReflexOutput& out = rec.Repeat(Swing(0.15), 3);
    EXPECT_TRUE(rec.events().empty());
    EXPECT_FALSE(out.hold_phase);
    EXPECT_EQ(out.target_offset_rad, Eigen::Vector3d::Zero());
  }
  {
    LegReflexParams p = PeelOnly();
    p.peel.enabled = false;
    LegReflex leg(p, kDt);
    Recorder rec(&leg);
    rec.Repeat(Attached(Stance()), 3);
    const LegReflexOutput& out = rec.Repeat(Attached(Swing(0.15)), 3);
    EXPECT_TRUE(rec.events().empty());
    EXPECT_EQ(out.target_offset_rad, Eigen::Vector3d::Zero());
  }
}

// ---------------------------------------------------------------------------------------------
// Re-grip
// ---------------------------------------------------------------------------------------------

LegReflexParams RegripOnly() {
  LegReflexParams p = PreloadOnly();
  p.preload.enabled = false;  // re-grip presses with the preload profile anyway
  p.regrip.enabled = true;
  p.regrip.hold_others_s = 0.05;  // 5 periods
  return p;
}

// The re-grip with a re-place of 8 periods, and a touch without a bond re-placed after 5.
LegReflexParams ReplaceRejected() {
  LegReflexParams p = RegripOnly();
  p.regrip.lift_rad = 0.2;
  p.regrip.replace_s = 0.08;        // 8 periods
  p.regrip.replace_after_s = 0.05;  // 5 periods
  return p;
}

// A touch in stance that adhesion refused for `refusal`.
LegSensing RefusedTouch(Refusal refusal) {
  LegSensing touch = Touching(Stance());
  touch.refusal = refusal;
  return touch;
}

// Bonds lost in stance by an attached pad: regrip, preload_start(regrip); hold_others for
// exactly hold_others_s; the press runs to its time limit since the pad stays attached.
TEST(ReflexRegrip, BondsLostInStancePressesAgainAndHoldsOthers) {
  LegReflex leg(RegripOnly(), kDt);
  Recorder rec(&leg);
  rec.Repeat(Attached(Stance()), 2);  // #0..#1
  LegSensing lost = Attached(Stance(), 0.7);
  lost.bonds_lost = true;
  const LegReflexOutput& out = rec.Step(lost);  // #2
  EXPECT_TRUE(out.hold_others());
  EXPECT_TRUE(out.hold_stance);
  EXPECT_EQ(out.target_offset_rad[kHipPitch], -(0.15 * (1.0 / 5.0)));
  EXPECT_TRUE(out.Fired(Reflex::kRegrip));
  rec.Repeat(Attached(Stance(), 0.7), 40);  // #3..#42
  for (int k = 2; k <= 42; ++k) {
    EXPECT_EQ(rec.output(k).hold_others(), k <= 6) << k;   // 5 periods: #2..#6
    EXPECT_EQ(rec.output(k).hold_stance, k <= 21) << k;  // 20 periods of press: #2..#21
  }
  EXPECT_EQ(rec.events(), (Events{At(2, E::kRegrip), At(2, E::kPreloadStart, R::kRegrip),
                                  At(22, E::kPreloadEnd, R::kTimeLimit)}));
}

// The pad comes off and attaches again: preload_end(attached). Bonds lost again during the
// episode extend hold_others without a second regrip event.
TEST(ReflexRegrip, ReattachEndsThePressAndRepeatedLossExtendsTheHold) {
  LegReflexParams p = RegripOnly();
  p.regrip.lift_rad = 0.0;  // press only, even when the pad lets go
  LegReflex leg(p, kDt);
  Recorder rec(&leg);
  rec.Repeat(Attached(Stance()), 2);  // #0..#1
  LegSensing lost = Attached(Stance(), 0.5);
  lost.bonds_lost = true;
  rec.Step(lost);                     // #2: regrip
  rec.Step(Attached(Stance(), 0.5));  // #3
  rec.Step(lost);                     // #4: again, within the episode
  LegSensing off = Touching(Stance());
  off.bonds_lost = true;
  rec.Step(off);                      // #5: detached (was attached at #4)
  rec.Step(Attached(Stance(), 0.1));  // #6: attached again
  for (int k = 7; k < 15; ++k) rec.Step(Attached(Stance(), 0.2));
  // The last loss, at #5, holds the others for 5 periods: #5..#9.
  for (int k = 2; k < 15; ++k) EXPECT_EQ(rec.output(k).hold_others(), k <= 9) << k;
  EXPECT_EQ(rec.events(), (Events{At(2, E::kRegrip), At(2, E::kPreloadStart, R::kRegrip),
                                  At(6, E::kPreloadEnd, R::kAttached)}));
}

// A pad that lets go entirely in stance is re-placed: the foot lifts by lift·sin²(π·s) over
// replace_s with the leg held in stance; it is pressed only once it has been off the surface
// and comes down (a new touchdown: the preload), and the re-place ends when it attaches.
TEST(ReflexRegrip, PadThatLetGoIsRePlacedThenPressedAtTheNewTouchdown) {
  LegReflexParams p = RegripOnly();
  p.preload.enabled = true;
  p.regrip.lift_rad = 0.2;
  p.regrip.replace_s = 0.08;  // 8 periods
  LegReflex leg(p, kDt);
  Recorder rec(&leg);
  rec.Repeat(Attached(Stance()), 2);  // #0, #1
  LegSensing off = Touching(Stance());
  off.bonds_lost = true;
  rec.Step(off);                       // #2: let go: s = 0
  rec.Step(Touching(Stance()));        // #3: s = 1/8, still touching: no press
  rec.Repeat(Stance(), 4);             // #4..#7: s = 2/8 .. 5/8, in the air
  rec.Step(Touching(Stance()));        // #8: s = 6/8, touches down: the press starts
  rec.Step(Attached(Stance(), 0.9));   // #9: attached: the re-place ends
  for (int k = 2; k <= 8; ++k) {
    const double s = (k - 2) / 8.0;
    const double lift = 0.2 * std::pow(std::sin(M_PI * s), 2);
    const double press = k == 8 ? 0.15 / 5.0 : 0.0;
    EXPECT_NEAR(rec.output(k).target_offset_rad[kHipPitch], lift - press, 1e-15) << k;
    EXPECT_NEAR(rec.output(k).target_offset_rad[kHipYaw], 0.0, 1e-15) << k;
    EXPECT_TRUE(rec.output(k).hold_stance) << k;
    EXPECT_TRUE(rec.output(k).Fired(Reflex::kRegrip)) << k;
  }
  EXPECT_FALSE(rec.output(9).hold_stance);
  EXPECT_EQ(rec.output(9).target_offset_rad, Eigen::Vector3d::Zero());
  EXPECT_EQ(rec.events(), (Events{At(2, E::kRegrip), At(8, E::kPreloadStart, R::kTouchdown),
                                  At(9, E::kPreloadEnd, R::kAttached)}));
}

// A re-place that puts the foot down on nothing (the body moved while the pad was gone) hands
// it to the search: search_start in the period after the re-place's last, the search's reach
// from there on.
TEST(ReflexRegrip, ARePlaceThatFindsNoSurfaceStartsASearch) {
  LegReflexParams p = RegripOnly();
  p.search.enabled = true;
  p.search.reach_pitch_rad = 0.2;
  p.search.attempt_duration_s = 0.05;  // 5 periods
  p.search.max_attempts = 2;
  p.search.lift_rad = 0.0;  // the reach alone: -0.2 rad times the share of the search done
  p.regrip.lift_rad = 0.2;
  p.regrip.replace_s = 0.08;  // 8 periods
  LegReflex leg(p, kDt);
  Recorder rec(&leg);
  rec.Repeat(Attached(Stance()), 2);  // #0, #1
  LegSensing off = Stance();
  off.bonds_lost = true;
  rec.Step(off);            // #2: let go, in the air at once
  rec.Repeat(Stance(), 9);  // #3..#11: the re-place ends at #9 (8 periods), touching nothing
  EXPECT_TRUE(rec.output(9).Fired(Reflex::kRegrip));
  EXPECT_FALSE(rec.output(10).Fired(Reflex::kRegrip));
  EXPECT_TRUE(rec.output(10).Fired(Reflex::kSearch));
  EXPECT_TRUE(rec.output(10).hold_stance);
  EXPECT_NEAR(rec.output(11).target_offset_rad[kHipPitch], -0.2 * 1 / 10.0, 1e-15);  // reaching
  EXPECT_EQ(rec.events(), (Events{At(2, E::kRegrip), At(10, E::kSearchStart)}));
  // A re-place that touches down does not search.
  LegReflex touched(p, kDt);
  Recorder quiet(&touched);
  quiet.Repeat(Attached(Stance()), 2);
  quiet.Step(off);
  quiet.Repeat(Stance(), 6);             // up to s = 7/8
  quiet.Repeat(Touching(Stance()), 4);  // down on the surface as it ends
  EXPECT_EQ(quiet.events(), (Events{At(2, E::kRegrip)}));
}

// A foot that touched down in stance and has not attached replace_after_s later (a rejected
// landing; its contact may chatter meanwhile) is re-placed: regrip(touchdown), the preload
// ends, the lift runs.
TEST(ReflexRegrip, ATouchThatDoesNotAttachIsRePlaced) {
  LegReflexParams p = ReplaceRejected();
  p.preload.enabled = true;
  LegReflex leg(p, kDt);
  Recorder rec(&leg);
  rec.Step(Swing());                  // #0
  rec.Repeat(Touching(Stance()), 2);  // #1, #2: touchdown, preload
  rec.Step(Stance());                 // #3: the edge lets go for a period
  rec.Step(Touching(Stance()));       // #4
  rec.Step(Touching(Stance()));       // #5: the fifth period since the touch: re-place
  rec.Step(Touching(Stance()));       // #6: lifting
  EXPECT_EQ(rec.events(), (Events{At(1, E::kPreloadStart, R::kTouchdown),
                                  At(5, E::kPreloadEnd, R::kRegrip),
                                  At(5, E::kRegrip, R::kTouchdown)}));
  EXPECT_GT(rec.output(6).target_offset_rad[kHipPitch], 0.0);
  EXPECT_TRUE(rec.output(6).hold_stance);
  // Off with replace_after_s = 0.
  p.regrip.replace_after_s = 0.0;
  LegReflex never(p, kDt);
  Recorder quiet(&never);
  quiet.Step(Swing());
  quiet.Repeat(Touching(Stance()), 40);
  for (const auto& e : quiet.events()) EXPECT_NE(e.event.type, E::kRegrip);
}

// A foot re-placed after a landing refused for too few contacts (a tilted pad on its corner)
// presses harder: after the n-th such re-place of a stance, min(1 + retry_gain·n,
// retry_max_scale) times the preload's press; the next stance starts at 1 again. A landing
// refused for too little of its face touching (a bump's top) or with retry_gain 0 is pressed
// as before. The foot touches the surface except while the re-place lifts it (a positive
// hip-pitch offset the period before).
TEST(ReflexRegrip, ARePlacedCornerLandingIsPressedHarderEachTime) {
  LegReflexParams p = ReplaceRejected();
  p.preload.enabled = true;
  p.preload.ramp_s = 0.0;    // the full press at once: one value per preload
  p.regrip.shift_rad = 0.0;  // every re-place lands where the last one did
  p.preload.retry_max_scale = 2.5;
  // The hip-pitch press of each touchdown preload in two stances of 60 periods each.
  const auto presses = [&](double retry_gain, Refusal refusal) {
    p.preload.retry_gain = retry_gain;
    LegReflex leg(p, kDt);
    Recorder rec(&leg);
    const LegSensing touch = RefusedTouch(refusal);
    std::vector<double> seen;
    for (int stance = 0; stance < 2; ++stance) {
      rec.Step(Swing());
      bool lifted = false;
      for (int k = 0; k < 60; ++k) {
        const LegReflexOutput& out = rec.Step(lifted ? Stance() : touch);
        lifted = out.target_offset_rad[kHipPitch] > 0.0;
        const double press = -out.target_offset_rad[kHipPitch];
        if (out.Fired(Reflex::kPreload) && !out.Fired(Reflex::kRegrip) &&
            (seen.empty() || seen.back() != press)) {
          seen.push_back(press);
        }
      }
    }
    return seen;
  };
  const std::vector<double> growing = presses(1.0, Refusal::kContacts);
  ASSERT_GE(growing.size(), 5u);
  EXPECT_EQ(growing[0], 0.15);
  EXPECT_EQ(growing[1], 0.15 * 2.0);  // 1 + 1·1
  EXPECT_EQ(growing[2], 0.15 * 2.5);  // 1 + 1·2 = 3, capped
  const auto next_stance = std::find(growing.begin() + 1, growing.end(), 0.15);
  ASSERT_NE(next_stance, growing.end());
  EXPECT_EQ(*(next_stance + 1), 0.15 * 2.0);
  for (double press : presses(1.0, Refusal::kShare)) EXPECT_EQ(press, 0.15);
  for (double press : presses(0.0, Refusal::kContacts)) EXPECT_EQ(press, 0.15);
}

// A re-placed landing moves shift_rad along hip yaw; with shift_approach_refusals off, one that
// adhesion refused for how it came (too fast, too oblique) comes down where it was, also when
// the foot bounced off (the pad forgets the refusal off the surface), while a refusal for its
// place (contacts, contact share) is still shifted.
TEST(ReflexRegrip, ALandingRefusedForItsApproachIsPutDownWhereItWasWhenAsked) {
  LegReflexParams p = ReplaceRejected();
  p.regrip.shift_rad = 0.1;
  const auto yaw_after_replace = [&](bool shift_approach_refusals, Refusal refusal) {
    p.regrip.shift_approach_refusals = shift_approach_refusals;
    LegReflex leg(p, kDt);
    Recorder rec(&leg);
    const LegSensing touch = RefusedTouch(refusal);
    rec.Step(Swing());            // #0
    rec.Step(touch);              // #1: refused at the touchdown
    rec.Repeat(Stance(), 3);      // #2..#4: bounced off, the pad's refusal forgotten
    rec.Repeat(Touching(Stance()), 10);  // #5..#14: re-placed at #5, down again from #13
    EXPECT_NE(std::find(rec.events().begin(), rec.events().end(), At(5, E::kRegrip, R::kTouchdown)),
              rec.events().end());
    return rec.output(14).target_offset_rad[kHipYaw];
  };
  EXPECT_EQ(yaw_after_replace(true, Refusal::kApproach), 0.1);
  EXPECT_EQ(yaw_after_replace(false, Refusal::kApproach), 0.0);
  EXPECT_EQ(yaw_after_replace(false, Refusal::kContacts), 0.1);
  EXPECT_EQ(yaw_after_replace(false, Refusal::kShare), 0.1);
}

// A landing that attaches touching less than min_touched_share of its face is let go at once
// and re-placed, the others held; partial_replaces later a landing is kept; a whole-face one is
// kept at once; one that attaches as the swing ends is let go there, re-placed at the stance.
TEST(ReflexRegrip, APartlyTouchingLandingIsLetGoAndRePlaced) {
  LegReflexParams p = RegripOnly();
  p.regrip.lift_rad = 0.2;
  p.regrip.replace_s = 0.08;  // 8 periods
  p.regrip.min_touched_share = 0.9;
  p.regrip.partial_replaces = 1;
  LegSensing partial = Attached(Stance(), 0.7);
  partial.touched_fraction = 0.7;
  {
    LegReflex leg(p, kDt);
    Recorder rec(&leg);
    rec.Step(Swing());              // #0
    rec.Step(Touching(Stance()));   // #1
    const LegReflexOutput& out = rec.Step(partial);  // #2: attaches touching 70 %
    EXPECT_TRUE(out.release_pad);
    EXPECT_TRUE(out.hold_others());
    EXPECT_TRUE(out.hold_stance);
    rec.Step(Touching(Stance()));   // #3: lifting
    EXPECT_GT(rec.output(3).target_offset_rad[kHipPitch], 0.0);
    rec.Repeat(Stance(), 7);        // #4..#10
    EXPECT_FALSE(rec.Step(partial).release_pad);  // #11: the second such landing is kept
    EXPECT_EQ(rec.events(), (Events{At(2, E::kRegrip, R::kPartialContact)}));
  }
  {
    LegReflex leg(p, kDt);
    Recorder rec(&leg);
    rec.Step(Swing());
    rec.Step(Touching(Stance()));
    EXPECT_FALSE(rec.Step(Attached(Stance(), 0.9)).release_pad);  // touched all its face
    EXPECT_TRUE(rec.events().empty());
  }
  {
    LegReflex leg(p, kDt);
    Recorder rec(&leg);
    rec.Step(Swing());                                 // #0
    LegSensing late = Attached(Swing(0.95), 0.7);
    late.touched_fraction = 0.7;
    EXPECT_TRUE(rec.Step(late).release_pad);           // #1: let go in the swing
    EXPECT_TRUE(rec.events().empty());
    EXPECT_TRUE(rec.Step(Touching(Stance())).hold_others());  // #2: re-placed with the stance
    EXPECT_EQ(rec.events(), (Events{At(2, E::kRegrip, R::kPartialContact)}));
  }
}

TEST(ReflexRegrip, SilentInSwingWhenNotHoldingOrSwitchedOff) {
  LegSensing lost_in_swing = Attached(Swing(), 0.5);
  lost_in_swing.bonds_lost = true;
  LegSensing lost_unattached = Touching(Stance());
  lost_unattached.bonds_lost = true;
  LegSensing lost_in_stance = Attached(Stance(), 0.5);
  lost_in_stance.bonds_lost = true;
  {
    LegReflex leg(RegripOnly(), kDt);
    Recorder rec(&leg);
    rec.Repeat(Attached(Swing()), 2);
    rec.Repeat(lost_in_swing, 5);  // peeling in swing is expected
    rec.Repeat(Touching(Stance()), 2);
    rec.Repeat(lost_unattached, 5);  // not attached last period: not holding
    EXPECT_TRUE(rec.events().empty());
    EXPECT_FALSE(rec.output(rec.updates() - 1).hold_others());
  }
  {
    LegReflexParams p = RegripOnly();
    p.regrip.enabled = false;
    LegReflex leg(p, kDt);
    Recorder rec(&leg);
    rec.Repeat(Attached(Stance()), 2);
    const LegReflexOutput& out = rec.Repeat(lost_in_stance, 5);
    EXPECT_TRUE(rec.events().empty());
    EXPECT_FALSE(out.hold_others());
    EXPECT_EQ(out.target_offset_rad, Eigen::Vector3d::Zero());
  }
}

// ---------------------------------------------------------------------------------------------
// GTO stance holding
// ---------------------------------------------------------------------------------------------

LegReflexParams GtoOnly() {
  LegReflexParams p = AllOff();
  p.gto.enabled = true;
  p.gto.hold = {.gain = 0.25, .threshold = 0.25, .delay_s = 0.02};  // 2 periods
  p.gto.hold_max_offset_rad = 0.15;
  p.gto.press = {.gain = 0.0, .threshold = 0.0, .delay_s = 0.0};
  p.gto.require_partner_attached = false;
  return p;
}

// A loaded leg holds stance and presses from exactly Δ after the load rises, and may swing
// from exactly Δ after it falls; at the threshold itself it is unloaded.
TEST(ReflexGtoHold, LoadedLegHoldsStanceUnloadedLegReleases) {
  LegReflexParams p = GtoOnly();
  p.gto.load_attached = true;  // the press on a welded pad, as Geyer and Herr's law
  LegReflex leg(p, kDt);
  Recorder rec(&leg);
  LegSensing s = Attached(Stance());
  s.normal_load_n = 0.25;  // exactly F0: unloaded
  rec.Repeat(s, 5);        // #0..#4
  s.normal_load_n = 0.75;
  rec.Repeat(s, 10);  // #5..#14
  s.normal_load_n = 0.125;
  rec.Repeat(s, 10);  // #15..#24
  for (int k = 0; k < 25; ++k) {
    const bool loaded = k >= 7 && k < 17;
    EXPECT_EQ(rec.output(k).hold_stance, loaded) << k;
    // 0.25·(0.75 − 0.25) = 0.125 below the 0.15 cap.
    EXPECT_EQ(rec.output(k).target_offset_rad[kHipPitch], loaded ? -0.125 : 0.0) << k;
  }
  EXPECT_EQ(rec.events(), (Events{At(7, E::kGtoHold, R::kLoad)}));
}

TEST(ReflexGtoHold, PressIsCappedAndNeverHoldsInSwing) {
  LegReflexParams p = GtoOnly();
  p.gto.load_attached = true;
  LegReflex leg(p, kDt);
  Recorder rec(&leg);
  LegSensing s = Attached(Stance());
  s.normal_load_n = 10.0;
  const LegReflexOutput& out = rec.Repeat(s, 5);
  EXPECT_EQ(out.target_offset_rad[kHipPitch], -0.15);
  LegSensing swing = Attached(Swing());
  swing.normal_load_n = 10.0;
  const LegReflexOutput& in_swing = rec.Step(swing);
  EXPECT_FALSE(in_swing.hold_stance);
  EXPECT_EQ(in_swing.target_offset_rad, Eigen::Vector3d::Zero());
  rec.Step(s);  // back in stance: a new hold onset
  EXPECT_EQ(rec.events(), (Events{At(2, E::kGtoHold, R::kLoad), At(6, E::kGtoHold, R::kLoad)}));
}

// On a floor (count_compression) a weight-bearing leg is loaded too.
TEST(ReflexGtoHold, CompressionCountsWhenAsked) {
  LegSensing s = Touching(Stance());  // a foot standing on a floor, not stuck
  s.preload_n = 0.5;
  s.normal_load_n = -0.5;
  LegReflexParams p = GtoOnly();
  {
    LegReflex leg(p, kDt);
    EXPECT_FALSE(Recorder(&leg).Repeat(s, 5).hold_stance);
  }
  p.gto.count_compression = true;
  {
    LegReflex leg(p, kDt);
    EXPECT_TRUE(Recorder(&leg).Repeat(s, 5).hold_stance);
  }
}

TEST(ReflexGtoHold, DetachedPartnerHoldsStance) {
  LegReflexParams p = GtoOnly();
  p.gto.require_partner_attached = true;
  LegReflex leg(p, kDt);
  Recorder rec(&leg);
  LegSensing s = Attached(Stance());
  rec.Repeat(s, 3);  // #0..#2
  s.partner_attached = false;
  rec.Repeat(s, 3);  // #3..#5
  s.partner_attached = true;
  rec.Step(s);  // #6
  for (int k = 0; k < 7; ++k) EXPECT_EQ(rec.output(k).hold_stance, k >= 3 && k <= 5) << k;
  EXPECT_EQ(rec.output(4).target_offset_rad, Eigen::Vector3d::Zero());  // holds, no press
  EXPECT_EQ(rec.events(), (Events{At(3, E::kGtoHold, R::kPartnerDetached)}));
}

// Positive force feedback on the compressive preload while the bond builds, and only then.
TEST(ReflexGtoHold, PadBuildingItsBondIsPressed) {
  LegReflexParams p = GtoOnly();
  p.gto.press = {.gain = 0.125, .threshold = 0.25, .delay_s = 0.01};  // 1 period
  p.gto.press_max_offset_rad = 0.1;
  p.gto.full_bond_fraction = 0.9375;
  LegReflex leg(p, kDt);
  Recorder rec(&leg);
  LegSensing s = Attached(Stance(), 0.5);
  s.preload_n = 0.75;
  rec.Repeat(s, 3);                                                // #0..#2
  EXPECT_EQ(rec.output(0).target_offset_rad[kHipPitch], 0.0);      // Δ not yet elapsed
  EXPECT_EQ(rec.output(1).target_offset_rad[kHipPitch], -0.0625);  // 0.125·(0.75 − 0.25)
  EXPECT_TRUE(rec.output(1).Fired(Reflex::kGtoPress));
  EXPECT_FALSE(rec.output(1).hold_stance);  // pressed, not loaded
  s.preload_n = 5.0;
  EXPECT_EQ(rec.Repeat(s, 2).target_offset_rad[kHipPitch], -0.1);  // capped
  s.bonded_fraction = 0.9375;                                      // built
  EXPECT_EQ(rec.Step(s).target_offset_rad[kHipPitch], 0.0);
  s = Touching(Stance());  // not attached: the preload's job
  s.preload_n = 5.0;
  EXPECT_EQ(rec.Step(s).target_offset_rad[kHipPitch], 0.0);
  EXPECT_TRUE(rec.events().empty());
}

TEST(ReflexGtoHold, SilentWhenSwitchedOff) {
  LegReflexParams p = GtoOnly();
  p.gto.enabled = false;
  p.gto.require_partner_attached = true;
  LegReflex leg(p, kDt);
  Recorder rec(&leg);
  LegSensing s = Attached(Stance(), 0.5);
  s.normal_load_n = 10.0;
  s.preload_n = 10.0;
  s.partner_attached = false;
  const LegReflexOutput& out = rec.Repeat(s, 10);
  EXPECT_TRUE(rec.events().empty());
  EXPECT_FALSE(out.hold_stance);
  EXPECT_EQ(out.target_offset_rad, Eigen::Vector3d::Zero());
}

// ---------------------------------------------------------------------------------------------
// Spindles in the leg
// ---------------------------------------------------------------------------------------------

LegReflexParams SpindleOnly() {
  LegReflexParams p = AllOff();
  p.spindle.enabled = true;
  p.spindle.resist = true;  // the per-joint law on a stance foot in the air
  for (SpindleParams& j : p.spindle.joints) {
    j = {.length_gain = 0.5,
         .velocity_gain_s = 0.0,
         .length_threshold_rad = 0.0625,
         .velocity_threshold_rad_per_s = 0.0,
         .delay_s = 0.01};
  }
  return p;
}

TEST(ReflexLegSpindle, EachJointResistsItsOwnStretchAfterTheDelay) {
  LegReflex leg(SpindleOnly(), kDt);
  Recorder rec(&leg);
  LegSensing s = Stance();  // a foot that is not stuck (in swing the law lifts instead)
  s.stretch_rad = {0.0, -0.3125, 0.5625};
  rec.Repeat(s, 4);  // #0..#3
  s.stretch_rad.setZero();
  rec.Repeat(s, 3);  // #4..#6
  EXPECT_EQ(rec.output(0).target_offset_rad, Eigen::Vector3d::Zero());
  for (int k = 1; k <= 4; ++k) {
    EXPECT_EQ(rec.output(k).target_offset_rad, Eigen::Vector3d(0.0, 0.125, -0.25)) << k;
  }
  EXPECT_EQ(rec.output(5).target_offset_rad, Eigen::Vector3d::Zero());
  EXPECT_EQ(rec.events(), (Events{At(1, E::kSpindle)}));  // one event at onset
}

TEST(ReflexLegSpindle, SummedOffsetIsClampedToMaxOffset) {
  LegReflexParams p = SpindleOnly();
  p.max_offset_rad = 0.25;
  LegReflex leg(p, kDt);
  LegSensing s = Stance();
  s.stretch_rad = {3.0, -3.0, 0.1875};
  leg.Update(s);
  EXPECT_EQ(leg.Update(s).target_offset_rad, Eigen::Vector3d(-0.25, 0.25, -0.0625));
}

TEST(ReflexLegSpindle, SilentWhenSwitchedOff) {
  LegReflexParams p = SpindleOnly();
  p.spindle.enabled = false;
  LegReflex leg(p, kDt);
  Recorder rec(&leg);
  LegSensing s = Stance();
  s.stretch_rad = {1.0, 1.0, 1.0};
  EXPECT_EQ(rec.Repeat(s, 5).target_offset_rad, Eigen::Vector3d::Zero());
  EXPECT_TRUE(rec.events().empty());
}

// ---------------------------------------------------------------------------------------------
// The whole machine
// ---------------------------------------------------------------------------------------------

// Random sensing with every reflex on (defaults): invariants that hold whatever happens.
// Each event type at most once per update (so kMaxLegEvents never overflows), offsets within
// ±max_offset_rad, holds only in stance, and Reset gives back a fresh leg.
LegSensing RandomSensing(std::mt19937* rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::bernoulli_distribution coin(0.5);
  std::bernoulli_distribution rare(0.1);
  LegSensing s;
  s.stance = coin(*rng);
  s.phase_progress = unit(*rng);
  s.touching = coin(*rng);
  s.attached = s.touching && coin(*rng);
  s.bonded_fraction = s.attached ? unit(*rng) : 0.0;
  s.normal_load_n = 2.0 * unit(*rng) - 1.0;
  s.preload_n = 2.0 * unit(*rng);
  s.bonds_lost = rare(*rng);
  s.partner_attached = !rare(*rng);
  for (int j = 0; j < kLegJoints; ++j) {
    s.stretch_rad[j] = unit(*rng) - 0.5;
    s.stretch_velocity_rad_per_s[j] = 10.0 * (unit(*rng) - 0.5);
  }
  return s;
}

TEST(ReflexLegMachine, InvariantsHoldUnderRandomSensing) {
  const LegReflexParams p;
  LegReflex leg(p, 0.002);
  std::mt19937 rng(42);
  int event_count = 0;
  for (int k = 0; k < 100000; ++k) {
    // Runs of the same phase, as a CPG gives.
    LegSensing s = RandomSensing(&rng);
    s.stance = (k / 37) % 2 == 0;
    const LegReflexOutput out = leg.Update(s);
    ASSERT_LE(out.events.size(), kMaxLegEvents);
    int per_type[kMaxLegEvents] = {};
    for (const LegEvent& e : out.events) ASSERT_LE(++per_type[static_cast<int>(e.type)], 1) << k;
    event_count += out.events.size();
    ASSERT_LE(out.target_offset_rad.cwiseAbs().maxCoeff(), p.max_offset_rad) << k;
    ASSERT_TRUE(out.target_offset_rad.allFinite());
    ASSERT_TRUE(!out.hold_stance || s.stance) << k;
  }
  EXPECT_GT(event_count, 1000);  // the script does exercise the machine
}

TEST(ReflexLegMachine, ResetGivesTheSameRunAsAFreshLeg) {
  const LegReflexParams p;
  LegReflex used(p, 0.002);
  std::mt19937 warmup(1);
  for (int k = 0; k < 500; ++k) used.Update(RandomSensing(&warmup));
  used.Reset();
  LegReflex fresh(p, 0.002);
  std::mt19937 a(2);
  std::mt19937 b(2);
  for (int k = 0; k < 2000; ++k) {
    const LegReflexOutput x = used.Update(RandomSensing(&a));
    const LegReflexOutput y = fresh.Update(RandomSensing(&b));
    ASSERT_EQ(x.target_offset_rad, y.target_offset_rad) << k;
    ASSERT_EQ(x.hold_stance, y.hold_stance) << k;
    ASSERT_EQ(x.hold_others(), y.hold_others()) << k;
    ASSERT_EQ(x.fired, y.fired) << k;
    ASSERT_EQ(x.events.size(), y.events.size()) << k;
    for (int i = 0; i < x.events.size(); ++i) ASSERT_EQ(x.events.items[i], y.events.items[i]);
  }
}

TEST(ReflexLegMachine, NonFiniteSensingIsCountedAndHarmless) {
  LegReflex leg(LegReflexParams{}, 0.002);
  LegSensing s = Attached(Stance(), NAN);
  s.normal_load_n = INFINITY;
  s.stretch_rad[kKnee] = NAN;
  const LegReflexOutput out = leg.Update(s);
  EXPECT_TRUE(out.target_offset_rad.allFinite());
  EXPECT_EQ(leg.state().nonfinite_inputs, 3);
}

TEST(ReflexLegMachine, NamesAreTheEventsCsvSpelling) {
  EXPECT_EQ(EventName(LegEventType::kPreloadStart), "preload_start");
  EXPECT_EQ(EventName(LegEventType::kPreloadEnd), "preload_end");
  EXPECT_EQ(EventName(LegEventType::kSearchStart), "search_start");
  EXPECT_EQ(EventName(LegEventType::kSearchEnd), "search_end");
  EXPECT_EQ(EventName(LegEventType::kPeel), "peel");
  EXPECT_EQ(EventName(LegEventType::kRegrip), "regrip");
  EXPECT_EQ(EventName(LegEventType::kGtoHold), "gto_hold");
  EXPECT_EQ(EventName(LegEventType::kSpindle), "spindle");
  EXPECT_EQ(ReasonName(LegEventReason::kNone), "");
  EXPECT_EQ(ReasonName(LegEventReason::kAttemptsExhausted), "attempts_exhausted");
  EXPECT_EQ(ReasonName(LegEventReason::kForceLimit), "force_limit");
  EXPECT_EQ(ReflexName(Reflex::kGtoPress), "gto_press");
}

// The robot's push hold (PushHold), max_hold_s = 5 periods: pushes of one leg after another
// hold the gait 5 periods in a row at most; the legs pushed then, and those pushed before every
// push has passed, hold nothing until they leave stance or let go; a leg that has stepped holds
// again.
TEST(ReflexPushHold, PushesOfOneLegAfterAnotherHoldTheGaitAtMostMaxHoldInARow) {
  PushHold hold(3, 5 * kDt, kDt);
  // pushed legs per period (bits 0, 1, 2), and whether the pushes hold the gait.
  struct Period {
    int pushed;
    bool holds;
  };
  const std::vector<Period> script = {
      {0b001, true},  {0b001, true},  {0b001, true},  {0b011, true}, {0b011, true},
      {0b011, false},  // 6 in a row: posture; legs 0 and 1 hold no more
      {0b011, false}, {0b110, false},  // leg 2, pushed before the pushes passed: posture too
      {0b000, false},                  // every push has passed
      {0b100, false},                  // leg 2 has not stepped: still posture
  };
  for (size_t k = 0; k < script.size(); ++k) {
    for (int i = 0; i < 3; ++i) hold.SetLeg(i, (script[k].pushed >> i) & 1, true);
    EXPECT_EQ(hold.Update(), script[k].holds) << "period " << k + 1;
  }
  hold.SetLeg(2, false, false);  // leg 2 swings
  EXPECT_FALSE(hold.Update());
  hold.SetLeg(2, true, true);  // and lands pushed: a push again
  EXPECT_TRUE(hold.Update());
  // Without a limit every push holds as long as it lasts.
  PushHold unbounded(3, 0.0, kDt);
  for (int k = 0; k < 50; ++k) {
    for (int i = 0; i < 3; ++i) unbounded.SetLeg(i, i == k % 3, true);
    EXPECT_TRUE(unbounded.Update()) << k;
  }
  unbounded.SetLeg(0, false, true);
  unbounded.SetLeg(1, false, true);
  unbounded.SetLeg(2, false, true);
  EXPECT_FALSE(unbounded.Update());
}

}  // namespace
}  // namespace climbsim::reflex
