// The CPG effect: one oscillator per leg (cpg/), its phases shaped into joint targets for
// the position servos. Control runs every control_period_s with sample-and-hold: at a tick
// the targets for the current phase are written to ctrl, then the oscillators advance one
// period. Reflex offsets (LegSignals::offset_rad) are added to the targets.
#ifndef CLIMBSIM_SIM_CPG_EFFECT_H_
#define CLIMBSIM_SIM_CPG_EFFECT_H_

#include <memory>
#include <string>
#include <vector>

#include "cpg/cpg.h"
#include "sim/effect.h"
#include "sim/effect_params.h"

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

  // The gait as resolved (preset name or "explicit") and its duty factor.
  const std::string& gait() const { return gait_name_; }
  double duty_factor() const { return shape_.duty_factor; }
  const cpg::OscillatorNetwork& network() const { return *network_; }

 private:
  void WriteTargets(World& world, RunContext& ctx);

  CpgParams params_;
  std::string gait_name_;
  std::vector<double> offsets_cycles_;
  std::unique_ptr<cpg::OscillatorNetwork> network_;
  cpg::PhaseNetworkParams phase_params_;
  cpg::LegShape shape_;
  int period_steps_ = 1;
  double period_s_ = 0.0;
  std::vector<double> feedback_;  // rad/s per oscillator, sized once
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_CPG_EFFECT_H_
