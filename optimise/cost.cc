#include <cmath>

#include "optimise/optimise.h"

namespace climbsim::optimise {
namespace {

// Pads detached by overload, from the adhesion effect's summary (0 without adhesion).
int OverloadDetaches(const nlohmann::json& summary) {
  int n = 0;
  if (!summary.contains("adhesion") || !summary["adhesion"].contains("pads")) return 0;
  for (const auto& [pad, counts] : summary["adhesion"]["pads"].items()) {
    if (counts.contains("detach_overload")) n += counts["detach_overload"].get<int>();
  }
  return n;
}

}  // namespace

Cost RolloutCost(const sim::Simulation& sim, const sim::ObjectiveParams& o) {
  Cost c;
  const sim::RunResult& r = sim.result();
  if (!r.stable) {
    c.failed = true;
    c.failure = r.failure;
    c.total = kFailedCost;
    return c;
  }
  const nlohmann::json summary = sim.Summary();
  c.speed_mps = r.distance_m / sim.scenario().duration_s;
  c.fall_penalty = r.fell ? o.fall_penalty_mps : 0.0;
  c.overload_penalty = o.overload_penalty_mps * OverloadDetaches(summary);
  c.energy_penalty = o.energy_weight_mps * summary["cost_of_transport"].get<double>();
  c.total = -c.speed_mps + c.fall_penalty + c.overload_penalty + c.energy_penalty;
  return c;
}

Cost NominalCost(const sim::Simulation& sim) {
  return RolloutCost(sim, sim.scenario().optimise ? sim.scenario().optimise->objective
                                                  : sim::ObjectiveParams{});
}

}  // namespace climbsim::optimise
