// climbsim bench robustness (optimise/optimise.h states what is searched and how).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <limits>
#include <mutex>
#include <thread>

#include "experiments/case_pool.h"
#include "experiments/experiments.h"
#include "common/common.h"

namespace climbsim::optimise {
namespace {

// The cases and the "survived" rule are the objective's robustness term's too
// (optimise/disturbance.h).
using Setup = DisturbanceSetup;

bool PushFamily(const std::string& family) { return family.rfind("push_", 0) == 0; }

bool Applicable(const Setup& u, const std::string& family) {
  return CannotTakeFamily(u, family).empty();
}

bool Survives(const sim::Scenario& s, double baseline_m, ModelCache* cache, std::string* how) {
  sim::Simulation run(s, cache->For(s));
  return SurvivedRun(run.Run(), baseline_m, how);
}

std::string Num(double v) { return sim::ExactNumber(v); }

}  // namespace

std::vector<std::string> RobustnessFamilyNames() {
  std::vector<std::string> names;
  for (const auto& f : AllRobustnessFamilies(1.0)) names.push_back(f.name);
  return names;
}

std::vector<RobustnessFamily> RobustnessFamilies(const sim::Scenario& scenario) {
  const Setup u = MakeDisturbanceSetup(scenario, RobustnessOptions{});
  std::vector<RobustnessFamily> out;
  for (const auto& f : AllRobustnessFamilies(u.robot_mass_kg)) {
    if (!f.named_only && Applicable(u, f.name)) out.push_back(f);
  }
  return out;
}

sim::Scenario RobustnessCase(const sim::Scenario& base, const RobustnessOptions& options,
                             const std::string& family, double magnitude, int mode, int seed,
                             int phase) {
  return DisturbanceCase(MakeDisturbanceSetup(base, options), family, magnitude, mode, seed, phase);
}

bool RobustnessSurvives(const sim::Scenario& scenario, double baseline_m, std::string* how) {
  ModelCache cache;
  return Survives(scenario, baseline_m, &cache, how);
}

namespace {

// What is refused before any work (bad input, exit code 2): an unknown family, a family the
// scenario cannot take, a push time the pushes' schedule cannot keep.
void CheckOptions(const Setup& u, const RobustnessOptions& options) {
  const std::vector<std::string> known = RobustnessFamilyNames();
  for (const std::string& f : options.families) {
    if (std::find(known.begin(), known.end(), f) == known.end()) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      throw InputError("climbsim bench robustness", 0, 0, "--families",
                       "unknown family '" + f + "' (" + list + ")");
    }
    const std::string why = CannotTakeFamily(u, f);
    if (!why.empty()) {
      throw InputError("climbsim bench robustness", 0, 0, "--families",
                       "the scenario cannot take family '" + f + "': " + why);
    }
  }
  // The pushes start within the first third of the run, so that every phase and its outcome
  // fit in it.
  const double latest_s = u.duration_s / 3.0;
  if (options.push_time_s && !(*options.push_time_s >= 0.0 && *options.push_time_s <= latest_s)) {
    char buf[160];
    std::snprintf(buf, sizeof(buf), "must be in [0, %g] s (a third of the %g s run), got %g",
                  latest_s, u.duration_s, *options.push_time_s);
    throw InputError("climbsim bench robustness", 0, 0, "--push-time", buf);
  }
  // Every phase's push inside the run (a push after its end would "survive" anything).
  const bool pushes = std::any_of(options.families.begin(), options.families.end(), PushFamily) ||
                      (options.families.empty() && u.frequency_hz > 0);
  if (pushes && DisturbancePushTime(u, u.options.phases - 1) + kPushDuration > u.duration_s) {
    char buf[200];
    std::snprintf(buf, sizeof(buf),
                  "the last of %d push phases, at %.3f s, ends after the %g s run: give a longer "
                  "--duration or fewer --phases",
                  u.options.phases, DisturbancePushTime(u, u.options.phases - 1), u.duration_s);
    throw InputError("climbsim bench robustness", 0, 0, "--phases", buf);
  }
}

}  // namespace

namespace {

// The families asked for (all when none are named) that the scenario can take, in table order.
std::vector<RobustnessFamily> WantedFamilies(const Setup& u, const RobustnessOptions& options) {
  std::vector<RobustnessFamily> families;
  for (const auto& f : AllRobustnessFamilies(u.robot_mass_kg)) {
    const bool wanted = (options.families.empty() && !f.named_only) ||
                        std::find(options.families.begin(), options.families.end(), f.name) !=
                            options.families.end();
    if (wanted && Applicable(u, f.name)) families.push_back(f);
  }
  return families;
}

// Every family's largest case must build before anything long runs (bad input: exit 2).
void CheckLargestCases(const Setup& u, const std::vector<RobustnessFamily>& families) {
  ModelCache cache;
  for (const auto& f : families) {
    const sim::Scenario s = DisturbanceCase(u, f.name, f.hi, 0, std::max(0, u.options.seeds - 1), 0);
    sim::Simulation check(s, cache.For(s));
  }
}

// Progress: each search counts its budget of evaluations (cases each), baselines one run.
// Called from the pool's threads, one at a time.
class Progress {
 public:
  Progress(const RobustnessOptions& options, const std::vector<RobustnessFamily>& families,
           int modes, const std::function<void(double)>& progress)
      : options_(options), progress_(progress) {
    total_ = modes * options.seeds;
    for (const auto& f : families) total_ += modes * Budget(f);
  }

  // The evaluations a search of `f` may spend, in runs: the two ends and the bisection.
  int Budget(const RobustnessFamily& f) const {
    const double steps =
        std::ceil(std::log2(std::log(f.hi / f.lo) / std::log1p(options_.tolerance)));
    return (2 + std::max(0, static_cast<int>(steps))) *
           (f.name.rfind("push_", 0) == 0 ? options_.seeds * options_.phases : options_.seeds);
  }

  void Advance(double runs) {
    std::lock_guard<std::mutex> lock(mutex_);
    done_ += runs;
    if (progress_) progress_(std::min(1.0, done_ / total_));
  }

 private:
  const RobustnessOptions& options_;
  const std::function<void(double)>& progress_;
  std::mutex mutex_;
  double total_ = 0;
  double done_ = 0;
};

// One family's search in one mode: the largest magnitude every case (seed, push phase)
// survives, bisected geometrically between the family's lo and hi to the tolerance. Each
// magnitude's cases run side by side on the pool (experiments/case_pool.h).
class Search {
 public:
  Search(const Setup& u, const RobustnessFamily& f, int mode,
         const std::vector<double>& baseline_m, internal::CasePool* pool, Progress* progress)
      : u_(u), f_(f), mode_(mode), baseline_m_(baseline_m), pool_(pool), progress_(progress),
        push_(f.name.rfind("push_", 0) == 0), phases_(push_ ? u.options.phases : 1) {
    row_.family = f.name;
    row_.unit = f.unit;
    row_.mode = mode == 0 ? "reflexes" : "spindle_gto_off";
    row_.lo = f.lo;
    row_.hi = f.hi;
  }

  RobustnessRow Run() {
    if (Evaluate(f_.hi)) {
      row_.survived = f_.hi;
      row_.failed = std::numeric_limits<double>::infinity();
    } else {
      const Failure hi = fail_;
      if (!Evaluate(f_.lo)) {
        row_.survived = 0.0;
        Record(f_.lo, fail_);
      } else {
        Bisect(hi);
      }
    }
    // The budget not spent still counts, so the bar ends full.
    const int spent = row_.evaluations * u_.options.seeds * phases_;
    progress_->Advance(std::max(0, progress_->Budget(f_) - spent));
    return row_;
  }

  // The pool's numbers of this search's steps, in order.
  const std::vector<int>& steps() const { return steps_; }

 private:
  // The first case that failed at a magnitude: its index (seed * phases + phase) and why.
  struct Failure {
    int index = 0;
    std::string how;
  };

  // lo survives, hi fails (as `hi` says): narrows [a, b] at the geometric mean.
  void Bisect(const Failure& hi) {
    double a = f_.lo, b = f_.hi;
    Failure at_b = hi;
    while (b > a * (1.0 + u_.options.tolerance)) {
      const double c = std::sqrt(a * b);
      if (Evaluate(c)) {
        a = c;
      } else {
        b = c;
        at_b = fail_;
      }
    }
    row_.survived = a;
    Record(b, at_b);
  }

  // The row's failure at magnitude m: the case's name, why, and the case as a file to replay
  // (the base scenario's outputs: the search runs without a trajectory).
  void Record(double m, const Failure& f) {
    row_.failed = m;
    row_.failing_case = "seed " + std::to_string(f.index / phases_) +
                        (push_ ? " phase " + std::to_string(f.index % phases_) : "");
    row_.failing_how = f.how;
    sim::Scenario s = DisturbanceCase(u_, f_.name, m, mode_, f.index / phases_, f.index % phases_);
    s.outputs = u_.base.outputs;
    char head[256];
    std::snprintf(head, sizeof(head),
                  "# climbsim bench robustness: the first case that failed, %s at %.6g (%s, %s)\n"
                  "# Replay: climbsim simulate THIS_FILE --out DIR\n",
                  f_.name.c_str(), m, row_.mode.c_str(), row_.failing_case.c_str());
    row_.failing_scenario_yaml = head + sim::ScenarioToYamlText(s);
  }

  // Whether every case (seed by seed, phase by phase) survives magnitude m; the first that
  // does not is kept in fail_.
  bool Evaluate(double m) {
    ++row_.evaluations;
    const int n = u_.options.seeds * phases_;
    // Copies, not references to this search: a failed step's unheeded cases run on after
    // RunStep returns (the Setup outlives the pool).
    const Setup* u = &u_;
    internal::CaseFn run = [u, family = f_.name, m, mode = mode_, baseline = baseline_m_,
                            phases = phases_](int i, ModelCache* cache, std::string* how) {
      return Survives(DisturbanceCase(*u, family, m, mode, i / phases, i % phases), baseline[i / phases],
                      cache, how);
    };
    std::string how;
    int id = 0;
    const int first = pool_->RunStep(n, std::move(run), &how, &id);
    steps_.push_back(id);
    // The runs the verdict needs: the cases up to the first failure, as one core runs them.
    row_.runs += first < n ? first + 1 : n;
    progress_->Advance(n);
    if (first == n) return true;
    fail_ = {first, how};
    return false;
  }

  const Setup& u_;
  const RobustnessFamily& f_;
  const int mode_;
  const std::vector<double>& baseline_m_;
  internal::CasePool* pool_;
  Progress* progress_;
  const bool push_;
  const int phases_;
  RobustnessRow row_;
  Failure fail_;  // the last failing magnitude's
  std::vector<int> steps_;
};

// The report's rows: per family, the reflexes' row then the spindle + GTO off one (a copy
// of the first when one search served both modes).
std::vector<RobustnessRow> PairedRows(std::vector<RobustnessRow> rows, size_t families,
                                      bool same) {
  std::vector<RobustnessRow> out;
  for (size_t i = 0; i < families; ++i) {
    if (same) {
      rows[2 * i + 1] = rows[2 * i];
      rows[2 * i + 1].mode = "spindle_gto_off";
      rows[2 * i + 1].same_as_reflexes = true;
    }
    out.push_back(rows[2 * i]);
    out.push_back(rows[2 * i + 1]);
  }
  return out;
}

// The shortest duration that leaves kRobustnessMinCycles after the last push (pushes) or in
// the run: the default first push moves with the duration (a third of it, at most 4 s).
double SuggestedDuration(const Setup& u, bool pushes) {
  const double need_s = kRobustnessMinCycles / u.frequency_hz;
  if (!pushes) return need_s;
  const double after_first_s = DisturbancePushTime(u, u.options.phases - 1) - u.push_time_s + need_s;
  if (u.options.push_time_s) {
    return std::max(*u.options.push_time_s + after_first_s, 3.0 * *u.options.push_time_s);
  }
  return after_first_s * 1.5 <= 3.0 * kDefaultPushTimeS ? after_first_s * 1.5
                                                        : kDefaultPushTimeS + after_first_s;
}

RobustnessPlan MakePlan(const Setup& u, const RobustnessOptions& options) {
  CheckOptions(u, options);
  RobustnessPlan plan;
  plan.duration_s = u.duration_s;
  plan.frequency_hz = u.frequency_hz;
  bool pushes = false;
  for (const auto& f : AllRobustnessFamilies(u.robot_mass_kg)) {
    const bool named = std::find(options.families.begin(), options.families.end(), f.name) !=
                       options.families.end();
    if (options.families.empty() ? f.named_only : !named) continue;
    const std::string why = CannotTakeFamily(u, f.name);
    if (!why.empty()) {
      plan.skipped.push_back(f.name + ": " + why);
      continue;
    }
    plan.families.push_back(f.name);
    pushes = pushes || PushFamily(f.name);
  }
  if (pushes) {
    for (int j = 0; j < options.phases; ++j) plan.push_times_s.push_back(DisturbancePushTime(u, j));
  }
  if (u.frequency_hz <= 0 || plan.families.empty()) return plan;
  const double left_s = u.duration_s - (pushes ? plan.push_times_s.back() : 0.0);
  plan.cycles_left = left_s * u.frequency_hz;
  plan.suggested_duration_s = SuggestedDuration(u, pushes);
  if (plan.cycles_left < kRobustnessMinCycles) {
    char buf[400];
    std::snprintf(buf, sizeof(buf),
                  "warning: the %g s runs leave %.2f gait cycles (%.2f s at %g Hz) %s, fewer "
                  "than %g: a robot that falls later counts as surviving; --duration %.3g "
                  "would leave %g",
                  u.duration_s, plan.cycles_left, left_s, u.frequency_hz,
                  pushes ? "after the last push" : "in the whole run", kRobustnessMinCycles,
                  std::ceil(plan.suggested_duration_s * 100.0) / 100.0, kRobustnessMinCycles);
    plan.warning = buf;
  }
  return plan;
}

}  // namespace

RobustnessPlan PlanRobustness(const sim::Scenario& scenario, const RobustnessOptions& options) {
  return MakePlan(MakeDisturbanceSetup(scenario, options), options);
}

std::string RobustnessPlanText(const RobustnessPlan& plan) {
  std::string out;
  if (!plan.push_times_s.empty()) {
    out += "  pushes at";
    char buf[64];
    for (double t : plan.push_times_s) {
      std::snprintf(buf, sizeof(buf), " %.3f", t);
      out += buf;
    }
    std::snprintf(buf, sizeof(buf), " s (one per phase of the %g Hz gait)\n", plan.frequency_hz);
    out += buf;
  }
  for (const std::string& s : plan.skipped) out += "  left out: " + s + "\n";
  if (!plan.warning.empty()) out += "  " + plan.warning + "\n";
  return out;
}

namespace {

// The undisturbed runs, then every family's search in every mode, one driver thread each,
// their cases side by side on the pool's workers (`threads`, 0: one per core). Fills the
// report's baselines, rows and records. An exception (bad input met only when a case is
// built) reaches the caller: the baselines', else the first search's in table order.
void RunAll(const Setup& u, const std::vector<RobustnessFamily>& families, int modes,
            Progress* bar, RobustnessReport* report) {
  const RobustnessOptions& options = u.options;
  const int workers = std::max(1, options.threads > 0
                                      ? options.threads
                                      : static_cast<int>(std::thread::hardware_concurrency()));
  const int searches = static_cast<int>(families.size()) * modes;
  internal::CasePool pool(workers);
  report->baseline_m.assign(2, std::vector<double>(options.seeds, 0.0));
  std::vector<RobustnessRow> rows(families.size() * 2);
  std::vector<std::vector<int>> steps(searches);
  std::vector<std::exception_ptr> errors(searches + 1);
  int baseline_step = 0;
  const auto t0 = std::chrono::steady_clock::now();
  common::ParallelFor(workers + 1, workers + 1, [&](int task) {
    if (task > 0) return pool.Work(task - 1);
    try {
      std::string how;
      pool.RunStep(modes * options.seeds, [&](int t, ModelCache* cache, std::string*) {
        const sim::Scenario s = DisturbanceCase(u, "", 0, t / options.seeds, t % options.seeds, 0);
        sim::Simulation run(s, cache->For(s));
        report->baseline_m[t / options.seeds][t % options.seeds] = run.Run().distance_m;
        bar->Advance(1);
        return true;
      }, &how, &baseline_step);
    } catch (...) {
      errors[0] = std::current_exception();
    }
    if (!errors[0]) {
      common::ParallelFor(searches, searches, [&](int t) {
        const int mode = t % modes;
        try {
          Search search(u, families[t / modes], mode, report->baseline_m[mode], &pool, bar);
          rows[2 * (t / modes) + mode] = search.Run();
          steps[t] = search.steps();
        } catch (...) {
          errors[t + 1] = std::current_exception();
        }
      });
    }
    pool.Close();
  });
  report->wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
  report->rows = PairedRows(std::move(rows), families.size(), modes == 1);
  report->baselines = pool.Record(baseline_step);
  for (const auto& ids : steps) {
    report->searches.emplace_back();
    for (int id : ids) report->searches.back().push_back(pool.Record(id));
  }
  report->worker_busy_s = pool.busy_s();
}

}  // namespace

RobustnessReport BenchRobustness(const std::string& file, const RobustnessOptions& options,
                                 const std::function<void(double)>& progress) {
  const sim::Scenario base = sim::LoadScenario(file);
  const Setup u = MakeDisturbanceSetup(base, options);
  const RobustnessPlan plan = MakePlan(u, options);
  const std::vector<RobustnessFamily> families = WantedFamilies(u, options);
  CheckLargestCases(u, families);
  // Spindle and GTO already off (or no reflexes): mode 1 is mode 0, searched once.
  const bool same = sim::ScenarioToYamlText(DisturbanceCase(u, "", 0, 0, 0, 0)) ==
                    sim::ScenarioToYamlText(DisturbanceCase(u, "", 0, 1, 0, 0));
  const int modes = same ? 1 : 2;

  RobustnessReport report;
  report.scenario_file = file;
  report.options = options;
  report.robot_mass_kg = u.robot_mass_kg;
  report.plan = plan;
  Progress bar(options, families, modes, progress);

  RunAll(u, families, modes, &bar, &report);
  if (same) report.baseline_m[1] = report.baseline_m[0];
  if (progress) progress(1.0);
  return report;
}

std::string RobustnessTable(const RobustnessReport& r) {
  std::string out;
  char buf[512];
  std::snprintf(buf, sizeof(buf),
                "climbsim bench robustness: %s, %.1f s per run, %d seeds, %d push phases\n",
                r.scenario_file.c_str(), r.options.duration_s, r.options.seeds, r.options.phases);
  out += buf;
  std::string base0, base1;
  for (double d : r.baseline_m[0])
    base0 += (base0.empty() ? "" : " ") + Num(std::round(d * 1e4) / 1e4);
  for (double d : r.baseline_m[1])
    base1 += (base1.empty() ? "" : " ") + Num(std::round(d * 1e4) / 1e4);
  out += "  undisturbed distance [m] per seed: reflexes " + base0 + "; spindle+GTO off " + base1 +
         "\n";
  out += RobustnessPlanText(r.plan);
  out +=
      "  survived = largest magnitude every case survives (no fall, >= half the undisturbed "
      "distance); fails = the next one tried\n";
  std::snprintf(buf, sizeof(buf), "  %-12s %-5s %12s %12s %12s %12s %7s  %s\n", "family", "unit",
                "reflexes", "fails at", "sp+GTO off", "fails at", "ratio",
                "first failure (reflexes)");
  out += buf;
  auto fmt = [](double v) {
    char b[32];
    if (std::isinf(v)) return std::string("-");
    std::snprintf(b, sizeof(b), "%.4g", v);
    return std::string(b);
  };
  for (size_t i = 0; i + 1 < r.rows.size(); i += 2) {
    const RobustnessRow& on = r.rows[i];
    const RobustnessRow& off = r.rows[i + 1];
    const std::string s_on = (std::isinf(on.failed) ? ">=" : "") + fmt(on.survived);
    const std::string s_off = (std::isinf(off.failed) ? ">=" : "") + fmt(off.survived);
    const std::string ratio = off.survived > 0 ? fmt(on.survived / off.survived) : "-";
    std::snprintf(buf, sizeof(buf), "  %-12s %-5s %12s %12s %12s %12s %7s  %s\n", on.family.c_str(),
                  on.unit.empty() ? "-" : on.unit.c_str(), s_on.c_str(), fmt(on.failed).c_str(),
                  s_off.c_str(), fmt(off.failed).c_str(), ratio.c_str(),
                  on.failing_case.empty() ? "" : (on.failing_case + ": " + on.failing_how).c_str());
    out += buf;
  }
  if (!r.rows.empty() && r.rows[1].same_as_reflexes) {
    out += "  (spindle and GTO are already off in this scenario: one search serves both columns)\n";
  }
  return out;
}

namespace {

std::string CsvQuote(const std::string& s) {
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

// robustness.csv: one line per row of the report.
std::string RobustnessCsv(const RobustnessReport& r) {
  std::string csv =
      "family,unit,mode,survived,failed,lo,hi,evaluations,runs,failing_case,failing_how,"
      "same_as_reflexes\n";
  for (const RobustnessRow& row : r.rows) {
    csv += row.family + "," + row.unit + "," + row.mode + "," + Num(row.survived) + "," +
           (std::isinf(row.failed) ? std::string("inf") : Num(row.failed)) + "," + Num(row.lo) +
           "," + Num(row.hi) + "," + std::to_string(row.evaluations) + "," +
           std::to_string(row.runs) + "," + CsvQuote(row.failing_case) + "," +
           CsvQuote(row.failing_how) + "," + (row.same_as_reflexes ? "1" : "0") + "\n";
  }
  return csv;
}

// robustness.dat: per family a block of two bars, reflexes and spindle + GTO off.
std::string RobustnessDat(const RobustnessReport& r) {
  std::string data;
  const int n = static_cast<int>(r.rows.size() / 2);
  for (int i = 0; i < n; ++i) {
    const RobustnessRow& on = r.rows[2 * i];
    const RobustnessRow& off = r.rows[2 * i + 1];
    data += "0 \"reflexes\" " + Num(std::max(on.survived, on.lo * 0.5)) + "\n";
    data += "1 \"spindle+GTO off\" " + Num(std::max(off.survived, off.lo * 0.5)) + "\n\n\n";
  }
  return data;
}

// The gnuplot script of robustness.png for n > 0 families: one panel each, survived
// magnitude on a log axis from lo to hi.
std::string RobustnessScript(const RobustnessReport& r, int n) {
  const int cols = std::min(n, 4), rows = (n + cols - 1) / cols;
  // Two lines: the file name single-quoted (inert), joined to climbsim's own "\n" (only a
  // double-quoted string turns it into a line break).
  const std::string title =
      common::GnuplotQuote("robustness of " +
                           std::filesystem::path(r.scenario_file).filename().string() +
                           ": largest magnitude survived") +
      ".\"\\n(a bar at the bottom: not even the smallest; at the top: the largest tried)\"";
  std::string script =
      "set terminal pngcairo size " + std::to_string(330 * cols) + "," +
      std::to_string(60 + 360 * rows) +
      " noenhanced\nset output OUTPUT(0)\n"
      "data = 'robustness.dat'\n"  // gnuplot runs in `dir`
      "set style fill solid 0.8\nset boxwidth 0.6\nset grid ytics\nset logscale y\n"
      "set lmargin 11\nset rmargin 2\nset bmargin 4\n"
      "set xrange [-0.6:1.6]\nset xtics rotate by 20 right font ',9'\nunset key\n"
      "set multiplot layout " +
      std::to_string(rows) + "," + std::to_string(cols) + " title " + title + " font ',10'\n";
  for (int i = 0; i < n; ++i) {
    const RobustnessRow& on = r.rows[2 * i];
    script +=
        "set title " + common::GnuplotQuote(on.family) + "\nset ylabel " +
        common::GnuplotQuote(on.family == "pad_failure"  ? "failure probability per attachment"
                             : on.family == "weak_patch" ? "share of sigma_T lost on a patch"
                             : on.family == "payload"    ? "payload [kg]"
                             : on.family == "roughness"  ? "bump height [m]"
                             : on.family == "terrain"    ? "RMS height of the rock [m]"
                                                         : "impulse in 10 ms [" + on.unit + "]") +
        "\nset yrange [" + Num(on.lo * 0.4) + ":" + Num(on.hi * 1.5) +
        "]\n"
        "plot data index " +
        std::to_string(i) +
        " using 1:3:($1 == 0 ? 0x3070c0 : 0xc05030):xtic(2) with boxes lc rgb variable\n";
  }
  return script + "unset multiplot\n";
}

}  // namespace

std::string WriteRobustness(const std::string& dir, const RobustnessReport& r) {
  std::filesystem::create_directories(dir);
  common::WriteFileAtomic(dir + "/robustness.csv", RobustnessCsv(r));
  common::WriteFileAtomic(dir + "/robustness.dat", RobustnessDat(r));
  for (const RobustnessRow& row : r.rows) {
    if (row.failing_scenario_yaml.empty() || row.same_as_reflexes) continue;
    std::filesystem::create_directories(dir + "/failing");
    common::WriteFileAtomic(dir + "/failing/" + row.family +
                                (row.mode == "reflexes" ? "" : "_" + row.mode) + ".yaml",
                            row.failing_scenario_yaml);
  }
  const int n = static_cast<int>(r.rows.size() / 2);
  if (n == 0) return "no family to plot";
  return common::RunGnuplot(dir, RobustnessScript(r, n), {"robustness.png"});
}

}  // namespace climbsim::optimise
