// Scenario keys of the `optimise:` block, read by `climbsim optimise` (optimise/). The block
// is part of the scenario so that it is validated like every other key and travels with
// best.yaml; `climbsim simulate` ignores it except to report the objective.
#ifndef CLIMBSIM_SCENARIO_OPTIMISE_PARAMS_H_
#define CLIMBSIM_SCENARIO_OPTIMISE_PARAMS_H_

#include <optional>
#include <string>
#include <vector>

#include "scenario/archive.h"

namespace climbsim::sim {

// One tuned parameter: a dotted key of this scenario file and its search interval.
struct OptimisedParameter {
  std::string key;
  double start = 0.0;
  double min = 0.0;
  double max = 0.0;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"key",
              "",
              "dotted key of this file: cpg.frequency_hz, cpg.stride_rad[0], reflex.preload.gain, "
              "cpg.phase_bias_rad[0][1]",
              {},
              true},
             &key);
    a->Visit({"start",
              "",
              "start value (start 0 begins here; other starts are drawn in the bounds)",
              {},
              true},
             &start);
    a->Visit({"min", "", "lower bound", {}, true}, &min);
    a->Visit({"max", "", "upper bound", {}, true}, &max);
  }
  void Validate(const Checker& c) const {
    if (!(min < max)) c.Fail("max", "must be greater than min");
    if (start < min || start > max) c.Fail("start", "must lie in [min, max]");
  }
};

// One case of the objective's robustness term: a `bench robustness` family at one magnitude,
// on seed cases first_seed .. first_seed + seeds - 1 and, for the push families, `phases`
// push phases (optimise/disturbance.h builds them as the bench does). The case SURVIVES when
// every one of its runs survives by the bench's rule (stable, no fall, at least half of what
// the same seed climbs undisturbed); J adds penalty_mps for each case that does not.
struct RobustnessCaseParams {
  std::string family;
  double magnitude = 0.0;
  int seeds = 3;
  int first_seed = 0;
  int phases = 4;
  std::optional<double> push_time_s;
  double duration_s = 0.0;
  double penalty_mps = 0.1;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"family", "",
              "a bench robustness family: push_off, push_down, push_side, payload, pad_failure, "
              "weak_patch, roughness",
              {},
              true},
             &family);
    a->Visit({"magnitude", "", "the disturbance, in the family's unit (N s, kg, -, m)",
              Range::Positive(), true},
             &magnitude);
    a->Visit({"seeds", "", "seed cases per case (the bench's: seed + k, start moved for k >= 1)",
              Range::Closed(1, 100)},
             &seeds);
    a->Visit({"first_seed", "",
              "the first seed case k (another range than the bench's 0.. tests what was not tuned "
              "on)",
              Range::Closed(0, 100000)},
             &first_seed);
    a->Visit({"phases", "", "push families: pushes per seed, spread over one gait cycle",
              Range::Closed(1, 100)},
             &phases);
    a->Visit({"push_time_s", "s",
              "first push, at most a third of the run; default 4 s or a third of the run",
              Range::NonNegative()},
             &push_time_s);
    a->Visit({"duration_s", "s", "each run's length, 0 = the scenario's duration_s",
              Range::NonNegative()},
             &duration_s);
    a->Visit({"penalty_mps", "m/s", "added to J when the case is not survived",
              Range::NonNegative()},
             &penalty_mps);
  }
};

// The cost J (m/s, minimised) of one rollout:
//   J = −v + fall_penalty_mps·[fell] + overload_penalty_mps·n_overload + energy_weight_mps·CoT
// v = distance along the travel direction / duration_s (a fall ends the run early, so the
// distance is what was climbed before it), n_overload = pads detached by overload, CoT =
// actuator work / (m·g·max(distance, 1 mm)). With runs > 1, runs 1.. are perturbed copies
// (initial pose noise, σ_T spread), each with its own fixed seed, and J is their mean or
// their worst.
struct ObjectiveParams {
  double fall_penalty_mps = 0.1;
  double overload_penalty_mps = 0.005;
  double energy_weight_mps = 0.0;
  int runs = 1;
  std::string aggregate = "mean";
  double pose_noise_m = 0.002;
  double yaw_noise_deg = 2.0;
  double sigma_t_spread = 0.1;
  // Early stopping (optimise/rollout.cc, docs/optimise.md): a rollout ends as soon as its
  // outcome is decided.
  double stall_window_s = 4.0;
  double stall_distance_m = 0.005;
  double max_speed_mps = 0.5;
  std::vector<RobustnessCaseParams> robustness;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"fall_penalty_mps", "m/s", "added to J when the robot falls", Range::NonNegative()},
             &fall_penalty_mps);
    a->Visit({"overload_penalty_mps", "m/s", "added to J per pad detached by overload",
              Range::NonNegative()},
             &overload_penalty_mps);
    a->Visit(
        {"energy_weight_mps", "m/s", "weight of the cost of transport in J", Range::NonNegative()},
        &energy_weight_mps);
    a->Visit({"runs", "", "rollouts per evaluation: 1 nominal and runs - 1 perturbed",
              Range::Closed(1, 100)},
             &runs);
    a->Choice({"aggregate", "", "how the runs' costs combine"}, &aggregate, {"mean", "worst"});
    a->Visit(
        {"pose_noise_m", "m", "standard deviation of the initial x and y offset of perturbed runs",
         Range::NonNegative()},
        &pose_noise_m);
    a->Visit({"yaw_noise_deg", "deg", "standard deviation of the initial heading of perturbed runs",
              Range::NonNegative()},
             &yaw_noise_deg);
    a->Visit({"sigma_t_spread", "",
              "relative standard deviation of adhesion.sigma_t_pa in perturbed runs",
              Range::Closed(0, 0.9)},
             &sigma_t_spread);
    a->Visit({"stall_window_s", "s",
              "a rollout that climbs less than stall_distance_m in this long stops (scored as if "
              "it stayed put), 0 = off",
              Range::NonNegative()},
             &stall_window_s);
    a->Visit({"stall_distance_m", "m",
              "progress below which a rollout counts as stalled over stall_window_s",
              Range::NonNegative()},
             &stall_distance_m);
    a->Visit({"max_speed_mps", "m/s",
              "speed no gait exceeds: a rollout that could not beat the start's J even at this "
              "speed for the rest of the run stops, 0 = off",
              Range::NonNegative()},
             &max_speed_mps);
    a->Visit({"robustness", "",
              "disturbance cases (family, magnitude, seeds, phases); J adds each one's "
              "penalty_mps when it is not survived. Empty: off"},
             &robustness);
  }
};

struct OptimiseParams {
  std::vector<OptimisedParameter> parameters;
  ObjectiveParams objective;
  std::string algorithm = "LN_SBPLX";
  std::string local_algorithm = "LN_SBPLX";
  double global_share = 0.5;
  int max_evaluations = 400;
  double max_time_s = 0.0;
  double xtol_rel = 1e-4;
  double ftol_abs = 0.0;
  double initial_step = 0.1;
  int starts = 2;
  int seed = 1;
  int population = 0;
  double sigma0 = 0.3;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"parameters", "", "the tuned parameters (key, start, min, max)"}, &parameters);
    a->Visit({"objective", "", "the cost each evaluation minimises"}, &objective);
    a->Choice({"algorithm", "",
               "NLopt algorithm; chain = GN_CRS2_LM, then local_algorithm from its best; cmaes = "
               "CMA-ES (pagmo), its population evaluated in parallel"},
              &algorithm,
              {"LN_SBPLX", "LN_NELDERMEAD", "LN_BOBYQA", "LN_COBYLA", "GN_CRS2_LM", "GN_ISRES",
               "GN_ESCH", "chain", "cmaes"});
    a->Choice({"local_algorithm", "", "the local stage of chain"}, &local_algorithm,
              {"LN_SBPLX", "LN_NELDERMEAD", "LN_BOBYQA", "LN_COBYLA"});
    a->Visit({"global_share", "", "share of each start's evaluations spent in chain's global stage",
              Range::OpenClosed(0, 1)},
             &global_share);
    a->Visit({"max_evaluations", "", "evaluations in all, shared equally by the starts",
              Range::Closed(1, 1000000)},
             &max_evaluations);
    a->Visit(
        {"max_time_s", "s",
         "wall-time limit per start, 0 = none (a time limit makes results depend on the machine)",
         Range::NonNegative()},
        &max_time_s);
    a->Visit({"xtol_rel", "",
              "stop when a step changes every parameter by less than this share of its range",
              Range::NonNegative()},
             &xtol_rel);
    a->Visit({"ftol_abs", "m/s", "stop when J improves by less than this, 0 = off",
              Range::NonNegative()},
             &ftol_abs);
    a->Visit(
        {"initial_step", "", "first step of local algorithms, as a share of each parameter's range",
         Range::OpenClosed(0, 1)},
        &initial_step);
    a->Visit({"starts", "",
              "independent starts (start 0 at the given start values, the others drawn in the "
              "bounds); run side by side",
              Range::Closed(1, 1000)},
             &starts);
    a->Visit({"seed", "", "seed of NLopt's random numbers and of the random starts",
              Range::Closed(0, 2147483647)},
             &seed);
    a->Visit({"population", "",
              "cmaes: candidates per generation, 0 = 4 + 3 ln(parameters) (at least 5)",
              Range::Closed(0, 10000)},
             &population);
    a->Visit({"sigma0", "", "cmaes: first step size, as a share of each parameter's range",
              Range::OpenClosed(0, 1)},
             &sigma0);
  }
  void Validate(const Checker& c) const {
    if (parameters.empty()) c.Fail("parameters", "list at least one parameter to tune");
    if (max_evaluations < starts)
      c.Fail("max_evaluations", "must be at least the number of starts");
  }
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SCENARIO_OPTIMISE_PARAMS_H_
