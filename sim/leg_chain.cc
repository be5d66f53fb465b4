#include "sim/leg_chain.h"

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

}  // namespace

LegChain::LegChain(const mjModel* m, const RobotInfo& robot, int leg) {
  const LegInfo& info = robot.legs[leg];
  // Bodies from the base's child down to the pad body.
  std::vector<int> bodies;
  for (int b = info.pad_body; b > 0 && b != robot.base_body; b = m->body_parentid[b]) {
    bodies.push_back(b);
  }
  std::reverse(bodies.begin(), bodies.end());
  if (bodies.empty() || m->body_parentid[bodies.front()] != robot.base_body) {
    throw std::invalid_argument("leg " + info.name + ": the pad body is not below the base");
  }
  int found = 0;
  for (int b : bodies) {
    Link l;
    l.pos = Eigen::Vector3d(m->body_pos[3 * b], m->body_pos[3 * b + 1], m->body_pos[3 * b + 2]);
    l.rot = QuatMat(m->body_quat + 4 * b);
    l.first_joint = static_cast<int>(joints_.size());
    for (int j = m->body_jntadr[b]; j >= 0 && j < m->body_jntadr[b] + m->body_jntnum[b]; ++j) {
      Joint jt;
      for (int k = 0; k < 3; ++k) {
        if (j == info.joint[k]) jt.role = k;
      }
      if (j == info.tilt_joint) jt.role = 3;
      if (jt.role >= 0 && m->jnt_type[j] != mjJNT_HINGE) {
        throw std::invalid_argument("leg " + info.name + ": its joints must be hinges");
      }
      if (m->jnt_type[j] != mjJNT_HINGE) continue;  // none on the bundled legs
      jt.axis = Eigen::Vector3d(m->jnt_axis[3 * j], m->jnt_axis[3 * j + 1], m->jnt_axis[3 * j + 2]);
      jt.anchor = Eigen::Vector3d(m->jnt_pos[3 * j], m->jnt_pos[3 * j + 1], m->jnt_pos[3 * j + 2]);
      if (jt.role >= 0 && jt.role < 3) {
        ++found;
        lo_[jt.role] = m->jnt_limited[j] ? m->jnt_range[2 * j] : -M_PI;
        hi_[jt.role] = m->jnt_limited[j] ? m->jnt_range[2 * j + 1] : M_PI;
      }
      if (jt.role == 3) {
        if (b != info.pad_body) {
          throw std::invalid_argument("leg " + info.name + ": the ankle tilt must turn the pad body");
        }
        tilt_index_ = static_cast<int>(joints_.size());
        tilt_axis_ = jt.axis;
        tilt_lo_ = m->jnt_limited[j] ? m->jnt_range[2 * j] : -M_PI;
        tilt_hi_ = m->jnt_limited[j] ? m->jnt_range[2 * j + 1] : M_PI;
      }
      joints_.push_back(jt);
      ++l.joints;
    }
    links_.push_back(l);
  }
  if (found != 3) {
    throw std::invalid_argument("leg " + info.name + ": hip_yaw, hip_pitch and knee must lie on "
                                "the chain from the base to the pad");
  }
  const int s = info.ankle_site;
  site_pos_ = Eigen::Vector3d(m->site_pos[3 * s], m->site_pos[3 * s + 1], m->site_pos[3 * s + 2]);
  if (m->site_bodyid[s] != info.pad_body) {
    throw std::invalid_argument("leg " + info.name + ": its ankle site must be in the pad body");
  }
  const adhesion::PadGeometry pad = adhesion::ReadPadGeometry(m, info.pad_body);
  face_normal_ = pad.face_rot_body.col(2);
  post_m_ = std::abs((pad.face_pos_body - site_pos_).dot(face_normal_));
  neutral_ankle_ = Ankle({0, 0, 0}, 0.0);
  // The joints' anchors in the base frame, joints at 0: the hip is the yaw joint's. The reach:
  // from it through the pitch and knee anchors to the ankle, each piece rigid between its
  // joints (the tilt and the passive joints at 0, as in Solve), so no q puts the ankle further
  // from the hip than their sum (the triangle inequality).
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
  reach_m_ = (anchor_w[1] - anchor_w[0]).norm() + (anchor_w[2] - anchor_w[1]).norm() +
             (neutral_ankle_ - anchor_w[2]).norm();
  hip_ = anchor_w[0];
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
    r = r * l.rot;
    for (int j = l.first_joint; j < l.first_joint + l.joints; ++j) {
      const Joint& jt = joints_[j];
      const double angle = jt.role >= 0 && jt.role < 3 ? q[jt.role] : jt.role == 3 ? tilt : 0.0;
      const Eigen::Vector3d xanchor = r * jt.anchor + p;
      if (jt.role >= 0 && jt.role < 3) {
        axis_w[jt.role] = r * jt.axis;
        anchor_w[jt.role] = xanchor;
      }
      if (angle != 0.0) {
        r = r * Eigen::AngleAxisd(angle, jt.axis).toRotationMatrix();
        p = xanchor - r * jt.anchor;
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
  // Every way out of the loop leaves *q where the last forward pass was made.
  for (int it = 0; it <= iterations; ++it) {
    Eigen::Matrix3d jac;
    const Eigen::Vector3d e = target - Ankle(*q, 0.0, pad_rot, &jac);
    err = e.norm();
    if (err < kSolvedM || it == iterations) break;
    // Damped least squares: finite near singular poses and at the joint limits.
    const Eigen::Vector3d dq =
        jac.transpose() * (jac * jac.transpose() + 1e-7 * Eigen::Matrix3d::Identity()).ldlt().solve(e);
    const Q before = *q;
    for (int k = 0; k < 3; ++k) (*q)[k] = std::clamp((*q)[k] + dq[k], lo_[k], hi_[k]);
    if (*q == before) break;
  }
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
    const Eigen::Vector3d turned = Eigen::AngleAxisd(tilt, a) * face_normal_;
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
