// Helpers shared by the cpg tests: running a network, finding swing onsets, closed forms.
#ifndef CLIMBSIM_TESTS_CPG_TEST_UTIL_H_
#define CLIMBSIM_TESTS_CPG_TEST_UTIL_H_

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <random>
#include <span>
#include <vector>

#include "cpg/cpg.h"

namespace climbsim::cpg::testing {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kTwoPi = 2.0 * std::numbers::pi;

// Δ into [−π, π).
inline double WrapPi(double delta_rad) {
  return delta_rad - kTwoPi * std::floor((delta_rad + kPi) / kTwoPi);
}

// A network of either type on the lateral-sequence walk (4 legs) or the wave (6), stride 1 Hz,
// coupling 2 /s, with the given stepper: what the allocation tests and the benchmarks step.
inline std::unique_ptr<OscillatorNetwork> MakeGaitNetwork(bool hopf, int legs, Stepper stepper) {
  const Gait gait = GaitPreset(legs == 4 ? "lateral_sequence" : "wave", legs);
  if (hopf) {
    HopfNetworkParams p = HopfNetworkParamsForGait(gait, 1.0, 2.0);
    p.stepper.type = stepper;
    return std::make_unique<HopfNetwork>(p);
  }
  PhaseNetworkParams p = PhaseNetworkParamsForGait(gait, 1.0, 2.0);
  p.stepper.type = stepper;
  return std::make_unique<PhaseNetwork>(p);
}

// Steps until time_s() reaches t_end_s (to within half a step).
inline void RunFor(OscillatorNetwork& network, double duration_s, double dt_s) {
  const int steps = static_cast<int>(std::lround(duration_s / dt_s));
  for (int k = 0; k < steps; ++k) network.Step(dt_s, {});
}

// For each oscillator, the times at which its unwrapped phase crosses a multiple of 2π (swing
// onset, θ = 0), linearly interpolated within the step, over duration_s of further stepping.
inline std::vector<std::vector<double>> SwingOnsetTimes(OscillatorNetwork& network,
                                                        double duration_s, double dt_s) {
  const int n = network.size();
  std::vector<std::vector<double>> onsets(n);
  std::vector<double> before(n);
  const int steps = static_cast<int>(std::lround(duration_s / dt_s));
  for (int k = 0; k < steps; ++k) {
    const double t0 = network.time_s();
    for (int i = 0; i < n; ++i) before[i] = network.phase_unwrapped_rad()[i];
    network.Step(dt_s, {});
    for (int i = 0; i < n; ++i) {
      const double after = network.phase_unwrapped_rad()[i];
      const double crossing = kTwoPi * std::floor(after / kTwoPi);
      if (crossing > before[i]) {
        onsets[i].push_back(t0 + dt_s * (crossing - before[i]) / (after - before[i]));
      }
    }
  }
  return onsets;
}

// Uniform phases in [0, 2π) and amplitudes in [lo, hi).
inline Eigen::VectorXd RandomPhases(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> u(0.0, kTwoPi);
  Eigen::VectorXd theta(n);
  for (int i = 0; i < n; ++i) theta[i] = u(rng);
  return theta;
}
inline Eigen::VectorXd RandomAmplitudes(std::mt19937& rng, int n, double lo, double hi) {
  std::uniform_real_distribution<double> u(lo, hi);
  Eigen::VectorXd r(n);
  for (int i = 0; i < n; ++i) r[i] = u(rng);
  return r;
}

// Two phase oscillators, w_12 = w_21 = w, φ_12 = φ = −φ_21, both amplitudes starting at r0 and
// relaxing to R at rate a: ψ = θ_2 − θ_1 obeys dψ/dt = −2w·r(t)·sin(ψ − φ), so
//   tan((ψ − φ)/2) = tan((ψ0 − φ)/2)·exp(−2w·∫₀ᵗ r),  ∫₀ᵗ r = R·t + (r0 − R)(1 − e^{−at})/a.
// (r constant: the e^{−2wrt} form of docs/control.md.)
inline double ClosedFormPhaseDifference(double psi0_rad, double phi_rad, double w_per_s, double r0,
                                        double big_r, double a_per_s, double t_s) {
  const double integral_r =
      a_per_s > 0.0 ? big_r * t_s + (r0 - big_r) * (1.0 - std::exp(-a_per_s * t_s)) / a_per_s
                    : r0 * t_s;
  const double half = WrapPi(psi0_rad - phi_rad) / 2.0;
  return phi_rad + 2.0 * std::atan(std::tan(half) * std::exp(-2.0 * w_per_s * integral_r));
}

inline PhaseNetworkParams TwoOscillators(double phi_rad, double w_per_s, double big_r,
                                         double a_per_s, Stepper stepper) {
  PhaseNetworkParams p;
  p.frequency_hz = 1.3;
  p.coupling_per_s = AllToAllCoupling(2, w_per_s);
  p.phase_bias_rad = PhaseBiasFromOffsets({0.0, -phi_rad / kTwoPi});  // φ_12 = φ
  p.target_amplitude = Eigen::VectorXd::Constant(2, big_r);
  p.amplitude_rate_per_s = a_per_s;
  p.stepper.type = stepper;
  return p;
}

}  // namespace climbsim::cpg::testing

#endif  // CLIMBSIM_TESTS_CPG_TEST_UTIL_H_
