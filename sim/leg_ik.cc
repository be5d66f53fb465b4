#include "sim/leg_ik.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace climbsim::sim {
namespace {

// The pad face position in the base frame for joint angles q of one leg.
Eigen::Vector3d FootInBase(const mjModel* m, mjData* d, const LegInfo& leg, int base,
                           const std::array<double, 3>& q) {
  for (int k = 0; k < 3; ++k) d->qpos[leg.qpos_adr[k]] = q[k];
  mj_kinematics(m, d);
  const Eigen::Map<const Eigen::Vector3d> site(d->site_xpos + 3 * leg.pad_face_site);
  const Eigen::Map<const Eigen::Vector3d> origin(d->xpos + 3 * base);
  const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rot(d->xmat + 9 * base);
  return rot.transpose() * (site - origin);
}

}  // namespace

LegIk::LegIk(const mjModel* m, const RobotInfo& robot, double reach_x_m, double reach_below_m,
             double reach_above_m, int cells)
    : cells_(cells), x0_(-reach_x_m), x1_(reach_x_m), z0_(-reach_below_m), z1_(reach_above_m) {
  mjData* d = mj_makeData(m);
  mju_copy(d->qpos, m->qpos0, m->nq);  // base at its spawn pose, every joint at zero
  const int n = cells_ + 1;
  for (const LegInfo& leg : robot.legs) {
    std::array<double, 3> lo, hi;
    for (int k = 0; k < 3; ++k) {
      const int j = leg.joint[k];
      lo[k] = m->jnt_limited[j] ? m->jnt_range[2 * j] : -M_PI;
      hi[k] = m->jnt_limited[j] ? m->jnt_range[2 * j + 1] : M_PI;
    }
    const Eigen::Vector3d neutral = FootInBase(m, d, leg, robot.base_body, {0, 0, 0});
    std::vector<std::array<double, 3>> table(n * n);
    // Row by row from the neutral pose outwards, each cell seeded by a solved neighbour.
    auto solve = [&](const Eigen::Vector3d& target, std::array<double, 3> q) {
      for (int it = 0; it < 100; ++it) {
        const Eigen::Vector3d e = target - FootInBase(m, d, leg, robot.base_body, q);
        if (e.norm() < 1e-9) break;
        Eigen::Matrix3d jac;
        const double h = 1e-6;
        for (int k = 0; k < 3; ++k) {
          std::array<double, 3> qp = q;
          qp[k] += h;
          jac.col(k) = (FootInBase(m, d, leg, robot.base_body, qp) -
                        FootInBase(m, d, leg, robot.base_body, q)) / h;
        }
        // Damped least squares: stays finite near singular poses and at the joint limits.
        const Eigen::Vector3d dq =
            jac.transpose() * (jac * jac.transpose() + 1e-6 * Eigen::Matrix3d::Identity()).ldlt().solve(e);
        for (int k = 0; k < 3; ++k) q[k] = std::clamp(q[k] + dq[k], lo[k], hi[k]);
      }
      return q;
    };
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
        const double err = (FootInBase(m, d, leg, robot.base_body, at(ix, iz)) - target(ix, iz)).norm();
        worst_error_m_ = std::max(worst_error_m_, err);
      }
    }
    // Back to zero for the next leg.
    for (int k = 0; k < 3; ++k) d->qpos[leg.qpos_adr[k]] = 0.0;
    table_.push_back(std::move(table));
  }
  mj_deleteData(d);
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
