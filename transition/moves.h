// The corner manoeuvre's small moves (manoeuvre.h runs them): a foot's state, the body's sag
// correction, a swing's path, a peel's pull and the probe for an edge. Pure geometry on the
// plan's types: no model, no data, no allocation.
#ifndef CLIMBSIM_TRANSITION_MOVES_H_
#define CLIMBSIM_TRANSITION_MOVES_H_

#include <Eigen/Core>
#include <string>

#include "transition/corner_plan.h"

namespace climbsim::sim {

// One leg during the manoeuvre: a stance foot (its ankle target on its surface), an idle one
// (held in the air) or the stepping one, and its joint targets.
struct Foot {
  bool stance = true;
  bool idle = false;
  int surface = 0;                                    // 0: old, 1: new
  Eigen::Vector3d ankle_w = Eigen::Vector3d::Zero();  // stance: ankle target (world, for the
                                                      // commanded body); idle: base frame
  Eigen::Vector3d normal_w = Eigen::Vector3d::UnitZ();
  LegChain::Q q{};
  double tilt = 0.0;
  // The last converged solve of this leg (RunTick's margin check, the stance targets, the
  // idle hold): with the same inputs, bit for bit, a solve would stop at once with the same
  // q and tilt, so HoldLeg skips it.
  bool held = false;
  BodyPose held_pose;
  Eigen::Vector3d held_target = Eigen::Vector3d::Zero(), held_normal = Eigen::Vector3d::Zero();
  LegChain::Q held_q{};
  double held_tilt = 0.0;

  // q and tilt are this leg's solve for these inputs, converged when err_m < kSolvedM.
  void Remember(const BodyPose& pose, const Eigen::Vector3d& target, double err_m);
  // The inputs are those of the last converged solve.
  bool Holds(const BodyPose& pose, const Eigen::Vector3d& target) const;
};

// The body sags on its compliant servos under its weight: an integral correction moves the
// stance legs' targets until the body is where the plan commands it (so that a foot lands, in
// its joints, where the plan expects). At most kTrackMaxM and kTrackMaxRad.
class SagCorrection {
 public:
  void Clear();
  // The commanded pose with the correction (what the stance legs' targets come from).
  BodyPose Apply(const BodyPose& pose) const;
  // One step of the integral with gain k (control period over track_s).
  void Track(const BodyPose& cmd, const BodyPose& actual, double k);

 private:
  Eigen::Vector3d p_ = Eigen::Vector3d::Zero(), w_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d r_ = Eigen::Matrix3d::Identity();  // Exp(w_), for Apply
};

// A swing from the pad's face where it left (lifted straight off that surface first, a peeled
// pad that falls back onto it sticks again), then along the polyline through the lifted point
// (and round the edge of an outer corner: via) to above the target.
struct SwingPath {
  Eigen::Vector3d from_face = Eigen::Vector3d::Zero(), from_normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d via = Eigen::Vector3d::Zero();
  bool use_via = false;

  // Where the pad is at u ∈ [0, 1] of the swing to `to` (above it at w2); an idle leg
  // (to.surface < 0) only lifts, to to.face.
  Eigen::Vector3d Face(double u, const Foothold& to, const Eigen::Vector3d& w2,
                       double lift_m) const;
};

// Which way a peel pulls a pad with face normal `normal` (unit, times peel_back_m by the
// caller): along `load`, the other pads' load on this pad's surface, when it has at least
// kPeelLoad there (peel_toward load), else along `normals`, the sum of their normals, when it
// has at least kPeelAlong there (not peel_toward back), else back along the surface against
// the body's `heading`. `load` and `normals` are projected on the surface here.
Eigen::Vector3d PeelPull(const Eigen::Vector3d& heading, const Eigen::Vector3d& normal,
                         Eigen::Vector3d load, Eigen::Vector3d normals,
                         const std::string& peel_toward);
// A peel that has not let go pulls the other way (attempt 1), then sideways, inwards of the
// leg's hip (hip_y: its side of the body; lateral: the body's y).
Eigen::Vector3d RetryPull(const Eigen::Vector3d& pull, int attempt, double hip_y,
                          const Eigen::Vector3d& lateral, const Eigen::Vector3d& normal);
// A peel that has not let go after peel_max_s pulls again: this many tries in all.
inline constexpr int kPeelAttempts = 3;

// The probe for an edge (a front foot that found no surface for lost_s): the body crouches
// over kProbeCrouchS, the foot turns its pad to face back and goes kProbeBelow past the old
// surface's plane (beyond the pad's half width), then back towards the body at kProbeSpeed for
// at most kProbeBack, until it touches.
struct Probe {
  static constexpr double kCrouchS = 1.0;
  static constexpr double kBelowM = 0.006;
  static constexpr double kSpeedMps = 0.02;
  static constexpr double kBackM = 0.06;

  int leg = -1, phase = 0;  // 0 crouch, 1 down, 2 back
  double t0 = 0.0;
  BodyPose start;
  Eigen::Vector3d n0 = Eigen::Vector3d::UnitZ(), p0 = Eigen::Vector3d::Zero(),
                  fwd = Eigen::Vector3d::UnitX();
  Eigen::Vector3d from_face = Eigen::Vector3d::Zero(), from_normal = Eigen::Vector3d::UnitZ();

  // Past the old surface's plane below where the foot was.
  Eigen::Vector3d Below(double pad_half_m) const;
  // Phase 1 at u ∈ [0, 1]: over the foot's place lift_m above the surface, then down to
  // `below`, the pad turning to face back.
  void Down(double u, double lift_m, const Eigen::Vector3d& below, Eigen::Vector3d* face,
            Eigen::Vector3d* normal) const;
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_TRANSITION_MOVES_H_
