// The scenario's reflex block (reflex/README.md has the laws).
#ifndef CLIMBSIM_SCENARIO_REFLEX_KEYS_H_
#define CLIMBSIM_SCENARIO_REFLEX_KEYS_H_

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "keys/keys.h"
#include "reflex/reflex.h"

namespace climbsim::sim {

// The leg reflexes (reflex/README.md has the laws, defaults and papers). Each block is the
// reflex module's own parameter struct with its keys: the defaults are the module's.
struct PreloadKeys : reflex::PreloadParams {
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
  }
};
struct SearchKeys : reflex::SearchParams {
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
  }
};
struct PeelKeys : reflex::PeelParams {
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
    a->Visit({"against_grip", "",
              "directional pads (adhesion.law frictional): the hip yaw moves each foot against "
              "its pad's gripping direction, |hip_yaw_rad| forward for a pad gripping back (-x) "
              "and back for one gripping forward, so the release unloads the gripping shear"},
             &against_grip);
  }
  bool against_grip = false;
};
struct RegripKeys : reflex::RegripParams {
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
  }
};
struct LoadSharingKeys : reflex::LoadSharingParams {
  std::string mode_name = "utilisation";
  double friction_credit = 0.5;
  double min_grip_n = 0.0;

  // The reflex module's parameters, the mode's name resolved.
  reflex::LoadSharingParams Params() const {
    reflex::LoadSharingParams p = *this;
    p.mode = mode_name == "force_tracking" ? reflex::SharingMode::kForceTracking
                                           : reflex::SharingMode::kUtilisation;
    return p;
  }

  template <class A>
  void Serialize(A* a) {
    a->Choice({"mode", "",
               "utilisation: drive down the worst pad's utilisation (bond stress); "
               "force_tracking (adhesion.law frictional): move each directional pad's gripping "
               "shear towards the least its pull needs plus an equal share of the rest (of the "
               "net force, when the pads grip in different directions), and a pad being let go "
               "towards no load (reflex/reflex.h)"},
              &mode_name, {"utilisation", "force_tracking"});
    a->Visit({"gain_per_s", "1/s",
              "K. utilisation: while the soft maximum S of the attached pads' utilisations is "
              "above the threshold, internal forces between the pads (the null space of the grasp "
              "map, set through the legs' servo targets) drive it down at K [S - threshold]+ per "
              "second. force_tracking: the internal force follows the internal part of the pads' "
              "force errors at rate K; 0 = off",
              Range::NonNegative()},
             &gain_per_s);
    a->Visit({"friction_credit", "",
              "force_tracking: share of a pressed pad's friction (mu times its press) that may be "
              "spent on reversed shear",
              Range::Closed(0, 1)},
             &friction_credit);
    a->Visit({"min_grip_n", "N",
              "force_tracking: every gripping pad's target shear is at least this; pads opposed "
              "in pairs (under a ceiling) then hold a grasp before their pull arrives; 0 = off",
              Range::NonNegative()},
             &min_grip_n);
    a->Visit({"threshold", "", "U_S: the soft maximum of the utilisations above which load is shared"},
             &threshold);
    a->Visit({"leak_s", "s", "time constant with which an internal force no longer needed fades",
              Range::Positive()},
             &leak_s);
    a->Visit({"softmax_beta", "", "sharpness of the soft maximum (large: the worst pad alone)",
              Range::Positive()},
             &softmax_beta);
    a->Visit({"max_force_n", "N", "largest internal force asked of one pad", Range::Positive()},
             &max_force_n);
    a->Visit({"max_rate_n_per_s", "N/s", "fastest change of one pad's internal force",
              Range::Positive()},
             &max_rate_n_per_s);
    a->Visit({"period_s", "s",
              "how often the law runs, rounded to whole control periods (the legs' offsets are "
              "held in between)",
              Range::Positive()},
             &period_s);
  }
};
// The GTO's posture channel (reflex::PostureReflex), robot level like the load sharing.
struct PostureKeys : reflex::PostureParams {
  template <class A>
  void Serialize(A* a) {
    a->Visit({"enabled", "",
              "lower the body as the pads are pulled off the surface (foot-space gaits, "
              "cpg.stride_m): the crouch c = min(max_crouch_m, gain_m [P(t-D) - threshold]+), "
              "lagged by time_constant_s, is added to cpg.crouch_m; P is the attached pads' pull "
              "over the robot's own weight, payload not counted (0 on a floor, about 0.4 on a "
              "wall, 1 under a ceiling)"},
             &enabled);
    a->Visit({"gain_m", "m", "K_P: crouch per unit of pull over weight", Range::NonNegative()},
             &pull.gain);
    a->Visit({"threshold", "", "P_0: pull over weight below which the body stands"},
             &pull.threshold);
    a->Visit({"delay_s", "s", "transmission delay of the pull", Range::NonNegative()},
             &pull.delay_s);
    a->Visit({"max_crouch_m", "m", "the largest crouch", Range::Closed(0, 0.03)}, &max_crouch_m);
    a->Visit({"time_constant_s", "s", "time constant with which the body follows the crouch",
              Range::Positive()},
             &time_constant_s);
  }
};

struct GtoKeys : reflex::GtoHoldParams {
  LoadSharingKeys share;
  PostureKeys posture;
  template <class A>
  void Serialize(A* a) {
    a->Visit({"enabled", "",
              "Golgi-tendon-organ-like load reflex: a loaded leg stays in stance and presses; a "
              "pad building its bond is pressed"},
             &enabled);
    a->Visit({"hold_gain_rad_per_n", "rad/N",
              "K_F of the stance-holding channel (pad adhesive load)", Range::NonNegative()},
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
         "K_F of the channel that presses a pad building its bond (preload)", Range::NonNegative()},
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
    a->Visit({"share", "",
              "load sharing among the attached pads: internal forces that drive down the worst "
              "pad's utilisation (reflex/README.md)"},
             &share);
    a->Visit({"posture", "",
              "posture: the pads' pull off the surface lowers the body (reflex/README.md)"},
             &posture);
  }
};
// One spindle law for the three joints of every leg.
struct SpindleKeys {
  bool enabled = reflex::LegSpindleParams{}.enabled;
  reflex::SpindleParams law;
  double swing_threshold_rad = reflex::LegSpindleParams{}.swing_threshold_rad;
  bool resist = reflex::LegSpindleParams{}.resist;
  double stance_band_rad = reflex::LegSpindleParams{}.stance_band_rad;
  double hold_s = reflex::LegSpindleParams{}.hold_s;
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
    a->Visit({"length_gain", "rad/rad", "K_L", Range::NonNegative()}, &law.length_gain);
    a->Visit({"velocity_gain_s", "s", "K_V", Range::NonNegative()}, &law.velocity_gain_s);
    a->Visit({"length_threshold_rad", "rad", "L_0", Range::NonNegative()},
             &law.length_threshold_rad);
    a->Visit({"velocity_threshold_rad_per_s", "rad/s", "V_0", Range::NonNegative()},
             &law.velocity_threshold_rad_per_s);
    a->Visit({"delay_s", "s", "transmission delay D", Range::NonNegative()}, &law.delay_s);
  }
};

struct ComplianceKeys : reflex::ComplianceParams {
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

// Landing on a directional pad (sim/reflex_effect.h, the landing channel): a pad welded at zero
// load holds no pull, so the leg that lands must neither pull it nor spring back off it.
struct LandingKeys {
  double settle_s = 0.0;
  double drag_n = 0.0;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"settle_s", "s",
              "at each attach the leg's servo error is taken into its target and fades with this "
              "time constant, so the leg holds the pad where it landed; 0 = off",
              Range::NonNegative()},
             &settle_s);
    a->Visit({"drag_n", "N",
              "settle_s > 0, adhesion.law frictional: the settled target also drags the pad this "
              "much along its gripping direction (through the servos' stiffness), engaging the "
              "adhesive before it is pulled",
              Range::NonNegative()},
             &drag_n);
  }
};

struct ReflexParams {
  LandingKeys landing;
  PreloadKeys preload;
  SearchKeys search;
  PeelKeys peel;
  RegripKeys regrip;
  GtoKeys gto;
  SpindleKeys spindle;
  ComplianceKeys compliance;
  double max_offset_rad = reflex::LegReflexParams{}.max_offset_rad;
  bool release_failed_peel = false;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"preload", "", "press on touchdown"}, &preload);
    a->Visit({"search", "", "reach again when a swing finds no surface"}, &search);
    a->Visit({"peel", "", "peel the pad at swing onset"}, &peel);
    a->Visit({"regrip", "", "press again after an unexpected bond loss"}, &regrip);
    a->Visit({"gto", "", "load reflexes"}, &gto);
    a->Visit({"spindle", "", "stretch reflexes"}, &spindle);
    a->Visit({"compliance", "", "servo stiffness by phase"}, &compliance);
    a->Visit({"landing", "", "settle and drag a leg as its pad attaches"}, &landing);
    a->Visit({"max_offset_rad", "rad", "the reflexes' summed offset per joint is clamped to this",
              Range::Positive()},
             &max_offset_rad);
    a->Visit({"release_failed_peel", "",
              "when a peel runs out of time, let the pad go (detach cause released), as a foot "
              "with an active release mechanism would"},
             &release_failed_peel);
  }

  // Whether the GTO's posture acts: the CPG sizes its leg IK table for it, the reflex effect
  // runs it.
  bool PostureOn() const { return gto.enabled && gto.posture.enabled; }

  // The reflex module's parameters for one leg.
  reflex::LegReflexParams Leg() const {
    reflex::LegReflexParams p;
    p.preload = preload;
    p.search = search;
    p.peel = peel;
    p.regrip = regrip;
    p.gto = gto;
    p.spindle.enabled = spindle.enabled;
    p.spindle.joints = {spindle.law, spindle.law, spindle.law};
    p.spindle.swing_threshold_rad = spindle.swing_threshold_rad;
    p.spindle.resist = spindle.resist;
    p.spindle.stance_band_rad = spindle.stance_band_rad;
    p.spindle.hold_s = spindle.hold_s;
    p.compliance = compliance;
    p.max_offset_rad = max_offset_rad;
    return p;
  }
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SCENARIO_REFLEX_KEYS_H_
