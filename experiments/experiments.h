// The verbs that run many simulations of one scenario and report what they measured:
// `climbsim sweep` (a key over a range), `bench accuracy` (what accuracy costs in time),
// `bench robustness` (the largest disturbance survived), `pulloff` (the pad's limit against
// the pulling angle) and `bench speed` (experiments/bench_speed.h). Their rollouts run on the
// one rollout pool (optimise::ParallelRollouts), which hands a worker's error to the caller.
#ifndef CLIMBSIM_EXPERIMENTS_EXPERIMENTS_H_
#define CLIMBSIM_EXPERIMENTS_EXPERIMENTS_H_

#include <string>
#include <vector>

#include "experiments/bench_speed.h"
#include "optimise/disturbance.h"
#include "optimise/optimise.h"

namespace climbsim::optimise {

// ---- Parameter sweeps ------------------------------------------------------------------
// `climbsim sweep`: each scenario run with one numeric key set to each value of a range
// (e.g. scene.incline_deg from 0 to 180 in steps of 15), runs side by side on threads and,
// under mpirun, ranks. With seeds > 1 each point runs seed cases 0 .. seeds-1
// (optimise::ApplyCaseSeed: the bench's seeds) and reports their worst and mean.
struct SweepOptions {
  std::string key;
  double from = 0.0, to = 0.0, step = 1.0;
  int threads = 0;  // 0: all cores
  int seeds = 1;
  // Non-empty: every run's folder is written under it (`--keep-runs`: DIR/runs), as
  // <file stem>/v<value index>_seed<k>; not under mpirun with more than one rank.
  std::string runs_dir;
};
// One run of a sweep: its result and what its summary.json says of a stall (the gait held
// to the end of the run: sim/cpg_effect.h).
struct SweepRun {
  sim::RunResult result;
  bool stalled = false;
  double stall_time_s = -1.0;
  nlohmann::json summary;  // the run's summary.json (what a --find condition reads)
};
// One scenario at one value, over its seeds. A run that fell or stalled is never progress:
// the worst speed is 0 when any seed fell or stalled.
struct SweepPoint {
  std::vector<SweepRun> seeds;
  int fell() const;                 // seeds that fell
  int stalled() const;              // seeds that stalled
  double first_fall_s() const;      // earliest fall, -1 when none
  double first_stall_s() const;     // earliest stall, -1 when none
  double worst_speed_mps() const;
  double mean_speed_mps() const;    // over every seed, fallen and stalled included
  double worst_distance_m() const;
};
struct SweepRow {
  double value = 0.0;
  std::vector<sim::RunResult> results;  // one per scenario, in the order given: seed 0's
  std::vector<SweepPoint> points;       // one per scenario: every seed
};
// The most values a sweep may take; the most seeds per point.
inline constexpr int kMaxSweepValues = 10000;
inline constexpr int kMaxSweepSeeds = 100;
// Throws InputError ("climbsim sweep" at --from, --to, --step or --seeds) for a range that
// is not finite, runs backwards, or holds more than kMaxSweepValues values.
void CheckSweepRange(const SweepOptions& options);
// Throws InputError for a key the files cannot hold or a value that makes a scenario invalid
// (checked for every value before anything runs).
std::vector<SweepRow> Sweep(const std::vector<std::string>& scenario_files,
                            const SweepOptions& options);
// sweep.csv (value, then per scenario: worst distance, worst and mean speed, seeds fallen,
// first fall, seeds stalled, first stall) and sweep.png. Returns the plot's warning ("" when
// drawn).
std::string WriteSweep(const std::string& dir, const std::vector<std::string>& scenario_files,
                       const SweepOptions& options, const std::vector<SweepRow>& rows);

// The terminal table (per value, each file's speed, fall and stall times) and the outputs line.
std::string SweepTable(const std::vector<std::string>& scenario_files, const SweepOptions& options,
                       const std::vector<SweepRow>& rows, const std::string& out_dir,
                       const std::string& plot_warning);

// ---- Thresholds (`climbsim sweep --find`, threshold.cc) -------------------------------------
// A condition on a run's summary.json: FIELD OP NUMBER, e.g. "distance_m>=0.1", or several
// joined by " and "; OP is one of < <= > >= == !=; a true/false field reads as 1/0. Parsed by
// this fixed grammar, never evaluated as code.
struct Condition {
  struct Term {
    std::string field, op;
    double value = 0.0;
  };
  std::vector<Term> terms;
  std::string text;
};
// Throws InputError ("climbsim sweep" at --condition) for text outside the grammar.
Condition ParseCondition(const std::string& text);
// Whether `summary` meets the condition; `why` (may be null) gets the first term that fails
// ("distance_m = 0.0712").
bool Meets(const Condition& condition, const nlohmann::json& summary, std::string* why);

struct FindOptions {
  std::string key;
  double low = 0.0, high = 0.0;
  Condition condition;
  double tolerance = 0.01;  // relative: stop when high - low <= tolerance * |edge|
  int seeds = 1;
  int threads = 0;
  std::string runs_dir;     // non-empty: each probe's runs under it (probe<i>_seed<k>)
};
struct FindProbe {
  double value = 0.0;
  bool holds = false;         // on every seed
  std::string failing;        // "seed 1: distance_m = 0.0712" when it does not
  SweepPoint point;
};
struct FindResult {
  std::vector<FindProbe> probes;  // in the order run: low, high, then the bisection
  double holds_at = 0.0, fails_at = 0.0;  // the last pair either side of the edge
  // Probes sorted by value whose outcome differs from their neighbour's: more than 1 means
  // the edge is not monotone in the key (the bisection found one flip of several).
  int flips = 0;
  double wall_s = 0.0;
};
// Bisects `key` in [low, high] for where the condition stops (or starts) holding on every
// seed. Throws InputError (exit 2) for bad options, and after the first two probes when the
// condition holds at both ends or at neither.
FindResult FindThreshold(const std::string& scenario_file, const FindOptions& options);
// find.csv (every probe: value, holds, worst distance, seeds fallen and stalled).
void WriteFind(const std::string& dir, const FindOptions& options, const FindResult& result);
// The probes and the result as printed.
std::string FindText(const FindOptions& options, const FindResult& result);

// Internal to sweep.cc and threshold.cc: every scenario of `scenarios` run in order on the
// rollout pool and, under mpirun, spread over the ranks (every rank gets every run back);
// with run_dirs (one per scenario, or empty), each run's folder is written there.
std::vector<SweepRun> RunSweepPoints(const std::vector<sim::Scenario>& scenarios,
                                     const std::vector<std::string>& run_dirs, int threads);

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
//   terrain     scene.terrain.rms_m (rough rock; seed case k: rock seed k + 1; only when
//               named in families)                                      m     0.0001 .. 0.005
// Families a scenario cannot take (pad_failure and weak_patch without adhesion, weak_patch,
// roughness and terrain off the plane scenes, pushes without cpg, and a family whose key the
// scenario sets itself: scene.roughness, scene.terrain, scene.weak_patches,
// adhesion.pad_failure_probability > 0, which the search would replace) are left out; named in `families`, one is refused (InputError saying
// why), before any run. So are pushes whose last phase would end after the run (--phases).
// RobustnessOptions and RobustnessFamily: optimise/disturbance.h (the objective's robustness
// term builds the same cases).

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
  // That case as a scenario file (its seed, jitter, disturbance and outputs resolved), for
  // `climbsim simulate` to replay and `inspect` to show; "" when nothing failed.
  std::string failing_scenario_yaml;
  int evaluations = 0, runs = 0;
  bool same_as_reflexes = false;  // spindle and GTO were already off: the rows are one search
};
// What a bench will do, known before any run: each push's time (one per phase; empty without
// push families) and a warning when the runs are too short to show a fall. A case survives
// only what its run lasts: a disturbance needs at least kRobustnessMinCycles gait cycles of
// run after the last push (push families) or in the whole run (the others, present from the
// start) before a survival means anything; otherwise `warning` says how many there are and
// which --duration would give them. Throws InputError (exit 2), like BenchRobustness, for what
// it refuses: an unknown family, one the scenario cannot take, a push outside the run.
inline constexpr double kRobustnessMinCycles = 3.0;
struct RobustnessPlan {
  double duration_s = 0.0;
  double frequency_hz = 0.0;            // 0: no cpg
  std::vector<std::string> families;    // those that will be searched, in table order
  std::vector<std::string> skipped;     // "family: why", families left out (none named)
  std::vector<double> push_times_s;     // phase j's push, s
  double cycles_left = 0.0;             // after the last push (or in the run), gait cycles
  double suggested_duration_s = 0.0;    // the shortest --duration with kRobustnessMinCycles
  std::string warning;                  // "" when the runs are long enough
};
RobustnessPlan PlanRobustness(const sim::Scenario& scenario, const RobustnessOptions& options);
// The plan as the verb prints it before the runs: push times, families left out, the warning.
std::string RobustnessPlanText(const RobustnessPlan& plan);

// One bisection step's cases (or the undisturbed runs) as they ran, for bench robustness's
// schedule simulation: per case, whether it ran here, its wall time, whether it failed.
struct RobustnessStepRecord {
  std::vector<double> wall_s;
  std::vector<char> ran, failed;
};
struct RobustnessReport {
  std::string scenario_file;
  RobustnessOptions options;
  RobustnessPlan plan;
  double robot_mass_kg = 0.0;
  std::vector<std::vector<double>> baseline_m;  // [mode][seed] undisturbed distance
  std::vector<RobustnessRow> rows;              // per family: reflexes, then spindle_gto_off
  // How the runs went (not part of the table, which no thread count changes): the
  // undisturbed runs, each search's steps (family by family, mode by mode), each worker's
  // time inside runs and the wall time of all the runs.
  RobustnessStepRecord baselines;
  std::vector<std::vector<RobustnessStepRecord>> searches;
  std::vector<double> worker_busy_s;
  double wall_s = 0.0;
};
// progress(fraction) is called from worker threads under a lock.
RobustnessReport BenchRobustness(const std::string& scenario_file, const RobustnessOptions& options,
                                 const std::function<void(double)>& progress = {});
// Whether one case survives `magnitude` (what the search evaluates), with why not in `how`.
bool RobustnessSurvives(const sim::Scenario& scenario, double baseline_m, std::string* how);
// robustness.csv, robustness.png (one panel per family, reflexes against spindle and GTO
// off) and failing/FAMILY[_spindle_gto_off].yaml, each row's failing case. Returns the plot's
// warning ("" when drawn).
std::string WriteRobustness(const std::string& dir, const RobustnessReport& report);
// The terminal table.
std::string RobustnessTable(const RobustnessReport& report);

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

#endif  // CLIMBSIM_EXPERIMENTS_EXPERIMENTS_H_
