#include <bit>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "cpg/cpg.h"
#include "cpg/internal/checks.h"

namespace climbsim::cpg {
namespace {

using internal::kTwoPi;

// The network's size comes from target_amplitude; everything else must agree with it.
const PhaseNetworkParams& Validated(const PhaseNetworkParams& p) {
  const int n = static_cast<int>(p.target_amplitude.size());
  if (n < 1) {
    internal::Fail(
        "PhaseNetworkParams.target_amplitude must have one entry per oscillator (at least 1), "
        "got 0");
  }
  internal::CheckPositive("PhaseNetworkParams.frequency_hz", p.frequency_hz);
  const std::string why = "one row and column per oscillator, n = target_amplitude.size()";
  internal::CheckSquare("PhaseNetworkParams.coupling_per_s", p.coupling_per_s, n, why);
  internal::CheckZeroDiagonal("PhaseNetworkParams.coupling_per_s", p.coupling_per_s);
  internal::CheckSquare("PhaseNetworkParams.phase_bias_rad", p.phase_bias_rad, n, why);
  for (int i = 0; i < n; ++i) {
    internal::CheckNonNegative("PhaseNetworkParams.target_amplitude[" + std::to_string(i) + "]",
                               p.target_amplitude[i]);
  }
  internal::CheckNonNegative("PhaseNetworkParams.amplitude_rate_per_s", p.amplitude_rate_per_s);
  internal::CheckStepperParams("PhaseNetworkParams", p.stepper);
  return p;
}

}  // namespace

PhaseNetwork::PhaseNetwork(const PhaseNetworkParams& params)
    : params_(Validated(params)),
      n_(static_cast<int>(params.target_amplitude.size())),
      omega_rad_per_s_(kTwoPi * params.frequency_hz),
      weight_per_s_(n_ * n_),
      cos_bias_(n_ * n_),
      sin_bias_(n_ * n_),
      sin_theta_(n_),
      cos_theta_(n_, 1.0),  // cos(+0); sin_theta_ holds sin(+0) = +0
      trig_theta_bits_(n_, std::bit_cast<std::uint64_t>(0.0)),
      inputs_(n_),
      theta_before_rad_(n_),
      unwrapped_rad_(n_),
      driver_(params.stepper, 2 * n_) {
  for (int i = 0; i < n_; ++i) {
    for (int j = 0; j < n_; ++j) {
      weight_per_s_[i * n_ + j] = params_.coupling_per_s(i, j);
      cos_bias_[i * n_ + j] = std::cos(params_.phase_bias_rad(i, j));
      sin_bias_[i * n_ + j] = std::sin(params_.phase_bias_rad(i, j));
    }
  }
  // The locked pattern θ_j − θ_0 = φ_0j, at zero amplitude: the legs start from neutral.
  Eigen::VectorXd theta(n_);
  for (int j = 0; j < n_; ++j) theta[j] = params_.phase_bias_rad(0, j);
  Reset(theta, Eigen::VectorXd::Zero(n_));
}

void PhaseNetwork::Reset(const Eigen::VectorXd& theta_rad, const Eigen::VectorXd& amplitude) {
  if (theta_rad.size() != n_ || amplitude.size() != n_) {
    internal::Fail("PhaseNetwork::Reset: theta_rad and amplitude must have " + std::to_string(n_) +
                   " entries (one per oscillator), got " + std::to_string(theta_rad.size()) +
                   " and " + std::to_string(amplitude.size()));
  }
  for (int i = 0; i < n_; ++i) {
    internal::CheckFinite("PhaseNetwork::Reset: theta_rad[" + std::to_string(i) + "]",
                          theta_rad[i]);
    internal::CheckNonNegative("PhaseNetwork::Reset: amplitude[" + std::to_string(i) + "]",
                               amplitude[i]);
  }
  std::vector<double>& x = driver_.x();
  for (int i = 0; i < n_; ++i) {
    x[i] = internal::WrapTwoPi(theta_rad[i]);
    x[n_ + i] = amplitude[i];
    unwrapped_rad_[i] = x[i];
  }
  inputs_.Clear();
  driver_.Restart();
  time_s_ = 0.0;
  steps_ = 0;
  rhs_evaluations_ = 0;
  status_ = StepStatus::kOk;
}

void PhaseNetwork::Derivative(const double* x, double* dxdt) {
  ++rhs_evaluations_;
  const double* theta = x;
  const double* r = x + n_;
  // sin(θ_j − θ_i − φ_ij) from sin/cos of each θ and of each φ: n sincos calls, not n² trig
  // calls; none for a θ_j whose bits have not changed. glibc's sincos gives sin's and cos's
  // own bits (cpg_test PhaseNetwork.SincosIsSinAndCosBitForBit).
  for (int j = 0; j < n_; ++j) {
    const std::uint64_t bits = std::bit_cast<std::uint64_t>(theta[j]);
    if (bits == trig_theta_bits_[j]) continue;
    ::sincos(theta[j], &sin_theta_[j], &cos_theta_[j]);
    trig_theta_bits_[j] = bits;
  }
  // Local pointers: otherwise each vector's data pointer is reloaded in every coupled pair
  // (the compiler cannot rule out that the stores to dxdt change it).
  const double* s = sin_theta_.data();
  const double* c = cos_theta_.data();
  const double* weight = weight_per_s_.data();
  const double* cos_bias = cos_bias_.data();
  const double* sin_bias = sin_bias_.data();
  for (int i = 0; i < n_; ++i) {
    double coupling = 0.0;
    for (int j = 0; j < n_; ++j) {
      const int ij = i * n_ + j;
      if (weight[ij] == 0.0) continue;
      const double sin_diff = s[j] * c[i] - c[j] * s[i];
      const double cos_diff = c[j] * c[i] + s[j] * s[i];
      coupling += weight[ij] * r[j] * (sin_diff * cos_bias[ij] - cos_diff * sin_bias[ij]);
    }
    dxdt[i] = omega_rad_per_s_ + coupling + inputs_.feedback(i);
    dxdt[n_ + i] = params_.amplitude_rate_per_s * (params_.target_amplitude[i] - r[i]);
    if (inputs_.held(i)) dxdt[i] = dxdt[n_ + i] = 0.0;
  }
}

void PhaseNetwork::Step(double dt_s, std::span<const double> feedback_rad_per_s,
                        std::span<const uint8_t> held) {
  // A new feedback or hold changes the right-hand side: Dopri5's derivative is stale.
  const bool changed = inputs_.Latch("PhaseNetwork", dt_s, feedback_rad_per_s, held);
  if (dt_s == 0.0) return;
  if (changed) driver_.InvalidateDerivative();

  std::vector<double>& x = driver_.x();
  for (int i = 0; i < n_; ++i) theta_before_rad_[i] = x[i];
  double unfinished_s = 0.0;
  const bool finished = driver_.Advance(
      [this](const double* x, double* dxdt) { Derivative(x, dxdt); }, dt_s, &unfinished_s);
  ++steps_;
  time_s_ += dt_s - unfinished_s;

  // Wrap after the step, not inside it: the right-hand side is 2π-periodic in θ, so Dopri5's
  // carried-over derivative stays valid, and Dopri5's error test sees |θ| ≤ 2π, not a phase
  // that grows without bound (its relative tolerance would loosen with it).
  bool finite = true;
  for (int i = 0; i < n_; ++i) {
    unwrapped_rad_[i] += x[i] - theta_before_rad_[i];
    x[i] = internal::WrapTwoPi(x[i]);
    finite = finite && std::isfinite(x[i]) && std::isfinite(x[n_ + i]);
  }
  status_ = internal::StepStatusOf(finite, finished);
}

void PhaseNetwork::Rephase(std::span<const double> theta_rad) {
  std::vector<double>& x = driver_.x();
  for (int i = 0; i < n_; ++i) {
    x[i] = internal::WrapTwoPi(theta_rad[i]);
    unwrapped_rad_[i] = x[i];
  }
  driver_.Restart();
}

std::span<const double> PhaseNetwork::phase_rad() const {
  return std::span<const double>(driver_.x().data(), n_);
}

std::span<const double> PhaseNetwork::amplitude() const {
  return std::span<const double>(driver_.x().data() + n_, n_);
}

IntegrationStats PhaseNetwork::stats() const {
  return {steps_, driver_.accepted_steps(), driver_.rejected_steps(), rhs_evaluations_};
}

}  // namespace climbsim::cpg
