#include <cmath>
#include <stdexcept>
#include <string>

#include "cpg/cpg.h"
#include "cpg/internal/checks.h"

namespace climbsim::cpg {
namespace {

using internal::kPi;
using internal::kTwoPi;

// The network's size comes from coupling_per_s; the bias must agree with it.
const HopfNetworkParams& Validated(const HopfNetworkParams& p) {
  const int n = static_cast<int>(p.coupling_per_s.rows());
  if (n < 1) {
    internal::Fail("HopfNetworkParams.coupling_per_s must be n x n with n >= 1 oscillators, got " +
                   std::to_string(p.coupling_per_s.rows()) + "x" +
                   std::to_string(p.coupling_per_s.cols()));
  }
  internal::CheckPositive("HopfNetworkParams.stance_frequency_hz", p.stance_frequency_hz);
  internal::CheckPositive("HopfNetworkParams.swing_frequency_hz", p.swing_frequency_hz);
  internal::CheckPositive("HopfNetworkParams.mu", p.mu);
  internal::CheckPositive("HopfNetworkParams.alpha_per_s", p.alpha_per_s);
  internal::CheckPositive("HopfNetworkParams.beta_per_s", p.beta_per_s);
  internal::CheckPositive("HopfNetworkParams.b", p.b);
  const std::string why = "one row and column per oscillator, n = coupling_per_s.rows()";
  internal::CheckSquare("HopfNetworkParams.coupling_per_s", p.coupling_per_s, n, why);
  internal::CheckZeroDiagonal("HopfNetworkParams.coupling_per_s", p.coupling_per_s);
  internal::CheckSquare("HopfNetworkParams.phase_bias_rad", p.phase_bias_rad, n, why);
  if (p.coupling_form != HopfCoupling::kRotation &&
      p.coupling_form != HopfCoupling::kTimeWarpedRotation) {
    internal::Fail("HopfNetworkParams.coupling_form", "kRotation or kTimeWarpedRotation",
                   static_cast<double>(p.coupling_form));
  }
  internal::CheckStepperParams("HopfNetworkParams", p.stepper);
  return p;
}

// 1/(1 + e^{−z}) without overflow for either sign of z (b·y can be large far off the cycle).
double Logistic(double z) {
  if (z >= 0.0) return 1.0 / (1.0 + std::exp(-z));
  const double e = std::exp(z);
  return e / (1.0 + e);
}

}  // namespace

HopfNetwork::HopfNetwork(const HopfNetworkParams& params)
    : params_(Validated(params)),
      n_(static_cast<int>(params.coupling_per_s.rows())),
      omega_stance_rad_per_s_(kTwoPi * params.stance_frequency_hz),
      omega_swing_rad_per_s_(kTwoPi * params.swing_frequency_hz),
      sqrt_mu_(std::sqrt(params.mu)),
      weight_per_s_(n_ * n_),
      cos_bias_(n_ * n_),
      sin_bias_(n_ * n_),
      swing_share_(params.stance_frequency_hz /
                   (params.stance_frequency_hz + params.swing_frequency_hz)),
      warp_bias_rad_(n_ * n_),
      warp_cos_(4 * n_ * n_),
      warp_sin_(4 * n_ * n_),
      time_phase_rad_(n_),
      radius_(n_),
      scaled_cos_(2 * n_),
      scaled_sin_(2 * n_),
      inputs_(n_),
      phase_rad_(n_),
      amplitude_(n_),
      unwrapped_rad_(n_),
      driver_(params.stepper, 2 * n_) {
  for (int i = 0; i < n_; ++i) {
    for (int j = 0; j < n_; ++j) {
      weight_per_s_[i * n_ + j] = params_.coupling_per_s(i, j);
      cos_bias_[i * n_ + j] = std::cos(params_.phase_bias_rad(i, j));
      sin_bias_[i * n_ + j] = std::sin(params_.phase_bias_rad(i, j));
    }
  }
  // Time-warped rotation. W⁻¹ is linear on each half: θ = a_s + c_s·Φ (s = 0 swing, 1
  // stance). The target time phase is Φ_j − ψ_ij + 2π·m, ψ_ij = φ_ij wrapped to [0, 2π) and
  // m = 1 when Φ_j < ψ_ij, so θ* = c_s·Φ_j + β, β = a_s − c_s·ψ_ij + 2π·m·c_s: four constant
  // angles per pair, whose cos/sin are taken here once.
  const double slope[2] = {1.0 / (2.0 * swing_share_), 1.0 / (2.0 * (1.0 - swing_share_))};
  const double intercept[2] = {0.0, kPi - kTwoPi * swing_share_ * slope[1]};
  for (int ij = 0; ij < n_ * n_; ++ij) {
    const double psi = internal::WrapTwoPi(params_.phase_bias_rad(ij / n_, ij % n_));
    warp_bias_rad_[ij] = psi;
    for (int half = 0; half < 2; ++half) {
      for (int m = 0; m < 2; ++m) {
        const double beta = intercept[half] - slope[half] * psi + kTwoPi * m * slope[half];
        warp_cos_[4 * ij + 2 * half + m] = std::cos(beta);
        warp_sin_[4 * ij + 2 * half + m] = std::sin(beta);
      }
    }
  }
  // The gait's pattern relative to leg 0 at θ = 0: lags in time phase, mapped back to θ by
  // W⁻¹ (identity for D = ½), so that the warped coupling starts locked.
  Eigen::VectorXd theta(n_);
  for (int j = 0; j < n_; ++j) {
    const double lag = internal::WrapTwoPi(params_.phase_bias_rad(0, j));
    const bool warped = params_.coupling_form == HopfCoupling::kTimeWarpedRotation;
    theta[j] = !warped                       ? lag
               : lag < kTwoPi * swing_share_ ? slope[0] * lag
                                             : intercept[1] + slope[1] * lag;
  }
  Reset(theta, Eigen::VectorXd::Ones(n_));
}

void HopfNetwork::Reset(const Eigen::VectorXd& theta_rad, const Eigen::VectorXd& amplitude) {
  if (theta_rad.size() != n_ || amplitude.size() != n_) {
    internal::Fail("HopfNetwork::Reset: theta_rad and amplitude must have " + std::to_string(n_) +
                   " entries (one per oscillator), got " + std::to_string(theta_rad.size()) +
                   " and " + std::to_string(amplitude.size()));
  }
  for (int i = 0; i < n_; ++i) {
    internal::CheckFinite("HopfNetwork::Reset: theta_rad[" + std::to_string(i) + "]", theta_rad[i]);
    internal::CheckPositive("HopfNetwork::Reset: amplitude[" + std::to_string(i) + "]",
                            amplitude[i]);
  }
  std::vector<double>& z = driver_.x();
  for (int i = 0; i < n_; ++i) {
    // θ = ϑ + π: swing starts at ϑ = −π, (x, y) = (−sqrt(μ), 0).
    const double radius = amplitude[i] * sqrt_mu_;
    z[i] = radius * std::cos(theta_rad[i] - kPi);
    z[n_ + i] = radius * std::sin(theta_rad[i] - kPi);
  }
  UpdateOutputs(/*accumulate=*/false);
  for (int i = 0; i < n_; ++i) unwrapped_rad_[i] = phase_rad_[i];
  inputs_.Clear();
  driver_.Restart();
  time_s_ = 0.0;
  steps_ = 0;
  rhs_evaluations_ = 0;
  status_ = StepStatus::kOk;
}

// Phase θ (swing [0, π), stance [π, 2π)) → phase uniform in time Φ, in the b → ∞ limit on
// the limit cycle: swing takes the share 1 − D of the period, stance D.
double HopfNetwork::TimePhase(double theta_rad) const {
  return theta_rad < kPi ? 2.0 * swing_share_ * theta_rad
                         : kTwoPi * swing_share_ + 2.0 * (1.0 - swing_share_) * (theta_rad - kPi);
}

void HopfNetwork::Derivative(const double* z, double* dzdt) {
  ++rhs_evaluations_;
  const double* x = z;
  const double* y = z + n_;
  // With equal halves (D = ½) W is the identity and the warped form is the plain rotation,
  // which needs no trigonometry here.
  const bool warped =
      params_.coupling_form == HopfCoupling::kTimeWarpedRotation && swing_share_ != 0.5;
  if (warped) PrepareWarp(x, y);
  for (int i = 0; i < n_; ++i) {
    const double pull = params_.mu - (x[i] * x[i] + y[i] * y[i]);
    // ω_stance/(e^{−by} + 1) + ω_swing/(e^{by} + 1) = ω_swing + (ω_stance − ω_swing)·σ(by).
    const double omega =
        omega_swing_rad_per_s_ +
        (omega_stance_rad_per_s_ - omega_swing_rad_per_s_) * Logistic(params_.b * y[i]);
    // Feedback on the tangent (−y, x): adds exactly feedback to dϑ/dt (hopf_network.h).
    const double rate = omega + inputs_.feedback(i);
    double dx = params_.alpha_per_s * pull * x[i] - rate * y[i];
    double dy = params_.beta_per_s * pull * y[i] + rate * x[i];
    for (int j = 0; j < n_; ++j) {
      const double k = weight_per_s_[i * n_ + j];
      if (k == 0.0) continue;
      double target_x, target_y;
      CouplingTarget(i, j, warped, x, y, &target_x, &target_y);
      // Diffusive: minus z_i, so that the term vanishes at the lock.
      dx += k * (target_x - x[i]);
      dy += k * (target_y - y[i]);
    }
    dzdt[i] = inputs_.held(i) ? 0.0 : dx;
    dzdt[n_ + i] = inputs_.held(i) ? 0.0 : dy;
  }
}

// Per oscillator, once per evaluation: its time phase, radius, and cos/sin of its time phase
// scaled by each half's slope (the warped coupling's angle addition reads them).
void HopfNetwork::PrepareWarp(const double* x, const double* y) {
  const double slope[2] = {1.0 / (2.0 * swing_share_), 1.0 / (2.0 * (1.0 - swing_share_))};
  for (int j = 0; j < n_; ++j) {
    time_phase_rad_[j] = TimePhase(std::atan2(y[j], x[j]) + kPi);
    radius_[j] = std::sqrt(x[j] * x[j] + y[j] * y[j]);
    for (int half = 0; half < 2; ++half) {
      scaled_cos_[2 * j + half] = std::cos(slope[half] * time_phase_rad_[j]);
      scaled_sin_[2 * j + half] = std::sin(slope[half] * time_phase_rad_[j]);
    }
  }
}

// c_ij: where z_i would be if it kept its bias φ_ij to z_j (the file comment's Coupling).
void HopfNetwork::CouplingTarget(int i, int j, bool warped, const double* x, const double* y,
                                 double* target_x, double* target_y) const {
  if (warped) {
    // Where z_i would be if it lagged z_j by φ_ij in time: θ* = W⁻¹(W(θ_j) − φ_ij) on the
    // circle of radius r_j; θ = ϑ + π, so the point is −r_j·(cos θ*, sin θ*). cos/sin of
    // θ* = c_s·Φ_j + β by angle addition (constructor).
    const int ij = i * n_ + j;
    const int m = time_phase_rad_[j] < warp_bias_rad_[ij] ? 1 : 0;
    const double target_phase = time_phase_rad_[j] - warp_bias_rad_[ij] + kTwoPi * m;
    const int half = target_phase < kTwoPi * swing_share_ ? 0 : 1;
    const double c = scaled_cos_[2 * j + half];
    const double s = scaled_sin_[2 * j + half];
    const double cb = warp_cos_[4 * ij + 2 * half + m];
    const double sb = warp_sin_[4 * ij + 2 * half + m];
    *target_x = -radius_[j] * (c * cb - s * sb);
    *target_y = -radius_[j] * (s * cb + c * sb);
  } else {
    // R(−φ_ij)·z_j = (cos φ·x_j + sin φ·y_j, −sin φ·x_j + cos φ·y_j).
    const double c = cos_bias_[i * n_ + j];
    const double s = sin_bias_[i * n_ + j];
    *target_x = c * x[j] + s * y[j];
    *target_y = -s * x[j] + c * y[j];
  }
}

void HopfNetwork::Rephase(std::span<const double> theta_rad) {
  std::vector<double>& z = driver_.x();
  for (int i = 0; i < n_; ++i) {
    const double radius = std::hypot(z[i], z[n_ + i]);
    z[i] = radius * std::cos(theta_rad[i] - kPi);
    z[n_ + i] = radius * std::sin(theta_rad[i] - kPi);
  }
  UpdateOutputs(/*accumulate=*/false);
  for (int i = 0; i < n_; ++i) unwrapped_rad_[i] = phase_rad_[i];
  driver_.Restart();
}

void HopfNetwork::UpdateOutputs(bool accumulate) {
  const std::vector<double>& z = driver_.x();
  for (int i = 0; i < n_; ++i) {
    const double x = z[i];
    const double y = z[n_ + i];
    const double theta = internal::WrapTwoPi(std::atan2(y, x) + kPi);
    if (accumulate) unwrapped_rad_[i] += internal::WrapPi(theta - phase_rad_[i]);
    phase_rad_[i] = theta;
    amplitude_[i] = std::hypot(x, y) / sqrt_mu_;
  }
}

void HopfNetwork::Step(double dt_s, std::span<const double> feedback_rad_per_s,
                       std::span<const uint8_t> held) {
  // A new feedback or hold changes the right-hand side: Dopri5's derivative is stale.
  const bool changed = inputs_.Latch("HopfNetwork", dt_s, feedback_rad_per_s, held);
  if (dt_s == 0.0) return;
  if (changed) driver_.InvalidateDerivative();

  double unfinished_s = 0.0;
  const bool finished = driver_.Advance(
      [this](const double* x, double* dxdt) { Derivative(x, dxdt); }, dt_s, &unfinished_s);
  ++steps_;
  time_s_ += dt_s - unfinished_s;
  UpdateOutputs(/*accumulate=*/true);

  bool finite = true;
  for (double value : driver_.x()) finite = finite && std::isfinite(value);
  status_ = internal::StepStatusOf(finite, finished);
}

std::span<const double> HopfNetwork::x() const {
  return std::span<const double>(driver_.x().data(), n_);
}

std::span<const double> HopfNetwork::y() const {
  return std::span<const double>(driver_.x().data() + n_, n_);
}

double HopfNetwork::duty_factor() const {
  return omega_swing_rad_per_s_ / (omega_stance_rad_per_s_ + omega_swing_rad_per_s_);
}

double HopfNetwork::stride_frequency_hz() const {
  const double f_stance = params_.stance_frequency_hz;
  const double f_swing = params_.swing_frequency_hz;
  return 2.0 * f_stance * f_swing / (f_stance + f_swing);
}

IntegrationStats HopfNetwork::stats() const {
  return {steps_, driver_.accepted_steps(), driver_.rejected_steps(), rhs_evaluations_};
}

}  // namespace climbsim::cpg
