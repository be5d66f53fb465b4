#include "sim/perturbation_effect.h"

#include <cmath>

namespace climbsim::sim {

PerturbationEffect::PerturbationEffect(const Scenario& scenario, const World& world) {
  const double dt = world.model()->opt.timestep;
  for (size_t i = 0; i < scenario.perturbations.size(); ++i) {
    const PushParams& p = scenario.perturbations[i];
    const int body = mj_name2id(world.model(), mjOBJ_BODY, p.body.c_str());
    if (body <= 0) {
      throw ScenarioError(scenario, "perturbations[" + std::to_string(i) + "].body",
                          "no body '" + p.body + "' in the model");
    }
    Push push;
    push.body = body;
    push.first_step = std::lround(p.time_s / dt);
    const long steps = std::max(1L, std::lround(p.duration_s / dt));
    push.end_step = push.first_step + steps;
    // The impulse is exact over the rounded duration.
    for (int k = 0; k < 3; ++k) push.force_n[k] = p.impulse_ns[k] / (steps * dt);
    pushes_.push_back(push);
  }
}

void PerturbationEffect::Reset(World& world, RunContext&) {
  for (const Push& p : pushes_) mju_zero(world.data()->xfrc_applied + 6 * p.body, 6);
}

void PerturbationEffect::BeforeStep(World& world, RunContext& ctx) {
  double* xfrc = world.data()->xfrc_applied;
  // Rebuilt every step on the pushed bodies only: pushes on one body add up.
  for (const Push& p : pushes_) mju_zero3(xfrc + 6 * p.body);
  for (const Push& p : pushes_) {
    if (ctx.step >= p.first_step && ctx.step < p.end_step) {
      for (int k = 0; k < 3; ++k) xfrc[6 * p.body + k] += p.force_n[k];
    }
  }
}

}  // namespace climbsim::sim
