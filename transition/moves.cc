#include "transition/moves.h"

#include <algorithm>
#include <array>

namespace climbsim::sim {
namespace {

// The sag correction's largest shift and turn.
constexpr double kTrackMaxM = 0.015;
constexpr double kTrackMaxRad = 0.15;
// The share of a swing spent lifting the foot straight off the surface it leaves.
constexpr double kLiftShare = 0.3;
// A peel pulls along the other pads' load when it has at least kPeelLoad (N) along the peeling
// pad's surface, else along their normals when their sum has at least kPeelAlong there.
constexpr double kPeelLoad = 0.2;
constexpr double kPeelAlong = 0.5;

}  // namespace

void Foot::Remember(const BodyPose& pose, const Eigen::Vector3d& target, double err_m) {
  held = err_m < LegChain::kSolvedM;
  held_pose = pose, held_target = target, held_normal = normal_w, held_q = q;
  held_tilt = tilt;
}

bool Foot::Holds(const BodyPose& pose, const Eigen::Vector3d& target) const {
  return held && held_q == q && held_tilt == tilt && held_target == target &&
         held_normal == normal_w && held_pose.p == pose.p && held_pose.r == pose.r;
}

void SagCorrection::Clear() {
  p_.setZero();
  w_.setZero();
  r_ = Exp(w_);
}

BodyPose SagCorrection::Apply(const BodyPose& pose) const {
  BodyPose p = pose;
  p.p += p_;
  p.r = p.r * r_;
  return p;
}

void SagCorrection::Track(const BodyPose& cmd, const BodyPose& actual, double k) {
  p_ += k * (cmd.p - actual.p);
  w_ += k * RotationLog(actual.r.transpose() * cmd.r);
  if (p_.norm() > kTrackMaxM) p_ *= kTrackMaxM / p_.norm();
  if (w_.norm() > kTrackMaxRad) w_ *= kTrackMaxRad / w_.norm();
  r_ = Exp(w_);
}

Eigen::Vector3d SwingPath::Face(double u, const Foothold& to, const Eigen::Vector3d& w2,
                                double lift_m) const {
  const Eigen::Vector3d w0 = from_face + lift_m * from_normal;
  if (u < kLiftShare || to.surface < 0) {
    return from_face + SmoothStep(u / (to.surface < 0 ? 1.0 : kLiftShare)) *
                           ((to.surface < 0 ? to.face : w0) - from_face);
  }
  const int n = use_via ? 3 : 2;
  const std::array<Eigen::Vector3d, 3> pts{w0, use_via ? via : w2, w2};
  double len[2] = {0, 0}, total = 0;
  for (int k = 0; k + 1 < n; ++k) total += len[k] = (pts[k + 1] - pts[k]).norm();
  double along = SmoothStep((u - kLiftShare) / (1 - kLiftShare)) * total;
  Eigen::Vector3d face = pts[n - 1];
  for (int k = 0; k + 1 < n; ++k) {
    if (along <= len[k] || k + 2 == n) {
      const double a = len[k] > 0 ? std::min(1.0, along / len[k]) : 1.0;
      face = pts[k] + a * (pts[k + 1] - pts[k]);
      break;
    }
    along -= len[k];
  }
  return face;
}

Eigen::Vector3d PeelPull(const Eigen::Vector3d& heading, const Eigen::Vector3d& normal,
                         Eigen::Vector3d load, Eigen::Vector3d normals,
                         const std::string& peel_toward) {
  const Eigen::Vector3d& x = heading;
  Eigen::Vector3d back = -(x - x.dot(normal) * normal).normalized();
  load -= load.dot(normal) * normal;
  normals -= normals.dot(normal) * normal;
  const bool by_load = peel_toward == "load";
  if (by_load && load.norm() > kPeelLoad) {
    back = load.normalized();
  } else if (peel_toward != "back" && normals.norm() > kPeelAlong) {
    back = normals.normalized();
  }
  return back;
}

Eigen::Vector3d RetryPull(const Eigen::Vector3d& pull, int attempt, double hip_y,
                          const Eigen::Vector3d& lateral, const Eigen::Vector3d& normal) {
  const double side = hip_y > 0 ? -1.0 : 1.0;
  const Eigen::Vector3d& y = lateral;
  const Eigen::Vector3d in = side * (y - y.dot(normal) * normal).normalized();
  return attempt == 1 ? Eigen::Vector3d(-pull) : Eigen::Vector3d(pull.norm() * in);
}

Eigen::Vector3d Probe::Below(double pad_half_m) const {
  const double level = (from_face - p0).dot(n0);
  return from_face - (level + pad_half_m + kBelowM) * n0;
}

void Probe::Down(double u, double lift_m, const Eigen::Vector3d& below, Eigen::Vector3d* face,
                 Eigen::Vector3d* normal) const {
  const double level = (from_face - p0).dot(n0);
  const Eigen::Vector3d above = from_face + (lift_m - level) * n0;
  const double s = SmoothStep(u);
  *face = s < 0.5 ? from_face + 2 * s * (above - from_face) : above + (2 * s - 1) * (below - above);
  *normal = Slerp(from_normal, fwd, std::min(1.0, 2 * s));
}

}  // namespace climbsim::sim
