// The reflex effect: one reflex::LegReflex per leg (reflex/), between the adhesion effect
// and the CPG in the pipeline. At each control tick (the CPG's period) it reads each leg's
// signals (the CPG's stance flag and progress of the last tick, the pad's state from the
// adhesion effect, the joints' stretch from the CPG's targets and their velocity), and writes
//   LegSignals::offset_rad     added by the CPG to its targets,
//   LegSignals::hold_stance    the leg may not leave stance yet,
//   LegSignals::hold_phase     the leg's phase is held (a peel that has not let go),
//   RunContext::hold_all_stance  a re-grip asks every leg to stay in stance,
// and one events.csv row per reflex event, on the leg's pad. With release_failed_peel, a
// peel that runs out of time lets the pad go through the adhesion effect (cause released).
// Stance compliance and GTO unloading ask for each leg servo's stiffness as a fraction f of
// its kp (LegSignals::kp_fraction = LegReflexOutput::kp_fraction), which the built-in
// controller hands on as its Command::kp_scale, the channel a user's controller has too; the
// pipeline sets kp' = f·kp on the run's own model copy (sim/controller.h). Reset and Suspend
// restore every kp at once.
#ifndef CLIMBSIM_SIM_REFLEX_EFFECT_H_
#define CLIMBSIM_SIM_REFLEX_EFFECT_H_

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "reflex/reflex.h"
#include "sim/adhesion_effect.h"
#include "sim/cpg_effect.h"
#include "sim/effect.h"
#include "sim/tail_driver.h"
#include "scenario/scenario.h"

namespace climbsim::sim {

class ReflexEffect final : public Effect {
 public:
  // `cpg` gives the control period and each leg's support legs; `adhesion` may be null (then
  // no pad ever touches or attaches, and only the stretch and load laws act). `event_pad` is
  // each leg's pad index in the EventLog, then, with reflex.tail, the tail's. Throws InputError at the reflex key at fault.
  ReflexEffect(const Scenario& scenario, const ReflexParams& params, const World& world,
               const CpgEffect& cpg, AdhesionEffect* adhesion, std::vector<int> event_pad);
  const char* name() const override { return "reflex"; }
  bool has_before_step() const override { return true; }
  void Reset(World& world, RunContext& ctx) override;
  void BeforeStep(World& world, RunContext& ctx) override;
  void Summarise(const World& world, nlohmann::json* summary) const override;
  // Leg i's reflexes (their parameters: peel.against_grip sets each leg's own peel sign).
  const reflex::LegReflex& leg(int i) const { return legs_[i]; }
  int leg_count() const { return static_cast<int>(legs_.size()); }
  // Another controller takes the legs (a surface transition): every servo back to its own kp,
  // no offsets, holds or peels left behind.
  void Suspend(World& world, RunContext& ctx);

 private:
  ReflexParams params_;
  AdhesionEffect* adhesion_;
  const CpgEffect* cpg_;  // owned beside this by the controller: its wait's awaited pad
  std::vector<std::vector<int>> support_;
  std::vector<std::vector<int>> supported_;  // per leg, the legs it supports (support_ inverted)
  std::vector<char> waited_on_;  // per leg: the gait waits for its pad (MarkWaitedOn)
  reflex::PushHold push_hold_;   // the spindles' push hold for the robot
  std::vector<int> event_pad_;
  std::vector<reflex::LegReflex> legs_;
  std::vector<std::array<long, reflex::kMaxLegEvents>> counts_;  // per leg, per LegEventType
  std::vector<std::array<int, 3>> actuator_;   // per leg, hip_yaw, hip_pitch, knee servo
  std::vector<std::array<double, 3>> kp_;      // their kp as compiled
  int period_steps_ = 1;
  // Load sharing (the GTO's robot-level channel, reflex/load_sharing.h): the law, each leg's
  // input, and the ankle's Jacobian buffer (3 × nv, sized once).
  std::optional<reflex::LoadSharing> sharing_;
  std::vector<reflex::SharingLeg> sharing_in_;
  std::vector<std::array<double, 3>> share_offset_;  // per leg, Δq of the last sharing run
  int share_every_ = 1;       // control periods between sharing runs
  std::vector<bool> unload_;  // per leg: its active-release peel asks the others to take its load
  std::vector<double> jacp_;
  // The GTO's posture channel (reflex.gto.posture): the crouch it gives the CPG, from the
  // attached pads' pull over the robot's own weight (weight_n_).
  std::optional<reflex::PostureReflex> posture_;
  double weight_n_ = 0.0;
  std::optional<TailDriver> tail_;  // reflex.tail (sim/tail_driver.h)

  // The gradient of leg i's pad utilisation with respect to the force the leg puts on the pad
  // at its ankle, world frame; false when the pad is not attached or it is not defined.
  bool UtilisationGradientWorld(const World& world, int leg, Eigen::Vector3d* grad) const;
  // waited_on_: the legs whose pad a peel or the standing gait waits for (at time_s), from
  // every leg's last period.
  void MarkWaitedOn(const std::vector<LegSignals>& signals, double time_s);
  // Runs the load sharing: each leg's Δq = Kp⁻¹·Jᵀ·λ into share_offset_.
  void ShareLoad(World& world, std::vector<LegSignals>& signals);

  // Force tracking (reflex.gto.share.mode force_tracking): each attached directional pad's
  // force error into sharing_in_ (the targets: reflex/load_sharing.h, GripShearTargets).
  struct TrackedPad {
    Eigen::Vector3d grip, normal, force;  // world; force: what the leg puts on the pad
    double shear = 0.0, pull = 0.0, need = 0.0;  // N: along grip, along normal, least shear
    double mu = 0.0;                             // the pad's friction coefficient
  };
  static constexpr double kReleaseShearN = 0.02;  // gripping shear a pad being let go keeps
  // A pad being let go with reversed shear F_t < 0 stays pressed by this times |F_t|/μ, half
  // again what friction needs, until its shear is turned round.
  static constexpr double kReleasePressFactor = 1.5;
  std::vector<TrackedPad> tracking_;
  std::vector<reflex::GripShare> grip_share_;
  std::vector<double> grip_target_;
  bool common_grip_ = true;  // every pad grips along one direction in its own frame
  void TrackingErrors(const World& world);

  // The landing channel (reflex.landing): per leg, whether its pad was attached at the last
  // tick and the settled offset.
  struct LandingState {
    bool attached = false;
    std::array<double, 3> offset_rad{};
  };
  std::vector<LandingState> landing_;
  void Land(World& world, std::vector<LegSignals>& signals);
  // Leg i's pad's gripping direction (unit), world frame; its pad is frictional.
  Eigen::Vector3d GripDirectionWorld(const World& world, int leg) const;
  void RequireFrictionalPads(const Scenario& scenario, int legs, const std::string& key,
                             const std::string& why) const;

  // Construction: the checks (ScenarioError at the key), then the wiring.
  bool SharingOn() const;  // the GTO's load sharing runs (gto on, gain > 0, pads)
  void CheckScenario(const Scenario& scenario, const World& world, const CpgEffect& cpg,
                     double dt) const;
  void CheckServos(const Scenario& scenario, const World& world) const;
  void BuildLegs(const World& world, double dt);
  void BuildSharing(const World& world, double dt);

  // One control tick, in BeforeStep's order (nothing allocates).
  reflex::LegSensing SenseLeg(const World& world, std::vector<LegSignals>& signals,
                              size_t i) const;
  void ApplyLeg(LegSignals& s, size_t i, const reflex::LegReflexOutput& out);
  void LogEvents(RunContext& ctx, const LegSignals& s, size_t i,
                 const reflex::LegReflexOutput& out);
  void RobotChannels(World& world, RunContext& ctx);
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_REFLEX_EFFECT_H_
