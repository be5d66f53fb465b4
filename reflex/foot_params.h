// The reflexes that place and release a foot (preload, search, peel, re-grip): their
// parameters, each struct with its scenario keys (reflex.preload, .search, .peel, .regrip).
#ifndef CLIMBSIM_REFLEX_FOOT_PARAMS_H_
#define CLIMBSIM_REFLEX_FOOT_PARAMS_H_

#include "keys/keys.h"

namespace climbsim::reflex {

// ---------------------------------------------------------------------------------------------
// Leg-level climbing reflexes
// ---------------------------------------------------------------------------------------------

// Joint indices in every 3-vector of this module.
enum Joint : int { kHipYaw = 0, kHipPitch = 1, kKnee = 2 };
inline constexpr int kLegJoints = 3;

// Press on touchdown (and on re-grip) until the pad attaches or a limit is reached.
// The offset ramps linearly from 1/n_ramp of full at the first period to full after ramp_s.
struct PreloadParams {
  bool enabled = true;                // the touchdown preload; re-grip presses even if false
  double hip_pitch_press_rad = 0.15;  // full press on hip pitch, >= 0, applied as −0.15 rad
  double knee_press_rad = 0.10;       // full press on the knee, >= 0, applied as −0.10 rad
  double ramp_s = 0.05;               // time to full press, >= 0 (0: full at once)
  double force_limit_n = 1.0;         // stop once the compressive preload reaches this, > 0
  double max_duration_s = 0.2;        // stop after this long, >= one control period
  // Fade of the press once the preload ends, >= 0 (0: at once). A press dropped at once on an
  // attach pulls the fresh pad off its surface by kp·press: harmless for a von Mises pad,
  // whose pull-off is σ_T·A, fatal for a directional one, which holds no pull before its
  // shear has built.
  double release_s = 0.0;
  // A foot re-placed because its landing met the surface with too few contacts comes down the
  // way it came (the same leg pose, the same tilt): a pad that lands on a corner is held tilted
  // by its ankle spring and the corner's friction, and a press that seats a square landing does
  // not flatten it. So after the n-th such re-place of a stance the foot is pressed
  // min(1 + retry_gain·n, retry_max_scale) times as hard; the force limit still ends each
  // press. A landing refused for its approach or for too little of its face touching (a
  // bump's top, which no press widens) does not count. 0: every press alike.
  double retry_gain = 0.0;
  double retry_max_scale = 3.0;
  // A pad bonds only while it is not pulled (adhesion/README.md). A support pad that lands with
  // fewer bonds than cpg.support_bond_fraction asks and is pulled at once never gets there, and
  // cpg.wait_for_support then holds the gait for good. With this, such a pad, attached in
  // stance while the gait waits for it, is pressed as at touchdown until it has bonded.
  bool press_awaited_bond = false;
  template <class A>
  void Serialize(A* a) {
    a->Visit(
        {"enabled", "",
         "press a pad that touched down without attaching until it attaches or a limit is reached"},
        &enabled);
    a->Visit(
        {"hip_pitch_press_rad", "rad", "press on hip pitch at full preload", Range::NonNegative()},
        &hip_pitch_press_rad);
    a->Visit({"knee_press_rad", "rad", "press on the knee at full preload", Range::NonNegative()},
             &knee_press_rad);
    a->Visit({"ramp_s", "s", "time to full press", Range::NonNegative()}, &ramp_s);
    a->Visit(
        {"force_limit_n", "N", "stop once the compressive preload reaches this", Range::Positive()},
        &force_limit_n);
    a->Visit({"max_duration_s", "s", "stop after this long", Range::Positive()}, &max_duration_s);
    a->Visit({"release_s", "s",
              "fade of the press once the preload ends (0: at once; a directional pad, which "
              "holds no pull before its shear builds, needs a fade)",
              Range::NonNegative()},
             &release_s);
    a->Visit({"retry_gain", "",
              "a foot re-placed after a landing with too few contacts presses harder: 1 + this "
              "x such re-places so far in the stance (0: every press alike)",
              Range::NonNegative()},
             &retry_gain);
    a->Visit({"retry_max_scale", "", "cap on that press scale", Range::Closed(1.0, 100.0)},
             &retry_max_scale);
    a->Visit({"press_awaited_bond", "",
              "press an attached stance pad that cpg.wait_for_support waits for to bond (a pulled "
              "pad does not grow its bonds, and the gait would wait for good)"},
             &press_awaited_bond);
  }
};

// Search when a swing ends without touchdown: reach further towards the surface, with a lift
// in each attempt so that the pad is re-placed rather than dragged. Attempt k = 0..N−1 runs
// for n_a samples; with s = (sample within the attempt)/n_a ∈ [0, 1) and the reach fraction
// ρ = (k + s)/N, which grows without jumps from 0 (the first period: no offset) towards 1:
//   hip_yaw   = +reach_yaw_rad·ρ
//   hip_pitch = −reach_pitch_rad·ρ + lift_rad·sin(π·s)
//   knee      = −reach_knee_rad·ρ  + lift_rad·sin(π·s)
// When the pad touches, the offset reached is held until the swing starts, then released
// linearly over release_s (as after the last attempt fails). A search that ran out starts
// again while the gait waits for the pad: a peel waits for it (peel.wait_for_support), or,
// with again_when_stood, the gait has stood still for longer than the whole search
// (N·attempt_duration_s): a foot that stays in stance never swings, so giving up would stand
// the robot still for good.
struct SearchParams {
  bool enabled = true;
  double reach_yaw_rad = 0.10;       // full forward reach, >= 0
  double reach_pitch_rad = 0.20;     // full extension towards the surface on hip pitch, >= 0
  double reach_knee_rad = 0.10;      // full extension towards the surface on the knee, >= 0
  double lift_rad = 0.08;            // peak lift within each attempt, >= 0
  double attempt_duration_s = 0.15;  // one attempt, >= one control period
  int max_attempts = 3;              // N >= 1
  double release_s = 0.1;            // fade of the held offset, >= 0 (0: at once)
  bool again_when_stood = false;
  template <class A>
  void Serialize(A* a) {
    a->Visit({"enabled", "",
              "a swing that ends without touching reaches further and places the foot again"},
             &enabled);
    a->Visit(
        {"reach_yaw_rad", "rad", "forward reach on hip yaw at full search", Range::NonNegative()},
        &reach_yaw_rad);
    a->Visit({"reach_pitch_rad", "rad", "extension towards the surface on hip pitch",
              Range::NonNegative()},
             &reach_pitch_rad);
    a->Visit({"reach_knee_rad", "rad", "extension towards the surface on the knee",
              Range::NonNegative()},
             &reach_knee_rad);
    a->Visit({"lift_rad", "rad", "lift within each attempt", Range::NonNegative()}, &lift_rad);
    a->Visit({"attempt_duration_s", "s", "one attempt", Range::Positive()}, &attempt_duration_s);
    a->Visit({"max_attempts", "", "attempts before giving up", Range::Closed(1, 1000)},
             &max_attempts);
    a->Visit({"release_s", "s", "fade of the reach once found, after the next swing starts",
              Range::NonNegative()},
             &release_s);
    a->Visit({"again_when_stood", "",
              "a search that ran out starts again once the gait has stood still for longer than "
              "the whole search (max_attempts x attempt_duration_s): the foot stands in stance "
              "and would never swing again (off: in the ceiling gaits it starts searches where "
              "a foot would come down by itself)"},
             &again_when_stood);
  }
};

// Peel at swing onset while still attached. The leg's phase is held at the start of its
// swing (hold_phase) while the pad holds, and the offsets rise with the smooth step
// r(t) = 3u² − 2u³, u = min(1, t / ramp_s), t the time since swing onset:
//   hip_yaw = hip_yaw_rad·r    hip_pitch = +hip_pitch_lift_rad·r    knee = +knee_lift_rad·r
// A negative hip yaw draws the foot back, so the pad is pulled nearly along the surface from
// the top of its ankle post: the pull puts a moment on the pad that lifts its front (toe)
// edge first, the way a gecko peels its toes from the tips (Tian et al. 2006; Autumn et al.
// 2006 find the release at a critical angle). Over a bonded b×h pad the edge stress is
// F/(b·h) + 6·M/(b·h²) (docs/design.md §3), so the edge row breaks and the crack runs across the
// pad at a pull far below the normal pull-off σ_T·b·h (Kendall 1975; `climbsim pulloff`
// with --arm-m shows it). The peel ends when the pad lets go (peel_end, detached) or after
// max_duration_s (peel_end, time_limit); the offsets then fade to zero over release_s while
// the swing goes on. Which edge a pull lifts depends on the robot (mjcf/README.md, "Feet").
struct PeelParams {
  bool enabled = true;
  double hip_yaw_rad = -0.2;         // signed: negative draws the foot back, the pull that peels
  double hip_pitch_lift_rad = 0.05;  // lift at full peel, >= 0
  double knee_lift_rad = 0.05;       // knee flexion at full peel, >= 0
  double ramp_s = 0.2;               // time to full peel (smooth step), > 0
  double max_duration_s = 0.6;       // give up (peel_end, time_limit), >= one control period
  double release_s = 0.1;            // fade of the offsets once the peel ends, >= 0
  // A foot with an ACTIVE RELEASE (a toe-peeling tendon as on Stickybot, a membrane that
  // buckles the adhesive): the pad is let go by its own mechanism, not torn by the leg. While
  // the peel holds the phase, the leg asks the other pads to take its pad's load
  // (LegReflexOutput::unload_pad, for the load sharing), and lets the pad go
  // (release_pad) once the force on it is at most release_load_n, or when max_duration_s is
  // up. Released unloaded, the pad drops little load on the others at once; a torn pad drops
  // the pull that peels it, its whole capacity.
  bool active_release = false;
  double release_load_n = 0.1;  // >= 0
  // While a support leg's pad is not attached (it failed, or tore), a peeling pad is a support
  // again: it is not unloaded or let go, and its time limit waits.
  bool wait_for_support = false;
  // Directional pads: the simulator signs hip_yaw_rad per leg against its pad's gripping
  // direction (sim/reflex_effect.cc); the leg itself uses hip_yaw_rad as given.
  bool against_grip = false;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"enabled", "",
              "at swing onset, draw an attached foot back and up until the pad peels, the leg's "
              "phase held"},
             &enabled);
    a->Visit({"hip_yaw_rad", "rad", "hip yaw at full peel (negative draws the foot back)"},
             &hip_yaw_rad);
    a->Visit({"hip_pitch_lift_rad", "rad", "hip pitch lift at full peel", Range::NonNegative()},
             &hip_pitch_lift_rad);
    a->Visit({"knee_lift_rad", "rad", "knee lift at full peel", Range::NonNegative()},
             &knee_lift_rad);
    a->Visit({"ramp_s", "s", "time to full peel (smooth step)", Range::Positive()}, &ramp_s);
    a->Visit({"max_duration_s", "s", "give up after this long", Range::Positive()},
             &max_duration_s);
    a->Visit({"release_s", "s", "fade of the peel offsets after it ends", Range::NonNegative()},
             &release_s);
    a->Visit({"active_release", "",
              "the foot has an active release (a toe-peeling tendon, a buckling membrane): the "
              "other legs first take the pad's load (load sharing), then the pad is let go "
              "(detach cause released) instead of being torn by the leg's pull"},
             &active_release);
    a->Visit({"release_load_n", "N",
              "active release: let the pad go once the force on it is at most this (or at "
              "max_duration_s)",
              Range::NonNegative()},
             &release_load_n);
    a->Visit({"wait_for_support", "",
              "while a support leg's pad is not attached, a peeling pad is not unloaded or let "
              "go, its time limit waits, and the support leg searches again if its search ran "
              "out"},
             &wait_for_support);
    a->Visit({"against_grip", "",
              "directional pads (adhesion.law frictional): the hip yaw moves each foot against "
              "its pad's gripping direction, |hip_yaw_rad| forward for a pad gripping back (-x) "
              "and back for one gripping forward, so the release unloads the gripping shear"},
             &against_grip);
  }
};

// Re-grip: a pad that loses bonds during stance while it was attached (it should be holding)
// is pressed again with the preload profile (PreloadParams, even if preload.enabled is false),
// and the other legs are asked to stay in stance for hold_others_s.
// A pad that lets go ENTIRELY in stance (bonds all lost: overload, a failure) cannot attach
// again by being pressed: adhesion asks for a new touchdown (adhesion/README.md, "Attachment").
// So the re-grip then re-places the foot: a lift of lift_rad on hip pitch and knee,
// lift·sin²(π·s) over replace_s (s from 0 to 1), holding the leg in stance; the foot that
// comes down touches down again and the touchdown preload attaches it.
// The same re-place serves a foot that touched down in stance and has not attached
// replace_after_s later (its landing was rejected: on an edge, too fast): adhesion would not
// try again before the pad leaves the surface.
struct RegripParams {
  bool enabled = true;
  double hold_others_s = 0.2;  // how long hold_others stays raised, >= 0
  double lift_rad = 0.08;      // re-place lift on hip pitch and knee, >= 0 (0: press only)
  double replace_s = 0.25;     // duration of the re-place, >= one control period
  double replace_after_s = 0.3;  // a touch without attach this long is re-placed, >= 0
                                 // (0: never)
  double shift_rad = 0.05;  // a re-placed rejected landing moves this much along hip yaw,
                            // ahead and behind in turn, >= 0 (see LegReflex::Regrip)
  // A landing refused for how it came (too fast, too oblique) is shifted too; off, it is put
  // down where it was: the place was not what failed, and a wide shift (one that clears a
  // bump) would cost a recovering foot its step.
  bool shift_approach_refusals = true;
  // A landing that touches less than this share of its pad's face (a pad set over a bump's
  // edge bonds only where it touches, and tears at that share of its load) is let go at once
  // and re-placed like a rejected one, at most partial_replaces times in a stance (then kept).
  // 0: never; on a flat surface the whole face touches and nothing changes.
  double min_touched_share = 0.0;  // 0..1
  int partial_replaces = 2;        // >= 0
  template <class A>
  void Serialize(A* a) {
    a->Visit(
        {"enabled", "",
         "a pad that loses bonds during stance is pressed again and the other legs hold stance"},
        &enabled);
    a->Visit({"hold_others_s", "s", "how long the other legs hold stance", Range::NonNegative()},
             &hold_others_s);
    a->Visit({"lift_rad", "rad",
              "a pad that let go entirely is re-placed: lift on hip pitch and knee (it can attach "
              "again only at a new touchdown); 0 = press only",
              Range::NonNegative()},
             &lift_rad);
    a->Visit({"replace_s", "s", "duration of the re-place (lift and put down)", Range::Positive()},
             &replace_s);
    a->Visit({"replace_after_s", "s",
              "a foot that touched down in stance and has not attached this long (a rejected "
              "landing) is re-placed too; 0 = never",
              Range::NonNegative()},
             &replace_after_s);
    a->Visit({"shift_rad", "rad",
              "each re-place of a rejected landing in one stance lands the foot this much "
              "further along hip yaw, ahead and behind in turn",
              Range::NonNegative()},
             &shift_rad);
    a->Visit({"shift_approach_refusals", "",
              "a landing refused for how it came (too fast, too oblique) is shifted too; off: "
              "put down where it was, since the place was not what failed"},
             &shift_approach_refusals);
    a->Visit({"min_touched_share", "",
              "a landing pad that touches less than this share of its face (over a bump's edge) "
              "is let go at once and re-placed, shifted along hip yaw like a rejected landing; "
              "0 = never",
              Range::Closed(0, 1)},
             &min_touched_share);
    a->Visit({"partial_replaces", "",
              "re-places of partly touching landings in one stance before one is kept",
              Range::Closed(0, 100)},
             &partial_replaces);
  }
};

}  // namespace climbsim::reflex

#endif  // CLIMBSIM_REFLEX_FOOT_PARAMS_H_
