// One leg's kinematics relative to the base, for controllers that place feet anywhere (not
// only on the grid of LegIk): the ankle centre as a function of the leg's three joints
// (hip_yaw, hip_pitch, knee) with its Jacobian, a damped Newton inverse kinematics warm-started
// from the last solution, and the ankle tilt (robots with actuated ankles, mjcf/README.md) that
// turns the pad's face normal towards a given direction. The chain of bodies from the base to
// the pad is read from the model once (body offsets, joint axes and anchors as compiled); the
// step only multiplies small matrices: nothing allocates.
#ifndef CLIMBSIM_ROBOT_LEG_CHAIN_H_
#define CLIMBSIM_ROBOT_LEG_CHAIN_H_

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "robot/robot.h"

namespace climbsim::sim {

class LegChain {
 public:
  using Q = std::array<double, 3>;  // hip_yaw, hip_pitch, knee

  // Leg `leg` of `robot`. Throws std::invalid_argument with Problem's text when it has one.
  LegChain(const mjModel* model, const RobotInfo& robot, int leg);
  // Why leg `leg`'s chain cannot be read ("" when it can): its pad body not below the base, a
  // leg joint not a hinge on the chain from the base to the pad body, the tilt not turning the
  // pad body, the ankle site outside it, or a pad body without exactly one box geom.
  static std::string Problem(const mjModel* model, const RobotInfo& robot, int leg);

  // The ankle centre (site L_ankle) in the base frame for joint angles q and ankle tilt `tilt`
  // (0 without a tilt servo); optionally the pad body's orientation in the base frame with
  // every passive ankle joint at 0, and d(ankle)/dq.
  Eigen::Vector3d Ankle(const Q& q, double tilt, Eigen::Matrix3d* pad_rot = nullptr,
                        Eigen::Matrix3d* jacobian = nullptr) const;

  // Joint angles that put the ankle at `target` (base frame), from *q (the warm start; the
  // result is written back, clamped to the joint ranges). Returns the distance left (m) and,
  // when asked, the pad's orientation at the result (as Ankle's, tilt 0: its last forward pass
  // was at the result, so Tilt need not run the chain again). Not for calls from two threads
  // at once (it remembers its passes).
  static constexpr int kSolveIterations = 12;
  static constexpr double kSolvedM = 1e-7;  // Solve stops this close to its target
  double Solve(const Eigen::Vector3d& target, Q* q, int iterations = kSolveIterations,
               Eigen::Matrix3d* pad_rot = nullptr) const;

  // The tilt that turns the pad's face normal (its frame's z with the passive joints at 0)
  // as close as a turn about the tilt axis can to `normal` (base frame, unit) for leg angles
  // q, and the angle left between them (rad, the passive ankle's to take). Without a tilt
  // servo: 0 and the angle between the untilted face normal and `normal`.
  double Tilt(const Q& q, const Eigen::Vector3d& normal, double* left_rad) const;
  // The same from the pad's orientation at q with tilt 0 (Ankle's or Solve's pad_rot).
  double Tilt(const Eigen::Matrix3d& pad_rot, const Eigen::Vector3d& normal,
              double* left_rad) const;

  // True when no joint angles put the ankle within tolerance_m of `target` (base frame): it lies
  // further from the hip-yaw anchor than the leg reaches. So Solve would end further than
  // tolerance_m from it, after all its iterations; callers that would reject such a target
  // skip the solve.
  bool OutOfReach(const Eigen::Vector3d& target, double tolerance_m) const;

  // True when no joint angles within the ranges (Solve's results are) put the ankle within
  // tolerance_m of `target`: OutOfReach, or, for tolerances up to kMapTolM, outside a map of
  // where the ankle can be. The map is conservative: built from the ankle over a grid of the
  // joints' ranges, each sample grown by how far the ankle can be from the nearest one (the
  // joints' lever arms times half the grid's spacing) and by the tolerance. Targets it rejects
  // are ones Solve would end further than tolerance_m from, after all its iterations.
  static constexpr double kMapTolM = 0.0025;
  bool Unreachable(const Eigen::Vector3d& target, double tolerance_m) const;

  // How far q lies inside the joint ranges: min over the three joints of the distance to the
  // nearer limit (rad; negative outside).
  double RangeMargin(const Q& q) const;

  const Q& lo() const { return lo_; }
  const Q& hi() const { return hi_; }
  bool has_tilt() const { return tilt_index_ >= 0; }
  double tilt_lo() const { return tilt_lo_; }
  double tilt_hi() const { return tilt_hi_; }
  // The ankle in the neutral pose (every joint 0), base frame.
  const Eigen::Vector3d& neutral_ankle() const { return neutral_ankle_; }
  // The hip-yaw axis' anchor, base frame.
  const Eigen::Vector3d& hip() const { return hip_; }
  // From the ankle centre to the pad's face centroid, along the face normal (m).
  double post_m() const { return post_m_; }

 private:
  struct Joint {
    int role = -1;  // 0..2: hip_yaw, hip_pitch, knee; 3: the tilt; -1: passive (held at 0)
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // body frame
    Eigen::Vector3d anchor = Eigen::Vector3d::Zero();  // body frame
    // k when the axis is exactly ±e_k (every joint of the bundled robots), else -1: Ankle then
    // turns two columns instead of multiplying by a rotation matrix, the same numbers (the
    // terms it skips are exact zeros).
    int unit = -1;
    bool at_origin = true;  // anchor exactly 0: no product for it
  };
  struct Link {
    Eigen::Vector3d pos;  // in the parent body's frame
    Eigen::Matrix3d rot;
    bool identity = false;  // rot is exactly the identity: the chain skips the product
    int first_joint = 0, joints = 0;  // into joints_
  };
  std::vector<Link> links_;  // base's child first, the pad body last
  std::vector<Joint> joints_;
  Eigen::Vector3d site_pos_ = Eigen::Vector3d::Zero();  // ankle site in the pad body
  Eigen::Vector3d face_normal_ = Eigen::Vector3d::UnitZ();  // pad face normal, pad body frame
  Eigen::Vector3d tilt_axis_ = Eigen::Vector3d::UnitY();    // pad body frame
  int tilt_index_ = -1;
  Q lo_{}, hi_{};
  double tilt_lo_ = 0.0, tilt_hi_ = 0.0;
  Eigen::Vector3d neutral_ankle_ = Eigen::Vector3d::Zero();
  double reach_m_ = 0.0;  // the furthest the ankle gets from hip_
  // The reach map (Unreachable): voxels of kVoxelM from map_lo_, map_n_ of them along each
  // base axis, one bit each, set where a target may be within kMapTolM of the ankle.
  void BuildReachMap(const std::array<double, 3>& lever_m);
  // The ankles on a grid of the joints' ranges (tilt 0), their box (*lo, *hi) and how far any
  // q's ankle may be from the nearest of them (*cover_m, added to).
  std::vector<Eigen::Vector3d> SampleAnkles(const std::array<double, 3>& lever_m,
                                            double* cover_m, Eigen::Vector3d* lo,
                                            Eigen::Vector3d* hi) const;
  // Sets every voxel whose box lies within r of x.
  void MarkBall(const Eigen::Vector3d& x, double r);
  // Reads joint j into joints_ (with its range, or the tilt's); false for a joint that is not
  // a hinge (the chain holds those at 0).
  bool AddJoint(const mjModel* m, const LegInfo& info, int j);
  // The anchors of hip_yaw, hip_pitch and knee in the base frame, joints at 0.
  std::array<Eigen::Vector3d, 3> JointAnchors() const;
  std::array<int, 3> Voxel(const Eigen::Vector3d& x) const;  // may lie outside the map
  size_t MapIndex(const std::array<int, 3>& v) const;         // v inside the map
  bool MapSet(const std::array<int, 3>& v) const;
  void SetRun(size_t first, size_t last);  // sets the map's bits first..last
  Eigen::Vector3d map_lo_ = Eigen::Vector3d::Zero();
  static constexpr double kVoxelM = 0.004;  // the map's voxel side (m)
  std::array<int, 3> map_n_{};
  std::vector<uint64_t> map_;
  Eigen::Vector3d hip_ = Eigen::Vector3d::Zero();
  double post_m_ = 0.0;
  // Solve's forward passes remembered by q. A solve's first pass, at its warm start, is often
  // the last pass of the solve before (a stance leg following a moving body: one pass a tick
  // instead of two) or the first pass of the solve before (a search trying many targets from
  // one warm start). Ankle is a function of q alone (tilt 0), so a remembered pass is the pass,
  // bit for bit. Mutable state: a chain belongs to one run, as its model copy does.
  struct Pass {
    Q q{};
    Eigen::Vector3d ankle = Eigen::Vector3d::Zero();
    Eigen::Matrix3d pad_rot = Eigen::Matrix3d::Zero(), jacobian = Eigen::Matrix3d::Zero();
    bool valid = false;
  };
  mutable Pass first_pass_, last_pass_;
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_ROBOT_LEG_CHAIN_H_
