// Scenario keys of the effects (see scenario.h for the archive pattern). Each block here is
// optional in a scenario; when absent, its effect is not constructed.
#ifndef CLIMBSIM_SIM_EFFECT_PARAMS_H_
#define CLIMBSIM_SIM_EFFECT_PARAMS_H_

#include <optional>
#include <string>
#include <vector>

#include "sim/archive.h"

namespace climbsim::sim {

// The CPG: one oscillator per leg (cpg/README.md has the laws).
struct CpgParams {
  std::string oscillator = "phase";
  std::string gait;  // empty: the robot's default (trot for 4 legs, tripod for 6)
  std::vector<double> offsets_cycles;
  std::vector<std::vector<double>> phase_bias_rad;
  std::optional<double> duty_factor;
  double frequency_hz = 1.0;
  double coupling_per_s = 4.0;
  double amplitude = 1.0;
  double start_amplitude = 0.0;
  double amplitude_rate_per_s = 5.0;
  std::string stepper = "rk4";
  double abs_tol = 1e-8;
  double rel_tol = 1e-6;
  std::optional<double> control_period_s;
  std::vector<double> stride_rad{0.35, 0.0, 0.0};
  std::vector<double> lift_rad{0.0, 0.5, 0.5};

  template <class A>
  void Serialize(A* a) {
    a->Choice({"oscillator", "", "oscillator type"}, &oscillator, {"phase"});
    a->Visit({"gait", "", "gait preset: trot or lateral_sequence (4 legs); tripod, tetrapod or wave (6 legs); default trot / tripod"}, &gait);
    a->Visit({"offsets_cycles", "cycle", "explicit gait: how far each leg lags, in the robot's leg order (instead of gait)", Range::Closed(-1, 1)}, &offsets_cycles, 0);
    a->Visit({"phase_bias_rad", "rad", "explicit phase-bias matrix phi_ij (instead of gait)"}, &phase_bias_rad);
    a->Visit({"duty_factor", "", "share of the cycle in stance; default from the gait (1/2 trot and tripod, 3/4 lateral sequence, 2/3 tetrapod, 5/6 wave)", Range::Closed(0.05, 0.95)}, &duty_factor);
    a->Visit({"frequency_hz", "Hz", "stepping frequency f", Range::OpenClosed(0, 20)}, &frequency_hz);
    a->Visit({"coupling_per_s", "1/s", "coupling weight w_ij between every pair of oscillators", Range::NonNegative()}, &coupling_per_s);
    a->Visit({"amplitude", "", "target amplitude R: scales the stride (lift is not scaled, so a leg still clears the surface at small strides)", Range::Closed(0, 10)}, &amplitude);
    a->Visit({"start_amplitude", "", "amplitude at t = 0; the gait fades in towards R with rate a", Range::Closed(0, 10)}, &start_amplitude);
    a->Visit({"amplitude_rate_per_s", "1/s", "amplitude convergence rate a", Range::Positive()}, &amplitude_rate_per_s);
    a->Choice({"stepper", "", "Odeint stepper integrating the oscillators"}, &stepper, {"euler", "rk4", "dopri5"});
    a->Visit({"abs_tol", "", "absolute tolerance (dopri5)", Range::Positive()}, &abs_tol);
    a->Visit({"rel_tol", "", "relative tolerance (dopri5)", Range::Positive()}, &rel_tol);
    a->Visit({"control_period_s", "s", "controller period, a whole multiple of the time step; default: every step", Range::Positive()}, &control_period_s);
    a->Visit({"stride_rad", "rad", "joint excursion per unit stride (+1 foot forward): hip_yaw, hip_pitch, knee"}, &stride_rad, 3);
    a->Visit({"lift_rad", "rad", "joint excursion at full lift in swing: hip_yaw, hip_pitch, knee"}, &lift_rad, 3);
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
  }
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_EFFECT_PARAMS_H_
