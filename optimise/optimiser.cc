// The checkpointed driver of `climbsim optimise`: the results folder, the starts (starts.cc)
// on the evaluator's queue (evaluator.cc, ranks.cc), every rank's common result, and the
// files rank 0 writes.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>

#include "common/common.h"
#include "optimise/checkpoint.h"
#include "optimise/comm.h"
#include "optimise/evaluator.h"
#include "optimise/optimise.h"
#include "optimise/starts.h"
#include "optimise/text.h"

namespace climbsim::optimise {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using internal::Shared;

// CPU seconds (user + system) of this process so far, all threads.
double CpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + 1e-6 * u.ru_utime.tv_usec + u.ru_stime.tv_sec +
         1e-6 * u.ru_stime.tv_usec;
}

// A resumed run's best, when checkpoint.json served it, evaluated again here (its runs with
// the bound it had), so that the best reported is always a value this process computed. The
// checksum catches accidental damage only: a checkpoint edited with its checksum recomputed
// is refused here (InputError at the evaluation), as would one written by another build.
void RecheckReplayedBest(const Problem& problem, const Shared& shared, const Evaluation& best,
                         int threads) {
  if (shared.replayed.count({best.start, best.index}) == 0) return;
  // A start's first batch (its evaluation 0) ran without the bound, later ones with it (Submit).
  const double bound = best.index == 0 ? std::numeric_limits<double>::infinity() : shared.bound;
  std::vector<Cost> costs(problem.rollouts());
  ParallelRollouts(problem.rollouts(), threads, [&](int run, ModelCache& cache) {
    costs[run] = internal::Rollout(problem, best.x, run, bound, cache);
  });
  Evaluation again;
  const double j = internal::EvaluationCost(problem, costs.data(), &again);
  if (j == best.objective) return;
  throw InputError(
      shared.checkpoint_path, 0, 0,
      "starts[" + std::to_string(best.start) + "][" + std::to_string(best.index) + "].objective",
      "the best evaluation it holds, J = " + sim::ExactNumber(best.objective) +
          ", computes to J = " + sim::ExactNumber(j) +
          " here: the checkpoint was edited or written by another build (its checksum guards "
          "against accidental damage, not edits); drop --resume (and use --force) to start over");
}


std::string HistoryCsv(const Problem& problem, const std::vector<Evaluation>& history) {
  std::string out = "evaluation,start";
  for (const auto& p : problem.params().parameters) out += "," + p.key;
  // The robustness term's columns only where it is on (other runs' history keeps its form),
  // before wall_time_s, which stays last.
  const bool robust = !problem.params().objective.robustness.empty();
  out += ",objective,speed_mps,fall_penalty_mps,overload_penalty_mps,energy_penalty_mps,"
         "failed_runs,early_stop,";
  out += robust ? "robustness_cases_failed,robustness_penalty_mps,wall_time_s\n"
                : "wall_time_s\n";
  for (const Evaluation& e : history) {
    out += std::to_string(e.index) + "," + std::to_string(e.start);
    for (double v : e.x) out += "," + sim::ExactNumber(v);
    out += "," + sim::ExactNumber(e.objective) + "," + sim::ExactNumber(e.nominal.speed_mps) +
           "," + sim::ExactNumber(e.nominal.fall_penalty) + "," +
           sim::ExactNumber(e.nominal.overload_penalty) + "," +
           sim::ExactNumber(e.nominal.energy_penalty) + "," + std::to_string(e.failed_runs) +
           "," + e.nominal.early_stop + ",";
    if (robust) {
      out += std::to_string(e.cases_failed) + "," + sim::ExactNumber(e.robustness_penalty) + ",";
    }
    out += sim::ExactNumber(e.wall_time_s) + "\n";
  }
  return out;
}

// Best-so-far J against the evaluation number, one curve per start.
void WriteConvergence(const std::string& dir, const Problem& problem,
                      const std::vector<Evaluation>& history, std::string* warning) {
  const int starts = problem.params().starts;
  std::string csv = "evaluation,start,objective,best_so_far\n";
  std::vector<double> best(starts, std::numeric_limits<double>::infinity());
  for (const Evaluation& e : history) {
    best[e.start] = std::min(best[e.start], e.objective);
    csv += std::to_string(e.index) + "," + std::to_string(e.start) + "," +
           sim::ExactNumber(e.objective) + "," + sim::ExactNumber(best[e.start]) + "\n";
  }
  common::WriteFileAtomic(dir + "/convergence.csv", csv);
  std::string plots;
  for (int s = 0; s < starts; ++s) {
    plots += std::string(s ? ", " : "") + "data using 1:($2 == " + std::to_string(s) +
             " ? $4 : NaN) with lines lw 2 title 'start " + std::to_string(s) + "'";
  }
  const std::string script =
      "set terminal pngcairo size 900,560 noenhanced\nset output OUTPUT(0)\n"
      "set datafile separator ','\nset key top right\nset grid\n"
      "set title 'climbsim optimise: best cost so far (lower is better)'\n"
      "set xlabel 'evaluation (within its start)'\nset ylabel 'J [m/s] = -speed + penalties'\n"
      "data = 'convergence.csv'\n"  // gnuplot runs in `dir`
      "plot " + plots + "\n";
  *warning = common::RunGnuplot(dir, script, {"convergence.png"});
}

// The results folder: checked and locked by rank 0 before any rollout (sim/run_folder.h);
// every rank learns whether it was refused, so that all stop together.
std::optional<sim::RunFolder> OpenRunFolder(const std::string& scenario_file,
                                            const Options& options, Comm& comm) {
  std::optional<sim::RunFolder> folder;
  std::string refused;
  if (comm.root()) {
    try {
      folder.emplace(sim::RunFolder::Live(options.out_dir,
                                          {.made_by = "optimise",
                                           .force = options.force,
                                           .keep_other_files = options.keep_other_files,
                                           .inputs = {scenario_file}},
                                          options.resume));
    } catch (const InputError& e) {
      if (comm.size() == 1) throw;
      refused = e.what();
    }
  }
  if (comm.size() > 1) {
    for (const std::string& r : comm.AllGather(refused)) {
      if (!r.empty()) throw InputError(options.out_dir, 0, 0, "", "refused on rank 0: " + r);
    }
  }
  return folder;
}

// What the starts share before the first rollout: the checkpoint's fingerprint, a resumed
// run's evaluations and what failures.log held (`resolved`: the scenario as written).
void PrepareShared(const Problem& problem, const sim::OptimiseParams& params,
                   const Options& options, const std::string& resolved, bool root,
                   Shared* shared) {
  const int starts = params.starts;
  shared->by_start.resize(starts);
  shared->recorded.resize(starts);
  shared->checkpoint_path = options.out_dir + "/checkpoint.json";
  shared->total_budget = params.max_evaluations;
  // The fingerprint ties a checkpoint to the scenario and the budget; not to the thread
  // count, which does not change the result.
  shared->fingerprint = std::to_string(Fnv1a(resolved + "|" +
                                             std::to_string(params.max_evaluations)));
  if (options.resume) {
    shared->recorded = ReadCheckpoint(shared->checkpoint_path, shared->fingerprint, starts,
                                      problem.start().size());
  }
  shared->failures_path = options.out_dir + "/failures.log";
  if (root) {
    std::ifstream in(shared->failures_path);
    shared->failures_before.assign(std::istreambuf_iterator<char>(in), {});
    if (!fs::exists(shared->failures_path)) common::WriteFileAtomic(shared->failures_path, "");
  }
}

// Budgets are fixed per start, so the split does not depend on the thread count.
std::vector<int> StartBudgets(const sim::OptimiseParams& params) {
  const int starts = params.starts;
  std::vector<int> budget(starts, params.max_evaluations / starts);
  for (int s = 0; s < params.max_evaluations % starts; ++s) budget[s] += 1;
  return budget;
}

// How the starts ended: each start's error ("" when none) and what stopped the run (a
// checkpoint not written): rank 0's exception, its text for all ranks.
struct StartsOutcome {
  std::vector<std::string> errors;
  std::exception_ptr stop_error;
  std::string stopped;
};

// Rank 0's evaluations, counts and outcome, as it sends them to the other ranks.
nlohmann::json RankZeroJson(const Shared& shared, const StartsOutcome& outcome) {
  nlohmann::json by_start = nlohmann::json::array();
  for (const auto& evals : shared.by_start) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& e : evals) list.push_back(ToJson(e));
    by_start.push_back(list);
  }
  nlohmann::json replayed = nlohmann::json::array();
  for (const auto& [start, index] : shared.replayed) replayed.push_back({start, index});
  return {{"by_start", by_start},
          {"errors", outcome.errors},
          {"stopped", outcome.stopped},
          {"replayed", replayed},
          {"bound", std::isfinite(shared.bound) ? nlohmann::json(shared.bound)
                                                : nlohmann::json(nullptr)},
          {"computed", shared.computed},
          {"rollouts", shared.rollouts},
          {"stalled", shared.stalled},
          {"bounded", shared.bounded},
          {"simulated_s", shared.simulated_s}};
}

// A rank other than 0 takes rank 0's RankZeroJson as its own.
void TakeRankZeroJson(const nlohmann::json& all, Shared* shared, StartsOutcome* outcome) {
  for (size_t s = 0; s < shared->by_start.size(); ++s) {
    shared->by_start[s].clear();
    const auto& list = all["by_start"][s];
    for (size_t i = 0; i < list.size(); ++i) {
      shared->by_start[s].push_back(
          FromJson(list[i], static_cast<int>(s), static_cast<int>(i)));
    }
  }
  outcome->errors = all["errors"].get<std::vector<std::string>>();
  outcome->stopped = all["stopped"].get<std::string>();
  for (const auto& r : all["replayed"]) {
    shared->replayed.insert({r[0].get<int>(), r[1].get<int>()});
  }
  if (!all["bound"].is_null()) shared->bound = all["bound"].get<double>();
  shared->computed = all["computed"].get<int>();
  shared->rollouts = all["rollouts"].get<int>();
  shared->stalled = all["stalled"].get<int>();
  shared->bounded = all["bounded"].get<int>();
  shared->simulated_s = all["simulated_s"].get<double>();
}

// Rank 0: each start drives its algorithm on its own thread; this thread serves their
// rollouts to the workers (and to the other ranks). The other ranks only compute rollouts.
// Every rank returns rank 0's outcome, `shared` holding rank 0's evaluations and counts.
StartsOutcome RunStarts(const Problem& problem, const std::vector<int>& budget, int threads,
                        Comm& comm, Shared* shared) {
  StartsOutcome outcome;
  outcome.errors.resize(budget.size());
  if (comm.root()) {
    outcome.stop_error =
        internal::DriveStarts(problem, budget, *shared, threads, comm, &outcome.errors);
    try {
      if (outcome.stop_error) std::rethrow_exception(outcome.stop_error);
    } catch (const std::exception& e) {
      outcome.stopped = e.what();
    }
  } else {
    internal::WorkForRankZero(problem, threads, comm);
  }
  if (comm.size() > 1) {
    nlohmann::json mine;
    if (comm.root()) mine = RankZeroJson(*shared, outcome);
    const nlohmann::json all = nlohmann::json::parse(comm.AllGather(mine.dump())[0]);
    if (!comm.root()) TakeRankZeroJson(all, shared, &outcome);
  }
  return outcome;
}

// Throws what ended a start or the run, if anything did.
void ThrowIfFailed(const StartsOutcome& outcome) {
  if (outcome.stop_error) std::rethrow_exception(outcome.stop_error);
  if (!outcome.stopped.empty()) throw std::runtime_error("rank 0 stopped: " + outcome.stopped);
  for (size_t s = 0; s < outcome.errors.size(); ++s) {
    if (!outcome.errors[s].empty()) {
      throw std::runtime_error("start " + std::to_string(s) + ": " + outcome.errors[s]);
    }
  }
}

// The result every rank returns, less its wall time and plot warning.
Result Collect(const Problem& problem, const Shared& shared, int threads, int processes) {
  Result result;
  for (const auto& p : problem.params().parameters) result.parameter_keys.push_back(p.key);
  for (auto& evals : shared.by_start) {
    result.history.insert(result.history.end(), evals.begin(), evals.end());
  }
  result.evaluations_computed = shared.computed;
  result.start_objective = shared.by_start[0].empty() ? 0.0 : shared.by_start[0][0].objective;
  // The best: lowest J; ties go to the earlier start and evaluation (thread-independent).
  result.best = *std::min_element(result.history.begin(), result.history.end(),
                                  [](const Evaluation& a, const Evaluation& b) {
                                    if (a.objective != b.objective)
                                      return a.objective < b.objective;
                                    if (a.start != b.start) return a.start < b.start;
                                    return a.index < b.index;
                                  });
  RecheckReplayedBest(problem, shared, result.best, threads);

  result.rollouts_computed = shared.rollouts;
  result.rollouts_stalled = shared.stalled;
  result.rollouts_bounded = shared.bounded;
  result.simulated_s = shared.simulated_s;
  result.processes = processes;
  return result;
}

// summary.json: the run's settings, counts, timing and best (`cpu_s`: rank 0's CPU time).
nlohmann::json SummaryJson(const std::string& scenario_file, const Problem& problem,
                           const sim::OptimiseParams& params, int threads, const Shared& shared,
                           const Result& result, double cpu_s) {
  const Evaluation& first = shared.by_start[0].front();
  nlohmann::json best_params;
  for (size_t i = 0; i < result.best.x.size(); ++i) {
    best_params[problem.params().parameters[i].key] = result.best.x[i];
  }
  return {
      {"scenario", scenario_file},
      {"algorithm", params.algorithm},
      {"starts", params.starts},
      {"threads", threads},
      {"processes", result.processes},
      {"rollouts_computed", result.rollouts_computed},
      {"rollouts_stopped_stalled", result.rollouts_stalled},
      {"rollouts_stopped_bound", result.rollouts_bounded},
      {"simulated_s", result.simulated_s},
      {"evaluations", result.history.size()},
      {"evaluations_computed", result.evaluations_computed},
      {"wall_time_s", result.wall_time_s},
      {"cpu_s_rank0", cpu_s},
      {"evaluations_per_s",
       result.wall_time_s > 0 ? result.evaluations_computed / result.wall_time_s : 0.0},
      {"start_objective", result.start_objective},
      {"start_speed_mps", first.nominal.speed_mps},
      {"best_objective", result.best.objective},
      {"best_speed_mps", result.best.nominal.speed_mps},
      {"speedup", first.nominal.speed_mps > 0
                      ? result.best.nominal.speed_mps / first.nominal.speed_mps
                      : 0.0},
      {"best_start", result.best.start},
      {"best_evaluation", result.best.index},
      {"best_parameters", best_params},
      {"plot_warning", result.plot_warning},
      {"checkpoint_warning", shared.error}};
}

}  // namespace

int ProcessRank() { return Comm::World().rank(); }
int ProcessCount() { return Comm::World().size(); }

const sim::CompiledModel& ModelCache::For(const sim::Scenario& s) {
  const sim::MjcfAdditions add = sim::EffectAdditions(s);
  const std::string key = sim::ComposeScenarioMjcf(s, add);
  auto it = models_.find(key);
  if (it == models_.end()) {
    // A robot key that varies makes a model per evaluation: keep the cache bounded. The
    // model handed out last is done with (one rollout at a time per cache).
    if (models_.size() >= kMaxModels) models_.clear();
    it = models_.emplace(key, sim::CompiledModel::Build(s, add)).first;
  }
  return *it->second;
}

void ParallelRollouts(int count, int threads,
                      const std::function<void(int task, ModelCache& cache)>& task) {
  std::mutex mutex;
  std::vector<std::unique_ptr<ModelCache>> caches;
  std::vector<ModelCache*> idle;
  common::ParallelFor(count, threads, [&](int t) {
    ModelCache* cache = nullptr;
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (idle.empty()) idle.push_back(caches.emplace_back(std::make_unique<ModelCache>()).get());
      cache = idle.back();
      idle.pop_back();
    }
    const auto give_back = [&] {
      std::lock_guard<std::mutex> lock(mutex);
      idle.push_back(cache);
    };
    try {
      task(t, *cache);
    } catch (...) {
      give_back();
      throw;
    }
    give_back();
  });
}


std::string ResultText(const Result& r, const std::string& out_dir) {
  std::string out;
  Appendf(&out, "climbsim optimise: %zu evaluations (%d computed) in %.1f s, %d process%s\n",
          r.history.size(), r.evaluations_computed, r.wall_time_s, r.processes,
          r.processes == 1 ? "" : "es");
  Appendf(&out, "  rollouts %d computed, stopped early: %d stalled, %d bound (%.0f s simulated)\n",
          r.rollouts_computed, r.rollouts_stalled, r.rollouts_bounded, r.simulated_s);
  out +=
      "    stalled: climbed less than optimise.objective.stall_distance_m in stall_window_s\n"
      "    bound: could no longer beat the best J even at optimise.objective.max_speed_mps\n";
  Appendf(&out, "  start  J %.6f m/s, speed %.4f m/s\n", r.start_objective,
          r.history.front().nominal.speed_mps);
  Appendf(&out, "  best   J %.6f m/s, speed %.4f m/s (start %d, evaluation %d)\n",
          r.best.objective, r.best.nominal.speed_mps, r.best.start, r.best.index);
  // The parameters themselves, as given (start 0's first evaluation) and at the best.
  if (!r.parameter_keys.empty()) out += "  parameters (as given -> best):\n";
  for (size_t i = 0; i < r.parameter_keys.size() && i < r.best.x.size(); ++i) {
    Appendf(&out, "    %-36s %12.6g -> %.6g\n", r.parameter_keys[i].c_str(), r.history.front().x[i],
            r.best.x[i]);
  }
  Appendf(&out, "  outputs %s/{best.yaml,history.csv,convergence.png,summary.json}\n",
          out_dir.c_str());
  return out;
}

Result Optimise(const std::string& scenario_file, const Options& options,
                const std::function<void(double, double)>& progress) {
  const auto t0 = Clock::now();
  const double cpu0 = CpuSeconds();
  const Problem problem(scenario_file);
  sim::OptimiseParams params = problem.params();
  if (options.max_evaluations > 0) params.max_evaluations = options.max_evaluations;
  if (params.max_evaluations < params.starts) {
    throw InputError(scenario_file, 0, 0, "optimise.max_evaluations",
                     "must be at least the number of starts (" + std::to_string(params.starts) +
                         ")");
  }

  Comm& comm = Comm::World();
  std::optional<sim::RunFolder> folder = OpenRunFolder(scenario_file, options, comm);
  const std::string resolved = sim::ScenarioToYamlText(problem.scenario());
  if (comm.root()) {
    fs::create_directories(options.out_dir);
    common::WriteFileAtomic(options.out_dir + "/scenario.yaml", resolved);
  }
  Shared shared;
  shared.progress = &progress;
  PrepareShared(problem, params, options, resolved, comm.root(), &shared);

  const int threads = std::max(1, options.threads > 0 ? options.threads : DefaultThreads());
  ThrowIfFailed(RunStarts(problem, StartBudgets(params), threads, comm, &shared));
  Result result = Collect(problem, shared, threads, comm.size());
  if (!comm.root()) {
    result.wall_time_s = std::chrono::duration<double>(Clock::now() - t0).count();
    return result;
  }
  common::WriteFileAtomic(options.out_dir + "/history.csv", HistoryCsv(problem, result.history));
  common::WriteFileAtomic(options.out_dir + "/best.yaml",
                          "# Best parameters found by climbsim optimise; replay with\n"
                          "#   climbsim simulate best.yaml --out DIR\n" +
                              sim::ScenarioToYamlText(problem.ScenarioFor(result.best.x, 0)));
  WriteConvergence(options.out_dir, problem, result.history, &result.plot_warning);
  result.wall_time_s = std::chrono::duration<double>(Clock::now() - t0).count();
  const nlohmann::json summary =
      SummaryJson(scenario_file, problem, params, threads, shared, result, CpuSeconds() - cpu0);
  common::WriteFileAtomic(options.out_dir + "/summary.json", summary.dump(2) + "\n");
  folder->Commit();
  return result;
}

}  // namespace climbsim::optimise
