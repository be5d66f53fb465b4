// The corner manoeuvre's state machine: the scenario's `transition:` block as a run drives it
// (sim/transition_effect.h is the adapter that reads the world and the adhesion effect for it,
// and writes its servo targets and events). While the CPG walks, Watch() looks at what the
// front pads touch; a front pad that touches a surface whose normal is more than
// trigger_angle_deg from the one the robot stands on is a corner. The manoeuvre then takes the
// legs over from the CPG and the reflexes (the caller suspends both) and runs a planned free
// gait (corner_plan.h has the geometry):
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
// Sensing only (ManoeuvreIo): the pads' signals (touch, attachment, bonded fraction, preload),
// their contacts (normal, point), faces and loads, the joint angles and the base pose (the
// IMU's), never the scene's geometry. Events: transition_start (the touching pad; cause inner
// or outer), transition_step (cause peel, place or idle), transition_end (every pad on the new
// surface), transition_failed (cause peel_time_limit, place_attempts, stuck_again or
// no_foothold: the manoeuvre stops and the legs hold). Nothing allocates in Watch or Update.
#ifndef CLIMBSIM_TRANSITION_MANOEUVRE_H_
#define CLIMBSIM_TRANSITION_MANOEUVRE_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "adhesion/pad_contact.h"
#include "transition/corner_plan.h"
#include "transition/moves.h"

namespace climbsim::sim {

// What the manoeuvre senses of a leg's pad each control tick (the adhesion effect's signals).
struct PadSignals {
  bool touching = false;
  bool attached = false;
  double bonded_fraction = 0.0;
  double touched_fraction = 1.0;  // the most bonded_fraction can reach (partial contact)
  double preload_n = 0.0;  // compressive contact force on the pad
  double bondable_fraction = 1.0;  // what it can still reach: touched less torn bonds
};

// What the manoeuvre reads and commands besides its pads' signals: the run's adapter
// implements it over the world, the adhesion effect and the gait. Read on demand, so that the
// manoeuvre senses exactly when it needs to.
class ManoeuvreIo {
 public:
  virtual ~ManoeuvreIo() = default;
  virtual BodyPose BasePose() const = 0;  // the IMU's
  // Leg `leg`'s pad: its face frame (world), what it touches, whether its bonds hold and the
  // load they carry (fx, fy, fn: the face frame).
  virtual adhesion::PadFrame PadFace(int leg) const = 0;
  virtual const adhesion::ContactSense& PadContact(int leg) const = 0;
  virtual bool PadHolds(int leg) const = 0;
  virtual Eigen::Vector3d PadLoad(int leg) const = 0;
  virtual LegChain::Q Joints(int leg) const = 0;  // the joint angles
  // The servo targets the gait wrote last (leg servos and ankle tilt).
  virtual void Commanded(int leg, LegChain::Q* q, double* tilt) const = 0;
  // A peel in progress (a detach meanwhile has cause "peel").
  virtual void SetPeeling(int leg, bool peeling) = 0;
  // then: gait. Where the gait has foot `leg` at phase theta, and the phases it goes on from.
  virtual void GaitFoot(int leg, double theta_rad, double* dx, double* dz) const = 0;
  virtual void GaitResumePhases(std::span<double> theta_rad) const = 0;
  // The leg servos' stiffness as compiled (the manoeuvre's unload law lowered it).
  virtual void RestoreKp() = 0;
  // This tick's targets: feet()' q and tilt.
  virtual void WriteTargets() = 0;
  virtual void Log(int leg, const char* kind, const char* cause) = 0;  // an event
};

// What summary.json's "transition" block reports (times < 0, legs < 0: none).
struct ManoeuvreReport {
  double trigger_time_s = -1.0, end_time_s = -1.0, fail_time_s = -1.0;
  int trigger_leg = -1, trigger_geom = -1, fail_leg = -1;
  const char* fail_why = "";
  double last_old_detach_s = -1.0, first_new_attach_s = -1.0;
  int last_old_leg = -1, first_new_leg = -1;
  long steps = 0;
};

class CornerManoeuvre {
 public:
  // `period_s`: the control period. `hand_back`: then: gait (the feet go back to the gait).
  CornerManoeuvre(CornerPlan plan, const TransitionParams& params, double period_s,
                  bool hand_back);
  void Reset();
  // Each leg's pad signals, filled by the caller before Watch and Update.
  std::vector<PadSignals>& pads() { return pads_; }
  // While the gait runs, at each control tick after it: true when the manoeuvre starts now
  // (it has written this tick's targets; the caller then suspends the gait and the reflexes).
  bool Watch(ManoeuvreIo& io, double t);
  // One control tick of the manoeuvre (every leg servo and ankle tilt).
  void Update(ManoeuvreIo& io, double t);
  bool active() const { return mode_ != Mode::kWatching; }
  bool failed() const { return mode_ == Mode::kFailed; }
  // then: gait. After the tick that handed the feet back: the phases the gait goes on from.
  bool resume_pending() const { return resume_pending_; }
  std::span<const double> resume_theta() const { return resume_theta_; }
  void ClearResume() { resume_pending_ = false; }
  // The servo targets (Foot::q, tilt) and the leg that steps (−1: none).
  const std::vector<Foot>& feet() const { return feet_; }
  int step_leg() const { return step_leg_; }
  const CornerPlan& plan() const { return plan_; }
  const ManoeuvreReport& report() const { return report_; }

 private:
  enum class Mode : uint8_t { kWatching, kProbe, kSettle, kRun, kHandBack, kFailed };
  enum class StepPhase : uint8_t { kNone, kPeel, kSwing, kPlace, kRetry };

  // The plane the attached pads stand on; false when none is attached.
  bool OldSurface(const ManoeuvreIo& io, Eigen::Vector3d* n0, Eigen::Vector3d* p0) const;
  // Leg `leg`'s pad touches a surface: when it is a corner ahead, plans it and starts.
  bool Corner(ManoeuvreIo& io, double t, int leg);
  void Trigger(ManoeuvreIo& io, double t, int leg);
  // Every leg holds what the gait commanded last (stance: the attached ones).
  void HoldFeet(const ManoeuvreIo& io, const BodyPose& pose);
  void StartProbe(ManoeuvreIo& io, double t, int leg);
  void ProbeTick(ManoeuvreIo& io, double t);
  // The probe's first phase: the body crouches on the stance feet.
  void ProbeCrouch(ManoeuvreIo& io, double t);
  // Starts leg i's step to `to` (to.surface −1: up into the air, idle), peeling first if its
  // pad holds.
  void StartStep(ManoeuvreIo& io, double t, int leg, const Foothold& to, bool peel);
  // Which way a peel pulls leg `leg`'s pad (see StartStep).
  Eigen::Vector3d PeelBack(const ManoeuvreIo& io, int leg) const;
  void AdvanceStep(ManoeuvreIo& io, double t);
  void PeelTick(ManoeuvreIo& io, double t);
  // The pad stuck again on its way: peel it again.
  void StuckAgain(ManoeuvreIo& io, double t);
  // The foot is lowered onto its foothold; *face: where its pad goes this tick. False when
  // the step ended (the foot stuck, or the manoeuvre failed).
  bool PlaceTick(ManoeuvreIo& io, double t, Eigen::Vector3d* face);
  // The foot stuck where it was placed: a stance foot from now on.
  void Landed(const ManoeuvreIo& io);
  void BeginSwing(const ManoeuvreIo& io, double t);
  void SettleTick(ManoeuvreIo& io, double t);
  void RunTick(ManoeuvreIo& io, double t);
  // A leg waiting in the air lands as soon as it has a foothold; true when one started.
  bool LandIdle(ManoeuvreIo& io, double t);
  // The body goes on along the path while every stance leg keeps its margin: −1, else the
  // leg that stops it.
  int AdvanceBody();
  // The leg that stops the body steps, once every other pad holds (and enough stand).
  void StepWorst(ManoeuvreIo& io, double t, int worst_leg);
  void HandBackTick(ManoeuvreIo& io, double t);
  // The body rises to its standing height over the new surface; false once it is there.
  bool RaiseTick(ManoeuvreIo& io, double t);
  // Steps the next foot to where the gait has it; false when every foot is there.
  bool HandBackStep(ManoeuvreIo& io, double t);
  // A stance pad that let go is placed again; true when that started.
  bool ReplaceLost(ManoeuvreIo& io, double t);
  // The last pad off the old surface and the first onto the new one.
  void Bookkeep(const ManoeuvreIo& io, double t);
  // The stance legs carry the body; the idle ones hold their place in its frame.
  void HoldLegs();
  void TrackBody(const ManoeuvreIo& io);
  void Fail(ManoeuvreIo& io, double t, int leg, const char* why);
  bool SupportsHold(int except) const;
  int StanceCount() const;
  // Leg i's joints for its stance target with the body at `pose` (idle legs: its ankle held
  // in the body frame), skipped when the inputs are those of its last converged solve.
  void HoldLeg(int i, const BodyPose& pose);

  CornerPlan plan_;
  TransitionParams params_;
  double dt_;
  bool hand_back_;
  std::vector<PadSignals> pads_;  // sized once
  std::vector<int> front_;  // legs whose hips are ahead of the base origin
  std::vector<double> resume_theta_;  // sized once
  bool resume_pending_ = false;
  double raise_t0_ = -1.0, raise_m_ = 0.0;  // the body's rise before the hand-back
  bool raised_ = false;
  std::vector<uint8_t> handed_;  // legs stepped to the gait's feet (sized once)
  std::vector<double> air_since_;  // per leg: since when it has not touched (−1: unknown)
  Probe probe_;
  BodyPose raise_from_;

  Mode mode_ = Mode::kWatching;
  std::vector<Foot> feet_;
  std::vector<uint8_t> attached_;  // last tick's attachment, for the bookkeeping
  double sigma_ = 0.0, idle_check_ = 0.0;
  BodyPose cmd_;
  SagCorrection sag_;
  int track_every_ = 1, track_tick_ = 0;  // the correction's period, in control ticks
  // The stepping leg.
  int step_leg_ = -1;
  StepPhase step_ = StepPhase::kNone;
  double step_t0_ = 0.0, touch_since_ = -1.0, place_d_ = 0.0;
  int attempts_ = 0;
  Foothold to_;
  LegChain::Q swing_q_{};  // the joints the swing started from
  SwingPath swing_;
  Eigen::Vector3d peel_dir_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d peel_from_ = Eigen::Vector3d::Zero();  // the pull a new try starts from
  int peel_attempts_ = 0;

  ManoeuvreReport report_;
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_TRANSITION_MANOEUVRE_H_
