// Load sharing among attached pads in the null space of the grasp map, and the posture (the
// laws are in load_sharing.h).
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "keys/keys.h"
#include "reflex/check.h"
#include "reflex/load_sharing.h"

namespace climbsim::reflex {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

Eigen::Matrix3d Skew(const Eigen::Vector3d& r) {
  Eigen::Matrix3d m;
  m << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
  return m;
}

}  // namespace

// The ranges as declared (Serialize); nothing here depends on dt_s but that it is a period.
void Validate(const LoadSharingParams& p, double dt_s, std::string_view name) {
  internal::CheckPeriod(dt_s);
  keys::Validate(p, name);
}

LoadSharing::LoadSharing(const LoadSharingParams& params, double dt_s)
    : params_(params), dt_s_(dt_s) {
  Validate(params_, dt_s_);
  Reset();
}

void LoadSharing::Reset() {
  for (Eigen::Vector3d& l : lambda_) l.setZero();
  soft_max_ = 0.0;
}

namespace {

using Forces = std::array<Eigen::Vector3d, kMaxSharingLegs>;
using Mask = std::array<bool, kMaxSharingLegs>;

// Which of legs[0, count) share (attached, every input finite); returns how many, their
// positions summed into *centre.
int ActivePads(const SharingLeg* legs, int count, Mask* on, Eigen::Vector3d* centre) {
  int n = 0;
  for (int i = 0; i < count; ++i) {
    const SharingLeg& l = legs[i];
    (*on)[i] = l.active && l.position_m.allFinite() && l.gradient_per_n.allFinite() &&
               std::isfinite(l.utilisation) && std::isfinite(l.bias);
    if ((*on)[i]) {
      ++n;
      *centre += l.position_m;
    }
  }
  return n;
}

// P, the projector onto ker G of the pads that share (n >= 2 of them, about their centre).
class GraspProjector {
 public:
  GraspProjector(const SharingLeg* legs, const Mask& on, int count, int n,
                 const Eigen::Vector3d& centre)
      : on_(on), count_(count) {
    // G·Gᵀ of the attached pads, the levers scaled by their RMS length (ker G is unchanged,
    // and the pseudo-inverse's rank decision sees forces and moments alike).
    double spread2 = 0.0;
    for (int i = 0; i < count; ++i) {
      if (on[i]) spread2 += (legs[i].position_m - centre).squaredNorm();
    }
    const double scale = std::sqrt(std::max(spread2 / n, 1e-12));
    Matrix6d ggt = Matrix6d::Zero();
    for (int i = 0; i < count; ++i) {
      if (!on[i]) continue;
      lever_[i] = (legs[i].position_m - centre) / scale;
      const Eigen::Matrix3d r = Skew(lever_[i]);
      ggt.topLeftCorner<3, 3>() += Eigen::Matrix3d::Identity();
      ggt.topRightCorner<3, 3>() += r.transpose();
      ggt.bottomLeftCorner<3, 3>() += r;
      ggt.bottomRightCorner<3, 3>() += r * r.transpose();
    }
    // Two pads leave the moment about the line through them unconstrained (rank 5). G·v lies
    // in the range of G·Gᵀ, so a ridge of 10⁻¹² of the trace leaves the solution's null part
    // at zero and changes the rest by that relative amount: the pseudo-inverse, at a
    // Cholesky's cost.
    const double ridge = 1e-12 * ggt.trace();
    ggt.diagonal().array() += ridge;
    chol_.compute(ggt);
  }

  // v ← P·v = v − Gᵀ·(G·Gᵀ)⁺·G·v, per pad: v_i − (y_f − r_i × y_m).
  void Project(Forces* v) const {
    Vector6d b = Vector6d::Zero();
    for (int i = 0; i < count_; ++i) {
      if (!on_[i]) continue;
      b.head<3>() += (*v)[i];
      b.tail<3>() += lever_[i].cross((*v)[i]);
    }
    const Vector6d y = chol_.solve(b);
    for (int i = 0; i < count_; ++i) {
      if (on_[i]) (*v)[i] -= y.head<3>() - lever_[i].cross(y.tail<3>());
    }
  }

 private:
  const Mask& on_;
  int count_;
  Forces lever_;
  Eigen::LLT<Matrix6d> chol_;
};

// Utilisation mode: λ descends the soft maximum S of the utilisations along the internal part
// of its gradient while S is above the threshold, each pad's step within the rate limit.
// Returns S.
double DescendSoftMax(const SharingLeg* legs, const Mask& on, int count,
                      const GraspProjector& projector, const LoadSharingParams& params,
                      double dt_s, Forces* lambda) {
  double u_max = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < count; ++i) {
    if (on[i]) u_max = std::max(u_max, legs[i].utilisation + legs[i].bias);
  }
  const double beta = params.softmax_beta;
  double sum = 0.0;
  std::array<double, kMaxSharingLegs> w{};
  for (int i = 0; i < count; ++i) {
    if (!on[i]) continue;
    w[i] = std::exp(beta * (legs[i].utilisation + legs[i].bias - u_max));
    sum += w[i];
  }
  const double soft_max = u_max + std::log(sum) / beta;
  const double excess = soft_max - params.threshold;
  if (excess <= 0.0) return soft_max;
  Forces d;
  for (int i = 0; i < count; ++i) {
    d[i] = on[i] ? Eigen::Vector3d(w[i] / sum * legs[i].gradient_per_n) : Eigen::Vector3d::Zero();
  }
  projector.Project(&d);
  double d2 = 0.0;
  for (int i = 0; i < count; ++i) d2 += d[i].squaredNorm();
  if (d2 > 0.0 && std::isfinite(d2)) {
    // dS = gᵀ·Δλ = −dt·K·excess (gᵀ·P·g = |P·g|²), each pad's step within the rate limit.
    const double step = dt_s * params.gain_per_s * excess / d2;
    double largest = 0.0;
    for (int i = 0; i < count; ++i) largest = std::max(largest, step * d[i].norm());
    const double limit = dt_s * params.max_rate_n_per_s;
    const double k = largest > limit ? step * limit / largest : step;
    for (int i = 0; i < count; ++i) (*lambda)[i] -= k * d[i];
  }
  return soft_max;
}

}  // namespace

const std::array<Eigen::Vector3d, kMaxSharingLegs>& LoadSharing::Update(const SharingLeg* legs,
                                                                       int count) {
  count = std::clamp(count, 0, kMaxSharingLegs);
  Mask on{};
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  const int n = ActivePads(legs, count, &on, &centre);
  for (int i = 0; i < kMaxSharingLegs; ++i) {
    if (i >= count || !on[i]) lambda_[i].setZero();
  }
  soft_max_ = 0.0;
  if (n < 2 || !enabled()) {
    for (Eigen::Vector3d& l : lambda_) l.setZero();
    return lambda_;
  }
  centre /= n;
  const GraspProjector projector(legs, on, count, n, centre);

  // Leak, and keep the request internal on the pads attached now (force tracking: λ as set).
  const double keep = std::max(0.0, 1.0 - dt_s_ / params_.leak_s);
  for (int i = 0; i < count; ++i) lambda_[i] *= keep;
  if (params_.mode == SharingMode::kForceTracking) {
    // λ follows the internal part of the pads' force errors at rate K.
    Forces e;
    for (int i = 0; i < count; ++i) e[i] = on[i] ? legs[i].force_error_n : Eigen::Vector3d::Zero();
    projector.Project(&e);
    const double step = params_.gain_per_s * dt_s_;
    for (int i = 0; i < count; ++i) lambda_[i] += step * e[i];
    CapLambda(count);
    return lambda_;
  }
  projector.Project(&lambda_);
  soft_max_ = DescendSoftMax(legs, on, count, projector, params_, dt_s_, &lambda_);
  CapLambda(count);
  return lambda_;
}

void LoadSharing::CapLambda(int count) {
  // The cap, as a whole: a uniform scale keeps λ internal.
  double largest = 0.0;
  for (int i = 0; i < count; ++i) largest = std::max(largest, lambda_[i].norm());
  if (largest > params_.max_force_n) {
    for (int i = 0; i < count; ++i) lambda_[i] *= params_.max_force_n / largest;
  }
}

int GripShearTargets(const GripShare* pads, int count, bool common_direction, double* target_n) {
  // The scalar sum in the order the wall gait was measured with (outputs bit-identical).
  double total = 0.0, keep_sum = 0.0;
  Eigen::Vector3d surplus = Eigen::Vector3d::Zero();
  int sharing = 0;
  for (int i = 0; i < count; ++i) {
    const GripShare& p = pads[i];
    if (!p.active) continue;
    total += p.shear_n;
    if (p.shares) {
      keep_sum += p.keep_n;
      ++sharing;
    } else {
      total -= p.keep_n;
    }
    if (!common_direction) surplus += (p.shear_n - p.keep_n) * p.grip;
  }
  if (sharing == 0) return 0;
  for (int i = 0; i < count; ++i) {
    const GripShare& p = pads[i];
    if (!p.active || !p.shares) continue;
    const double rest = common_direction ? total - keep_sum : surplus.dot(p.grip);
    target_n[i] = p.keep_n + rest / sharing;
  }
  return sharing;
}

// The ranges as declared (Serialize), then the pull's delay's fit to dt_s.
void Validate(const PostureParams& params, double dt_s, std::string_view name) {
  internal::CheckPeriod(dt_s);
  keys::Validate(params, name);
  DelayToSamples(params.pull.delay_s, dt_s, keys::KeyPath(name, "delay_s"));
}

namespace {
// The parameters, validated (throws), for the constructor's initialiser list.
const PostureParams& Validated(const PostureParams& params, double dt_s) {
  Validate(params, dt_s);
  return params;
}
}  // namespace

PostureReflex::PostureReflex(const PostureParams& params, double dt_s)
    : params_(Validated(params, dt_s)),
      law_(params.pull, dt_s),
      keep_(std::exp(-dt_s / params.time_constant_s)) {}

// c* = min(c_max, K_P·[P̃(t−Δ) − P0]₊); c ← c* + (c − c*)·e^(−dt/τ), the exact step of the
// first-order lag for a c* held over the period.
double PostureReflex::Update(double pull_over_weight) {
  const double target = std::min(params_.max_crouch_m, law_.Update(pull_over_weight));
  if (!params_.enabled) return crouch_m_ = 0.0;
  crouch_m_ = target + (crouch_m_ - target) * keep_;
  return crouch_m_;
}

void PostureReflex::Reset() {
  law_.Reset();
  crouch_m_ = 0.0;
}

}  // namespace climbsim::reflex
