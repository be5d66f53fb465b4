#include <algorithm>
#include <chrono>
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

// J for a rollout whose base has moved `distance_m` along the travel direction: the one
// formula behind the finished run's cost and the early-stopped one's.
Cost CostOf(const sim::Simulation& sim, double distance_m, const sim::ObjectiveParams& o) {
  Cost c;
  const sim::RunResult& r = sim.result();
  if (!r.stable) {
    c.failed = true;
    c.failure = r.failure;
    c.total = kFailedCost;
    return c;
  }
  const nlohmann::json summary = sim.Summary();
  const sim::World& w = sim.world();
  // Cost of transport as Simulation::Summary computes it, with this distance.
  const double cot =
      r.actuator_work_j / (w.robot().mass_kg * w.gravity().norm() * std::max(distance_m, 1e-3));
  c.speed_mps = distance_m / sim.scenario().duration_s;
  c.fall_penalty = r.fell ? o.fall_penalty_mps : 0.0;
  c.overload_penalty = o.overload_penalty_mps * OverloadDetaches(summary);
  c.energy_penalty = o.energy_weight_mps * cot;
  c.total = -c.speed_mps + c.fall_penalty + c.overload_penalty + c.energy_penalty;
  return c;
}

Eigen::Vector3d BasePosition(const sim::Simulation& sim) {
  const double* q = sim.world().data()->qpos + sim.world().robot().root_qpos_adr;
  return {q[0], q[1], q[2]};
}

}  // namespace

Cost RolloutCost(const sim::Simulation& sim, const sim::ObjectiveParams& o) {
  return CostOf(sim, sim.result().distance_m, o);
}

Cost NominalCost(const sim::Simulation& sim) {
  return RolloutCost(sim, sim.scenario().optimise ? sim.scenario().optimise->objective
                                                  : sim::ObjectiveParams{});
}

Cost RunRollout(sim::Simulation& sim, const sim::ObjectiveParams& o, double bound_j) {
  const auto t0 = std::chrono::steady_clock::now();
  const double dt = sim.world().model()->opt.timestep;
  const double T = sim.scenario().duration_s;
  const long total = sim.steps_total();
  const Eigen::Vector3d start = BasePosition(sim);
  const Eigen::Vector3d travel = sim.world().scene().travel;
  auto distance = [&] { return travel.dot(BasePosition(sim) - start); };

  // The rules are checked every 50 ms of simulated time; the stall rule keeps the distance
  // of the last stall_window_s at those checks in a ring (allocated here, not in the loop).
  const long every = std::max<long>(1, std::lround(0.05 / dt));
  const bool stall_on = o.stall_window_s > 0;
  const size_t window =
      stall_on ? static_cast<size_t>(std::ceil(o.stall_window_s / (every * dt))) : 0;
  std::vector<double> ring(window + 1, 0.0);
  size_t checks = 0;
  const bool bound_on = o.max_speed_mps > 0 && std::isfinite(bound_j);

  std::string rule;
  long step = 0;
  double d = 0.0;
  while (step < total) {
    const bool go = sim.Step();
    ++step;
    if (!go) break;  // fell (fall.stop is set) or numerically bad: exact
    if (step % every != 0 || step == total) continue;
    d = distance();
    if (stall_on) {
      ring[checks % ring.size()] = d;
      // d `window` checks ago is the oldest entry of the ring once it is full.
      if (checks >= window && d - ring[(checks - window) % ring.size()] < o.stall_distance_m) {
        rule = "stalled";
        break;
      }
    }
    ++checks;
    if (bound_on) {
      // Even at max_speed_mps from now on, with no penalty added, J stays above the bound.
      const double t = step * dt;
      const Cost now = CostOf(sim, d, o);
      const double lower =
          -(d + o.max_speed_mps * (T - t)) / T + now.fall_penalty + now.overload_penalty;
      if (lower > bound_j) {
        rule = "bound";
        Cost c = now;
        c.energy_penalty = 0.0;
        c.total = lower;
        c.early_stop = rule;
        c.stop_time_s = t;
        c.wall_time_s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        return c;
      }
    }
  }
  if (rule.empty()) d = distance();
  Cost c = CostOf(sim, d, o);
  c.early_stop = rule;
  c.stop_time_s = step * dt;
  c.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return c;
}

}  // namespace climbsim::optimise
