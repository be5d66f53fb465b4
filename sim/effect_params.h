// Scenario keys of the effects (see scenario.h for the archive pattern). Each block here is
// optional in a scenario; when absent, its effect is not constructed.
#ifndef CLIMBSIM_SIM_EFFECT_PARAMS_H_
#define CLIMBSIM_SIM_EFFECT_PARAMS_H_

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "adhesion/adhesion.h"
#include "adhesion/frictional_law.h"
#include "cpg/cpg.h"
#include "reflex/reflex.h"
#include "sim/archive.h"

namespace climbsim::sim {

// Hopf oscillators (cpg/README.md, Righetti and Ijspeert 2008); their stance and swing
// frequencies follow from cpg.frequency_hz and the duty factor.
struct HopfParams {
  double mu = cpg::HopfNetworkParams{}.mu;
  double alpha_per_s = cpg::HopfNetworkParams{}.alpha_per_s;
  double beta_per_s = cpg::HopfNetworkParams{}.beta_per_s;
  double switch_sharpness = cpg::HopfNetworkParams{}.b;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"mu", "", "squared radius of the limit cycle", Range::Positive()}, &mu);
    a->Visit(
        {"alpha_per_s", "1/s", "convergence rate to the limit cycle along x", Range::Positive()},
        &alpha_per_s);
    a->Visit(
        {"beta_per_s", "1/s", "convergence rate to the limit cycle along y", Range::Positive()},
        &beta_per_s);
    a->Visit({"switch_sharpness", "",
              "b: sharpness of the switch between stance and swing frequency", Range::Positive()},
             &switch_sharpness);
  }
};

// The CPG: one oscillator per leg (cpg/README.md has the laws), its phase shaped into the
// leg's joint targets either in joint space (stride_rad, lift_rad) or in foot space
// (stride_m, lift_m: straight foot paths in the body frame through the legs' inverse
// kinematics, which stance legs welded to a wall need).
struct CpgParams {
  std::string oscillator = "phase";
  std::string gait;  // empty: the robot's default (trot for 4 legs, tripod for 6)
  std::vector<double> offsets_cycles;
  std::vector<std::vector<double>> phase_bias_rad;
  std::optional<double> duty_factor;
  double frequency_hz = cpg::PhaseNetworkParams{}.frequency_hz;
  double coupling_per_s = 4.0;
  double amplitude = 1.0;
  double start_amplitude = 0.0;
  double amplitude_rate_per_s = cpg::PhaseNetworkParams{}.amplitude_rate_per_s;
  std::string stepper = "rk4";
  double abs_tol = cpg::StepperParams{}.abs_tol;
  double rel_tol = cpg::StepperParams{}.rel_tol;
  std::optional<double> control_period_s;
  std::vector<double> stride_rad;  // joint space; default [0.35, 0, 0]
  std::vector<double> lift_rad;    // joint space; default [0, 0.5, 0.5]
  std::optional<double> stride_m;  // foot space when given
  double lift_m = 0.015;
  double press_m = 0.0;
  double crouch_m = 0.0;
  double squeeze_m = 0.0;
  double lift_share = cpg::LegShape{}.lift_share;
  HopfParams hopf;
  double tegotae_sigma_rad_per_n_s = 0.0;
  bool wait_for_support = false;
  double support_bond_fraction = 0.95;

  template <class A>
  void Serialize(A* a) {
    a->Choice({"oscillator", "",
               "phase: phase oscillators with amplitude (Ijspeert 2007); hopf: Hopf oscillators "
               "with separate stance and swing frequencies (Righetti and Ijspeert 2008)"},
              &oscillator, {"phase", "hopf"});
    a->Visit({"gait", "",
              "gait preset: trot or lateral_sequence (4 legs); tripod, tetrapod or wave (6 legs); "
              "default trot / tripod"},
             &gait);
    a->Visit({"offsets_cycles", "cycle",
              "explicit gait: how far each leg lags, in the robot's leg order (instead of gait)",
              Range::Closed(-1, 1)},
             &offsets_cycles, 0);
    a->Visit({"phase_bias_rad", "rad", "explicit phase-bias matrix phi_ij (instead of gait)"},
             &phase_bias_rad);
    a->Visit({"duty_factor", "",
              "share of the cycle in stance; default from the gait (1/2 trot and tripod, 3/4 "
              "lateral sequence, 2/3 tetrapod, 5/6 wave)",
              Range::Closed(0.05, 0.95)},
             &duty_factor);
    a->Visit({"frequency_hz", "Hz", "stepping frequency f", Range::OpenClosed(0, 20)},
             &frequency_hz);
    a->Visit({"coupling_per_s", "1/s", "coupling weight w_ij between every pair of oscillators",
              Range::NonNegative()},
             &coupling_per_s);
    a->Visit({"amplitude", "",
              "target amplitude R: scales the stride (lift is not scaled, so a leg still clears "
              "the surface at small strides)",
              Range::Closed(0, 10)},
             &amplitude);
    a->Visit({"start_amplitude", "",
              "amplitude at t = 0; the gait fades in towards R with rate a (phase oscillators)",
              Range::Closed(0, 10)},
             &start_amplitude);
    a->Visit({"amplitude_rate_per_s", "1/s", "amplitude convergence rate a", Range::Positive()},
             &amplitude_rate_per_s);
    a->Choice({"stepper", "", "Odeint stepper integrating the oscillators"}, &stepper,
              {"euler", "rk4", "dopri5"});
    a->Visit({"abs_tol", "", "absolute tolerance (dopri5)", Range::Positive()}, &abs_tol);
    a->Visit({"rel_tol", "", "relative tolerance (dopri5)", Range::Positive()}, &rel_tol);
    a->Visit({"control_period_s", "s",
              "controller period, a whole multiple of the time step; default: every step",
              Range::Positive()},
             &control_period_s);
    a->Visit({"stride_rad", "rad",
              "joint space: joint excursion per unit stride (+1 foot forward) of hip_yaw, "
              "hip_pitch, knee; default [0.35, 0, 0]"},
             &stride_rad, 3);
    a->Visit({"lift_rad", "rad",
              "joint space: joint excursion at full lift in swing of hip_yaw, hip_pitch, knee; "
              "default [0, 0.5, 0.5]"},
             &lift_rad, 3);
    a->Visit({"stride_m", "m",
              "foot space: foot travel along the body axis per stance (feet follow straight lines "
              "through the legs' inverse kinematics)",
              Range::OpenClosed(0, 0.2)},
             &stride_m);
    a->Visit(
        {"lift_m", "m", "foot space: height of the swing above the surface", Range::Closed(0, 0.1)},
        &lift_m);
    a->Visit({"press_m", "m",
              "foot space: how far stance feet are aimed into the surface (a preload through the "
              "servos)",
              Range::Closed(0, 0.02)},
             &press_m);
    a->Visit(
        {"crouch_m", "m",
         "foot space: feet held this much closer to the body than in the neutral pose, so the body "
         "rides lower (a climber's centre of mass near the wall pulls its front pads off less)",
         Range::Closed(0, 0.03)},
        &crouch_m);
    a->Visit({"squeeze_m", "m",
              "foot space: stance feet aimed this much towards the middle of the body along its "
              "axis (front feet back, hind feet forward; legs at the middle not at all), reached "
              "over the first tenth of the stance: a welded stance becomes a grasp whose internal "
              "force drags opposed directional pads along their gripping directions",
              Range::Closed(-0.01, 0.01)},
             &squeeze_m);
    a->Visit({"lift_share", "",
              "0: smooth swing (stride and lift together); a > 0: lift-move-place swing, rising "
              "over the first share a of the swing and landing over the last (climbers: a peeled "
              "foot must clear the surface before it moves)",
              Range{0, 0.5, false, true}},
             &lift_share);
    a->Visit({"hopf", "", "Hopf oscillator options (oscillator: hopf)"}, &hopf);
    a->Visit({"tegotae_sigma_rad_per_n_s", "rad/(N s)",
              "Tegotae load feedback dtheta_i/dt += -sigma N_i cos(theta_i), N_i the pad's normal "
              "load; 0 = off (Owaki et al. 2013)",
              Range::NonNegative()},
             &tegotae_sigma_rad_per_n_s);
    a->Visit({"wait_for_support", "",
              "a leg does not start its swing until the legs that support the robot during that "
              "swing (the other diagonal in a trot) have their pads attached and bonded"},
             &wait_for_support);
    a->Visit({"support_bond_fraction", "",
              "wait_for_support: the bonded fraction a support pad must have built",
              Range::Closed(0, 1)},
             &support_bond_fraction);
  }

  void Validate(const Checker& c) const {
    const int given = !gait.empty() + !offsets_cycles.empty() + !phase_bias_rad.empty();
    if (given > 1) {
      c.Fail(!offsets_cycles.empty() ? "offsets_cycles" : "phase_bias_rad",
             "give only one of gait, offsets_cycles and phase_bias_rad");
    }
    if (!phase_bias_rad.empty() && phase_bias_rad.size() != phase_bias_rad[0].size()) {
      c.Fail("phase_bias_rad", "must be a square matrix");
    }
    if (stride_m && (!stride_rad.empty() || !lift_rad.empty())) {
      c.Fail("stride_m",
             "give the gait in joint space (stride_rad, lift_rad) or in foot space (stride_m, "
             "lift_m), not both");
    }
  }
};

// Dry adhesion (adhesion/README.md has the model; docs/design.md section 3). Material and attach
// keys apply to every pad; pad_overrides changes a few of them for one pad.
struct AdhesionPadOverride {
  std::string pad;
  std::optional<double> sigma_t_pa;
  std::optional<double> mu;
  std::optional<double> gain_n;
  std::optional<double> grip_x;
  std::optional<double> grip_y;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"pad", "", "the pad body this entry changes (one of adhesion.pads)", {}, true}, &pad);
    a->Visit({"sigma_t_pa", "Pa", "this pad's rupture threshold", Range::Positive()}, &sigma_t_pa);
    a->Visit({"mu", "", "this pad's compression gain", Range::NonNegative()}, &mu);
    a->Visit({"gain_n", "N", "this pad's adhesion-actuator gain (model mujoco)", Range::Positive()},
             &gain_n);
    a->Visit({"grip_x", "",
              "this pad's gripping direction, x component (law frictional; pad frame, as "
              "adhesion.frictional.grip_x): e.g. hind feet gripping up the wall, opposed to the "
              "front feet",
              Range::Any()},
             &grip_x);
    a->Visit(
        {"grip_y", "", "this pad's gripping direction, y component (law frictional)", Range::Any()},
        &grip_y);
  }
};

// adhesion.frictional: the directional law's parameters (adhesion/frictional_law.h; used
// with adhesion.law: frictional).
struct FrictionalKeys : adhesion::FrictionalParams {
  template <class A>
  void Serialize(A* a) {
    a->Visit({"critical_angle_deg", "deg",
              "alpha*: a pulled pad holds while F_n <= F_t tan(alpha*) (Autumn et al. 2006: about "
              "25-30 deg for geckos)",
              Range{0.0, 90.0, true, true}},
             &critical_angle_deg);
    a->Visit({"shear_limit_pa", "Pa",
              "tau_max: the shear limit F_t,max = tau_max times the pad area (also per bond)",
              Range::Positive()},
             &shear_limit_pa);
    a->Visit({"friction_mu", "",
              "Coulomb friction of a pressed pad: reversed shear up to mu C, gripping shear up to "
              "F_t,max + mu C (C the compression)",
              Range::NonNegative()},
             &friction_mu);
    a->Visit({"grip_x", "",
              "gripping direction d in the pad frame, x component (x across the pad width, along "
              "the heading for the bundled robots); normalised; default -1: down the wall for a "
              "robot climbing +x",
              Range::Any()},
             &grip_x);
    a->Visit({"grip_y", "",
              "gripping direction d in the pad frame, y component (y along the pad length); a "
              "climber's d points down the wall",
              Range::Any()},
             &grip_y);
    a->Visit({"moment_share", "",
              "share of the pad's moments the bonds carry: 1 a rigid pad on a rigid ankle (moments "
              "peel it bond by bond); 0 a compliant toe or passive ankle (the pad-level law)",
              Range::Closed(0, 1)},
             &moment_share);
  }
  void Validate(const Checker& c) const {
    if (!(std::hypot(grip_x, grip_y) > 1e-9))
      c.Fail("grip_x", "the gripping direction (grip_x, grip_y) must not be zero");
  }
};

// The bond grid's keys (adhesion::PadParams: one declaration and one default each; width_m
// and length_m are not keys, they come from each pad's box geom) and the attach conditions
// (adhesion::AttachParams), plus what only the scenario has.
struct AdhesionParams : adhesion::PadParams, adhesion::AttachParams {
  std::string model = "bonds";
  std::vector<std::string> pads;
  std::vector<std::string> surfaces;
  bool start_attached = adhesion::AdhesionSystemParams{}.start_attached;
  double start_gap_m = adhesion::AdhesionSystemParams{}.start_gap_m;
  std::vector<double> weld_solref =
      std::vector<double>(adhesion::kDefaultWeldSolref.begin(), adhesion::kDefaultWeldSolref.end());
  std::optional<double> gain_n;
  double ctrl = adhesion::StickyPadParams{}.actuator_ctrl;
  double reach_m = adhesion::AdhesionSystemParams{}.reach_m;
  std::vector<AdhesionPadOverride> pad_overrides;
  double pad_failure_probability = 0.0;
  double pad_failure_window_s = 1.0;
  std::string law = "von_mises";
  FrictionalKeys frictional;
  double release_contact_delay_s = adhesion::StickyPadParams{}.release_contact_delay_s;

  template <class A>
  void Serialize(A* a) {
    a->Choice({"model", "",
               "bonds: this project's weld-and-bond-grid model; mujoco: MuJoCo's built-in adhesion "
               "actuator (the baseline)"},
              &model, {"bonds", "mujoco"});
    a->Visit({"pads", "",
              "sticky pad bodies (each holds one box geom); default: every leg's pad body (LF_pad, "
              "RF_pad, ...)"},
             &pads);
    a->Visit({"surfaces", "",
              "bodies or geoms the pads may stick to; default: any geom that is not a sticky pad"},
             &surfaces);
    a->Visit({"start_attached", "",
              "pads within start_gap_m of a surface at t = 0 attach fully, without the attach "
              "conditions (a robot that starts on a wall or a ceiling)"},
             &start_attached);
    a->Visit({"start_gap_m", "m",
              "how far a pad face may be from a surface at t = 0 and still start attached (the "
              "robots start 0.5 mm above it)",
              Range::OpenClosed(0, 0.1)},
             &start_gap_m);
    a->Visit({"sigma_t_pa", "Pa",
              "sigma_T, bond rupture threshold (10 kPa: the seed authors' estimate for their dry "
              "adhesive)",
              Range::Positive()},
             &sigma_t_pa);
    a->Visit({"mu", "",
              "gain of compression on the shear threshold: a compressed bond breaks when sqrt(3) "
              "times its shear reaches sigma_T + mu times its compression",
              Range::NonNegative()},
             &mu);
    a->Visit({"grid_x", "", "bonds across the pad width (accuracy against time)",
              Range::Closed(1, 1024)},
             &grid_x);
    a->Visit({"grid_y", "", "bonds along the pad length", Range::Closed(1, 1024)}, &grid_y);
    a->Visit({"min_bonds", "", "the pad detaches when fewer bonds than this remain",
              Range::Closed(1, 1048576)},
             &min_bonds);
    a->Visit({"min_contacts", "",
              "attach condition: contact points with the surface (box on plane gives 4)",
              Range::Closed(1, 1000)},
             &min_contacts);
    a->Visit(
        {"max_approach_speed_mps", "m/s",
         "attach condition: normal speed towards the surface at touchdown", Range::NonNegative()},
        &max_approach_speed_mps);
    a->Visit({"max_approach_angle_deg", "deg",
              "attach condition: angle between pad normal and surface normal at touchdown",
              Range::Closed(0, 180)},
             &max_approach_angle_deg);
    a->Visit({"min_preload_n", "N", "attach condition: compressive contact force on the pad",
              Range::NonNegative()},
             &min_preload_n);
    a->Visit(
        {"initial_fraction", "", "bonded fraction at attach (centre-out)", Range::Closed(0, 1)},
        &initial_fraction);
    a->Visit({"buildup_time_s", "s",
              "time constant of the growth of the bonded fraction towards 1 while the pad is not "
              "pulled; 0: full at once",
              Range::NonNegative()},
             &buildup_time_s);
    a->Visit({"attach_window_s", "s",
              "after touchdown, how long contacts and preload may take to meet their conditions "
              "before the attach is rejected",
              Range::NonNegative()},
             &attach_window_s);
    a->Visit({"weld_solref", "s, -",
              "solref (time constant, damping ratio) of the welds that hold attached pads; MuJoCo "
              "raises the time constant to 2 time steps",
              Range::Positive()},
             &weld_solref, 2);
    a->Visit({"gain_n", "N",
              "model mujoco: adhesion-actuator force at ctrl 1; default sigma_T times the pad area",
              Range::Positive()},
             &gain_n);
    a->Visit({"ctrl", "", "model mujoco: actuator ctrl while attached", Range::Closed(0, 1)},
             &ctrl);
    a->Visit(
        {"reach_m", "m",
         "model mujoco: pad geom margin = gap, so the actuator pulls a pad this close to a surface",
         Range::Closed(0, 0.1)},
        &reach_m);
    a->Visit({"pad_overrides", "",
              "per-pad changes: a list of maps with pad and any of sigma_t_pa, mu, gain_n, grip_x, "
              "grip_y"},
             &pad_overrides);
    a->Visit({"pad_failure_probability", "",
              "each attachment fails with this probability (drawn from seed): all its bonds break "
              "at once (detach cause failure) at a time uniform in [0, pad_failure_window_s) after "
              "the attach, if the pad still holds then",
              Range::Closed(0, 1)},
             &pad_failure_probability);
    a->Visit({"pad_failure_window_s", "s",
              "pad failures: the window after an attach in which a failing pad fails (about one "
              "stance of the example gaits: 1.25 s gecko, 0.95 s spider)",
              Range::Positive()},
             &pad_failure_window_s);
    a->Choice({"law", "",
               "model bonds: when bonds break. von_mises: the seed's isotropic law (sigma_T, mu); "
               "frictional: directional dry adhesion, adhesion only under shear along the gripping "
               "direction (adhesion.frictional)"},
              &law, {"von_mises", "frictional"});
    a->Visit({"frictional", "", "the frictional law's parameters (law: frictional)"}, &frictional);
    a->Visit({"release_contact_delay_s", "s",
              "model bonds: a pad let go by its release (detach cause released) collides again "
              "only this much later, so that it is not pushed out of the depth its landing pressed "
              "it to (a kick the other pads feel); 0 = at once",
              Range::NonNegative()},
             &release_contact_delay_s);
  }

  void Validate(const Checker& c) const {
    if (static_cast<long>(min_bonds) > static_cast<long>(grid_x) * grid_y) {
      c.Fail("min_bonds", "must be <= grid_x * grid_y = " + std::to_string(grid_x * grid_y) +
                              ", got " + std::to_string(min_bonds));
    }
  }
};

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

// Surface transitions (sim/transition_effect.h): a planned free gait that takes the robot over a
// sharp 90-degree corner (inner: floor to wall, wall to ceiling; outer: a wall onto its top),
// started when a front pad touches a surface whose normal differs from the one it stands on.
// Needs the cpg and adhesion blocks and a robot with actuated ankles (gecko_ankle,
// spider_ankle).
struct TransitionParams {
  double trigger_angle_deg = 45.0;
  double lost_s = 1.5;
  double body_speed_mps = 0.02;
  double pitch_rate_rad_per_s = 0.2;
  double swing_s = 0.5;
  double lift_m = 0.015;
  double place_speed_mps = 0.06;
  double press_m = 0.001;
  double place_depth_m = 0.004;
  double place_force_n = 0.4;
  double track_s = 0.0;
  double peel_back_m = 0.02;
  std::string peel_toward = "load";
  double peel_lift_m = 0.005;
  double peel_tilt_rad = 0.6;
  double peel_ramp_s = 0.3;
  double peel_max_s = 1.0;
  double margin_rad = 0.05;
  double reach_share = 0.8;
  double crouch_m = 0.02;
  double support_bond_fraction = 0.85;
  int max_place_attempts = 4;
  double unload_gain = 2.0;
  double unload_threshold = 0.8;
  std::string then = "crawl";

  template <class A>
  void Serialize(A* a) {
    a->Visit(
        {"trigger_angle_deg", "deg",
         "a front pad that touches a surface whose normal is more than this from the normal of "
         "the surface the robot stands on starts the manoeuvre",
         Range::OpenClosed(0, 90)},
        &trigger_angle_deg);
    a->Visit({"lost_s", "s",
              "a front foot that has touched nothing for this long has found the surface ended: "
              "the body crouches and the foot probes down past the edge and back until it touches "
              "the surface beyond (an outer corner)",
              Range::Positive()},
             &lost_s);
    a->Visit({"body_speed_mps", "m/s", "body speed along a surface during the manoeuvre",
              Range::Positive()},
             &body_speed_mps);
    a->Visit({"pitch_rate_rad_per_s", "rad/s", "body pitch rate while it turns round the corner",
              Range::Positive()},
             &pitch_rate_rad_per_s);
    a->Visit({"swing_s", "s", "duration of a foot's move from one foothold to the next",
              Range::Positive()},
             &swing_s);
    a->Visit({"lift_m", "m", "clearance of a moving foot above the surfaces it leaves and lands on",
              Range::Closed(0, 0.1)},
             &lift_m);
    a->Visit({"place_speed_mps", "m/s",
              "speed at which a foot is lowered onto its foothold (below the attach limit "
              "adhesion.max_approach_speed_mps)",
              Range::Positive()},
             &place_speed_mps);
    a->Visit(
        {"press_m", "m", "how far a stance foot is aimed into its surface", Range::Closed(0, 0.02)},
        &press_m);
    a->Visit({"place_depth_m", "m",
              "how far a foot being placed is pressed into its surface until its pad attaches",
              Range::Closed(0, 0.03)},
             &place_depth_m);
    a->Visit({"place_force_n", "N",
              "a foot being placed is pressed no further once its pad's contact force reaches this "
              "(a harder press pushes the body off the other pads)",
              Range::Positive()},
             &place_force_n);
    a->Visit({"track_s", "s",
              "time constant of the integral correction that moves the stance legs' targets until "
              "the body, sagging on its compliant servos, is where the plan commands it (updated "
              "every 10 ms); 0: off",
              Range::NonNegative()},
             &track_s);
    a->Visit({"peel_back_m", "m",
              "a foot about to move is drawn this far back along its surface to peel its pad",
              Range::Closed(0, 0.1)},
             &peel_back_m);
    a->Choice({"peel_toward", "",
               "the direction of the peel's pull along the pad's surface, chosen so that its "
               "reaction relieves the other pads. load: along the load they carry (the weight), "
               "else as normals; normals: along the sum of their normals, so that it presses them "
               "into their surfaces, else as back; back: against the body's heading"},
              &peel_toward, {"load", "normals", "back"});
    a->Visit({"peel_lift_m", "m",
              "and this far away from its surface (with peel_back_m: the peel's pull)",
              Range::Closed(0, 0.1)},
             &peel_lift_m);
    a->Visit(
        {"peel_tilt_rad", "rad",
         "while it peels, the ankle tilt is turned this far the way the pull turns the pad (the "
         "servo's torque adds to the pull's moment on the bonds)",
         Range::Closed(0, 2)},
        &peel_tilt_rad);
    a->Visit({"peel_ramp_s", "s", "time to the full peel pull", Range::Positive()}, &peel_ramp_s);
    a->Visit({"peel_max_s", "s", "a peel that has not let go after this long stops the manoeuvre",
              Range::Positive()},
             &peel_max_s);
    a->Visit({"margin_rad", "rad",
              "every joint of a stance leg stays this far inside its range; a leg that would not "
              "steps to a new foothold",
              Range::Closed(0, 0.5)},
             &margin_rad);
    a->Visit({"reach_share", "",
              "inner corner: the front feet step onto the new surface with the front hips this "
              "share of a foot's forward reach (plus the foot post) away from it",
              Range::OpenClosed(0, 1)},
             &reach_share);
    a->Visit({"crouch_m", "m",
              "outer corner: the body rides this much closer to the surfaces while it turns over "
              "the edge",
              Range::Closed(0, 0.05)},
             &crouch_m);
    a->Visit({"support_bond_fraction", "",
              "a foot moves only while every other pad is attached with at least this bonded "
              "fraction",
              Range::Closed(0, 1)},
             &support_bond_fraction);
    a->Visit({"max_place_attempts", "",
              "a foot that does not attach is lifted and placed again up to this many times; then "
              "the manoeuvre stops",
              Range::Closed(1, 100)},
             &max_place_attempts);
    a->Visit({"unload_gain", "",
              "a stance leg whose pad is at utilisation U above unload_threshold has its servos' "
              "kp lowered by the factor max(0.2, 1 - unload_gain (U - unload_threshold)) (the GTO "
              "unload law of reflex.gto), so the other pads take the load; 0: off",
              Range::NonNegative()},
             &unload_gain);
    a->Visit({"unload_threshold", "", "utilisation from which a stance leg yields",
              Range::Closed(0, 10)},
             &unload_threshold);
    a->Choice({"then", "",
               "once every foot is on the new surface: gait, the feet are stepped to where the "
               "CPG's gait has them and the CPG and reflexes go on (and the next corner is "
               "watched for); crawl, the manoeuvre's free gait walks on along the new surface"},
              &then, {"gait", "crawl"});
  }
};

// A push: a force F = impulse / duration on a body, applied at its centre of mass in the world
// frame from time_s for duration_s.
struct PushParams {
  double time_s = 0.0;
  std::string body = "base";
  std::vector<double> impulse_ns{0.0, 0.0, 0.0};
  double duration_s = 0.01;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"time_s", "s", "when the push starts", Range::NonNegative(), true}, &time_s);
    a->Visit({"body", "", "the body pushed"}, &body);
    a->Visit({"impulse_ns", "N s", "impulse in the world frame (x, y, z)", {}, true}, &impulse_ns,
             3);
    a->Visit({"duration_s", "s", "over how long the impulse is spread (rounded to whole steps)",
              Range::Positive()},
             &duration_s);
  }
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_EFFECT_PARAMS_H_
