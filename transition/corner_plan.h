// The geometry of a surface transition (manoeuvre.h runs it): a sharp 90-degree
// corner between the surface the robot stands on (old, normal n0) and the one ahead (new),
// the path of the body round it, and where each foot may stand. Pure kinematics on the legs'
// chains (robot/leg_chain.h): no mjData, no allocation after construction, so a plan can be
// tried without simulating it (CornerPlan::DryRun, tests/sim/corner_plan_test.cc).
//
// FRAME. The corner: a point o on it, t0 the old surface's direction towards it (the way the
// robot goes), n0 the old normal, y0 = n0 × t0 along the corner. Inner corner (floor to wall,
// wall to ceiling): the new surface faces the robot, normal −t0, and goes on along +n0. Outer
// (a wall over its top edge): normal +t0, going on along −n0.
//
// PATH. σ parametrises the body pose; the body stays in the plane of t0 and n0 and pitches by
// φ about y0 (nose towards +n0 inner, −n0 outer), its hips ("front": the foremost hip-yaw
// axes, "hind": the hindmost) at x_f and x_h of the base frame, span x_f − x_h:
//   σ ≤ 0        along the old surface, φ = 0: front hips at s = −d0 + σ (inner) or
//                d0 + σ (outer) from the corner, h0 above the old surface
//   0 < σ < π/2  the turn, φ = σ: a ladder whose ends slide along the two surfaces. Inner: hind
//                hips at h0 above the old surface, front hips at d(φ) (d0 → d1) off the new
//                one; outer: hind hips at h0 over the old surface, front hips d0 off the new one
//   σ ≥ π/2      along the new surface (σ − π/2 in m) at d0 off it
// Inner: d0 = post + how far the front feet stand ahead of the front hips + reach_share ·
// forward reach of a foot, h0 = the robot's standing height d1. Outer: d0 = h0 = d1 − crouch_m.
// Closer to the new surface than standing height: the feet reach both surfaces; the
// transition raises the body to d1 (standing_height_m()) before it hands the feet to the gait. Start() blends
// from the pose the body is in over the first kBlend of σ.
//
// FOOTHOLDS. A stance foot stays where it stuck; the body may move while every stance leg
// reaches its foot with its joints margin_rad inside their ranges and its pad turned off the
// foot's face by at most the passive ankle's range. Next(): where a leg that would not steps to
// — below its neutral ankle for the body further along the path (projected on the old or
// the new surface, kept clear of the corner line), moved sideways up to 3 cm for a flatter
// landing, which it must reach now with landing margins; of these the one it can keep the
// longest as the body goes on.
#ifndef CLIMBSIM_TRANSITION_CORNER_PLAN_H_
#define CLIMBSIM_TRANSITION_CORNER_PLAN_H_

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "transition/transition_params.h"
#include "robot/leg_chain.h"
#include "robot/robot.h"

namespace climbsim::sim {

// The manoeuvre's small geometry, shared by the plan and the effect that runs it.
// Minimum-jerk blend 0 -> 1 for u in [0, 1] (u clamped).
double SmoothStep(double u);
// Unit vectors a to b by fraction u along the great circle.
Eigen::Vector3d Slerp(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double u);
// Rotation by the rotation vector w, and back.
Eigen::Matrix3d Exp(const Eigen::Vector3d& w);
Eigen::Vector3d RotationLog(const Eigen::Matrix3d& r);

struct BodyPose {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();  // columns: body x, y, z in the world
};

struct Foothold {
  Eigen::Vector3d face = Eigen::Vector3d::Zero();  // the pad face's centre, world
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  int surface = 0;      // 0 old, 1 new
  double margin = -1;   // joint-range margin on landing (rad); < 0: none found
  double reach = 0;     // how far along the path (σ) the foot stays of use
  LegChain::Q q{};      // the leg's joints on landing (the branch of its kinematics to land in)
  double approach_m = 0.0;  // lowered onto it from this far off it
};

// A leg steps, or waits in the air when it has no foothold (the spider's middle legs mid-turn,
// a hind foot of the gecko between the two faces of an outer corner), only while at least this
// many others stand.
inline constexpr int kMinStance = 3;

class CornerPlan {
 public:
  // Throws std::invalid_argument when a leg's chain cannot be read (Problem says why first).
  CornerPlan(const mjModel* model, const RobotInfo& robot, const TransitionParams& params);
  // Why the robot's legs cannot be planned for ("" when they can): the first leg's
  // LegChain::Problem.
  static std::string Problem(const mjModel* model, const RobotInfo& robot);

  void SetCorner(const Eigen::Vector3d& origin, const Eigen::Vector3d& n0,
                 const Eigen::Vector3d& t0, bool inner);
  // The path's σ for a body in pose `now` (a robot that came closer to a wall ahead than the
  // turn would start at makes the turn start there); later poses blend from `now`.
  double Start(const BodyPose& now);
  BodyPose Pose(double sigma) const;
  // dσ/dt: body_speed_mps along a surface, pitch_rate_rad_per_s in the turn.
  double Rate(double sigma) const;
  // From this σ on the body is on the new surface (parallel to it, crouched: standoff d0).
  double Settled() const;
  // How far the base origin is from the new surface's plane.
  double Standoff(const BodyPose& pose) const;

  // Leg i with its ankle at `ankle_w`, its pad facing `normal_w` and the body at `pose`: the
  // joint-range margin (rad; −1 when out of reach or the pad would be more than `max_left_rad`
  // off its face), the solution (*q from its warm start, *tilt), the angle left and the
  // distance the solve ended from ankle_w.
  double Margin(int i, const BodyPose& pose, const Eigen::Vector3d& ankle_w,
                const Eigen::Vector3d& normal_w, LegChain::Q* q, double* tilt,
                double max_left_rad, double* left_rad = nullptr, double* err_m = nullptr) const;
  // True when ankle_w (world) lies out of leg i's reach from the body at `pose`: Margin
  // would return -1 for it after a full solve.
  bool OutOfReach(int i, const BodyPose& pose, const Eigen::Vector3d& ankle_w) const;
  // The ankle of a foot standing on `face` with normal `normal` (its stance target: press_m in).
  Eigen::Vector3d StanceAnkle(int i, const Eigen::Vector3d& face, const Eigen::Vector3d& normal) const;
  // Where leg i steps to when the body waits at σ in pose `now` (see the file comment); margin
  // −1 when nothing can be reached. old_only: back onto the old surface, below the leg as the
  // body is now (σ unused); σ = kHere: onto either surface, below the leg as the body is now.
  static constexpr double kHere = -1e9;
  // A stuck pad's leg may turn it this far from its face (the passive ankle's stops, 0.5 rad).
  static constexpr double kStanceTurn = 0.45;
  Foothold Next(int i, double sigma, const BodyPose& now, const LegChain::Q& warm,
                bool old_only) const;


  // A dry run: the body and feet move as planned, every foot lands where planned. From the
  // body at `start` with every foot on the old surface below its neutral ankle; steps until
  // the body is `beyond_m` along the new surface or a leg has no foothold. The steps, one line
  // each, go to *log (when given). Returns the σ reached.
  double DryRun(const BodyPose& start, double beyond_m, std::string* log, int* steps) const;

  const std::vector<LegChain>& chains() const { return chains_; }
  bool inner() const { return sign_ > 0; }
  const Eigen::Vector3d& normal(int surface) const { return n_[surface]; }
  const Eigen::Vector3d& origin() const { return origin_; }
  const Eigen::Vector3d& lateral() const { return y0_; }
  double pad_half_m() const { return pad_half_m_; }
  double height_m() const { return height_m_; }  // standing height, base origin over a surface
  double hip_front_x() const { return hip_front_x_; }
  // The surface (0 old, 1 new) a pad with face normal `n` stands on; −1 neither.
  int SurfaceOf(const Eigen::Vector3d& n) const;

 private:
  BodyPose PathPose(double sigma) const;  // without the blend

  // Next's candidates: the best landing of one surface at one look-ahead.
  struct Candidate {
    Foothold h;
    double left = 1e9;  // angle left to the ankle, plus a little for each cm sideways
    int side = -1;
    double reach = -1.0;  // σ the body may go on with it; < 0 not yet followed
  };
  // Below the ankle `a` on surface k, kept clear of the corner line.
  Eigen::Vector3d Below(const Eigen::Vector3d& a, int k) const;
  // How far along the path (σ beyond `sigma`) leg i's foot on h stays of use: the body goes on
  // until the leg would be out of margin.
  double Follow(int i, double sigma, const Foothold& h) const;
  // How far off surface k leg i can be lowered onto face point f from (the body at `now`, in
  // the branch of q): lift_m or less; −1 when not at all.
  double Approach(int i, const BodyPose& now, const Eigen::Vector3d& f, int k,
                  const LegChain::Q& q) const;
  // Leg i's best flat and best tilted landings on surface k around `below` (the lateral
  // offsets) for the body at `now`.
  void Landings(int i, const BodyPose& now, const Eigen::Vector3d& below, int k,
                const LegChain::Q& warm, Candidate* flat, Candidate* tilt_one) const;

  // DryRun's legs, and its steps: the idle legs that land now (logged; how many), and the leg
  // whose margin stops the body at `pose` (−1: none; every leg's joints updated).
  struct DryLegs;
  int DryLand(double sigma, DryLegs* legs, std::string* log) const;
  int DryWorst(const BodyPose& pose, DryLegs* legs) const;

  TransitionParams params_;
  std::vector<LegChain> chains_;
  double pad_half_m_ = 0.0;
  double reach_x_m_ = 0.0;
  double height_m_ = 0.0;
  double hip_front_x_ = 0.0, hip_hind_x_ = 0.0;
  double front_ankle_x_ = 0.0;  // front feet ahead of the front hips in the neutral pose

  Eigen::Vector3d origin_ = Eigen::Vector3d::Zero(), t0_ = Eigen::Vector3d::UnitX(),
                  n0_ = Eigen::Vector3d::UnitZ(), y0_ = Eigen::Vector3d::UnitY();
  double sign_ = 1.0;
  std::array<Eigen::Vector3d, 2> n_{}, away_{};
  double d0_ = 0.0, d1_ = 0.0, h0_ = 0.0;
  double sigma_start_ = -1e9;
  Eigen::Vector3d blend_p_ = Eigen::Vector3d::Zero(), blend_w_ = Eigen::Vector3d::Zero();
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_TRANSITION_CORNER_PLAN_H_
