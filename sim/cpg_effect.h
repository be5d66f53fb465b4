// The CPG effect: one oscillator per leg (cpg/), its phase shaped into joint targets for the
// position servos, either in joint space or in foot space (straight foot paths through the
// legs' inverse kinematics, sim/leg_ik.h). Control runs every control_period_s with
// sample-and-hold: at a tick the targets for the current phase are written to ctrl, then
// the oscillators advance one period with this tick's feedback:
//   Tegotae:  dθ_i/dt += −σ·N_i·cos θ_i (N_i: the pad's normal load, from the adhesion effect)
//   hold:     the oscillator of every leg in stance is held (its state does not change) while
//             any leg must wait: a reflex
//             asks for it (LegSignals::hold_stance in stance, hold_phase,
//             RunContext::hold_all_stance) or, with wait_for_support, a leg in the last two
//             ticks of its stance waits for the legs that carry the robot through its swing
//             to be attached. All stance legs pause because feet welded to a wall must keep
//             moving together (a leg that stopped alone would push against the others);
//             legs in swing go on, so the legs being waited for can land. A leg holding its
//             phase (hold_phase, a peel) pauses in swing too.
// Reflex offsets (LegSignals::offset_rad) are added to the targets.
// A stall: a hold that lasts to the end of the run, at least two strides (2 / frequency_hz)
// and 1 s long. Summarise then sets summary.json's stalled, stall_time_s (the hold's start),
// stall_leg (the leg that holds: the one waited for) and stall_reason.
#ifndef CLIMBSIM_SIM_CPG_EFFECT_H_
#define CLIMBSIM_SIM_CPG_EFFECT_H_

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "cpg/cpg.h"
#include "sim/effect.h"
#include "scenario/scenario.h"
#include "robot/leg_ik.h"

namespace climbsim::sim {

class CpgEffect final : public Effect {
 public:
  // Throws InputError (at the cpg keys) when the gait does not fit the robot's legs.
  CpgEffect(const Scenario& scenario, const CpgParams& params, const World& world);
  const char* name() const override { return "cpg"; }
  bool has_before_step() const override { return true; }
  // The legs start where the gait puts them at t = 0 (foot space, or joint space at the start
  // amplitude): feet welded to a wall at the start then need not move against each other.
  void InitialPose(World& world, RunContext& ctx) override;
  void Reset(World& world, RunContext& ctx) override;
  void BeforeStep(World& world, RunContext& ctx) override;
  void Summarise(const World& world, nlohmann::json* summary) const override;

  // The parameters as resolved (gait name, duty factor, joint-space defaults filled in).
  const CpgParams& resolved() const { return params_; }
  const cpg::OscillatorNetwork& network() const { return *network_; }
  // The leg whose attached pad wait_for_support holds the gait for at the last tick (it has not
  // bonded support_bond_fraction), or -1.
  int awaited_bond_leg() const {
    const bool waiting = hold_since_s_ >= 0.0 && hold_.cause == HoldCause::kWaitForSupport;
    return waiting && hold_.attached ? hold_.leg : -1;
  }
  // When the hold that stands the gait still now began (s), or −1 when it moves.
  double held_since_s() const { return hold_since_s_; }
  // Legs that must be attached before leg i may swing (wait_for_support).
  const std::vector<std::vector<int>>& support() const { return support_; }
  double control_period_s() const { return period_s_; }
  // Another controller takes the legs (a surface transition): a hold under way is not a stall.
  void Suspend() { hold_since_s_ = -1.0; }
  // Foot space (stride_m given): the gait's feet can be asked for and the gait resumed.
  bool foot_space() const { return ik_.has_value(); }
  // Leg i's foot at oscillator phase `theta_rad`, foot space: *dx along the body axis and *dz
  // along its normal (+ away from the surface) from the neutral foot, press and crouch
  // included. Returns whether the leg is in stance there.
  bool FootAt(int i, double theta_rad, double* dx, double* dz) const;
  // The phases of a moment of the gait with every foot down (the leg that swings next at
  // the end of its stance), into `theta_rad` (one per leg). No allocation.
  void ResumePhases(std::span<double> theta_rad) const;
  // The oscillators jump to `theta_rad` and the gait goes on from there (after another
  // controller had the legs and put the feet where FootAt says). Its targets start from the
  // servos' current ones (ctrl) and blend into the gait's over kResumeBlendS.
  void Resume(std::span<const double> theta_rad, const World& world);
  static constexpr double kResumeBlendS = 0.5;

 private:
  // Construction: the checks the reader could not make, then the gait, the leg shape and
  // the squeeze's sides.
  void CheckFitsScenario(const Scenario& scenario, int n) const;
  void ResolveGait(int n);
  void ResolveShape(const Scenario& scenario, const World& world);
  void ResolveSqueezeSigns(const World& world);
  std::unique_ptr<cpg::OscillatorNetwork> MakeNetwork() const;
  void WriteTargets(World& world, RunContext& ctx);
  // This tick's targets of leg i (before reflex offsets); sets its LegSignals' CPG fields.
  std::array<double, 3> Targets(size_t i, LegSignals* s) const;
  void Feedback(RunContext& ctx);
  // cpg.spine: this tick's spine_yaw target, locked to the first leg's oscillator.
  double SpineTarget() const;

  CpgParams params_;
  std::vector<double> offsets_cycles_;
  Eigen::MatrixXd bias_;
  double gait_duty_ = 0.5;
  std::unique_ptr<cpg::OscillatorNetwork> network_;
  cpg::LegShape shape_;
  std::optional<LegIk> ik_;
  double posture_crouch_m_ = 0.0;  // RunContext::crouch_m at the last WriteTargets (foot space)
  std::vector<std::vector<int>> support_;
  int period_steps_ = 1;
  double period_s_ = 0.0;
  std::vector<double> feedback_;  // rad/s per oscillator, sized once
  std::vector<std::array<double, 3>> blend_;  // per leg: ctrl − target at Resume, sized once
  int blend_ticks_ = 0, blend_left_ = 0;
  std::vector<uint8_t> held_;     // oscillators held this tick
  std::vector<double> squeeze_sign_;
  bool placing_ = false;  // InitialPose: targets without the squeeze  // +1 legs ahead of the
                          // middle, −1 behind, 0 at it

  // What holds the gait (a stall when it lasts to the end of the run: Summarise).
  enum class HoldCause : uint8_t { kNone, kReflexAll, kHoldPhase, kHoldStance, kWaitForSupport };
  struct Hold {
    HoldCause cause = HoldCause::kNone;
    int leg = -1;          // the leg that holds: the one waited for, or the one asking
    int waiting_leg = -1;  // wait_for_support: the leg that cannot swing
    bool attached = false;
    double bonded_fraction = 0.0;
  };
  double hold_since_s_ = -1.0;  // start of the current hold, -1 when none
  Hold hold_;
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_CPG_EFFECT_H_
