#include "transition/corner_plan.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace climbsim::sim {
namespace {

constexpr double kHalfPi = M_PI / 2;
// The pose the run starts in blends into the path over this much of σ.
constexpr double kBlend = 0.04;
// Outer corner: how far the body's ladder bulges out from the edge mid-turn (m), so that the
// body plate clears it.
constexpr double kBulge = 0.015;
// A pad is kept this far from the corner line beyond its half width (m).
constexpr double kCornerClearance = 0.004;
// A foot lands only where its joints have this much more than margin_rad left, with its pad
// facing the surface within kLandingTurn (the rest is the passive ankle's to take, and a pad
// that lands on an edge does not attach), and a step lets the body go on at least kShortestReach
// (σ units).
constexpr double kLandingMargin = 0.04;
constexpr double kLandingTurn = 0.25;
constexpr double kFlatLanding = 0.08;
constexpr double kShortestReach = 0.01;
// Lateral offsets tried for a foothold (m, along the corner).
constexpr double kSideOffsets[] = {0.0,   0.005, -0.005, 0.01,   -0.01, 0.015, -0.015,
                                   0.02,  -0.02, 0.025,  -0.025, 0.03,  -0.03};
// Look-ahead along the path for a foothold, and how far its reach is followed (σ units).
constexpr double kLookAheadStep = 0.02;
constexpr double kLookAheadMax = 0.6;
constexpr double kReachStep = 0.02;
constexpr double kReachMax = 1.2;
// A leg's solve that ends further than this from its target has no foothold there (m).
constexpr double kSolveTolM = 0.002;

}  // namespace

double SmoothStep(double u) {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * u * (10 + u * (-15 + 6 * u));  // minimum jerk
}

Eigen::Vector3d Slerp(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double u) {
  const double th = std::acos(std::clamp(a.dot(b), -1.0, 1.0));
  if (th < 1e-6) return b;
  return (std::sin((1 - u) * th) * a + std::sin(u * th) * b) / std::sin(th);
}

Eigen::Matrix3d Exp(const Eigen::Vector3d& w) {
  const double a = w.norm();
  if (a < 1e-12) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(a, w / a).toRotationMatrix();
}

Eigen::Vector3d RotationLog(const Eigen::Matrix3d& r) {
  const Eigen::AngleAxisd aa(r);
  return aa.angle() * aa.axis();
}

std::string CornerPlan::Problem(const mjModel* m, const RobotInfo& robot) {
  for (size_t i = 0; i < robot.legs.size(); ++i) {
    std::string problem = LegChain::Problem(m, robot, static_cast<int>(i));
    if (!problem.empty()) return problem;
  }
  return "";
}

CornerPlan::CornerPlan(const mjModel* m, const RobotInfo& robot, const TransitionParams& params)
    : params_(params) {
  for (size_t i = 0; i < robot.legs.size(); ++i) {
    chains_.emplace_back(m, robot, static_cast<int>(i));
    const LegChain& c = chains_.back();
    hip_front_x_ = std::max(hip_front_x_, c.hip().x());
    hip_hind_x_ = std::min(hip_hind_x_, c.hip().x());
    const int g = robot.legs[i].pad_geom;
    pad_half_m_ = std::max({pad_half_m_, m->geom_size[3 * g], m->geom_size[3 * g + 1]});
    height_m_ = std::max(height_m_, -c.neutral_ankle().z() + c.post_m());
    // Forward reach: hip yaw at its upper limit less the margin, the other joints neutral.
    const Eigen::Vector3d reach = c.Ankle({c.hi()[0] - params_.margin_rad, 0, 0}, 0.0);
    reach_x_m_ = std::max(reach_x_m_, reach.x() - c.neutral_ankle().x());
  }
  // How far ahead of the front hips the front feet stand (splayed legs).
  for (const LegChain& c : chains_) {
    if (c.hip().x() > hip_front_x_ - 1e-9) {
      front_ankle_x_ = std::max(front_ankle_x_, c.neutral_ankle().x() - c.hip().x());
    }
  }
}

void CornerPlan::SetCorner(const Eigen::Vector3d& origin, const Eigen::Vector3d& n0,
                           const Eigen::Vector3d& t0, bool inner) {
  origin_ = origin;
  n0_ = n0.normalized();
  t0_ = (t0 - t0.dot(n0_) * n0_).normalized();
  y0_ = n0_.cross(t0_);
  sign_ = inner ? 1.0 : -1.0;
  n_ = {n0_, inner ? Eigen::Vector3d(-t0_) : t0_};
  away_ = {Eigen::Vector3d(-t0_), inner ? n0_ : Eigen::Vector3d(-n0_)};
  const double post = chains_.front().post_m();
  if (inner) {
    d0_ = post + front_ankle_x_ + params_.reach_share * reach_x_m_;
    d1_ = h0_ = height_m_;
  } else {
    d0_ = h0_ = height_m_ - params_.crouch_m;
    d1_ = height_m_;
  }
  sigma_start_ = -1e9;
  blend_p_.setZero();
  blend_w_.setZero();
}

double CornerPlan::Start(const BodyPose& now) {
  const Eigen::Vector3d front = now.p + hip_front_x_ * now.r.col(0);
  const double s = (front - origin_).dot(t0_);
  // Came closer to a wall ahead than the turn starts at: the turn starts here.
  if (sign_ > 0 && s + d0_ > 0) d0_ = std::max(-s, chains_.front().post_m() + front_ankle_x_ + 0.005);
  const double sigma = std::min(sign_ > 0 ? s + d0_ : s - d0_, 0.0);
  sigma_start_ = -1e9;
  const BodyPose path = PathPose(sigma);
  blend_p_ = now.p - path.p;
  blend_w_ = RotationLog(path.r.transpose() * now.r);
  sigma_start_ = sigma;
  return sigma;
}

double CornerPlan::Rate(double sigma) const {
  return sigma > 0.0 && sigma < kHalfPi ? params_.pitch_rate_rad_per_s : params_.body_speed_mps;
}

double CornerPlan::Settled() const { return kHalfPi; }

double CornerPlan::Standoff(const BodyPose& pose) const {
  return (pose.p - origin_).dot(n_[1]);
}

BodyPose CornerPlan::PathPose(double sigma) const {
  // The front hips' point (s along t0, h along n0 from the corner) and the pitch φ.
  const double span = hip_front_x_ - hip_hind_x_;
  double s, h, phi;
  if (sign_ > 0) {
    if (sigma <= 0.0) {
      phi = 0.0, s = -d0_ + sigma, h = h0_;
    } else if (sigma < kHalfPi) {
      phi = sigma, s = -d0_, h = h0_ + span * std::sin(phi);
    } else {
      phi = kHalfPi, s = -d0_, h = h0_ + span + (sigma - kHalfPi);
    }
  } else {
    // A ladder over the edge: hind hips at h0 over the old surface, front hips d0 off the new
    // one, both bulging out by kBulge mid-turn so that the body clears the edge; then down
    // the new surface, crouched until the hind hips are over it, then back to standing height.
    if (sigma <= 0.0) {
      phi = 0.0, s = d0_ + sigma, h = h0_;
    } else if (sigma < kHalfPi) {
      phi = sigma;
      const double bulge = kBulge * std::sin(2 * phi);
      s = d0_ + bulge, h = h0_ + bulge - span * std::sin(phi);
      // The hind hips stay h0 + bulge over the old surface: h is the front hips' height.
    } else {
      phi = kHalfPi, s = d0_, h = h0_ - span - (sigma - kHalfPi);
    }
  }
  BodyPose p;
  const Eigen::Vector3d x = std::cos(phi) * t0_ + sign_ * std::sin(phi) * n0_;
  const Eigen::Vector3d z = -sign_ * std::sin(phi) * t0_ + std::cos(phi) * n0_;
  p.r.col(0) = x;
  p.r.col(1) = z.cross(x);
  p.r.col(2) = z;
  p.p = origin_ + s * t0_ + h * n0_ - hip_front_x_ * x;
  return p;
}

BodyPose CornerPlan::Pose(double sigma) const {
  BodyPose p = PathPose(sigma);
  const double w = 1.0 - SmoothStep((sigma - sigma_start_) / kBlend);
  if (w > 0.0) {
    p.p += w * blend_p_;
    p.r = p.r * Exp(w * blend_w_);
  }
  return p;
}

double CornerPlan::Margin(int i, const BodyPose& pose, const Eigen::Vector3d& ankle_w,
                          const Eigen::Vector3d& normal_w, LegChain::Q* q, double* tilt,
                          double max_left_rad, double* left_rad, double* err_m) const {
  const LegChain& c = chains_[i];
  Eigen::Matrix3d pad_rot;
  const double err = c.Solve(pose.r.transpose() * (ankle_w - pose.p), q, LegChain::kSolveIterations, &pad_rot);
  double left = 0.0;
  *tilt = c.Tilt(pad_rot, pose.r.transpose() * normal_w, &left);
  if (left_rad != nullptr) *left_rad = left;
  if (err_m != nullptr) *err_m = err;
  if (err > kSolveTolM || left > max_left_rad) return -1.0;
  return std::min({c.RangeMargin(*q), *tilt - c.tilt_lo(), c.tilt_hi() - *tilt});
}

bool CornerPlan::OutOfReach(int i, const BodyPose& pose, const Eigen::Vector3d& ankle_w) const {
  // 1 µm over the solve's tolerance: rounding in the two computations of the ankle.
  return chains_[i].Unreachable(pose.r.transpose() * (ankle_w - pose.p), kSolveTolM + 1e-6);
}

Eigen::Vector3d CornerPlan::StanceAnkle(int i, const Eigen::Vector3d& face,
                                        const Eigen::Vector3d& normal) const {
  return face + (chains_[i].post_m() - params_.press_m) * normal;
}

int CornerPlan::SurfaceOf(const Eigen::Vector3d& n) const {
  const double c = std::cos(M_PI / 4);
  return n.dot(n_[1]) > c ? 1 : n.dot(n_[0]) > c ? 0 : -1;
}

Eigen::Vector3d CornerPlan::Below(const Eigen::Vector3d& a, int k) const {
  Eigen::Vector3d below = a - (a - origin_).dot(n_[k]) * n_[k];
  const double clear = pad_half_m_ + kCornerClearance;
  const double along = (below - origin_).dot(away_[k]);
  if (along < clear) below += (clear - along) * away_[k];
  return below;
}

double CornerPlan::Follow(int i, double sigma, const Foothold& h) const {
  const Eigen::Vector3d ankle = StanceAnkle(i, h.face, h.normal);
  double reach = 0.0;
  LegChain::Q q = h.q;
  double tilt = 0.0;
  while (reach < kReachMax) {
    const BodyPose pose = Pose(sigma + reach + kReachStep);
    if (OutOfReach(i, pose, ankle) ||
        Margin(i, pose, ankle, h.normal, &q, &tilt, kStanceTurn) < params_.margin_rad) {
      break;
    }
    reach += kReachStep;
  }
  return reach;
}

double CornerPlan::Approach(int i, const BodyPose& now, const Eigen::Vector3d& f, int k,
                            const LegChain::Q& q) const {
  for (double share : {1.0, 0.6, 0.35}) {
    LegChain::Q qa = q;
    double ta = 0.0;
    const double lift = share * params_.lift_m;
    const Eigen::Vector3d above = StanceAnkle(i, f, n_[k]) + (lift + params_.press_m) * n_[k];
    if (!OutOfReach(i, now, above) && Margin(i, now, above, n_[k], &qa, &ta, kLandingTurn) >= 0.0) {
      return lift;
    }
  }
  return -1.0;
}

void CornerPlan::Landings(int i, const BodyPose& now, const Eigen::Vector3d& below, int k,
                          const LegChain::Q& warm, Candidate* flat, Candidate* tilt_one) const {
  // The leg's joints roll the pad about its own axis, which the one tilt axis cannot undo: a
  // foot placed a little wider or narrower lands flatter.
  for (int s = 0; s < static_cast<int>(std::size(kSideOffsets)); ++s) {
    const double side = kSideOffsets[s];
    const Eigen::Vector3d f = below + side * y0_;
    LegChain::Q q = warm;
    double tilt = 0.0, left = 0.0;
    // Landing: reachable pressed into the surface as far as a placed foot is. (Out of the
    // leg's reach Margin would say so after a full solve: skipped, the same answer.)
    const Eigen::Vector3d landing = StanceAnkle(i, f, n_[k]) - params_.place_depth_m * n_[k];
    if (OutOfReach(i, now, landing)) continue;
    const double m = Margin(i, now, landing, n_[k], &q, &tilt, kLandingTurn, &left);
    const double need = params_.margin_rad + kLandingMargin;
    if (m < need) continue;
    const bool is_flat = left <= kFlatLanding;
    const double score = left + 0.3 * std::abs(side);
    if (score >= tilt_one->left && !(is_flat && score < flat->left)) continue;
    // And lowered onto it from off it (the approach: lift_m, or less where the leg cannot
    // reach that far out), in the same branch of the leg's kinematics.
    const double approach = Approach(i, now, f, k, q);
    if (approach < 0.0) continue;
    const Foothold h{f, n_[k], k, m, 0.0, q, approach};
    if (score < tilt_one->left) *tilt_one = {h, score, s};
    if (is_flat && score < flat->left) *flat = {h, score, s};
  }
}

Foothold CornerPlan::Next(int i, double sigma, const BodyPose& now, const LegChain::Q& warm,
                          bool old_only) const {
  // A pad that lands flat attaches at once; one that lands on an edge may not flatten in time
  // on its soft ankle. Flat landings first (at most kFlatLanding off the face), tilted ones
  // (kLandingTurn) only when there is no flat one. One sweep serves both: a candidate's solve
  // does not depend on how far off flat it may land, only its acceptance does.
  const LegChain& c = chains_[i];
  // The best of one kind (flat or tilted) over the look-ahead.
  struct Best {
    Foothold h;
    double score = -1e9;
  };
  // Settling (σ < −1e8 by the caller, or old_only): below the leg as the body is now.
  const bool here = old_only || sigma < -1e8;
  const auto consider = [&](Candidate& cand, Best* best) {
    if (cand.h.margin < 0) return;
    if (here) {
      if (best->h.margin < 0 || cand.left < best->score) best->h = cand.h, best->score = cand.left;
      return;
    }
    // How long a foothold keeps the foot: the body goes on until the leg would be out of
    // margin.
    if (cand.reach < 0) cand.reach = Follow(i, sigma, cand.h);
    cand.h.reach = cand.reach;
    // A step must buy the body some way along.
    if (cand.reach < kShortestReach) return;
    const double score = cand.reach - 0.5 * cand.left;
    if (score > best->score) best->score = score, best->h = cand.h;
  };
  constexpr int kLookAheads = static_cast<int>(kLookAheadMax / kLookAheadStep + 1e-9) + 1;
  std::array<Candidate, 2 * kLookAheads> tilted{};  // by look-ahead and surface, kept in order
  int n_tilted = 0;
  Best flat_best;
  for (double la = here ? 0.0 : kLookAheadStep; la <= kLookAheadMax + 1e-9;
       la += kLookAheadStep) {
    const BodyPose ahead = here ? now : Pose(sigma + la);
    const Eigen::Vector3d a = ahead.p + ahead.r * c.neutral_ankle();
    for (int k = 0; k < (old_only ? 1 : 2); ++k) {
      Candidate flat, tilt_one;
      Landings(i, now, Below(a, k), k, warm, &flat, &tilt_one);
      consider(flat, &flat_best);
      // The same candidate as the flat one: followed once.
      if (tilt_one.side == flat.side) tilt_one.reach = flat.reach;
      if (tilt_one.h.margin >= 0 && n_tilted < static_cast<int>(tilted.size())) {
        tilted[n_tilted++] = tilt_one;
      }
    }
    if (here) break;
  }
  if (flat_best.h.margin >= 0) return flat_best.h;
  Best tilted_best;
  for (int t = 0; t < n_tilted; ++t) consider(tilted[t], &tilted_best);
  return tilted_best.h;
}

// A dry run's legs: where each foot stands, which wait in the air, and their last joints.
struct CornerPlan::DryLegs {
  std::vector<Foothold> feet;
  std::vector<uint8_t> idle;
  std::vector<LegChain::Q> q;
};

namespace {

void Append(std::string* log, const char* line) {
  if (log != nullptr) *log += line;
}

}  // namespace

int CornerPlan::DryLand(double sigma, DryLegs* legs, std::string* log) const {
  int landed = 0;
  char line[256];
  for (size_t i = 0; i < legs->feet.size(); ++i) {
    if (!legs->idle[i]) continue;
    const Foothold h = Next(static_cast<int>(i), sigma, Pose(sigma), legs->q[i], false);
    if (h.margin < 0) continue;
    legs->idle[i] = 0;
    legs->feet[i] = h;
    ++landed;
    std::snprintf(line, sizeof(line), "sigma %.3f: idle leg %d lands on surface %d at (%.3f %.3f %.3f)\n",
                  sigma, static_cast<int>(i), h.surface, h.face.x(), h.face.y(), h.face.z());
    Append(log, line);
  }
  return landed;
}

int CornerPlan::DryWorst(const BodyPose& pose, DryLegs* legs) const {
  double worst = 1e9;
  int worst_leg = -1;
  for (size_t i = 0; i < legs->feet.size(); ++i) {
    if (legs->idle[i]) continue;
    LegChain::Q qq = legs->q[i];
    double tilt = 0.0;
    const Foothold& foot = legs->feet[i];
    const double m = Margin(static_cast<int>(i), pose,
                            StanceAnkle(static_cast<int>(i), foot.face, foot.normal), foot.normal,
                            &qq, &tilt, kStanceTurn);
    if (m < worst) worst = m, worst_leg = static_cast<int>(i);
    legs->q[i] = qq;
  }
  return worst >= params_.margin_rad ? -1 : worst_leg;
}

double CornerPlan::DryRun(const BodyPose& start, double beyond_m, std::string* log,
                          int* steps) const {
  CornerPlan plan = *this;
  double sigma = plan.Start(start);
  const size_t n = chains_.size();
  DryLegs legs{std::vector<Foothold>(n), std::vector<uint8_t>(n, 0),
               std::vector<LegChain::Q>(n, LegChain::Q{})};
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d a = start.p + start.r * chains_[i].neutral_ankle();
    legs.feet[i].face = a - (a - origin_).dot(n_[0]) * n_[0];
    legs.feet[i].normal = n_[0];
    legs.feet[i].surface = 0;
  }
  int count = 0;
  char line[256];
  const double end = kHalfPi + beyond_m;
  double idle_check = 0.0;
  for (int guard = 0; guard < 100000 && sigma < end; ++guard) {
    // An idle leg lands as soon as it has a foothold.
    if (sigma >= idle_check) {
      idle_check = sigma + 0.02;
      count += plan.DryLand(sigma, &legs, log);
    }
    const double next = sigma + 0.005;
    const int worst_leg = plan.DryWorst(plan.Pose(next), &legs);
    if (worst_leg < 0) {
      sigma = next;
      continue;
    }
    const Foothold h = plan.Next(worst_leg, sigma, plan.Pose(sigma), legs.q[worst_leg], false);
    if (h.margin < 0) {
      int stance = 0;
      for (size_t i = 0; i < n; ++i) stance += legs.idle[i] ? 0 : 1;
      if (stance - 1 >= kMinStance) {
        legs.idle[worst_leg] = 1;
        std::snprintf(line, sizeof(line), "sigma %.3f: leg %d idles\n", sigma, worst_leg);
        Append(log, line);
        continue;
      }
      std::snprintf(line, sizeof(line), "sigma %.3f: leg %d has no foothold\n", sigma, worst_leg);
      Append(log, line);
      break;
    }
    ++count;
    std::snprintf(line, sizeof(line),
                  "sigma %.3f: leg %d to surface %d at (%.3f %.3f %.3f), margin %.3f, reach %.2f\n",
                  sigma, worst_leg, h.surface, h.face.x(), h.face.y(), h.face.z(), h.margin,
                  h.reach);
    Append(log, line);
    legs.feet[worst_leg] = h;
  }
  if (steps != nullptr) *steps = count;
  return sigma;
}

}  // namespace climbsim::sim
