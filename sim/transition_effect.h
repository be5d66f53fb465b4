// Surface transitions: the scenario's `transition:` block. Part of the built-in controller
// (sim/controller.h): while the CPG walks, Watch() looks at what the front pads touch; a front
// pad that touches a surface whose normal is more than trigger_angle_deg from the one the
// robot stands on is a corner. The manoeuvre then takes the legs over from the CPG and the
// reflexes (the caller suspends both) and runs a planned free gait (sim/corner_plan.h has the
// geometry):
//
//   corner   from the touch: the new surface's plane (contact point and normal) and the old
//            one's (the attached pads' faces); their line is the corner; inner when the new
//            surface faces the robot (floor to wall, wall to ceiling), outer when it faces
//            the way the robot goes (a wall over its top edge). 90-degree corners only.
//   settle   every foot that is not attached is placed back on the old surface.
//   body     the body follows the plan's path round the corner and on along the new surface
//            for as long as the run lasts; the stance feet stay where they stuck and carry it:
//            their joint targets come from the commanded body pose through the legs'
//            kinematics, the ankle tilt turning each pad to its surface.
//   steps    the body moves while every stance leg stays margin_rad inside its joint ranges;
//            when one would not, that leg steps to the plan's next foothold for it: it waits
//            until every other pad is attached and bonded (support_bond_fraction), peels its
//            pad (drawn back and away, the ankle tilt turning the pad the same way), swings to
//            the foothold (lifted off the surface it leaves, turned to face the one it lands on,
//            round the edge of an outer corner), is lowered onto it and pressed until it
//            attaches (lifted and placed again when it does not). Hind feet thus let go of the
//            old surface only while every other foot holds. A leg with no foothold waits in the
//            air while at least kMinStance others stand (the spider's middle legs in mid-
//            turn) and lands as soon as it has one.
//   gait     (then: gait) once every foot is on the new surface and the body at its standing
//            height there, the feet are stepped one by one to where the CPG's gait has them at
//            a moment with every foot down; the CPG goes on from that moment with the reflexes
//            (reset), and the next corner is watched for. then: crawl keeps the free gait.
//
// Sensing only: the plan uses the pads' contacts (touch, normal, point), attachment and
// bonded fraction, the joint angles and the base pose (the IMU's), never the scene's geometry.
// Events (events.csv): transition_start (the touching pad; cause inner or outer), transition_step
// (cause peel, place or idle), transition_end (every pad on the new surface), transition_failed
// (cause peel_time_limit, place_attempts, stuck_again or no_foothold: the manoeuvre stops and
// the legs hold). summary.json's "transition" block has the times and pads. Nothing allocates
// in Watch or Update.
#ifndef CLIMBSIM_SIM_TRANSITION_EFFECT_H_
#define CLIMBSIM_SIM_TRANSITION_EFFECT_H_

#include <Eigen/Core>
#include <array>
#include <vector>

#include "sim/adhesion_effect.h"
#include "transition/corner_plan.h"
#include "sim/cpg_effect.h"
#include "sim/effect.h"
#include "scenario/scenario.h"

namespace climbsim::sim {

class TransitionEffect final : public Effect {
 public:
  // Throws InputError at the transition key when the robot has no ankle tilt servos, a leg
  // has no sticky pad or the scenario no adhesion block. `period_s` is the control period;
  // `event_pad` each leg's pad in the EventLog.
  // `cpg`: the gait the feet are handed back to (then: gait), foot space.
  TransitionEffect(const Scenario& scenario, const TransitionParams& params, const World& world,
                   AdhesionEffect* adhesion, const CpgEffect* cpg, double period_s,
                   std::vector<int> event_pad);
  const char* name() const override { return "transition"; }
  void Reset(World& world, RunContext& ctx) override;
  // While the gait runs, at each control tick after it: true when the manoeuvre starts now
  // (it has written this tick's targets; the caller then suspends the gait and the reflexes).
  bool Watch(World& world, RunContext& ctx);
  // One control tick of the manoeuvre (every leg servo and ankle tilt).
  void Update(World& world, RunContext& ctx);
  bool active() const { return mode_ != Mode::kWatching; }
  // then: gait. After the tick that handed the feet back: the phases the gait goes on from
  // (CpgEffect::Resume); the caller clears it.
  bool resume_pending() const { return resume_pending_; }
  std::span<const double> resume_theta() const { return resume_theta_; }
  void ClearResume() { resume_pending_ = false; }
  void Summarise(const World& world, nlohmann::json* summary) const override;

 private:
  enum class Mode : uint8_t { kWatching, kProbe, kSettle, kRun, kHandBack, kFailed };
  enum class StepPhase : uint8_t { kNone, kPeel, kSwing, kPlace, kRetry };
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
  };

  BodyPose ActualPose(const World& world) const;
  // The plane the attached pads stand on; false when none is attached.
  bool OldSurface(const World& world, const std::vector<LegSignals>& legs, Eigen::Vector3d* n0,
                  Eigen::Vector3d* p0) const;
  // Leg `leg`'s pad touches a surface: when it is a corner ahead, plans it and starts.
  bool Corner(World& world, RunContext& ctx, int leg);
  void Trigger(World& world, RunContext& ctx, int leg);
  // Every leg holds what the gait commanded last (stance: the attached ones).
  void HoldFeet(World& world, RunContext& ctx);
  void StartProbe(World& world, RunContext& ctx, int leg);
  void ProbeTick(World& world, RunContext& ctx);
  // Starts leg i's step to `to` (to.surface −1: up into the air, idle), peeling first if its
  // pad holds.
  void StartStep(World& world, RunContext& ctx, int leg, const Foothold& to, bool peel);
  void AdvanceStep(World& world, RunContext& ctx);
  void BeginSwing(World& world, double t);
  void RunTick(World& world, RunContext& ctx);
  void HandBackTick(World& world, RunContext& ctx);
  // A stance pad that let go is placed again; true when that started.
  bool ReplaceLost(World& world, RunContext& ctx);
  void RestoreKp(World& world) const;
  // The commanded pose with the sag correction (what the stance legs' targets come from).
  BodyPose Corrected(const BodyPose& pose) const;
  void TrackBody(const World& world);
  void Fail(RunContext& ctx, int leg, const char* why);
  void Log(RunContext& ctx, int leg, const char* kind, const char* cause) const;
  void WriteTargets(World& world) const;
  bool SupportsHold(int except, const std::vector<LegSignals>& legs) const;
  int StanceCount() const;
  Eigen::Vector3d StanceTarget(int i) const;
  // Leg i's joints for its stance target with the body at `pose` (idle legs: its ankle held
  // in the body frame), skipped when the inputs are those of its last converged solve.
  void HoldLeg(int i, const BodyPose& pose);
  // Leg i's q and tilt are its solve for these inputs, converged when err_m < kSolvedM.
  void Remember(int i, const BodyPose& pose, const Eigen::Vector3d& target, double err_m);

  TransitionParams params_;
  AdhesionEffect* adhesion_;
  double dt_;
  std::vector<int> event_pad_;
  CornerPlan plan_;
  std::vector<int> front_;  // legs whose hips are ahead of the base origin
  std::vector<std::array<double, 3>> kp_;  // each leg servo's kp as compiled
  const CpgEffect* cpg_;
  std::vector<double> resume_theta_;  // sized once
  bool resume_pending_ = false;
  double raise_t0_ = -1.0, raise_m_ = 0.0;  // the body's rise before the hand-back
  bool raised_ = false;
  std::vector<uint8_t> handed_;  // legs stepped to the gait's feet (sized once)
  std::vector<double> air_since_;  // per leg: since when it has not touched (−1: unknown)
  // The probe for an edge.
  int probe_leg_ = -1, probe_phase_ = 0;
  double probe_t0_ = 0.0;
  BodyPose probe_start_;
  Eigen::Vector3d probe_n0_ = Eigen::Vector3d::UnitZ(), probe_p0_ = Eigen::Vector3d::Zero(),
                  probe_fwd_ = Eigen::Vector3d::UnitX();
  BodyPose raise_from_;

  Mode mode_ = Mode::kWatching;
  std::vector<Foot> feet_;
  std::vector<uint8_t> attached_;  // last tick's attachment, for the bookkeeping
  double sigma_ = 0.0, idle_check_ = 0.0;
  BodyPose cmd_;
  Eigen::Vector3d corr_p_ = Eigen::Vector3d::Zero(), corr_w_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d corr_r_ = Eigen::Matrix3d::Identity();  // Exp(corr_w_), for Corrected
  int track_every_ = 1, track_tick_ = 0;  // the correction's period, in control ticks
  Eigen::Vector3d up_ = Eigen::Vector3d::UnitZ();  // against gravity
  // The stepping leg.
  int step_leg_ = -1;
  StepPhase step_ = StepPhase::kNone;
  double step_t0_ = 0.0, touch_since_ = -1.0, place_d_ = 0.0;
  int attempts_ = 0;
  Foothold to_;
  LegChain::Q swing_q_{};  // the joints the swing started from
  Eigen::Vector3d from_face_ = Eigen::Vector3d::Zero(), from_normal_ = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d via_ = Eigen::Vector3d::Zero();
  bool use_via_ = false;
  Eigen::Vector3d peel_dir_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d peel_from_ = Eigen::Vector3d::Zero();  // the pull a new try starts from
  int peel_attempts_ = 0;

  // What the summary reports.
  double trigger_time_s_ = -1.0, end_time_s_ = -1.0, fail_time_s_ = -1.0;
  int trigger_leg_ = -1, trigger_geom_ = -1, fail_leg_ = -1;
  const char* fail_why_ = "";
  double last_old_detach_s_ = -1.0, first_new_attach_s_ = -1.0;
  int last_old_leg_ = -1, first_new_leg_ = -1;
  long steps_ = 0;
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_TRANSITION_EFFECT_H_
