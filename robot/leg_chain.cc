#include "robot/leg_chain.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "adhesion/pad_contact.h"

namespace climbsim::sim {
namespace {

Eigen::Matrix3d QuatMat(const mjtNum* q) {
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
}

// k when `axis` is exactly ±e_k, else -1.
int UnitAxis(const Eigen::Vector3d& axis) {
  for (int k = 0; k < 3; ++k) {
    if (std::abs(axis[k]) == 1.0 && axis[(k + 1) % 3] == 0.0 && axis[(k + 2) % 3] == 0.0) return k;
  }
  return -1;
}

// r ← r · R(angle about ±e_k), with R as Eigen's AngleAxis builds it: R(k,k) = (1 − c) + c,
// the other diagonal entries c, R(j,i) = s_k = −R(i,j) for (k, i, j) cyclic, s_k = ±sin, and
// zeros. Each column of the product then has at most two nonzero terms, whose sum does not
// depend on the order of addition: bit for bit the general product.
void TurnAboutUnit(int k, double sign, double angle, Eigen::Matrix3d* r) {
  const double s = std::sin(angle) * sign, c = std::cos(angle);
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  const Eigen::Vector3d ci = r->col(i), cj = r->col(j);
  r->col(i) = ci * c + cj * s;
  r->col(j) = ci * (-s) + cj * c;
  r->col(k) *= (1.0 - c) + c;
}

// R(angle about ±e_k)·v with the same R: each entry two nonzero terms, as in TurnAboutUnit.
Eigen::Vector3d RotateAboutUnit(int k, double sign, double angle, const Eigen::Vector3d& v) {
  const double s = std::sin(angle) * sign, c = std::cos(angle);
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  Eigen::Vector3d out;
  out[i] = c * v[i] + (-s) * v[j];
  out[j] = s * v[i] + c * v[j];
  out[k] = ((1.0 - c) + c) * v[k];
  return out;
}

// The bodies from the base's child down to leg `info`'s pad body (not below the base: the
// first one's parent is not the base).
std::vector<int> ChainBodies(const mjModel* m, const RobotInfo& robot, const LegInfo& info) {
  std::vector<int> bodies;
  for (int b = info.pad_body; b > 0 && b != robot.base_body; b = m->body_parentid[b]) {
    bodies.push_back(b);
  }
  std::reverse(bodies.begin(), bodies.end());
  return bodies;
}

// The role of joint j in leg `info`: 0..2 hip_yaw, hip_pitch, knee; 3 the tilt; −1 passive.
int RoleOf(const LegInfo& info, int j) {
  int role = -1;
  for (int k = 0; k < 3; ++k) {
    if (j == info.joint[k]) role = k;
  }
  if (j == info.tilt_joint) role = 3;
  return role;
}

}  // namespace

std::string LegChain::Problem(const mjModel* m, const RobotInfo& robot, int leg) {
  const LegInfo& info = robot.legs[leg];
  const std::vector<int> bodies = ChainBodies(m, robot, info);
  if (bodies.empty() || m->body_parentid[bodies.front()] != robot.base_body) {
    return "leg " + info.name + ": the pad body is not below the base";
  }
  int found = 0;
  for (int b : bodies) {
    for (int j = m->body_jntadr[b]; j >= 0 && j < m->body_jntadr[b] + m->body_jntnum[b]; ++j) {
      const int role = RoleOf(info, j);
      if (role >= 0 && m->jnt_type[j] != mjJNT_HINGE) {
        return "leg " + info.name + ": its joints must be hinges";
      }
      if (m->jnt_type[j] != mjJNT_HINGE) continue;
      if (role >= 0 && role < 3) ++found;
      if (role == 3 && b != info.pad_body) {
        return "leg " + info.name + ": the ankle tilt must turn the pad body";
      }
    }
  }
  if (found != 3) {
    return "leg " + info.name + ": hip_yaw, hip_pitch and knee must lie on the chain from the "
           "base to the pad";
  }
  if (m->site_bodyid[info.ankle_site] != info.pad_body) {
    return "leg " + info.name + ": its ankle site must be in the pad body";
  }
  // The pad's own check ("" when it holds), which adhesion::ReadPadGeometry would throw.
  return adhesion::PadGeometryProblem(m, info.pad_body);
}

LegChain::LegChain(const mjModel* m, const RobotInfo& robot, int leg) {
  if (const std::string problem = Problem(m, robot, leg); !problem.empty()) {
    throw std::invalid_argument(problem);
  }
  const LegInfo& info = robot.legs[leg];
  for (int b : ChainBodies(m, robot, info)) {
    Link l;
    l.pos = Eigen::Vector3d(m->body_pos[3 * b], m->body_pos[3 * b + 1], m->body_pos[3 * b + 2]);
    l.rot = QuatMat(m->body_quat + 4 * b);
    l.identity = l.rot == Eigen::Matrix3d::Identity();
    l.first_joint = static_cast<int>(joints_.size());
    for (int j = m->body_jntadr[b]; j >= 0 && j < m->body_jntadr[b] + m->body_jntnum[b]; ++j) {
      if (AddJoint(m, info, j)) ++l.joints;
    }
    links_.push_back(l);
  }
  const int s = info.ankle_site;
  site_pos_ = Eigen::Vector3d(m->site_pos[3 * s], m->site_pos[3 * s + 1], m->site_pos[3 * s + 2]);
  const adhesion::PadGeometry pad = adhesion::ReadPadGeometry(m, info.pad_body);
  face_normal_ = pad.face_rot_body.col(2);
  post_m_ = std::abs((pad.face_pos_body - site_pos_).dot(face_normal_));
  neutral_ankle_ = Ankle({0, 0, 0}, 0.0);
  // The reach: from the hip (the yaw joint's anchor) through the pitch and knee anchors to the
  // ankle, each piece rigid between its joints (the tilt and the passive joints at 0, as in
  // Solve), so no q puts the ankle further from the hip than their sum (the triangle
  // inequality).
  const std::array<Eigen::Vector3d, 3> anchor_w = JointAnchors();
  reach_m_ = (anchor_w[1] - anchor_w[0]).norm() + (anchor_w[2] - anchor_w[1]).norm() +
             (neutral_ankle_ - anchor_w[2]).norm();
  hip_ = anchor_w[0];
  // A turn of joint k by δ moves the ankle at most its distance from the joint's anchor times
  // δ: these bound those distances (rigid pieces, as the reach).
  BuildReachMap({reach_m_, (anchor_w[2] - anchor_w[1]).norm() + (neutral_ankle_ - anchor_w[2]).norm(),
                 (neutral_ankle_ - anchor_w[2]).norm()});
}

bool LegChain::AddJoint(const mjModel* m, const LegInfo& info, int j) {
  if (m->jnt_type[j] != mjJNT_HINGE) return false;  // none on the bundled legs
  Joint jt;
  jt.role = RoleOf(info, j);
  jt.axis = Eigen::Vector3d(m->jnt_axis[3 * j], m->jnt_axis[3 * j + 1], m->jnt_axis[3 * j + 2]);
  jt.anchor = Eigen::Vector3d(m->jnt_pos[3 * j], m->jnt_pos[3 * j + 1], m->jnt_pos[3 * j + 2]);
  jt.unit = UnitAxis(jt.axis);
  jt.at_origin = jt.anchor.isZero(0.0);
  if (jt.role >= 0 && jt.role < 3) {
    lo_[jt.role] = m->jnt_limited[j] ? m->jnt_range[2 * j] : -M_PI;
    hi_[jt.role] = m->jnt_limited[j] ? m->jnt_range[2 * j + 1] : M_PI;
  }
  if (jt.role == 3) {
    tilt_index_ = static_cast<int>(joints_.size());
    tilt_axis_ = jt.axis;
    tilt_lo_ = m->jnt_limited[j] ? m->jnt_range[2 * j] : -M_PI;
    tilt_hi_ = m->jnt_limited[j] ? m->jnt_range[2 * j + 1] : M_PI;
  }
  joints_.push_back(jt);
  return true;
}

std::array<Eigen::Vector3d, 3> LegChain::JointAnchors() const {
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  std::array<Eigen::Vector3d, 3> anchor_w;
  for (const Link& l : links_) {
    p += r * l.pos;
    r = r * l.rot;
    for (int j = l.first_joint; j < l.first_joint + l.joints; ++j) {
      if (joints_[j].role >= 0 && joints_[j].role < 3) anchor_w[joints_[j].role] = r * joints_[j].anchor + p;
    }
  }
  return anchor_w;
}

void LegChain::BuildReachMap(const std::array<double, 3>& lever_m) {
  double cover_m = 0.0;
  Eigen::Vector3d lo, hi;
  const std::vector<Eigen::Vector3d> samples = SampleAnkles(lever_m, &cover_m, &lo, &hi);
  // A target within r = cover + tolerance of a sample lies in a voxel whose box is within r of
  // the sample: each sample marks exactly those voxels (their box's distance to it, not their
  // centres', so no voxel diagonal is added to the growth).
  const double r = cover_m + kMapTolM + 1e-9;  // 1 nm: rounding of the boxes' corners
  map_lo_ = lo - Eigen::Vector3d::Constant(r + kVoxelM);
  for (int k = 0; k < 3; ++k) {
    map_n_[k] = static_cast<int>(std::ceil((hi[k] - lo[k] + 2.0 * (r + kVoxelM)) / kVoxelM)) + 1;
  }
  const size_t cells = static_cast<size_t>(map_n_[0]) * map_n_[1] * map_n_[2];
  map_.assign((cells + 63) / 64, 0);
  for (const Eigen::Vector3d& x : samples) MarkBall(x, r);
}

std::vector<Eigen::Vector3d> LegChain::SampleAnkles(const std::array<double, 3>& lever_m,
                                                    double* cover_m, Eigen::Vector3d* lo,
                                                    Eigen::Vector3d* hi) const {
  // The joints' grid: every q in the ranges is within half a spacing of a grid point in each
  // joint, so its ankle is within cover_m of that point's (one joint at a time, each moving
  // the ankle at most lever × its share).
  constexpr double kCoverM = 0.008;
  std::array<int, 3> n{};
  std::array<double, 3> step{};
  for (int k = 0; k < 3; ++k) {
    const double range = hi_[k] - lo_[k];
    const double want = 2.0 * kCoverM / (3.0 * std::max(lever_m[k], 1e-6));
    n[k] = std::max(2, static_cast<int>(std::ceil(range / want)) + 1);
    step[k] = range / (n[k] - 1);
    *cover_m += 0.5 * lever_m[k] * step[k];
  }
  std::vector<Eigen::Vector3d> samples;
  samples.reserve(static_cast<size_t>(n[0]) * n[1] * n[2]);
  *lo = Eigen::Vector3d::Constant(1e9), *hi = Eigen::Vector3d::Constant(-1e9);
  for (int a = 0; a < n[0]; ++a) {
    for (int b = 0; b < n[1]; ++b) {
      for (int c = 0; c < n[2]; ++c) {
        const Eigen::Vector3d x =
            Ankle({lo_[0] + a * step[0], lo_[1] + b * step[1], lo_[2] + c * step[2]}, 0.0);
        samples.push_back(x);
        *lo = lo->cwiseMin(x), *hi = hi->cwiseMax(x);
      }
    }
  }
  return samples;
}

void LegChain::MarkBall(const Eigen::Vector3d& x, double r) {
  const std::array<int, 3> v0 = Voxel(x - Eigen::Vector3d::Constant(r));
  const std::array<int, 3> v1 = Voxel(x + Eigen::Vector3d::Constant(r));
  // Distance from x to the slab of voxels `v` along axis k.
  const auto gap = [&](int k, int v) {
    const double box_lo = map_lo_[k] + v * kVoxelM;
    return std::max({0.0, box_lo - x[k], x[k] - (box_lo + kVoxelM)});
  };
  for (int a = std::max(0, v0[0]); a <= std::min(map_n_[0] - 1, v1[0]); ++a) {
    const double da = gap(0, a);
    for (int b = std::max(0, v0[1]); b <= std::min(map_n_[1] - 1, v1[1]); ++b) {
      const double db = gap(1, b), left = r * r - da * da - db * db;
      if (left < 0.0) continue;
      // Along z (the map's fastest index) the voxels within r form one run.
      const double rz = std::sqrt(left);
      const int c0 = std::max(0, static_cast<int>(std::floor((x[2] - rz - map_lo_[2]) / kVoxelM)));
      const int c1 = std::min(map_n_[2] - 1,
                              static_cast<int>(std::floor((x[2] + rz - map_lo_[2]) / kVoxelM)));
      if (c1 >= c0) SetRun(MapIndex({a, b, c0}), MapIndex({a, b, c1}));
    }
  }
}

void LegChain::SetRun(size_t first, size_t last) {
  while (first <= last) {
    const size_t bit = first % 64, n = std::min<size_t>(64 - bit, last - first + 1);
    map_[first / 64] |= (n == 64 ? ~uint64_t{0} : ((uint64_t{1} << n) - 1)) << bit;
    first += n;
  }
}

std::array<int, 3> LegChain::Voxel(const Eigen::Vector3d& x) const {
  std::array<int, 3> v{};
  for (int k = 0; k < 3; ++k) v[k] = static_cast<int>(std::floor((x[k] - map_lo_[k]) / kVoxelM));
  return v;
}

size_t LegChain::MapIndex(const std::array<int, 3>& v) const {
  return (static_cast<size_t>(v[0]) * map_n_[1] + v[1]) * map_n_[2] + v[2];
}

bool LegChain::MapSet(const std::array<int, 3>& v) const {
  for (int k = 0; k < 3; ++k) {
    if (v[k] < 0 || v[k] >= map_n_[k]) return false;
  }
  const size_t i = MapIndex(v);
  return (map_[i / 64] >> (i % 64)) & 1;
}

bool LegChain::Unreachable(const Eigen::Vector3d& target, double tolerance_m) const {
  if (OutOfReach(target, tolerance_m)) return true;
  if (tolerance_m > kMapTolM || map_.empty()) return false;
  return !MapSet(Voxel(target));
}

bool LegChain::OutOfReach(const Eigen::Vector3d& target, double tolerance_m) const {
  return (target - hip_).norm() > reach_m_ + tolerance_m;
}

Eigen::Vector3d LegChain::Ankle(const Q& q, double tilt, Eigen::Matrix3d* pad_rot,
                                Eigen::Matrix3d* jacobian) const {
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_w[3], anchor_w[3];
  for (const Link& l : links_) {
    p += r * l.pos;
    if (!l.identity) r = r * l.rot;
    for (int j = l.first_joint; j < l.first_joint + l.joints; ++j) {
      const Joint& jt = joints_[j];
      const double angle = jt.role >= 0 && jt.role < 3 ? q[jt.role] : jt.role == 3 ? tilt : 0.0;
      if (angle == 0.0 && (jt.role < 0 || jt.role > 2)) continue;  // a joint at 0 moves nothing
      const Eigen::Vector3d xanchor = jt.at_origin ? p : Eigen::Vector3d(r * jt.anchor + p);
      if (jt.role >= 0 && jt.role < 3) {
        axis_w[jt.role] = jt.unit >= 0 ? Eigen::Vector3d(r.col(jt.unit) * jt.axis[jt.unit])
                                       : Eigen::Vector3d(r * jt.axis);
        anchor_w[jt.role] = xanchor;
      }
      if (angle != 0.0) {
        if (jt.unit >= 0) {
          TurnAboutUnit(jt.unit, jt.axis[jt.unit], angle, &r);
        } else {
          r = r * Eigen::AngleAxisd(angle, jt.axis).toRotationMatrix();
        }
        if (!jt.at_origin) p = xanchor - r * jt.anchor;
      }
    }
  }
  const Eigen::Vector3d ankle = p + r * site_pos_;
  if (pad_rot != nullptr) *pad_rot = r;
  if (jacobian != nullptr) {
    for (int k = 0; k < 3; ++k) jacobian->col(k) = axis_w[k].cross(ankle - anchor_w[k]);
  }
  return ankle;
}

double LegChain::Solve(const Eigen::Vector3d& target, Q* q, int iterations,
                       Eigen::Matrix3d* pad_rot) const {
  double err = 0.0;
  Pass pass, start;
  // Every way out of the loop leaves *q where the last forward pass was made.
  for (int it = 0; it <= iterations; ++it) {
    if (it == 0 && last_pass_.valid && last_pass_.q == *q) {
      pass = last_pass_;
    } else if (it == 0 && first_pass_.valid && first_pass_.q == *q) {
      pass = first_pass_;
    } else {
      pass.q = *q;
      pass.ankle = Ankle(*q, 0.0, &pass.pad_rot, &pass.jacobian);
      pass.valid = true;
    }
    if (it == 0) start = pass;
    const Eigen::Vector3d e = target - pass.ankle;
    err = e.norm();
    if (err < kSolvedM || it == iterations) break;
    // Damped least squares: finite near singular poses and at the joint limits.
    const Eigen::Matrix3d& jac = pass.jacobian;
    const Eigen::Vector3d dq =
        jac.transpose() * (jac * jac.transpose() + 1e-7 * Eigen::Matrix3d::Identity()).ldlt().solve(e);
    const Q before = *q;
    for (int k = 0; k < 3; ++k) (*q)[k] = std::clamp((*q)[k] + dq[k], lo_[k], hi_[k]);
    if (*q == before) break;
  }
  first_pass_ = start, last_pass_ = pass;
  if (pad_rot != nullptr) *pad_rot = pass.pad_rot;
  return err;
}

double LegChain::Tilt(const Q& q, const Eigen::Vector3d& normal, double* left_rad) const {
  Eigen::Matrix3d r0;
  Ankle(q, 0.0, &r0);
  return Tilt(r0, normal, left_rad);
}

double LegChain::Tilt(const Eigen::Matrix3d& r0, const Eigen::Vector3d& normal,
                      double* left_rad) const {
  const Eigen::Vector3d n = r0.transpose() * normal;  // wanted normal, pad body frame
  if (!has_tilt()) {
    if (left_rad != nullptr) *left_rad = std::acos(std::clamp(face_normal_.dot(n), -1.0, 1.0));
    return 0.0;
  }
  const Eigen::Vector3d& a = tilt_axis_;
  const Eigen::Vector3d f = face_normal_ - face_normal_.dot(a) * a;
  const Eigen::Vector3d w = n - n.dot(a) * a;
  double tilt = std::atan2(a.dot(f.cross(w)), f.dot(w));
  tilt = std::clamp(tilt, tilt_lo_, tilt_hi_);
  if (left_rad != nullptr) {
    const int k = joints_[tilt_index_].unit;  // the tilt joint's, found with the chain
    const Eigen::Vector3d turned = k >= 0 ? RotateAboutUnit(k, a[k], tilt, face_normal_)
                                          : Eigen::Vector3d(Eigen::AngleAxisd(tilt, a) * face_normal_);
    *left_rad = std::acos(std::clamp(turned.dot(n), -1.0, 1.0));
  }
  return tilt;
}

double LegChain::RangeMargin(const Q& q) const {
  double m = 1e9;
  for (int k = 0; k < 3; ++k) m = std::min({m, q[k] - lo_[k], hi_[k] - q[k]});
  return m;
}

}  // namespace climbsim::sim
