// A leg's load and stretch reflexes and its stiffness (reflex.gto, .spindle, .compliance),
// each struct with its scenario keys, and LegReflexParams: every reflex of one leg, checked as a
// whole.
#ifndef CLIMBSIM_REFLEX_LEG_PARAMS_H_
#define CLIMBSIM_REFLEX_LEG_PARAMS_H_

#include <array>
#include <string_view>

#include "keys/keys.h"
#include "reflex/foot_params.h"
#include "reflex/laws.h"

namespace climbsim::reflex {

// GTO load reflexes (Ekeberg and Pearson 2005's load rule; Geyer and Herr 2010's positive
// force feedback), four channels on the pad:
//  hold:    F̃ = the adhesive load normal_load_n (or, with count_compression, the larger of
//           |normal_load_n| and preload_n). Loaded (F̃(t−Δ) > F0) ⇒ hold_stance and press:
//           hip_pitch −= min(u, hold_max_offset); unloaded ⇒ the leg may swing. Only for a
//           pad that is not attached (a foot that can still move: floors), unless
//           load_attached: on a welded foot the press is only internal force between the pads
//           (docs/control.md "Reflexes on a closed chain"), and on a wall the front pads hang in
//           tension all the time, so the hold stalled the gait; the support channel decides
//           for attached pads instead.
//  press:   F̃ = the compressive preload_n. While the pad is building its bond (stance,
//           attached, bonded_fraction < full_bond_fraction): hip_pitch −= min(u, press_max).
//  unload:  F̃ = the pad's utilisation U (peak bond demand over threshold, 1 breaks). While
//           the pad is attached in stance, u = K_U·[U(t−Δ) − U0]₊ lowers the leg's servo
//           stiffness: kp_fraction ×= max(unload_min_kp_fraction, 1 − u). The leg yields and
//           the pads with margin take its load (load sharing through stiffness).
//  support: F̃ = support_utilisation, the largest utilisation among the pads that carry this
//           leg's swing. Above its threshold (delayed) a stance leg holds stance: lifting it
//           would shift its load onto pads already near their limit.
// Load sharing among the attached pads is the GTO's robot-level channel: LoadSharing
// (load_sharing.h), which the simulator runs across the legs.
// With require_partner_attached, a leg whose partner is not attached also holds stance (lifting
// it would leave the pair without a grip).
struct GtoHoldParams {
  bool enabled = true;
  GtoParams hold{.gain = 0.2, .threshold = 0.15, .delay_s = 0.01};  // rad/N, N, s; gain >= 0
  double hold_max_offset_rad = 0.15;                                // >= 0
  bool count_compression = false;  // true on floors: a weight-bearing leg is loaded too
  bool load_attached = false;     // the hold channel acts on an attached (welded) pad too
  GtoParams press{.gain = 0.1, .threshold = 0.05, .delay_s = 0.01};  // rad/N, N, s; gain >= 0
  double press_max_offset_rad = 0.10;                                // >= 0
  double full_bond_fraction = 0.95;  // bond counts as built from here, in (0, 1]
  bool require_partner_attached = true;
  GtoParams unload{.gain = 2.0, .threshold = 0.8, .delay_s = 0.01};  // 1/utilisation, -, s
  double unload_min_kp_fraction = 0.2;                               // in (0, 1]
  GtoParams support{.gain = 1.0, .threshold = 0.8, .delay_s = 0.01};  // gain unused; -, s
  // Keys flattened per channel (hold_gain_rad_per_n is hold.gain); the scenario's gto block
  // adds the robot-level channels (GtoBlockParams, reflex_params.h).
  template <class A>
  void Serialize(A* a) {
    a->Visit({"enabled", "",
              "Golgi-tendon-organ-like load reflex: a loaded leg stays in stance and presses; a "
              "pad building its bond is pressed"},
             &enabled);
    a->Visit({"hold_gain_rad_per_n", "rad/N",
              "K_F of the stance-holding channel (pad adhesive load)", GainRange()},
             &hold.gain);
    a->Visit({"hold_threshold_n", "N", "F_0 of the stance-holding channel"}, &hold.threshold);
    a->Visit({"hold_delay_s", "s", "transmission delay of the stance-holding channel",
              Range::NonNegative()},
             &hold.delay_s);
    a->Visit({"hold_max_offset_rad", "rad", "largest press of the stance-holding channel",
              Range::NonNegative()},
             &hold_max_offset_rad);
    a->Visit(
        {"count_compression", "", "a leg pressed onto the surface counts as loaded too (floors)"},
        &count_compression);
    a->Visit({"load_attached", "",
              "the stance-holding channel (hold and press on the pad load) acts on an attached "
              "(welded) pad too; off: on a welded foot the press is only internal force between "
              "the pads, and on a wall the always-loaded front pads would never swing (the support "
              "channel decides instead)"},
             &load_attached);
    a->Visit(
        {"press_gain_rad_per_n", "rad/N",
         "K_F of the channel that presses a pad building its bond (preload)", GainRange()},
        &press.gain);
    a->Visit({"press_threshold_n", "N", "F_0 of the pressing channel"}, &press.threshold);
    a->Visit(
        {"press_delay_s", "s", "transmission delay of the pressing channel", Range::NonNegative()},
        &press.delay_s);
    a->Visit({"press_max_offset_rad", "rad", "largest press of the pressing channel",
              Range::NonNegative()},
             &press_max_offset_rad);
    a->Visit({"full_bond_fraction", "", "a bond counts as built from this bonded fraction on",
              Range::OpenClosed(0, 1)},
             &full_bond_fraction);
    a->Visit({"require_partner_attached", "",
              "a leg also holds stance while the legs that support its swing are not attached"},
             &require_partner_attached);
    a->Visit({"unload_gain", "1",
              "K_U of the unloading channel: a pad at utilisation U (peak bond demand / threshold) "
              "above U_0 lowers its leg's servo stiffness by the factor max(min, 1 - K_U [U(t-D) - "
              "U_0]+), so the other pads take its load",
              Range::NonNegative()},
             &unload.gain);
    a->Visit(
        {"unload_threshold", "", "U_0 of the unloading channel (utilisation; a bond breaks at 1)"},
        &unload.threshold);
    a->Visit({"unload_delay_s", "s", "transmission delay of the unloading channel",
              Range::NonNegative()},
             &unload.delay_s);
    a->Visit({"unload_min_kp_fraction", "", "the least stiffness fraction unloading leaves a leg",
              Range::OpenClosed(0, 1)},
             &unload_min_kp_fraction);
    a->Visit({"support_threshold", "",
              "a stance leg also holds stance while the largest utilisation of the pads that "
              "support its swing is above this"},
             &support.threshold);
    a->Visit(
        {"support_delay_s", "s", "transmission delay of the support channel", Range::NonNegative()},
        &support.delay_s);
  }
};

// The spindle law on each joint, indexed by Joint. Where the stretch of a joint means what:
//  * foot in the air (swing, or a stance foot searching): a stretch beyond
//    swing_threshold_rad on any joint means the leg is
//    blocked or tripping (Forssberg's stumbling-corrective reaction: lift and re-place). With
//    s = max_j [|q̃_j(t−Δ)| − swing_threshold]₊ the foot is lifted: hip_pitch += K_L,pitch·s,
//    knee += K_L,knee·s. (Resisting every stretch in swing, the law below, set the free foot
//    chattering against its own servo lag with the 10 ms delay.)
//  * with `resist` (off by default), a stance foot in the air gets instead the law of
//    SpindleReflex on each joint, against the stretch. Off because resisting the lag of a
//    commanded motion speeds it up: a searching foot hit the ceiling at 0.45 m/s (too fast to
//    attach) and the gait stalled. A foot that touches without a bond gets nothing: the
//    preload presses it, and resisting the contact's stretch bounced the spider's feet off
//    the wall (it fell).
//  * pad attached (stance or a peel): no offset (a welded foot cannot follow one; it would
//    only load the other pads). In stance a delayed stretch |q̃(t−Δ)| beyond stance_band_rad
//    on any joint means the body is being pushed: the leg asks every leg to stay in stance
//    (hold_others) while it lasts and for hold_s after, so that no pad leaves the surface
//    while the body is pushed. A push passes; a stretch that lasts longer than max_hold_s is
//    the leg's posture (its welded foot is where the gait would not put it, after a re-place
//    or a recovery), and holding every leg for it would stall the gait for good: the hold
//    lets go, and holds again only once the stretch has been back inside the band. After a
//    slide the legs' stretches take turns, each bounded alone; PushHold (push_hold.h) bounds
//    them together for the robot.
struct LegSpindleParams {
  bool enabled = true;
  std::array<SpindleParams, kLegJoints> joints{};
  double swing_threshold_rad = 0.3;  // >= 0
  bool resist = false;               // the per-joint law on a stance foot in the air
  double stance_band_rad = 0.15;     // >= 0
  double hold_s = 0.2;               // >= 0
  double max_hold_s = 0.0;           // >= 0; 0: a stretch holds as long as it lasts
  // The keys of the leg's spindle block but the per-joint law (the scenario gives one law
  // for every joint: SpindleBlockParams, reflex_params.h).
  template <class A>
  void Serialize(A* a) {
    a->Visit({"enabled", "",
              "muscle-spindle-like stretch reflex: a foot in the air stretched beyond "
              "swing_threshold_rad is lifted (stumbling correction); with the pad attached, no "
              "offset, and in stance a stretch beyond stance_band_rad holds every leg in stance; "
              "with resist, the law u = K_L [stretch(t-D) - L_0]+ + K_V [rate(t-D) - V_0]+ against "
              "the stretch on a stance foot in the air"},
             &enabled);
    a->Visit({"swing_threshold_rad", "rad",
              "free swing leg: a delayed stretch beyond this on any joint means it is blocked, and "
              "lifts the foot by K_L times the excess (stumbling correction)",
              Range::NonNegative()},
             &swing_threshold_rad);
    a->Visit({"resist", "",
              "a stance foot in the air (a search) resists its stretch with the law above instead "
              "of lifting only when blocked (off: resisting the lag of a commanded reach sped the "
              "foot into the surface too fast to attach)"},
             &resist);
    a->Visit(
        {"stance_band_rad", "rad",
         "attached stance leg: a delayed stretch beyond this on any joint means the body is pushed",
         Range::NonNegative()},
        &stance_band_rad);
    a->Visit({"hold_s", "s", "how long every leg stays in stance after a push ends",
              Range::NonNegative()},
             &hold_s);
    a->Visit({"max_hold_s", "s",
              "a stretch beyond the band held longer than this is the leg's posture, not a push: "
              "the hold lets go until the stretch is back inside the band; so are pushes of one "
              "leg after another that hold the gait longer than this in a row, and those legs "
              "hold no more until they step or let go; 0 = no limit",
              Range::NonNegative()},
             &max_hold_s);
  }
};

// Stance compliance (docs/control.md, "Reflexes on a closed chain"): the servos' stiffness is
// scheduled by phase, full in swing (accurate placement) and lowered to stance_kp_fraction
// while the pad is attached in stance, so that welded feet and the body settle without
// internal force. LegReflexOutput::kp_fraction (per joint, in (0, 1]) multiplies each
// servo's kp; it moves towards its target at 1/ramp_s per second (no jump in torque).
struct ComplianceParams {
  bool enabled = false;  // off by default: see docs/climbing.md for what it did on the wall
  double stance_kp_fraction = 0.5;  // in (0, 1]
  double ramp_s = 0.02;             // >= 0 (0: at once)
  template <class A>
  void Serialize(A* a) {
    a->Visit(
        {"enabled", "",
         "stance compliance: servo stiffness scheduled by phase, full in swing, stance_kp_fraction "
         "of kp while the pad is attached in stance (smart servos expose this; mjcf/README.md)"},
        &enabled);
    a->Visit({"stance_kp_fraction", "", "kp in attached stance over the servo's kp",
              Range::OpenClosed(0, 1)},
             &stance_kp_fraction);
    a->Visit({"ramp_s", "s", "time to change between the two stiffnesses", Range::NonNegative()},
             &ramp_s);
  }
};

struct LegReflexParams {
  PreloadParams preload;
  SearchParams search;
  PeelParams peel;
  RegripParams regrip;
  GtoHoldParams gto;
  LegSpindleParams spindle;
  ComplianceParams compliance;
  double max_offset_rad = 0.4;  // |summed offset| per joint is clamped to this, > 0

  // The key of max_offset_rad, which the scenario's reflex block lists after its blocks.
  template <class A>
  static void VisitMaxOffset(A* a, double* max_offset_rad) {
    a->Visit({"max_offset_rad", "rad", "the reflexes' summed offset per joint is clamped to this",
              Range::Positive()},
             max_offset_rad);
  }
  // The leg's own key; each reflex's block declares its keys (Validate checks them in turn).
  template <class A>
  void Serialize(A* a) {
    VisitMaxOffset(a, &max_offset_rad);
  }
};

// Throws std::invalid_argument on the first bad field: a key out of its declared range
// ("<name>.<reflex>.<key> must be >= 0, got -1"; the spindle's per-joint laws as
// "<name>.spindle.joints[2].<key>"), then what CheckControlPeriod finds.
void Validate(const LegReflexParams& params, double dt_s, std::string_view name = "leg_reflex");

// The checks that need the control period dt_s, which no declared range can make: durations
// of at most 1e8 periods and of at least one where one is needed (preload.max_duration_s,
// search.attempt_duration_s, peel.max_duration_s, regrip.replace_s), search attempts of at
// most 1e8 periods in all, delays that fit a DelayLine. A failure calls checker.Fail with the
// key below the leg ("preload.max_duration_s", "spindle.joints[2].delay_s"; with
// one_spindle_law, the three joints share one law and its delay is "spindle.delay_s").
void CheckControlPeriod(const LegReflexParams& params, double dt_s, const Checker& checker,
                        bool one_spindle_law = false);

}  // namespace climbsim::reflex

#endif  // CLIMBSIM_REFLEX_LEG_PARAMS_H_
