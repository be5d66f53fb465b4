#include "experiments/bench_speed.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <stdexcept>
#include <string>

#include "sim/simulation.h"

namespace climbsim::sim {
namespace {

// CPU time of the calling thread: on an idle machine the same as wall time, and on a busy
// one it does not count the time other processes hold the core, so ratios stay comparable.
struct ThreadClock {
  static double Now() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  }
};

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

namespace {

// The cumulative variants, each a scenario with a prefix of the effects: what each effect
// adds to the step's cost is the difference between neighbours.
std::vector<std::pair<std::string, Scenario>> CumulativeVariants(const Scenario& base) {
  std::vector<std::pair<std::string, Scenario>> variants;
  Scenario s = base;
  s.adhesion.reset();
  s.cpg.reset();
  s.reflex.reset();
  s.transition.reset();  // it needs the CPG: it joins after the reflexes
  s.perturbations.clear();
  s.outputs.trajectory_rate_hz = 0.0;
  variants.push_back({"no effects", s});
  if (base.adhesion) {
    s.adhesion = base.adhesion;
    variants.push_back({"+adhesion", s});
  }
  if (base.cpg) {
    s.cpg = base.cpg;
    variants.push_back({"+cpg", s});
  }
  if (base.reflex) {
    s.reflex = base.reflex;
    variants.push_back({"+reflex", s});
  }
  if (base.transition && base.cpg) {
    s.transition = base.transition;
    variants.push_back({"+transition", s});
  }
  if (!base.perturbations.empty()) {
    s.perturbations = base.perturbations;
    variants.push_back({"+perturbation", s});
  }
  if (base.outputs.trajectory_rate_hz > 0) {
    s.outputs = base.outputs;
    variants.push_back({"+trajectory", s});
  }
  return variants;
}

// Bare mj_step over duration_s: the same model copy and the same options as every
// Simulation gets. Returns steps per second; `steps` is the step count.
double BareStepsPerS(const CompiledModel& model, const Scenario& base, double duration_s,
                     long* steps) {
  World world(model, base);
  mj_resetData(world.model(), world.data());
  *steps = std::lround(duration_s / world.model()->opt.timestep);
  const double t0 = ThreadClock::Now();
  for (long i = 0; i < *steps; ++i) mj_step(world.model(), world.data());
  const double dt = ThreadClock::Now() - t0;
  return *steps / dt;
}

double VariantStepsPerS(const Scenario& variant, const CompiledModel& model) {
  Simulation sim(variant, model);
  const double t0 = ThreadClock::Now();
  const long steps = sim.steps_total();
  for (long i = 0; i < steps; ++i) sim.Step();
  const double dt = ThreadClock::Now() - t0;
  return steps / dt;
}

// Profile of the full scenario from profile_from_s into `report`.
void ProfileFull(const Scenario& full, const CompiledModel& model, double profile_from_s,
                 SpeedReport* report) {
  Simulation sim(full, model);
  Simulation::Profile p;
  const double dt = sim.world().model()->opt.timestep;
  report->profile_from_s = profile_from_s;
  for (long i = 0; i < sim.steps_total(); ++i) {
    // Step i starts at i·dt: profiled from the first step that starts at or after the window.
    if (i * dt + 0.5 * dt < profile_from_s) {
      sim.Step();
    } else {
      sim.StepProfiled(&p);
      ++report->profiled_steps;
    }
  }
  // Each lap holds the clock's own cost once: taken off (never below 0).
  const double lap = Simulation::Profile::LapSeconds();
  auto less_clock = [lap](double s, long laps) { return std::max(0.0, s - laps * lap); };
  report->clock_lap_s = lap;
  report->mj_step_with_clock_s = p.mj_step_s;
  report->mj_step_s = less_clock(p.mj_step_s, p.steps);
  report->monitor_s = less_clock(p.monitor_s, p.steps);
  report->effects_with_clock_s = 0.0;
  for (size_t i = 0; i < p.effect_s.size(); ++i) {
    const Effect& e = *sim.effects()[i];
    const long laps = p.steps * (int{e.has_before_step()} + int{e.has_after_step()});
    report->effect_s.push_back({e.name(), less_clock(p.effect_s[i], laps)});
    report->effects_with_clock_s += p.effect_s[i];
  }
}

}  // namespace

SpeedReport BenchSpeed(const Scenario& full, double duration_s, int repetitions,
                       double profile_from_s) {
  if (!(profile_from_s >= 0.0 && profile_from_s < duration_s)) {
    throw std::invalid_argument("the profile must start in [0, duration): " +
                                std::to_string(profile_from_s) + " s");
  }
  Scenario base = full;
  base.duration_s = duration_s;
  base.fall.stop = false;
  const auto model = CompileScenario(base);
  const std::vector<std::pair<std::string, Scenario>> variants = CumulativeVariants(base);

  SpeedReport report;
  report.repetitions = repetitions;
  report.variants.push_back({"bare mj_step", {}, 0.0, 0.0});
  for (const auto& v : variants) report.variants.push_back({v.first, {}, 0.0, 0.0});
  for (int rep = 0; rep < repetitions; ++rep) {
    report.variants[0].steps_per_s.push_back(
        BareStepsPerS(*model, base, duration_s, &report.steps));
    for (size_t k = 0; k < variants.size(); ++k) {
      report.variants[k + 1].steps_per_s.push_back(VariantStepsPerS(variants[k].second, *model));
    }
  }
  for (auto& v : report.variants) v.median_steps_per_s = Median(v.steps_per_s);
  for (auto& v : report.variants) {
    v.overhead = report.variants[0].median_steps_per_s / v.median_steps_per_s - 1.0;
  }
  ProfileFull(variants.back().second, *model, profile_from_s, &report);
  return report;
}

SpeedComparison BenchSpeedCompare(const Scenario& a_in, const Scenario& b_in, double duration_s,
                                  int repetitions) {
  Scenario a = a_in, b = b_in;
  a.duration_s = b.duration_s = duration_s;
  const auto model_a = CompileScenario(a);
  const auto model_b = CompileScenario(b);
  SpeedComparison c;
  auto run = [](const Scenario& s, const CompiledModel& model, SpeedComparison::Side* side) {
    Simulation sim(s, model);
    const double t0 = ThreadClock::Now();
    const RunResult r = sim.Run();
    const double dt = ThreadClock::Now() - t0;
    side->steps_per_s.push_back(r.steps / dt);
    side->steps = r.steps;
    side->distance_m = r.distance_m;
    side->fell = r.fell;
    side->stable = r.stable;
  };
  for (int rep = 0; rep < repetitions; ++rep) {
    run(a, *model_a, &c.a);
    run(b, *model_b, &c.b);
  }
  c.a.median_steps_per_s = Median(c.a.steps_per_s);
  c.b.median_steps_per_s = Median(c.b.steps_per_s);
  c.ratio = c.a.median_steps_per_s / c.b.median_steps_per_s;
  return c;
}

}  // namespace climbsim::sim
