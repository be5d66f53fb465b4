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

// The rollout pool of sweep, bench accuracy and bench robustness (and of optimise's recheck
// of a resumed best; its queue's workers run on common::ParallelFor too): task(i, cache) for
// i in [0, count) on common::ParallelFor's threads (`threads` clamped to [1, count]). Each running task holds a cache no other running task holds; caches are kept
// across tasks (at most one per thread), so a model compiles about once per thread. A task's
// exception reaches the caller (the lowest failing i's) after the running tasks finish.
void ParallelRollouts(int count, int threads,
                      const std::function<void(int task, ModelCache& cache)>& task);

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

// ---- Robustness ----------------------------------------------------------------------------
// `climbsim bench robustness`: for each family of disturbance, the largest magnitude the robot
// survives, with the scenario's reflexes and with spindle and GTO off, on the same cases.
//
// A case is a seed k (0 .. seeds−1): the scenario's seed + k for every random draw, and for
// k ≥ 1 a start moved by up to ±5 mm along x and y and turned by up to ±5° (uniform draws
// from that seed), so the cases differ even where no disturbance is random. Push families
// add the phases: a push at push_time_s + j/(phases·f) (f = cpg.frequency_hz), j = 0 ..
// phases−1. A case SURVIVES a magnitude when its run (the given duration, fall.stop on) is
// stable, does not fall, and climbs at least half of what the same case climbs undisturbed
// (when that is positive). A magnitude survives when every case does.
//
// The search, per family and mode: the family's largest magnitude hi is tried first (if it
// survives, the answer is "≥ hi"), then the smallest lo ("< lo" if it fails), then geometric
// bisection between a surviving and a failing magnitude until they are within `tolerance`
// (10 %: failing ≤ 1.1 × survived). Cases run in order and an evaluation stops at its first
// failing case. (family, mode) searches run side by side on threads, each run on its own
// model copy: the report does not depend on the number of threads.
//
// Families (magnitude, unit, range):
//   push_off    10 ms push along the surface normal, away from it      N s   0.005 .. 1
//   push_down   10 ms push down the slope (gravity along the surface)  N s   0.005 .. 1
//   push_side   10 ms push across the slope (normal x down: -y on the wall) N s   0.005 .. 1
//   payload     payload_kg on the base                                 kg    2 % .. 400 % of the
//   robot's mass pad_failure adhesion.pad_failure_probability                       -     0.01 .. 1
//   weak_patch  1 − scene.weak_patches.fraction (σ_T lost on a patch; 5 cm cells, 30 % weak)
//                                                                      -     0.02 .. 0.99
//   roughness   scene.roughness.height_m (4 cm pitch, 1.5 cm tops)     m     0.0005 .. 0.03
// Families a scenario cannot take (pad_failure and weak_patch without adhesion, weak_patch and
// roughness off the plane scenes, pushes without cpg) are left out; named in `families`, one
// is refused (InputError saying why), before any run.
struct RobustnessOptions {
  double duration_s = 10.0;   // 0: the scenario's
  int seeds = 3;
  int phases = 4;
  // First push, at most a third of the duration (else InputError); default: 4 s, or a
  // third of the duration when that is earlier.
  std::optional<double> push_time_s;
  double tolerance = 0.1;
  int threads = 0;            // 0: all cores
  std::vector<std::string> families;  // empty: all
};

struct RobustnessFamily {
  std::string name, unit, what;
  double lo = 0.0, hi = 0.0;
};
// The families a scenario can take (ranges resolved: payload from the robot's mass).
std::vector<RobustnessFamily> RobustnessFamilies(const sim::Scenario& scenario);
// The names of every family, in order.
std::vector<std::string> RobustnessFamilyNames();

// The scenario of one case at one magnitude: mode 0 the scenario's reflexes, 1 spindle and GTO
// off; magnitude 0 (or family "") is the undisturbed case. Throws InputError for an unknown
// family.
sim::Scenario RobustnessCase(const sim::Scenario& base, const RobustnessOptions& options,
                             const std::string& family, double magnitude, int mode, int seed,
                             int phase);

struct RobustnessRow {
  std::string family, unit, mode;  // mode: "reflexes" or "spindle_gto_off"
  double lo = 0.0, hi = 0.0;
  double survived = 0.0;  // largest magnitude every case survived (0: not even lo)
  double failed = 0.0;    // smallest magnitude found failing (+inf: hi survived)
  std::string failing_case;  // the first case that failed at `failed` ("seed 1 phase 2")
  std::string failing_how;   // "fell at 4.21 s", "climbed 0.012 m of 0.150 m", "unstable"
  int evaluations = 0, runs = 0;
  bool same_as_reflexes = false;  // spindle and GTO were already off: the rows are one search
};
struct RobustnessReport {
  std::string scenario_file;
  RobustnessOptions options;
  double robot_mass_kg = 0.0;
  std::vector<std::vector<double>> baseline_m;  // [mode][seed] undisturbed distance
  std::vector<RobustnessRow> rows;              // per family: reflexes, then spindle_gto_off
};
// progress(fraction) is called from worker threads under a lock.
RobustnessReport BenchRobustness(const std::string& scenario_file, const RobustnessOptions& options,
                                 const std::function<void(double)>& progress = {});
// Whether one case survives `magnitude` (what the search evaluates), with why not in `how`.
bool RobustnessSurvives(const sim::Scenario& scenario, double baseline_m, std::string* how);
// robustness.csv and robustness.png (one panel per family, reflexes against spindle and GTO
// off). Returns the plot's warning ("" when drawn).
std::string WriteRobustness(const std::string& dir, const RobustnessReport& report);
// The terminal table.
std::string RobustnessTable(const RobustnessReport& report);

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

// The cost of a nominal rollout of a scenario with an optimise block: what `climbsim
// simulate` reports as "objective" for best.yaml.
Cost NominalCost(const sim::Simulation& sim);

// ---- climbsim pulloff (pulloff.cc) --------------------------------------------------------
// The options: the rig's and the sweep's own parameters (their defaults are the library's),
// and what only the command has.
struct PulloffExperimentOptions {
  std::string out_dir;
  std::string model = "both";
  adhesion::PulloffRigParams rig;
  adhesion::SweepRange range;
  std::optional<double> length_m;  // default: the width
  int grid = 0;                    // > 0 sets both sides
  double azimuth_deg = 0.0;        // rig.azimuth_rad in degrees
  bool quiet = false;
  bool force = false;
  bool keep_other_files = false;  // with force: carry a user's files along (sim/run_folder.h)
  std::string law = "von_mises";  // frictional: RunPulloffLaws
  adhesion::FrictionalParams frictional;
  double grip_deg = 0.0;
};

// Sweeps the angles, writes DIR/pulloff.csv, pulloff.gp and pulloff.png and prints the table
// (unless quiet). Throws InputError for options that do not fit (exit code 2), before
// anything runs; returns false when only the plot could not be drawn (exit code 1).
bool RunPulloffExperiment(PulloffExperimentOptions options);

struct PulloffLawOptions {
  std::string out_dir;
  bool force = false;
  bool keep_other_files = false;
  bool quiet = false;
  adhesion::PadParams pad;             // the von Mises law's pad (σ_T, μ) and the grid
  adhesion::FrictionalParams law;      // the frictional law (grip direction in the pad frame)
  double arm_m = 0.0;                  // lever of the pull (0: the closed forms apply)
  double from_deg = 0.0, to_deg = 180.0, step_deg = 5.0;
  double max_force_factor = 8.0;
};

// Runs both quasi-static sweeps (along the gripping direction and against it), writes the
// files and prints the table. Returns false when the plot could not be drawn (as
// RunPulloffExperiment).
bool RunPulloffLaws(const PulloffLawOptions& options);

}  // namespace climbsim::optimise

#endif  // CLIMBSIM_OPTIMISE_OPTIMISE_H_
