// climbsim's offline gait optimiser: NLopt or CMA-ES (pagmo2) tunes the parameters an
// `optimise:` block lists (any numeric scenario key, by its dotted name) to minimise a
// documented cost over rollouts of the scenario. Independent starts hand their candidates to
// one queue whose rollouts run on threads and MPI ranks as they free up; the result does not
// depend on the number of threads or processes. Every batch is checkpointed atomically, so a
// killed run resumes to the same end.
//
//   climbsim::optimise::Options o;  o.out_dir = "runs/opt";  o.threads = 2;
//   climbsim::optimise::Result r = climbsim::optimise::Optimise("examples/gecko_wall.yaml", o);
#ifndef CLIMBSIM_OPTIMISE_OPTIMISE_H_
#define CLIMBSIM_OPTIMISE_OPTIMISE_H_

#include <yaml-cpp/yaml.h>

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sim/sim.h"

namespace climbsim::optimise {

// ---- Dotted keys ------------------------------------------------------------------------
// "cpg.frequency_hz", "cpg.stride_rad[0]", "cpg.phase_bias_rad[0][1]", "reflex.preload.gain".
// Set creates a missing map key; a list element must exist. Both throw std::invalid_argument
// with a message naming the part of the key that does not fit.
void SetDottedKey(YAML::Node root, std::string_view key, double value);
// The same for any scalar given as its YAML text ("physics.integrator" = "euler").
void SetDottedKeyText(YAML::Node root, std::string_view key, const std::string& text);
double GetDottedKey(const YAML::Node& root, std::string_view key);

// ---- Cost of a rollout ------------------------------------------------------------------
// J in m/s, minimised (sim/optimise_params.h states the formula). A rollout that went
// numerically bad, or whose scenario could not be built, costs kFailedCost.
inline constexpr double kFailedCost = 10.0;

struct Cost {
  double total = 0.0;             // J
  double speed_mps = 0.0;         // v
  double fall_penalty = 0.0;
  double overload_penalty = 0.0;
  double energy_penalty = 0.0;
  bool failed = false;
  std::string failure;            // why, when failed
  std::string early_stop;         // "" ran to its end (or fell), "stalled", "bound"
  double stop_time_s = 0.0;       // simulated time at which the rollout ended
  double wall_time_s = 0.0;
  // A robustness rollout's outcome, for the bench's survived rule (total stays 0).
  bool stable = true;
  bool fell = false;
  double fall_time_s = -1.0;
  double distance_m = 0.0;
};

// The cost of a finished run of `sim` (its scenario's duration_s is T).
Cost RolloutCost(const sim::Simulation& sim, const sim::ObjectiveParams& objective);

// Runs a fresh `sim` (its scenario with fall.stop set, as Problem::ScenarioFor makes it) and
// stops it as soon as its outcome is decided (docs/optimise.md, "Early stopping"):
//  - fell or numerically bad: Step() says stop; J is exactly the finished run's;
//  - stalled: less than objective.stall_distance_m climbed in the last stall_window_s; J as
//    if it stayed where it is (early_stop = "stalled");
//  - bound: even at objective.max_speed_mps for the rest of the run, with no penalty added,
//    J would stay above `bound_j` (the cost a rollout must beat to matter); J is that lower
//    bound, which is above bound_j (early_stop = "bound"). bound_j = +inf: rule off.
// A rollout that reaches duration_s gets exactly RolloutCost's J.
Cost RunRollout(sim::Simulation& sim, const sim::ObjectiveParams& objective, double bound_j);

// ---- The problem ------------------------------------------------------------------------
// A scenario file with an optimise block. Parameter vectors are in the parameters' own units.
class Problem {
 public:
  // Reads and validates the file; checks that each parameter's key names a number in the
  // file and that its bounds and start give valid scenarios (InputError at the key).
  explicit Problem(const std::string& scenario_file);
  Problem(const YAML::Node& root, const std::string& file);

  const sim::Scenario& scenario() const { return scenario_; }
  const sim::OptimiseParams& params() const { return *scenario_.optimise; }
  int dimension() const { return static_cast<int>(params().parameters.size()); }
  std::vector<double> start() const;
  std::vector<double> lower() const;
  std::vector<double> upper() const;

  // The YAML tree with x written in (and the optimise block's starts moved to x, so that an
  // optimisation of best.yaml continues from there).
  YAML::Node TreeFor(std::span<const double> x) const;
  // Rollout `run` of x: run 0 is the nominal scenario, runs 1 .. objective.runs − 1 perturbed
  // with seeds that depend only on the scenario's seed and the run (common random numbers
  // across x); runs from objective.runs on are the robustness term's (robustness_rollouts()).
  // fall.stop is set: a fall ends the rollout. Throws InputError if x makes it invalid.
  sim::Scenario ScenarioFor(std::span<const double> x, int run) const;

  // Rollouts per evaluation: objective.runs, then the robustness term's.
  int rollouts() const { return params().objective.runs + static_cast<int>(robust_.size()); }
  // Rollout objective.runs + i: case `case_index` of objective.robustness, its seed (0-based
  // within the case) undisturbed (baseline) or disturbed at push phase `phase`. Per case:
  // each seed's baseline, then each seed's phases.
  struct RobustnessRollout {
    int case_index = 0, seed = 0, phase = 0;
    bool baseline = false;
  };
  const std::vector<RobustnessRollout>& robustness_rollouts() const { return robust_; }

 private:
  // The robustness term's cases: each family known and one the scenario can take (InputError
  // at optimise.objective.robustness[i]); fills robust_.
  void CheckRobustnessCases();

  YAML::Node root_;  // as read, with its places; every tree for an x is a clone of it
  std::string file_;
  sim::Scenario scenario_;
  std::vector<RobustnessRollout> robust_;
};

// ---- Compiled models -------------------------------------------------------------------
// One thread's compiled models, by structure: scenarios that differ only in values (which the
// World applies per run) share one; a robot design's keys change the structure (a model is
// generated and compiled per design). Not thread-safe: one cache per thread. A reference
// For returns holds until the next call.
class ModelCache {
 public:
  const sim::CompiledModel& For(const sim::Scenario& scenario);

 private:
  // At most this many models (a few MB each): the structures a sweep or optimise of effect
  // keys visits fit; one of robot keys replaces them as it goes.
  static constexpr size_t kMaxModels = 16;
  std::map<std::string, std::unique_ptr<sim::CompiledModel>> models_;
};

// The rollout pool of sweep, bench accuracy and bench robustness (and of optimise's recheck
// of a resumed best; its queue's workers run on common::ParallelFor too): task(i, cache) for
// i in [0, count) on common::ParallelFor's threads (`threads` clamped to [1, count]). Each
// running task holds a cache no other running task holds; caches are kept across tasks (at
// most one per thread), so a model compiles about once per thread. A task's exception
// reaches the caller (the lowest failing i's) after the running tasks finish.
void ParallelRollouts(int count, int threads,
                      const std::function<void(int task, ModelCache& cache)>& task);

// ---- Running it ---------------------------------------------------------------------------
struct Evaluation {
  int start = 0;
  int index = 0;                  // 0-based within its start
  std::vector<double> x;
  double objective = 0.0;         // aggregate J over the runs
  Cost nominal;                   // run 0 (what best.yaml replays)
  int failed_runs = 0;
  double wall_time_s = 0.0;
  int cases_failed = 0;             // robustness cases not survived
  double robustness_penalty = 0.0;  // their penalties, in objective
};

struct Options {
  std::string out_dir;
  int threads = 0;                // per process; 0: the cores / the processes on this machine
  bool resume = false;
  bool force = false;             // replace an earlier climbsim folder at out_dir
  bool keep_other_files = false;  // with force: carry a user's files along (sim/run_folder.h)
  int max_evaluations = 0;        // 0: the file's
  bool quiet = false;
};

struct Result {
  Evaluation best;
  double start_objective = 0.0;   // start 0's first evaluation: the scenario as given
  std::vector<Evaluation> history;  // ordered by start, then index
  double wall_time_s = 0.0;
  int evaluations_computed = 0;   // not served from a checkpoint
  int rollouts_computed = 0;
  int rollouts_stalled = 0;       // stopped early by the stall rule
  int rollouts_bounded = 0;       // stopped early by the bound rule
  double simulated_s = 0.0;       // simulated time of the computed rollouts
  int processes = 1;              // MPI ranks (1 without mpirun)
  std::string plot_warning;       // why convergence.png is missing (rank 0); "" when drawn
  std::vector<std::string> parameter_keys;  // optimise.parameters' keys, the order of x
};

// The MPI rank of this process and the number of ranks (0 and 1 without mpirun).
int ProcessRank();
int ProcessCount();
// Whether this build spreads work over MPI ranks (CMake option CLIMBSIM_MPI).
bool BuiltWithMpi();

// Writes DIR/scenario.yaml, history.csv, best.yaml, convergence.png (and .csv), summary.json
// and keeps DIR/checkpoint.json current after every batch of evaluations (all atomically).
// Under mpirun every rank calls it with the same arguments: rank 0 runs the starts and hands
// rollouts to the other ranks as they ask, every rank returns the same Result, and rank 0
// alone writes DIR. progress(fraction, best_objective) is called after each batch, one call
// at a time, from the thread that completed it.
Result Optimise(const std::string& scenario_file, const Options& options,
                const std::function<void(double, double)>& progress = {});

// What `climbsim optimise` prints after a run: evaluations, rollouts, start and best J,
// the outputs in out_dir.
std::string ResultText(const Result& result, const std::string& out_dir);

// The cost of a nominal rollout of a scenario with an optimise block: what `climbsim
// simulate` reports as "objective" for best.yaml.
Cost NominalCost(const sim::Simulation& sim);

}  // namespace climbsim::optimise

#endif  // CLIMBSIM_OPTIMISE_OPTIMISE_H_
