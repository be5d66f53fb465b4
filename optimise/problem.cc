#include <algorithm>
#include <cmath>
#include <random>

#include "optimise/disturbance.h"
#include "optimise/optimise.h"

namespace climbsim::optimise {
namespace {

// Seeds for perturbed run k: a function of the scenario's seed and k only, so every
// parameter vector meets the same perturbations (common random numbers).
uint64_t RunSeed(int scenario_seed, int run) {
  uint64_t z = static_cast<uint64_t>(scenario_seed) * 0x9E3779B97F4A7C15ull + run;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;  // splitmix64
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// A robustness case's run length, phases and push time as the bench's options.
RobustnessOptions CaseOptions(const sim::RobustnessCaseParams& c) {
  RobustnessOptions o;
  o.duration_s = c.duration_s;
  o.seeds = c.seeds;
  o.phases = c.phases;
  o.push_time_s = c.push_time_s;
  return o;
}

bool PushFamily(const std::string& family) { return family.rfind("push_", 0) == 0; }

}  // namespace

void Problem::CheckRobustnessCases() {
  const auto& cases = params().objective.robustness;
  if (cases.empty()) return;
  std::vector<std::string> known;
  std::string names;
  for (const auto& f : AllRobustnessFamilies(1.0)) {
    known.push_back(f.name);
    names += (names.empty() ? "" : ", ") + f.name;
  }
  for (size_t i = 0; i < cases.size(); ++i) {
    const sim::RobustnessCaseParams& c = cases[i];
    const std::string at = "optimise.objective.robustness[" + std::to_string(i) + "]";
    if (std::find(known.begin(), known.end(), c.family) == known.end()) {
      throw sim::ScenarioError(scenario_, at + ".family",
                               "unknown family '" + c.family + "' (" + names + ")");
    }
    const DisturbanceSetup u = MakeDisturbanceSetup(scenario_, CaseOptions(c));
    const std::string why = CannotTakeFamily(u, c.family);
    if (!why.empty()) {
      throw sim::ScenarioError(scenario_, at + ".family",
                               "the scenario cannot take family '" + c.family + "': " + why);
    }
    if (PushFamily(c.family) && c.push_time_s && *c.push_time_s > u.duration_s / 3.0) {
      throw sim::ScenarioError(scenario_, at + ".push_time_s",
                               "must be at most a third of the " +
                                   sim::ExactNumber(u.duration_s) + " s run");
    }
    const int phases = PushFamily(c.family) ? c.phases : 1;
    for (int k = 0; k < c.seeds; ++k) robust_.push_back({static_cast<int>(i), k, 0, true});
    for (int k = 0; k < c.seeds; ++k) {
      for (int j = 0; j < phases; ++j) robust_.push_back({static_cast<int>(i), k, j, false});
    }
  }
}

Problem::Problem(const std::string& scenario_file)
    : Problem(sim::LoadYamlFile(scenario_file), scenario_file) {}

Problem::Problem(const YAML::Node& root, const std::string& file)
    : root_(root), file_(file), scenario_(sim::ParseScenario(root_, file)) {
  if (!scenario_.optimise) {
    throw InputError(file, 0, 0, "optimise", "the scenario has no optimise block");
  }
  // Every parameter must name a number the file can hold, and its start and both bounds
  // must give valid scenarios: checked here, before any rollout.
  const auto& ps = scenario_.optimise->parameters;
  for (size_t i = 0; i < ps.size(); ++i) {
    const std::string where = "optimise.parameters[" + std::to_string(i) + "].key";
    for (double v : {ps[i].start, ps[i].min, ps[i].max}) {
      YAML::Node tree = YAML::Clone(root_);
      // SetDottedKey names the part of the key that does not fit; `where` the parameter.
      try {
        SetDottedKey(tree, ps[i].key, v);
      } catch (const std::invalid_argument& e) {
        throw sim::ScenarioError(scenario_, where, e.what());
      }
      try {
        sim::ParseScenario(tree, file_);
      } catch (const InputError& e) {
        // The tree is a copy (YAML::Clone keeps no places): name the key, not a line.
        throw sim::ScenarioError(scenario_, where,
                                 ps[i].key + " = " + sim::ExactNumber(v) +
                                     " does not give a valid scenario: " + e.key() + " " +
                                     e.message());
      }
    }
  }
  // Keys checked only when the run is built (a gait name, a pad body) are caught here too:
  // the start builds, before any rollout.
  if (!ps.empty()) {
    const sim::Scenario s = ScenarioFor(start(), 0);
    try {
      const auto model = sim::CompileScenario(s);
      sim::Simulation check(s, *model);
    } catch (const InputError& e) {
      throw sim::ScenarioError(scenario_, "optimise.parameters",
                               "the start values do not give a runnable scenario: " + e.key() +
                                   " " + e.message() + " (is every key a number?)");
    }
  }
  CheckRobustnessCases();
}

std::vector<double> Problem::start() const {
  std::vector<double> x;
  for (const auto& p : params().parameters) x.push_back(p.start);
  return x;
}
std::vector<double> Problem::lower() const {
  std::vector<double> x;
  for (const auto& p : params().parameters) x.push_back(p.min);
  return x;
}
std::vector<double> Problem::upper() const {
  std::vector<double> x;
  for (const auto& p : params().parameters) x.push_back(p.max);
  return x;
}

YAML::Node Problem::TreeFor(std::span<const double> x) const {
  YAML::Node tree = YAML::Clone(root_);
  const auto& ps = params().parameters;
  for (size_t i = 0; i < ps.size(); ++i) {
    SetDottedKey(tree, ps[i].key, x[i]);
    tree["optimise"]["parameters"][i]["start"] = sim::ExactNumber(x[i]);
  }
  return tree;
}

sim::Scenario Problem::ScenarioFor(std::span<const double> x, int run) const {
  YAML::Node tree = TreeFor(x);
  // A fall ends a rollout: the time after it says nothing about the gait.
  tree["fall"]["stop"] = true;
  sim::Scenario s = sim::ParseScenario(tree, file_);
  if (run == 0) return s;
  const sim::ObjectiveParams& o = params().objective;
  if (run >= o.runs) {
    // The bench's case, built from this x's scenario (its gait times the pushes).
    const RobustnessRollout& r = robust_.at(run - o.runs);
    const sim::RobustnessCaseParams& c = o.robustness[r.case_index];
    const DisturbanceSetup u = MakeDisturbanceSetup(s, CaseOptions(c));
    return DisturbanceCase(u, r.baseline ? "" : c.family, r.baseline ? 0.0 : c.magnitude, 0,
                           c.first_seed + r.seed, r.phase);
  }
  std::mt19937_64 rng(RunSeed(s.seed, run));
  std::normal_distribution<double> normal(0.0, 1.0);
  s.initial.offset_m[0] += o.pose_noise_m * normal(rng);
  s.initial.offset_m[1] += o.pose_noise_m * normal(rng);
  s.initial.yaw_deg = std::clamp(s.initial.yaw_deg + o.yaw_noise_deg * normal(rng), -180.0, 180.0);
  const double spread = normal(rng);
  const double factor = std::max(0.1, 1.0 + o.sigma_t_spread * spread);
  [&](auto& sc) {  // generic until the adhesion block lands in Scenario
    if constexpr (requires { sc.adhesion; }) {
      if (sc.adhesion) sc.adhesion->sigma_t_pa *= factor;
    }
  }(s);
  return s;
}

}  // namespace climbsim::optimise
