// Phase oscillators with amplitude (Ijspeert et al. 2007); cpg/cpg.h has the conventions.
#ifndef CLIMBSIM_CPG_PHASE_NETWORK_H_
#define CLIMBSIM_CPG_PHASE_NETWORK_H_

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "cpg/gait.h"
#include "cpg/internal/checks.h"
#include "cpg/internal/odeint_driver.h"
#include "cpg/oscillator_network.h"

namespace climbsim::cpg {

// ---------------------------------------------------------------------------------------------
// Phase oscillators (Ijspeert et al. 2007)
// ---------------------------------------------------------------------------------------------

// n oscillators, n = target_amplitude.size() ≥ 1.
//   frequency_hz          f > 0, common intrinsic frequency, Hz.               default 1
//   coupling_per_s        w_ij finite, n×n, zero diagonal, 1/s.                no default
//                         (w > 0 attracts to the bias; AllToAllCoupling builds one.)
//   phase_bias_rad        φ_ij, n×n, rad (PhaseBiasFromOffsets).               no default
//                         Its diagonal does not enter (w_ii = 0).
//   target_amplitude      R_i ≥ 0, dimensionless (1 = nominal stride).         no default
//   amplitude_rate_per_s  a ≥ 0, 1/s: r reaches R with time constant 1/a.      default 5
//   stepper               see StepperParams.
// Two oscillators with w_12 = w_21 = w and φ_21 = −φ_12 = −φ, at equal amplitude r, have
// ψ = θ_2 − θ_1 obeying dψ/dt = −2wr·sin(ψ − φ): tan((ψ−φ)/2) = tan((ψ0−φ)/2)·e^{−2wrt}.
// Throws std::invalid_argument (constructor) for a wrong size, a non-finite entry, f ≤ 0,
// R < 0, a < 0, a non-zero w_ii, or bad StepperParams; the message names the field.
struct PhaseNetworkParams {
  double frequency_hz = 1.0;
  Eigen::MatrixXd coupling_per_s;
  Eigen::MatrixXd phase_bias_rad;
  Eigen::VectorXd target_amplitude;
  double amplitude_rate_per_s = 5.0;  // the scenario key cpg.amplitude_rate_per_s
  StepperParams stepper;
};

// Equal coupling between all legs, the gait's bias, and amplitude R for every leg.
PhaseNetworkParams PhaseNetworkParamsForGait(const Gait& gait, double frequency_hz,
                                             double coupling_per_s, double amplitude = 1.0);

class PhaseNetwork final : public OscillatorNetwork {
 public:
  // Starts at t = 0 in the locked pattern, θ_i = φ_0i wrapped (leg 0 at θ = 0), with every
  // amplitude r_i = 0: the legs ease out of the neutral pose with time constant 1/a. Throws as
  // PhaseNetworkParams says.
  explicit PhaseNetwork(const PhaseNetworkParams& params);

  // Puts the network at θ (any real, wrapped into [0, 2π)) and r ≥ 0, t = 0, counters and
  // status cleared. Throws std::invalid_argument for a wrong size or a bad value.
  void Reset(const Eigen::VectorXd& theta_rad, const Eigen::VectorXd& amplitude);

  int size() const override { return n_; }
  using OscillatorNetwork::Step;
  void Step(double dt_s, std::span<const double> feedback_rad_per_s,
            std::span<const uint8_t> held) override;
  std::span<const double> phase_rad() const override;
  std::span<const double> phase_unwrapped_rad() const override { return unwrapped_rad_; }
  std::span<const double> amplitude() const override;
  double time_s() const override { return time_s_; }
  std::optional<double> phase_duty_factor() const override { return std::nullopt; }
  StepStatus status() const override { return status_; }
  IntegrationStats stats() const override;
  void Rephase(std::span<const double> theta_rad) override;

  const PhaseNetworkParams& params() const { return params_; }

 private:
  // dx/dt for x = [θ_0..θ_{n−1}, r_0..r_{n−1}], with the feedback held in feedback_.
  void Derivative(const double* x, double* dxdt);

  PhaseNetworkParams params_;
  int n_;
  // Params unpacked into flat row-major arrays, so that the right-hand side reads no Eigen
  // object; sin and cos of the biases are taken once, here, not in every evaluation.
  double omega_rad_per_s_;
  std::vector<double> weight_per_s_;
  std::vector<double> cos_bias_;
  std::vector<double> sin_bias_;
  // Scratch and state: all sized in the constructor. sin and cos of θ_j with the bits of the θ_j
  // they were taken of: a phase that has not moved (a held leg, in every stage of a step)
  // reuses them (a pure function of those bits: no reset ever stales them).
  std::vector<double> sin_theta_;
  std::vector<double> cos_theta_;
  std::vector<std::uint64_t> trig_theta_bits_;
  internal::StepInputs inputs_;
  std::vector<double> theta_before_rad_;
  std::vector<double> unwrapped_rad_;
  internal::OdeintDriver driver_;
  double time_s_ = 0.0;
  std::int64_t steps_ = 0;
  std::int64_t rhs_evaluations_ = 0;
  StepStatus status_ = StepStatus::kOk;
};

}  // namespace climbsim::cpg

#endif  // CLIMBSIM_CPG_PHASE_NETWORK_H_
