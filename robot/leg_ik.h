// Foot-space leg control: the joint angles (hip yaw, hip pitch, knee) that put a leg's pad
// face at a point given in the base frame, relative to where it stands in the neutral pose:
//   dx along the base's forward axis (stride), dz along its normal (lift, + away from the
//   surface), the lateral position held.
// Feet that follow straight lines in the body frame move consistently with a rigid body:
// stance feet welded to a wall then do not fight each other through the pads, as feet
// swept on arcs by hip yaw alone do. The inverse kinematics is solved once, at
// construction, with MuJoCo's kinematics (damped least squares on a scratch mjData, base
// fixed, ankles at zero; mj_kinematics' operations for the one leg's chain of bodies, which
// gives its poses bit for bit at a fraction of the whole robot's cost) on a grid; the step only
// interpolates it (bilinear, no allocation). Solutions are continuous across the grid (each cell
// starts from its neighbour's solution) and clamped to the joint ranges.
#ifndef CLIMBSIM_ROBOT_LEG_IK_H_
#define CLIMBSIM_ROBOT_LEG_IK_H_

#include <mujoco/mujoco.h>

#include <array>
#include <vector>

#include "robot/robot.h"

namespace climbsim::sim {

class LegIk {
 public:
  static constexpr int kDefaultCells = 40;
  // Tables for every leg of `robot` over dx ∈ [−reach_x_m, reach_x_m] and dz ∈
  // [−reach_below_m, reach_above_m], with `cells` intervals per axis.
  LegIk(const mjModel* model, const RobotInfo& robot, double reach_x_m, double reach_below_m,
        double reach_above_m, int cells = kDefaultCells);

  // Joint targets for leg `leg` (clamped to the table's box). Allocation-free.
  std::array<double, 3> Solve(int leg, double dx_m, double dz_m) const;
  // Largest distance between the foot a table entry reaches and its target (m): how well
  // the table's box fits the leg (a test bounds it).
  double worst_error_m() const { return worst_error_m_; }
  // Table entry of leg `leg` at grid node (ix, iz), each in [0, cells] (tests).
  const std::array<double, 3>& entry(int leg, int ix, int iz) const {
    return table_[leg][iz * (cells_ + 1) + ix];
  }

 private:
  // Leg `leg`'s table, solved on scratch data d (its joints left as the last solve put them);
  // raises worst_error_m_ to the table's worst entry.
  std::vector<std::array<double, 3>> LegTable(const mjModel* m, mjData* d, const LegInfo& leg,
                                              int base);

  int cells_;
  double x0_, x1_, z0_, z1_;
  std::vector<std::vector<std::array<double, 3>>> table_;  // [leg][iz * (cells+1) + ix]
  double worst_error_m_ = 0.0;
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_ROBOT_LEG_IK_H_
