// The controller interface: what a robot's controller senses and what it commands, once per
// control period. climbsim's own CPG + reflex controller (the scenario's `cpg:` and `reflex:`
// blocks) is one implementation (CpgReflexController); a user's is another, set on the
// Simulation from C++ (Simulation's constructor) or Python (python/). When both run, the
// built-in one acts first and the user's sees its command and may change it: write offsets
// on top of the CPG's targets, replace the targets, or let pads go.
//
// Timing: at every control tick (step k with k mod period_steps = 0, before that step's
// mj_step) the pipeline fills an Observation, calls Update, and applies the Command:
//   ctrl[leg i, joint j] = target_rad[3i + j] + offset_rad[3i + j]    (rad, position servos)
//   kp[leg i, joint j]   = kp_scale[3i + j] · the servo's own kp        (N·m/rad)
//   release[i] != 0  →  the pad of leg i lets go now (detach event, cause "released")
// The command is held (sample and hold) until the next tick. The period is the CPG's
// (cpg.control_period_s, whose default 0 is every physics step) when a CPG runs, else the
// user controller's control_period_s() (0: every physics step).
//
// Stiffness: kp_scale is the servo's stiffness as a fraction of its own kp (the MJCF
// <position kp>, mjcf/README.md), clamped to [0, 1]: a smart servo lowers its P gain at run
// time (compliance, yielding), but a gain above the one modelled would be a stiffer servo
// than the robot has (its torque limit, damping and the time step are sized for that kp).
// 0 leaves the joint to its damping alone (torque off). The built-in reflexes' stance
// compliance and GTO unloading write it (reflex.compliance, reflex.gto); a later controller
// of the chain sees their values and may change them. NaN is an error.
//
// Units and frames (SI): joint angles in rad, joint velocities in rad/s, in the robot's leg
// order (custom text climbsim_legs) and joint order hip_yaw, hip_pitch, knee (mjcf/README.md).
// Base position in m and orientation as a unit quaternion (w, x, y, z), world frame; base
// linear velocity in m/s in the world frame, angular velocity in rad/s in the base frame
// (MuJoCo's free-joint qvel). Pad values are those of the last physics step.
//
// No allocation: an implementation must not allocate in Update (the views below point into
// buffers the pipeline sizes once; tests/sim/controller_test.cc counts allocations).
#ifndef CLIMBSIM_SIM_CONTROLLER_H_
#define CLIMBSIM_SIM_CONTROLLER_H_

#include <array>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "sim/effect.h"

namespace climbsim::sim {

class AdhesionEffect;
class CpgEffect;
class ReflexEffect;
class TransitionEffect;

// One leg's pad as the adhesion effect sees it (all false / 0 without an adhesion block).
struct PadSense {
  bool touching = false;         // in contact with the surface
  bool attached = false;         // bonded (weld or adhesion actuator on)
  double bonded_fraction = 0.0;  // bonded share of the pad's area, 0..1
  double normal_load_n = 0.0;    // load along the pad normal, + pulls the pad off (N)
  double preload_n = 0.0;        // compressive contact force on the pad (N)
  double utilisation = 0.0;      // peak bond stress / strength, ≥ 1 breaks (0 when not bonded)
};

// What a controller reads at a control tick. Spans stay valid for the whole run.
struct Observation {
  long step = 0;        // physics steps done
  double time_s = 0.0;  // simulated time
  int legs = 0;
  std::span<const double> joint_angle_rad;       // legs × 3
  std::span<const double> joint_velocity_rad_s;  // legs × 3
  std::array<double, 3> base_pos_m{};
  std::array<double, 4> base_quat{1, 0, 0, 0};  // w, x, y, z
  std::array<double, 3> base_linvel_m_s{};      // world frame
  std::array<double, 3> base_angvel_rad_s{};    // base frame
  std::span<const PadSense> pads;               // one per leg
  std::span<const double> cpg_phase_rad;        // one per leg; empty when no CPG runs
  std::span<const uint8_t> cpg_stance;          // 1 when the CPG has the leg in stance
};

// What a controller writes. On entry: the previous controller's command in the chain (the
// built-in CPG's targets when it runs), else the targets held since the last tick, with
// offsets and releases at zero.
struct Command {
  std::span<double> target_rad;  // legs × 3, absolute servo targets
  std::span<double> offset_rad;  // legs × 3, added to the targets
  std::span<uint8_t> release;    // one per leg: non-zero lets that leg's pad go now
  std::span<double> kp_scale;    // legs × 3, servo stiffness over its own kp, [0, 1]; held
};

// The starting pose, which a controller may set before the first step (the CPG puts the
// legs where its gait starts). Joint angles as above; base position in m, world frame.
struct StartPose {
  std::span<double> joint_angle_rad;  // legs × 3
  std::array<double, 3> base_pos_m{};
};

class Controller {
 public:
  virtual ~Controller() = default;
  // Shown in summary.json's "effects" list and by `bench speed`.
  virtual const char* name() const { return "controller"; }
  // Wanted control period in s, used when no CPG runs; 0 = every physics step.
  virtual double control_period_s() const { return 0.0; }
  // Called once per reset (run start), before Reset: may change the start pose.
  virtual void InitialPose(StartPose* pose) { (void)pose; }
  // Back to the controller's initial state; called at each run start, after InitialPose.
  virtual void Reset() {}
  // One control tick: read `obs`, write `cmd`. Must not allocate.
  virtual void Update(const Observation& obs, Command* cmd) = 0;
  // Controller-specific figures for summary.json.
  virtual void Summarise(nlohmann::json* summary) const { (void)summary; }
};

// --- The pipeline side (sim/simulation.cc builds these) ---

// climbsim's own controller: the scenario's cpg block (CpgEffect) and, when given, its reflex
// block (ReflexEffect) acting on it, composed as before the interface existed: reflexes
// first, then the CPG, at the CPG's period. Its command is the servo targets the CPG wrote
// (reflex offsets included); reflex pad releases go straight through the adhesion effect.
// With a transition block (TransitionEffect) it watches the front pads after the CPG; once a
// corner is sensed the manoeuvre drives every leg (and the ankle tilts) instead, and the CPG
// and the reflexes are suspended until it hands the feet back (transition.then: gait).
class CpgReflexController final : public Controller {
 public:
  CpgReflexController(World& world, RunContext& ctx, std::unique_ptr<CpgEffect> cpg,
                      std::unique_ptr<ReflexEffect> reflex,
                      std::unique_ptr<TransitionEffect> transition = nullptr);
  ~CpgReflexController() override;
  const char* name() const override {
    if (transition_) return reflex_ ? "cpg+reflex+transition" : "cpg+transition";
    return reflex_ ? "cpg+reflex" : "cpg";
  }
  double control_period_s() const override;
  void InitialPose(StartPose* pose) override;
  void Reset() override;
  void Update(const Observation& obs, Command* cmd) override;
  void Summarise(nlohmann::json* summary) const override;
  const CpgEffect& cpg() const { return *cpg_; }
  const TransitionEffect* transition() const { return transition_.get(); }

 private:
  World& world_;
  RunContext& ctx_;
  std::unique_ptr<CpgEffect> cpg_;
  std::unique_ptr<ReflexEffect> reflex_;
  std::unique_ptr<TransitionEffect> transition_;
};

// The effect that runs a chain of controllers (the built-in one first when the scenario has
// a cpg block, then the user's) at each control tick and applies their command.
class ControllerEffect final : public Effect {
 public:
  // `chain` is not empty; `period_steps` ≥ 1; `adhesion` may be null (releases then do
  // nothing); `has_cpg`: the legs' CPG phases are observed.
  ControllerEffect(const World& world, std::vector<std::shared_ptr<Controller>> chain,
                   int period_steps, AdhesionEffect* adhesion, bool has_cpg);
  const char* name() const override { return name_.c_str(); }
  bool has_before_step() const override { return true; }
  void InitialPose(World& world, RunContext& ctx) override;
  void Reset(World& world, RunContext& ctx) override;
  void BeforeStep(World& world, RunContext& ctx) override;
  void Summarise(const World& world, nlohmann::json* summary) const override;

  int period_steps() const { return period_steps_; }
  // The last command applied (after every controller of the chain), and what was observed
  // (filled only when a user's controller runs: the built-in one reads the world itself).
  const Command& command() const { return command_; }
  const Observation& observation() const { return obs_; }
  long ticks() const { return ticks_; }

 private:
  void Observe(const World& world, const RunContext& ctx);
  void ObservePhases(const RunContext& ctx);

  std::vector<std::shared_ptr<Controller>> chain_;
  std::string name_;
  int period_steps_;
  AdhesionEffect* adhesion_;
  bool has_cpg_;
  bool observe_ = false;  // some controller of the chain reads the Observation
  long ticks_ = 0;
  std::vector<double> q_, qd_, phase_, target_, offset_;
  // Stiffness: the command's scale, the scale last written into the model, the servos' own
  // kp, and whether each is a position servo (gain kp, bias −kp·q) whose kp can be scaled.
  std::vector<double> kp_scale_, kp_applied_, kp_own_;
  std::vector<int> actuator_;
  std::vector<uint8_t> scalable_;
  void ApplyStiffness(World& world);
  void RestoreStiffness(World& world);
  std::vector<uint8_t> stance_, release_;
  std::vector<PadSense> pads_;
  Observation obs_;
  Command command_;
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_CONTROLLER_H_
