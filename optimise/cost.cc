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

// The stall rule: the distance at the last stall_window_s of checks, kept in a ring
// allocated here, not in the step loop.
class StallRule {
 public:
  // Checks `every` steps of `dt`.
  StallRule(const sim::ObjectiveParams& o, long every, double dt)
      : on_(o.stall_window_s > 0),
        window_(on_ ? static_cast<size_t>(std::ceil(o.stall_window_s / (every * dt))) : 0),
        distance_m_(o.stall_distance_m),
        ring_(window_ + 1, 0.0) {}

  // A check at distance d: whether less than stall_distance_m was climbed in the window.
  bool Stalled(double d) {
    if (on_) {
      ring_[checks_ % ring_.size()] = d;
      // d `window` checks ago is the oldest entry of the ring once it is full.
      if (checks_ >= window_ && d - ring_[(checks_ - window_) % ring_.size()] < distance_m_) {
        return true;
      }
    }
    ++checks_;
    return false;
  }

 private:
  const bool on_;
  const size_t window_;
  const double distance_m_;
  std::vector<double> ring_;
  size_t checks_ = 0;
};

// The bound rule at simulated time t, distance d: even at max_speed_mps from now on, with
// no penalty added, J stays above bound_j. Then *stop is the rollout's cost, that lower
// bound (wall time not set).
// The cost the bound rule stops a rollout with at time t; its total is the lower bound on J.
Cost BoundStop(const sim::Simulation& sim, double d, double t, const sim::ObjectiveParams& o) {
  const double T = sim.scenario().duration_s;
  Cost stop = CostOf(sim, d, o);
  stop.total = -(d + o.max_speed_mps * (T - t)) / T + stop.fall_penalty + stop.overload_penalty;
  stop.energy_penalty = 0.0;
  stop.early_stop = "bound";
  stop.stop_time_s = t;
  return stop;
}

bool BoundReached(const sim::Simulation& sim, double d, double t, const sim::ObjectiveParams& o,
                  double bound_j, Cost* stop) {
  const Cost now = BoundStop(sim, d, t, o);
  if (!(now.total > bound_j)) return false;
  *stop = now;
  return true;
}

}  // namespace

Cost RolloutCost(const sim::Simulation& sim, const sim::ObjectiveParams& o) {
  return CostOf(sim, sim.result().distance_m, o);
}

Cost NominalCost(const sim::Simulation& sim) {
  return RolloutCost(sim, sim.scenario().optimise ? sim.scenario().optimise->objective
                                                  : sim::ObjectiveParams{});
}

Cost BoundedCost(const Cost& traced, const BoundTrace& trace, double bound_j) {
  for (size_t k = 0; k < trace.lower_j.size(); ++k) {
    if (!(trace.lower_j[k] > bound_j)) continue;
    Cost stop = trace.stop[k];
    stop.wall_time_s = traced.wall_time_s;
    return stop;
  }
  return traced;
}

Cost RunRollout(sim::Simulation& sim, const sim::ObjectiveParams& o, double bound_j,
                BoundTrace* trace) {
  const auto t0 = std::chrono::steady_clock::now();
  const double dt = sim.world().model()->opt.timestep;
  const long total = sim.steps_total();
  const Eigen::Vector3d start = BasePosition(sim);
  const Eigen::Vector3d travel = sim.world().scene().travel;
  auto distance = [&] { return travel.dot(BasePosition(sim) - start); };
  const auto wall_s = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };

  // The rules are checked every 50 ms of simulated time.
  const long every = std::max<long>(1, std::lround(0.05 / dt));
  StallRule stall(o, every, dt);
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
    if (stall.Stalled(d)) {
      rule = "stalled";
      break;
    }
    Cost stop;
    if (bound_on && BoundReached(sim, d, step * dt, o, bound_j, &stop)) {
      stop.wall_time_s = wall_s();
      return stop;
    }
    if (trace && o.max_speed_mps > 0) {
      trace->stop.push_back(BoundStop(sim, d, step * dt, o));
      trace->lower_j.push_back(trace->stop.back().total);
    }
  }
  if (rule.empty()) d = distance();
  Cost c = CostOf(sim, d, o);
  c.early_stop = rule;
  c.stop_time_s = step * dt;
  c.wall_time_s = wall_s();
  return c;
}

}  // namespace climbsim::optimise
