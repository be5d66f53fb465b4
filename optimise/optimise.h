// climbsim's offline gait optimiser: NLopt tunes the parameters an `optimise:` block lists
// (any numeric scenario key, by its dotted name) to minimise a documented cost over rollouts
// of the scenario. Independent starts run side by side, one thread each, each with its own
// model copy; the result does not depend on the number of threads. Every evaluation is
// checkpointed atomically, so a killed run resumes to the same end.
//
//   climbsim::optimise::Options o;  o.out_dir = "runs/opt";  o.threads = 2;
//   climbsim::optimise::Result r = climbsim::optimise::Optimise("examples/gecko_wall_optimise.yaml", o);
#ifndef CLIMBSIM_OPTIMISE_OPTIMISE_H_
#define CLIMBSIM_OPTIMISE_OPTIMISE_H_

#include <yaml-cpp/yaml.h>

#include <functional>
#include <map>
#include <memory>
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
};

// The cost of a finished run of `sim` (its scenario's duration_s is T).
Cost RolloutCost(const sim::Simulation& sim, const sim::ObjectiveParams& objective);

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
  // Rollout `run` of x: run 0 is the nominal scenario, runs ≥ 1 perturbed with seeds that
  // depend only on the scenario's seed and the run (common random numbers across x).
  // fall.stop is set: a fall ends the rollout. Throws InputError if x makes it invalid.
  sim::Scenario ScenarioFor(std::span<const double> x, int run) const;

 private:
  YAML::Node root_;  // as read, with its places; every tree for an x is a clone of it
  std::string file_;
  sim::Scenario scenario_;
};

// ---- Compiled models -------------------------------------------------------------------
// One thread's compiled models, by structure: scenarios that differ only in values (which the
// World applies per run) share one. Not thread-safe: one cache per thread.
class ModelCache {
 public:
  const sim::CompiledModel& For(const sim::Scenario& scenario);

 private:
  std::map<std::string, std::unique_ptr<sim::CompiledModel>> models_;
};

// ---- Parameter sweeps ------------------------------------------------------------------
// `climbsim sweep`: each scenario run with one numeric key set to each value of a range
// (e.g. scene.incline_deg from 0 to 180 in steps of 15), runs side by side on threads.
struct SweepOptions {
  std::string key;
  double from = 0.0, to = 0.0, step = 1.0;
  int threads = 0;  // 0: all cores
};
struct SweepRow {
  double value = 0.0;
  std::vector<sim::RunResult> results;  // one per scenario, in the order given
};
// Throws InputError for a key the files cannot hold or a value that makes a scenario invalid
// (checked for every value before anything runs).
std::vector<SweepRow> Sweep(const std::vector<std::string>& scenario_files,
                            const SweepOptions& options);
// sweep.csv (value, then distance, speed, fell and fall time per scenario) and sweep.png.
// Returns the plot's warning ("" when drawn).
std::string WriteSweep(const std::string& dir, const std::vector<std::string>& scenario_files,
                       const SweepOptions& options, const std::vector<SweepRow>& rows);

// ---- What accuracy costs in time -------------------------------------------------------
// `climbsim bench accuracy`: one knob at a time (time step; MuJoCo integrator; solver
// iterations; solver tolerance; bond grid; Odeint stepper and tolerance) swept around the
// scenario, each run measured against a reference at the finest setting of every knob.
struct AccuracyRun {
  double wall_s = 0.0;
  bool stable = true, fell = false;
  double distance_m = 0.0;
  std::vector<std::vector<double>> detach_s;  // per pad, in order
  std::vector<double> peak_load_n;            // per pad, over the event rows
  double pulloff_n = 0.0;                     // pull-off at 45° (pull-off rig), 0 without adhesion
};
struct AccuracyRow {
  std::string knob, setting;
  AccuracyRun run;
  double distance_error_m = 0.0;
  double detach_time_error_s = 0.0;  // mean |Δt| of the detaches matched in order per pad
  int detach_count_diff = 0;         // detaches one run has and the other has not
  double peak_load_error = 0.0;      // largest relative error of a pad's peak load
  double pulloff_error = 0.0;        // relative
};
struct AccuracyReport {
  double duration_s = 0.0;
  AccuracyRun reference;
  std::vector<AccuracyRow> rows;
};
AccuracyReport BenchAccuracy(const std::string& scenario_file, double duration_s, int threads);
// accuracy.csv and accuracy.png (error against wall time on log axes, a curve per knob).
std::string WriteAccuracy(const std::string& dir, const AccuracyReport& report);

// ---- Running it ---------------------------------------------------------------------------
struct Evaluation {
  int start = 0;
  int index = 0;                  // 0-based within its start
  std::vector<double> x;
  double objective = 0.0;         // aggregate J over the runs
  Cost nominal;                   // run 0 (what best.yaml replays)
  int failed_runs = 0;
  double wall_time_s = 0.0;
};

struct Options {
  std::string out_dir;
  int threads = 0;                // 0: all cores
  bool resume = false;
  int max_evaluations = 0;        // 0: the file's
  bool quiet = false;
};

struct Result {
  Evaluation best;
  double start_objective = 0.0;   // start 0's first evaluation: the scenario as given
  std::vector<Evaluation> history;  // ordered by start, then index
  double wall_time_s = 0.0;
  int evaluations_computed = 0;   // not served from a checkpoint
};

// Writes DIR/scenario.yaml, history.csv, best.yaml, convergence.png (and .csv), summary.json
// and keeps DIR/checkpoint.json current after every evaluation (all atomically).
// progress(fraction, best_objective) is called from worker threads under a lock.
Result Optimise(const std::string& scenario_file, const Options& options,
                const std::function<void(double, double)>& progress = {});

// The cost of a nominal rollout of a scenario with an optimise block: what `climbsim
// simulate` reports as "objective" for best.yaml.
Cost NominalCost(const sim::Simulation& sim);

}  // namespace climbsim::optimise

#endif  // CLIMBSIM_OPTIMISE_OPTIMISE_H_
