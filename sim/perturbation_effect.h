// The perturbation effect: timed pushes (xfrc_applied) on bodies, for disturbance tests. Each
// push is a constant force impulse/duration over a whole number of steps.
#ifndef CLIMBSIM_SIM_PERTURBATION_EFFECT_H_
#define CLIMBSIM_SIM_PERTURBATION_EFFECT_H_

#include <array>
#include <vector>

#include "sim/effect.h"
#include "scenario/scenario.h"

namespace climbsim::sim {

class PerturbationEffect final : public Effect {
 public:
  // Throws InputError at perturbations[i].body when a body does not exist.
  PerturbationEffect(const Scenario& scenario, const World& world);
  const char* name() const override { return "perturbation"; }
  bool has_before_step() const override { return true; }
  void Reset(World& world, RunContext& ctx) override;
  void BeforeStep(World& world, RunContext& ctx) override;

 private:
  struct Push {
    int body;
    long first_step, end_step;  // [first, end)
    std::array<double, 3> force_n;
  };
  std::vector<Push> pushes_;
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_PERTURBATION_EFFECT_H_
