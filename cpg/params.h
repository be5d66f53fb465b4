// The scenario's cpg block: every cpg key declared once, beside the networks it configures
// (sim/cpg_effect.h builds them from it). Defaults are those of the library's structs
// (PhaseNetworkParams, HopfNetworkParams, StepperParams, LegShape), so a key and its
// network field cannot disagree. cpg/README.md has the laws.
#ifndef CLIMBSIM_CPG_PARAMS_H_
#define CLIMBSIM_CPG_PARAMS_H_

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "cpg/hopf_network.h"
#include "cpg/leg_shape.h"
#include "cpg/oscillator_network.h"
#include "cpg/phase_network.h"
#include "keys/keys.h"

namespace climbsim::cpg {

// Hopf oscillators (cpg/README.md, Righetti and Ijspeert 2008); their stance and swing
// frequencies follow from cpg.frequency_hz and the duty factor.
struct HopfKeys {
  double mu = HopfNetworkParams{}.mu;
  double alpha_per_s = HopfNetworkParams{}.alpha_per_s;
  double beta_per_s = HopfNetworkParams{}.beta_per_s;
  double switch_sharpness = HopfNetworkParams{}.b;

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

// A spine (robot.body.spine) bent by the gait: spine_yaw = amplitude_rad·sin(θ_0 + phase_rad),
// θ_0 the first leg's oscillator phase, so the trunk bends locked to the legs.
struct SpineKeys {
  double amplitude_rad = 0.0;
  double phase_rad = 0.0;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"amplitude_rad", "rad",
              "spine yaw amplitude; 0-1: a gecko's trunk swings about 0.3 rad each way in a trot "
              "(the spine's servo range bounds the command)",
              Range::Closed(0, 1)},
             &amplitude_rad);
    a->Visit({"phase_rad", "rad", "phase of the bend after the first leg's oscillator",
              Range::Closed(-2 * M_PI, 2 * M_PI)},
             &phase_rad);
  }
};

// The CPG: one oscillator per leg (cpg/README.md has the laws), its phase shaped into the
// leg's joint targets either in joint space (stride_rad, lift_rad) or in foot space
// (stride_m, lift_m: straight foot paths in the body frame through the legs' inverse
// kinematics, which stance legs welded to a wall need).
struct CpgKeys {
  std::string oscillator = "phase";
  std::string gait;  // empty: the robot's default (trot for 4 legs, tripod for 6)
  std::vector<double> offsets_cycles;
  std::vector<std::vector<double>> phase_bias_rad;
  std::optional<double> duty_factor;
  double frequency_hz = PhaseNetworkParams{}.frequency_hz;
  double coupling_per_s = 4.0;
  double amplitude = 1.0;
  double start_amplitude = 0.0;
  double amplitude_rate_per_s = PhaseNetworkParams{}.amplitude_rate_per_s;
  std::string stepper = "rk4";
  double abs_tol = StepperParams{}.abs_tol;
  double rel_tol = StepperParams{}.rel_tol;
  std::optional<double> control_period_s;
  std::vector<double> stride_rad;  // joint space; default [0.35, 0, 0]
  std::vector<double> lift_rad;    // joint space; default [0, 0.5, 0.5]
  std::optional<double> stride_m;  // foot space when given
  double lift_m = 0.015;
  double press_m = 0.0;
  double crouch_m = 0.0;
  double squeeze_m = 0.0;
  double lift_share = LegShape{}.lift_share;
  HopfKeys hopf;
  double tegotae_sigma_rad_per_n_s = 0.0;
  bool wait_for_support = false;
  double support_bond_fraction = 0.95;
  std::optional<SpineKeys> spine;

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
              "wait_for_support: the bonded fraction a support pad must have built, of the share "
              "of its face that touches the surface (all of it on a flat surface); a pad that has "
              "bonded all that its torn bonds leave has built all it can",
              Range::Closed(0, 1)},
             &support_bond_fraction);
    a->Visit({"spine", "", "drive the robot's spine (robot.body.spine) with the gait; absent: off"},
             &spine);
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

}  // namespace climbsim::cpg

#endif  // CLIMBSIM_CPG_PARAMS_H_
