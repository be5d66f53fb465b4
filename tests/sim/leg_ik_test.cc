// The leg IK tables: built with kinematics of one leg's chain of bodies, they hold the same
// joint angles bit for bit as the straightforward construction with mj_kinematics of the
// whole robot (the reference below, as sim/leg_ik.cc first had it), for every robot.
#include "robot/leg_ik.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "sim/sim.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

Eigen::Vector3d ReferenceFootInBase(const mjModel* m, mjData* d, const LegInfo& leg, int base,
                                    const std::array<double, 3>& q) {
  for (int k = 0; k < 3; ++k) d->qpos[leg.qpos_adr[k]] = q[k];
  mj_kinematics(m, d);
  const Eigen::Map<const Eigen::Vector3d> site(d->site_xpos + 3 * leg.pad_face_site);
  const Eigen::Map<const Eigen::Vector3d> origin(d->xpos + 3 * base);
  const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rot(d->xmat + 9 * base);
  return rot.transpose() * (site - origin);
}

// The reference table of one leg: damped least squares from the neutral cell outwards, each
// cell seeded by its solved neighbour, the whole robot's mj_kinematics for every foot.
std::vector<std::array<double, 3>> ReferenceTable(const mjModel* m, const RobotInfo& robot,
                                                  int leg_index, double reach_x, double below,
                                                  double above, int cells) {
  const LegInfo& leg = robot.legs[leg_index];
  mjData* d = mj_makeData(m);
  mju_copy(d->qpos, m->qpos0, m->nq);
  std::array<double, 3> lo, hi;
  for (int k = 0; k < 3; ++k) {
    const int j = leg.joint[k];
    lo[k] = m->jnt_limited[j] ? m->jnt_range[2 * j] : -M_PI;
    hi[k] = m->jnt_limited[j] ? m->jnt_range[2 * j + 1] : M_PI;
  }
  const int base = robot.base_body;
  const Eigen::Vector3d neutral = ReferenceFootInBase(m, d, leg, base, {0, 0, 0});
  auto solve = [&](const Eigen::Vector3d& target, std::array<double, 3> q) {
    for (int it = 0; it < 100; ++it) {
      const Eigen::Vector3d e = target - ReferenceFootInBase(m, d, leg, base, q);
      if (e.norm() < 1e-9) break;
      Eigen::Matrix3d jac;
      const double h = 1e-6;
      for (int k = 0; k < 3; ++k) {
        std::array<double, 3> qp = q;
        qp[k] += h;
        jac.col(k) =
            (ReferenceFootInBase(m, d, leg, base, qp) - ReferenceFootInBase(m, d, leg, base, q)) /
            h;
      }
      const Eigen::Vector3d dq =
          jac.transpose() *
          (jac * jac.transpose() + 1e-6 * Eigen::Matrix3d::Identity()).ldlt().solve(e);
      for (int k = 0; k < 3; ++k) q[k] = std::clamp(q[k] + dq[k], lo[k], hi[k]);
    }
    return q;
  };
  const int n = cells + 1;
  const double x0 = -reach_x, x1 = reach_x, z0 = -below, z1 = above;
  std::vector<std::array<double, 3>> table(n * n);
  const int ix0 = static_cast<int>(std::lround((0 - x0) / (x1 - x0) * cells));
  const int iz0 = static_cast<int>(std::lround((0 - z0) / (z1 - z0) * cells));
  auto target = [&](int ix, int iz) {
    return Eigen::Vector3d(neutral.x() + x0 + (x1 - x0) * ix / cells, neutral.y(),
                           neutral.z() + z0 + (z1 - z0) * iz / cells);
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
  mj_deleteData(d);
  return table;
}

TEST(LegIk, ChainKinematicsGivesTheWholeRobotsTableBitForBit) {
  // The wall scenes place the base rotated (a quaternion MuJoCo renormalises); the floor
  // ones upright. A box that reaches the joint limits exercises the clamped cells too.
  for (const char* robot : {"gecko", "spider"}) {
    for (const char* scene : {"floor", "wall"}) {
      const Scenario s = LoadScenario(climbsim::testing::WriteFile(
          std::string("ik_") + robot + "_" + scene + ".yaml",
          std::string("robot: ") + robot + "\nscene: " + scene + "\nduration_s: 0.01\n"));
      auto model = CompileScenario(s);
      const mjModel* m = model->model();
      const double reach_x = 0.025, below = 0.012, above = 0.04;
      const int cells = 8;
      const LegIk ik(m, model->robot(), reach_x, below, above, cells);
      for (int leg = 0; leg < static_cast<int>(model->robot().legs.size()); ++leg) {
        const auto ref = ReferenceTable(m, model->robot(), leg, reach_x, below, above, cells);
        for (int iz = 0; iz <= cells; ++iz) {
          for (int ix = 0; ix <= cells; ++ix) {
            for (int k = 0; k < 3; ++k) {
              ASSERT_EQ(ref[iz * (cells + 1) + ix][k], ik.entry(leg, ix, iz)[k])
                  << robot << " " << scene << " leg " << leg << " node " << ix << "," << iz
                  << " joint " << k;
            }
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace climbsim::sim
