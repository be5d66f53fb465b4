#include "robot/leg_ik.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace climbsim::sim {
namespace {

// The bodies from the root down to `body` (world excluded), root first.
std::vector<int> ChainTo(const mjModel* m, int body) {
  std::vector<int> chain;
  for (int b = body; b > 0; b = m->body_parentid[b]) chain.push_back(b);
  return {chain.rbegin(), chain.rend()};
}

// mj_kinematics for the bodies of `chain` only, each with MuJoCo 2.2.2's own sequence of
// operations (engine_core_smooth.c: free joint from qpos, else the parent's frame times the
// body's offset, then each joint; normalise, then the rotation matrix), so the poses are
// those mj_kinematics computes, bit for bit, at a fraction of its cost (one leg, not the
// whole robot and its geoms). The world body's pose is mj_kinematics' (set once before).
void ChainKinematics(const mjModel* m, mjData* d, const std::vector<int>& chain) {
  mjtNum pos[3], quat[4], qloc[4], vec[3], vec1[3], xanchor[3], xaxis[3];
  for (int i : chain) {
    if (m->body_jntnum[i] == 1 && m->jnt_type[m->body_jntadr[i]] == mjJNT_FREE) {
      const int jid = m->body_jntadr[i];
      const int qadr = m->jnt_qposadr[jid];
      mju_normalize4(d->qpos + qadr + 3);  // mj_normalizeQuat
      mju_copy3(pos, d->qpos + qadr);
      mju_copy4(quat, d->qpos + qadr + 3);
      mju_copy3(d->xanchor + 3 * jid, pos);
      d->xaxis[3 * jid] = d->xaxis[3 * jid + 1] = 0;
      d->xaxis[3 * jid + 2] = 1;
    } else {
      const int pid = m->body_parentid[i];
      const mjtNum* bodypos = m->body_pos + 3 * i;
      const mjtNum* bodyquat = m->body_quat + 4 * i;
      if (m->body_mocapid[i] >= 0) {
        bodypos = d->mocap_pos + 3 * m->body_mocapid[i];
        bodyquat = d->mocap_quat + 4 * m->body_mocapid[i];
      }
      mju_rotVecMat(vec, bodypos, d->xmat + 9 * pid);
      mju_add3(pos, d->xpos + 3 * pid, vec);
      mju_mulQuat(quat, d->xquat + 4 * pid, bodyquat);
      for (int j = 0; j < m->body_jntnum[i]; ++j) {
        const int jid = m->body_jntadr[i] + j;
        const int qadr = m->jnt_qposadr[jid];
        const int jtype = m->jnt_type[jid];
        mju_rotVecQuat(xaxis, m->jnt_axis + 3 * jid, quat);
        mju_rotVecQuat(xanchor, m->jnt_pos + 3 * jid, quat);
        mju_addTo3(xanchor, pos);
        if (jtype == mjJNT_SLIDE) {
          mju_addToScl3(pos, xaxis, d->qpos[qadr] - m->qpos0[qadr]);
        } else {  // hinge or ball
          if (jtype == mjJNT_BALL) {
            mju_normalize4(d->qpos + qadr);  // mj_normalizeQuat
            mju_copy4(qloc, d->qpos + qadr);
          } else {
            mju_axisAngle2Quat(qloc, m->jnt_axis + 3 * jid, d->qpos[qadr] - m->qpos0[qadr]);
          }
          mju_mulQuat(quat, quat, qloc);
          mju_sub3(vec, xanchor, pos);
          mju_rotVecQuat(vec1, m->jnt_pos + 3 * jid, quat);
          pos[0] += (vec[0] - vec1[0]);
          pos[1] += (vec[1] - vec1[1]);
          pos[2] += (vec[2] - vec1[2]);
        }
        mju_copy3(d->xanchor + 3 * jid, xanchor);
        mju_copy3(d->xaxis + 3 * jid, xaxis);
      }
    }
    mju_normalize4(quat);
    mju_copy4(d->xquat + 4 * i, quat);
    mju_copy3(d->xpos + 3 * i, pos);
    mju_quat2Mat(d->xmat + 9 * i, quat);
  }
}

// The pad face position in the base frame for joint angles q of one leg; `chain` holds the
// bodies from the root to the pad face site's body.
Eigen::Vector3d FootInBase(const mjModel* m, mjData* d, const LegInfo& leg, int base,
                           const std::vector<int>& chain, const std::array<double, 3>& q) {
  for (int k = 0; k < 3; ++k) d->qpos[leg.qpos_adr[k]] = q[k];
  ChainKinematics(m, d, chain);
  const int s = leg.pad_face_site;
  mj_local2Global(d, d->site_xpos + 3 * s, d->site_xmat + 9 * s, m->site_pos + 3 * s,
                  m->site_quat + 4 * s, m->site_bodyid[s], m->site_sameframe[s]);
  const Eigen::Map<const Eigen::Vector3d> site(d->site_xpos + 3 * s);
  const Eigen::Map<const Eigen::Vector3d> origin(d->xpos + 3 * base);
  const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rot(d->xmat + 9 * base);
  return rot.transpose() * (site - origin);
}

// One leg's joints that put its foot at `target` (base frame), damped least squares from q.
struct FootSolver {
  const mjModel* m;
  mjData* d;
  const LegInfo& leg;
  int base;
  const std::vector<int>& chain;
  std::array<double, 3> lo, hi;  // the joints' ranges

  std::array<double, 3> Solve(const Eigen::Vector3d& target, std::array<double, 3> q) const {
    // The foot position is a function of q alone, so it is computed once per iterate
    // (for the error and as the finite differences' base), and an iterate that does not
    // move q (held at a joint limit) would repeat itself to the 100th: it ends the loop.
    for (int it = 0; it < 100; ++it) {
      const Eigen::Vector3d foot = FootInBase(m, d, leg, base, chain, q);
      const Eigen::Vector3d e = target - foot;
      if (e.norm() < 1e-9) break;
      Eigen::Matrix3d jac;
      const double h = 1e-6;
      for (int k = 0; k < 3; ++k) {
        std::array<double, 3> qp = q;
        qp[k] += h;
        jac.col(k) = (FootInBase(m, d, leg, base, chain, qp) - foot) / h;
      }
      // Damped least squares: stays finite near singular poses and at the joint limits.
      const Eigen::Vector3d dq =
          jac.transpose() *
          (jac * jac.transpose() + 1e-6 * Eigen::Matrix3d::Identity()).ldlt().solve(e);
      const std::array<double, 3> before = q;
      for (int k = 0; k < 3; ++k) q[k] = std::clamp(q[k] + dq[k], lo[k], hi[k]);
      if (q == before) break;
    }
    return q;
  }
};

}  // namespace

LegIk::LegIk(const mjModel* m, const RobotInfo& robot, double reach_x_m, double reach_below_m,
             double reach_above_m, int cells)
    : cells_(cells), x0_(-reach_x_m), x1_(reach_x_m), z0_(-reach_below_m), z1_(reach_above_m) {
  mjData* d = mj_makeData(m);
  mju_copy(d->qpos, m->qpos0, m->nq);  // base at its spawn pose, every joint at zero
  mj_kinematics(m, d);  // the world body's pose (and every other) for ChainKinematics
  for (const LegInfo& leg : robot.legs) {
    table_.push_back(LegTable(m, d, leg, robot.base_body));
    // Back to zero for the next leg.
    for (int k = 0; k < 3; ++k) d->qpos[leg.qpos_adr[k]] = 0.0;
  }
  mj_deleteData(d);
}

std::vector<std::array<double, 3>> LegIk::LegTable(const mjModel* m, mjData* d,
                                                   const LegInfo& leg, int base) {
  const int n = cells_ + 1;
  std::array<double, 3> lo, hi;
  for (int k = 0; k < 3; ++k) {
    const int j = leg.joint[k];
    lo[k] = m->jnt_limited[j] ? m->jnt_range[2 * j] : -M_PI;
    hi[k] = m->jnt_limited[j] ? m->jnt_range[2 * j + 1] : M_PI;
  }
  const std::vector<int> chain = ChainTo(m, m->site_bodyid[leg.pad_face_site]);
  const Eigen::Vector3d neutral = FootInBase(m, d, leg, base, chain, {0, 0, 0});
  const FootSolver solver{m, d, leg, base, chain, lo, hi};
  const auto solve = [&](const Eigen::Vector3d& target, const std::array<double, 3>& q) {
    return solver.Solve(target, q);
  };
  std::vector<std::array<double, 3>> table(n * n);
  // Row by row from the neutral pose outwards, each cell seeded by a solved neighbour.
  const int ix0 = static_cast<int>(std::lround((0 - x0_) / (x1_ - x0_) * cells_));
  const int iz0 = static_cast<int>(std::lround((0 - z0_) / (z1_ - z0_) * cells_));
  auto target = [&](int ix, int iz) {
    return Eigen::Vector3d(neutral.x() + x0_ + (x1_ - x0_) * ix / cells_, neutral.y(),
                           neutral.z() + z0_ + (z1_ - z0_) * iz / cells_);
  };
  auto at = [&](int ix, int iz) -> std::array<double, 3>& { return table[iz * n + ix]; };
  at(ix0, iz0) = solve(target(ix0, iz0), {0, 0, 0});
  for (int ix = ix0 + 1; ix < n; ++ix) at(ix, iz0) = solve(target(ix, iz0), at(ix - 1, iz0));
  for (int ix = ix0 - 1; ix >= 0; --ix) at(ix, iz0) = solve(target(ix, iz0), at(ix + 1, iz0));
  for (int iz = iz0 + 1; iz < n; ++iz) {
    for (int ix = 0; ix < n; ++ix) at(ix, iz) = solve(target(ix, iz), at(ix, iz - 1));
  }
  for (int iz = iz0 - 1; iz >= 0; --iz) {
    for (int ix = 0; ix < n; ++ix) at(ix, iz) = solve(target(ix, iz), at(ix, iz + 1));
  }
  for (int iz = 0; iz < n; ++iz) {
    for (int ix = 0; ix < n; ++ix) {
      const double err = (FootInBase(m, d, leg, base, chain, at(ix, iz)) - target(ix, iz)).norm();
      worst_error_m_ = std::max(worst_error_m_, err);
    }
  }
  return table;
}

std::array<double, 3> LegIk::Solve(int leg, double dx_m, double dz_m) const {
  const double fx = std::clamp((dx_m - x0_) / (x1_ - x0_), 0.0, 1.0) * cells_;
  const double fz = std::clamp((dz_m - z0_) / (z1_ - z0_), 0.0, 1.0) * cells_;
  const int ix = std::min(static_cast<int>(fx), cells_ - 1);
  const int iz = std::min(static_cast<int>(fz), cells_ - 1);
  const double ax = fx - ix, az = fz - iz;
  const int n = cells_ + 1;
  const auto& t = table_[leg];
  std::array<double, 3> q;
  for (int k = 0; k < 3; ++k) {
    q[k] = (1 - az) * ((1 - ax) * t[iz * n + ix][k] + ax * t[iz * n + ix + 1][k]) +
           az * ((1 - ax) * t[(iz + 1) * n + ix][k] + ax * t[(iz + 1) * n + ix + 1][k]);
  }
  return q;
}

}  // namespace climbsim::sim
