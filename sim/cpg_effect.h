// The CPG effect: one oscillator per leg (cpg/), its phase shaped into joint targets for the
// position servos, either in joint space or in foot space (straight foot paths through the
// legs' inverse kinematics, sim/leg_ik.h). Control runs every control_period_s with
// sample-and-hold: at a tick the targets for the current phase are written to ctrl, then
// the oscillators advance one period with this tick's feedback:
//   Tegotae:  dθ_i/dt += −σ·N_i·cos θ_i (N_i: the pad's normal load, from the adhesion effect)
//   hold:     dθ_i/dt += −2πf while leg i must stay in stance: a reflex asks for it
//             (LegSignals::hold_stance, RunContext::hold_all_stance) or, with
//             wait_for_support, the legs that carry the robot through i's swing are not all
//             attached yet.
// Reflex offsets (LegSignals::offset_rad) are added to the targets.
#ifndef CLIMBSIM_SIM_CPG_EFFECT_H_
#define CLIMBSIM_SIM_CPG_EFFECT_H_

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cpg/cpg.h"
#include "sim/effect.h"
#include "sim/effect_params.h"
#include "sim/leg_ik.h"

namespace climbsim::sim {

class CpgEffect final : public Effect {
 public:
  // Throws InputError (at the cpg keys) when the gait does not fit the robot's legs.
  CpgEffect(const Scenario& scenario, const CpgParams& params, const World& world);
  const char* name() const override { return "cpg"; }
  bool has_before_step() const override { return true; }
  void Reset(World& world, RunContext& ctx) override;
  void BeforeStep(World& world, RunContext& ctx) override;
  void Summarise(const World& world, nlohmann::json* summary) const override;

  // The parameters as resolved (gait name, duty factor, joint-space defaults filled in).
  const CpgParams& resolved() const { return params_; }
  const cpg::OscillatorNetwork& network() const { return *network_; }
  // Legs that must be attached before leg i may swing (wait_for_support).
  const std::vector<std::vector<int>>& support() const { return support_; }
  double control_period_s() const { return period_s_; }

 private:
  std::unique_ptr<cpg::OscillatorNetwork> MakeNetwork() const;
  void WriteTargets(World& world, RunContext& ctx);
  void Feedback(RunContext& ctx);

  CpgParams params_;
  std::vector<double> offsets_cycles_;
  Eigen::MatrixXd bias_;
  double gait_duty_ = 0.5;
  std::unique_ptr<cpg::OscillatorNetwork> network_;
  cpg::LegShape shape_;
  std::optional<LegIk> ik_;
  std::vector<std::vector<int>> support_;
  int period_steps_ = 1;
  double period_s_ = 0.0;
  std::vector<double> feedback_;  // rad/s per oscillator, sized once
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_CPG_EFFECT_H_
