#include <nlopt.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <random>
#include <sstream>
#include <thread>

#include "optimise/optimise.h"
#include "sim/gnuplot.h"

namespace climbsim::optimise {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

uint64_t Fnv1a(std::string_view s) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  return h;
}

// Checksum of a checkpoint: FNV-1a of the fingerprint (scenario and budget) and the
// canonical dump of the evaluations, as hex.
std::string CheckpointChecksum(const std::string& fingerprint, const nlohmann::json& starts) {
  char buf[17];
  std::snprintf(buf, sizeof(buf), "%016llx",
                static_cast<unsigned long long>(Fnv1a(fingerprint + "|" + starts.dump())));
  return buf;
}

nlopt::algorithm Algorithm(const std::string& name) {
  static const std::map<std::string, nlopt::algorithm> k{
      {"LN_SBPLX", nlopt::LN_SBPLX},     {"LN_NELDERMEAD", nlopt::LN_NELDERMEAD},
      {"LN_BOBYQA", nlopt::LN_BOBYQA},   {"LN_COBYLA", nlopt::LN_COBYLA},
      {"GN_CRS2_LM", nlopt::GN_CRS2_LM}, {"GN_ISRES", nlopt::GN_ISRES},
      {"GN_ESCH", nlopt::GN_ESCH}};
  return k.at(name);
}

nlohmann::json ToJson(const Evaluation& e) {
  return {{"x", e.x},
          {"objective", e.objective},
          {"nominal",
           {{"total", e.nominal.total},
            {"speed_mps", e.nominal.speed_mps},
            {"fall_penalty", e.nominal.fall_penalty},
            {"overload_penalty", e.nominal.overload_penalty},
            {"energy_penalty", e.nominal.energy_penalty},
            {"failed", e.nominal.failed},
            {"failure", e.nominal.failure}}},
          {"failed_runs", e.failed_runs},
          {"wall_time_s", e.wall_time_s}};
}

Evaluation FromJson(const nlohmann::json& j, int start, int index) {
  Evaluation e;
  e.start = start;
  e.index = index;
  e.x = j.at("x").get<std::vector<double>>();
  e.objective = j.at("objective").get<double>();
  const auto& n = j.at("nominal");
  e.nominal.total = n.at("total").get<double>();
  e.nominal.speed_mps = n.at("speed_mps").get<double>();
  e.nominal.fall_penalty = n.at("fall_penalty").get<double>();
  e.nominal.overload_penalty = n.at("overload_penalty").get<double>();
  e.nominal.energy_penalty = n.at("energy_penalty").get<double>();
  e.nominal.failed = n.at("failed").get<bool>();
  e.nominal.failure = n.at("failure").get<std::string>();
  e.failed_runs = j.at("failed_runs").get<int>();
  e.wall_time_s = j.at("wall_time_s").get<double>();
  return e;
}

// What the starts share: their evaluations (for the checkpoint and the progress bar) and
// the evaluations a resumed run replays. Touched only between evaluations, under the lock.
struct Shared {
  std::mutex mutex;
  std::vector<std::vector<Evaluation>> by_start;
  std::vector<std::vector<Evaluation>> recorded;
  std::string checkpoint_path;
  std::string fingerprint;
  int total_budget = 0;
  int done = 0;
  int computed = 0;
  double best = std::numeric_limits<double>::infinity();
  std::string error;  // first checkpoint mismatch, reported after the run
  const std::function<void(double, double)>* progress = nullptr;
  std::ofstream failures;
};

void WriteCheckpoint(Shared& s) {
  nlohmann::json starts = nlohmann::json::array();
  for (const auto& evals : s.by_start) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& e : evals) list.push_back(ToJson(e));
    starts.push_back(list);
  }
  const nlohmann::json j{{"fingerprint", s.fingerprint},
                         {"checksum", CheckpointChecksum(s.fingerprint, starts)},
                         {"starts", starts}};
  sim::WriteFileAtomic(s.checkpoint_path, j.dump() + "\n");
}

// Reads DIR/checkpoint.json for --resume: every value of the right type, the scenario's
// fingerprint, and the checksum of the content (an edited number is refused, not trusted).
std::vector<std::vector<Evaluation>> ReadCheckpoint(const std::string& path,
                                                    const std::string& fingerprint, int starts,
                                                    size_t dimension) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    throw InputError(path, 0, 0, "",
                     "missing: nothing to resume (drop --resume to start over, with --force)");
  }
  nlohmann::json j;
  try {
    std::ifstream in(path);
    j = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw InputError(path, 0, 0, "", std::string("unreadable: ") + e.what());
  }
  if (!j.is_object() || !j.contains("fingerprint") || !j["fingerprint"].is_string() ||
      !j.contains("checksum") || !j["checksum"].is_string() || !j.contains("starts") ||
      !j["starts"].is_array()) {
    throw InputError(path, 0, 0, "",
                     "not a climbsim checkpoint (expected an object with fingerprint, checksum "
                     "and starts)");
  }
  if (j["fingerprint"].get<std::string>() != fingerprint) {
    throw InputError(path, 0, 0, "fingerprint",
                     "belongs to another scenario or budget; drop --resume (and use --force) "
                     "to start over");
  }
  if (j["checksum"].get<std::string>() != CheckpointChecksum(fingerprint, j["starts"])) {
    throw InputError(path, 0, 0, "checksum",
                     "does not match the content: the checkpoint was edited or damaged; drop "
                     "--resume (and use --force) to start over");
  }
  std::vector<std::vector<Evaluation>> recorded(starts);
  const auto& list = j["starts"];
  for (int s = 0; s < starts && s < static_cast<int>(list.size()); ++s) {
    if (!list[s].is_array()) throw InputError(path, 0, 0, "starts", "expected lists");
    for (size_t i = 0; i < list[s].size(); ++i) {
      const std::string where = "starts[" + std::to_string(s) + "][" + std::to_string(i) + "]";
      try {
        recorded[s].push_back(FromJson(list[s][i], s, static_cast<int>(i)));
      } catch (const nlohmann::json::exception& e) {
        throw InputError(path, 0, 0, where, std::string("wrong value: ") + e.what());
      }
      if (recorded[s].back().x.size() != dimension) {
        throw InputError(path, 0, 0, where + ".x",
                         "expected " + std::to_string(dimension) + " parameters");
      }
    }
  }
  return recorded;
}

// One start: its own NLopt object, seed and model copies; evaluations in a fixed order.
class StartRunner {
 public:
  StartRunner(const Problem& problem, int start, int budget, Shared& shared)
      : problem_(problem), start_(start), budget_(budget), shared_(shared),
        lo_(problem.lower()), hi_(problem.upper()) {}

  void Run() {
    const sim::OptimiseParams& p = problem_.params();
    // NLopt's random numbers are per thread: seeding here makes each start reproducible
    // whichever thread runs it.
    nlopt::srand(static_cast<unsigned long>(p.seed) * 1000003ul + start_);
    std::vector<double> x0 = problem_.start();
    if (start_ > 0) {
      std::mt19937_64 rng(Fnv1a("start") ^ (static_cast<uint64_t>(p.seed) << 20) ^ start_);
      std::uniform_real_distribution<double> u(0.0, 1.0);
      for (size_t i = 0; i < x0.size(); ++i) x0[i] = lo_[i] + u(rng) * (hi_[i] - lo_[i]);
    }
    std::vector<double> u0(x0.size());
    for (size_t i = 0; i < x0.size(); ++i) u0[i] = (x0[i] - lo_[i]) / (hi_[i] - lo_[i]);

    if (p.algorithm == "chain") {
      const int global = std::max(1, static_cast<int>(std::lround(budget_ * p.global_share)));
      Stage(nlopt::GN_CRS2_LM, u0, std::min(global, budget_));
      if (count_ < budget_) Stage(Algorithm(p.local_algorithm), best_u_, budget_ - count_);
    } else {
      Stage(Algorithm(p.algorithm), u0, budget_);
    }
  }

 private:
  void Stage(nlopt::algorithm algorithm, std::vector<double> u, int evaluations) {
    const sim::OptimiseParams& p = problem_.params();
    const unsigned n = static_cast<unsigned>(u.size());
    nlopt::opt opt(algorithm, n);
    opt.set_lower_bounds(std::vector<double>(n, 0.0));
    opt.set_upper_bounds(std::vector<double>(n, 1.0));
    opt.set_min_objective(&StartRunner::Trampoline, this);
    opt.set_maxeval(evaluations);
    // Coordinates are shares of each range, so an absolute tolerance is "share of range".
    if (p.xtol_rel > 0) opt.set_xtol_abs(p.xtol_rel);
    if (p.ftol_abs > 0) opt.set_ftol_abs(p.ftol_abs);
    if (p.max_time_s > 0) opt.set_maxtime(p.max_time_s);
    opt.set_initial_step(p.initial_step);
    double f = 0.0;
    try {
      opt.optimize(u, f);
    } catch (const std::exception&) {
      // Round-off limits and forced stops end the stage; the best point is kept below.
    }
  }

  static double Trampoline(const std::vector<double>& u, std::vector<double>& grad, void* self) {
    (void)grad;  // derivative-free algorithms only
    return static_cast<StartRunner*>(self)->Objective(u);
  }

  // Never throws: an exception through NLopt would end the whole optimisation.
  double Objective(const std::vector<double>& u) {
    std::vector<double> x(u.size());
    for (size_t i = 0; i < u.size(); ++i) {
      x[i] = lo_[i] + std::clamp(u[i], 0.0, 1.0) * (hi_[i] - lo_[i]);
    }
    Evaluation e;
    bool replayed = false;
    {
      std::lock_guard<std::mutex> lock(shared_.mutex);
      const auto& rec = shared_.recorded[start_];
      if (count_ < static_cast<int>(rec.size())) {
        if (rec[count_].x == x) {
          e = rec[count_];
          replayed = true;
        } else if (shared_.error.empty()) {
          shared_.error = "checkpoint.json does not match this run at start " +
                          std::to_string(start_) + ", evaluation " + std::to_string(count_) +
                          ": evaluations from here are computed anew";
        }
      }
    }
    if (!replayed) e = Evaluate(x);
    e.start = start_;
    e.index = count_++;
    if (e.objective < best_f_) {
      best_f_ = e.objective;
      best_u_ = u;
    }
    std::lock_guard<std::mutex> lock(shared_.mutex);
    shared_.by_start[start_].push_back(e);
    shared_.done += 1;
    if (!replayed) {
      shared_.computed += 1;
      WriteCheckpoint(shared_);
    }
    shared_.best = std::min(shared_.best, e.objective);
    if (shared_.progress && *shared_.progress) {
      (*shared_.progress)(std::min(1.0, static_cast<double>(shared_.done) / shared_.total_budget),
                          shared_.best);
    }
    return e.objective;
  }

  Evaluation Evaluate(const std::vector<double>& x) {
    const sim::ObjectiveParams& o = problem_.params().objective;
    const auto t0 = Clock::now();
    Evaluation e;
    e.x = x;
    double sum = 0.0, worst = -std::numeric_limits<double>::infinity();
    for (int run = 0; run < o.runs; ++run) {
      Cost c;
      try {
        const sim::Scenario s = problem_.ScenarioFor(x, run);
        sim::Simulation rollout(s, models_.For(s));
        rollout.Run();
        c = RolloutCost(rollout, o);
      } catch (const std::exception& ex) {
        c.failed = true;
        c.failure = ex.what();
        c.total = kFailedCost;
      }
      if (c.failed) {
        ++e.failed_runs;
        std::lock_guard<std::mutex> lock(shared_.mutex);
        shared_.failures << "start " << start_ << " evaluation " << count_ << " run " << run
                         << ": " << c.failure << "\n";
        shared_.failures.flush();
      }
      if (run == 0) e.nominal = c;
      sum += c.total;
      worst = std::max(worst, c.total);
    }
    e.objective = o.aggregate == "worst" ? worst : sum / o.runs;
    e.wall_time_s = std::chrono::duration<double>(Clock::now() - t0).count();
    return e;
  }

  const Problem& problem_;
  const int start_;
  const int budget_;
  Shared& shared_;
  const std::vector<double> lo_, hi_;
  int count_ = 0;
  double best_f_ = std::numeric_limits<double>::infinity();
  std::vector<double> best_u_;
  ModelCache models_;
};

std::string HistoryCsv(const Problem& problem, const std::vector<Evaluation>& history) {
  std::string out = "evaluation,start";
  for (const auto& p : problem.params().parameters) out += "," + p.key;
  out += ",objective,speed_mps,fall_penalty_mps,overload_penalty_mps,energy_penalty_mps,"
         "failed_runs,wall_time_s\n";
  for (const Evaluation& e : history) {
    out += std::to_string(e.index) + "," + std::to_string(e.start);
    for (double v : e.x) out += "," + sim::ExactNumber(v);
    out += "," + sim::ExactNumber(e.objective) + "," + sim::ExactNumber(e.nominal.speed_mps) +
           "," + sim::ExactNumber(e.nominal.fall_penalty) + "," +
           sim::ExactNumber(e.nominal.overload_penalty) + "," +
           sim::ExactNumber(e.nominal.energy_penalty) + "," + std::to_string(e.failed_runs) +
           "," + sim::ExactNumber(e.wall_time_s) + "\n";
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
  sim::WriteFileAtomic(dir + "/convergence.csv", csv);
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
      "data = " + sim::GnuplotQuote(dir + "/convergence.csv") + "\n"
      "plot " + plots + "\n";
  *warning = sim::RunGnuplot(script, {dir + "/convergence.png"});
}

}  // namespace

const sim::CompiledModel& ModelCache::For(const sim::Scenario& s) {
  const sim::MjcfAdditions add = sim::EffectAdditions(s);
  const std::string key = sim::ComposeMjcf(sim::RobotFile(s), sim::SceneFile(s), add);
  auto it = models_.find(key);
  if (it == models_.end()) it = models_.emplace(key, sim::CompiledModel::Build(s, add)).first;
  return *it->second;
}

Result Optimise(const std::string& scenario_file, const Options& options,
                const std::function<void(double, double)>& progress) {
  const auto t0 = Clock::now();
  const Problem problem(scenario_file);
  sim::OptimiseParams params = problem.params();
  if (options.max_evaluations > 0) params.max_evaluations = options.max_evaluations;
  const int starts = params.starts;
  if (params.max_evaluations < starts) {
    throw InputError(scenario_file, 0, 0, "optimise.max_evaluations",
                     "must be at least the number of starts (" + std::to_string(starts) + ")");
  }

  // The results folder: checked and locked before any rollout (sim/run_folder.h).
  sim::RunFolder folder = sim::RunFolder::Live(
      options.out_dir, {.made_by = "optimise", .force = options.force, .inputs = {scenario_file}},
      options.resume);
  const std::string resolved = sim::ScenarioToYamlText(problem.scenario());
  sim::WriteFileAtomic(options.out_dir + "/scenario.yaml", resolved);

  Shared shared;
  shared.by_start.resize(starts);
  shared.recorded.resize(starts);
  shared.checkpoint_path = options.out_dir + "/checkpoint.json";
  shared.total_budget = params.max_evaluations;
  shared.progress = &progress;
  // The fingerprint ties a checkpoint to the scenario and the budget; not to the thread
  // count, which does not change the result.
  shared.fingerprint = std::to_string(Fnv1a(resolved + "|" +
                                            std::to_string(params.max_evaluations)));
  if (options.resume) {
    shared.recorded =
        ReadCheckpoint(shared.checkpoint_path, shared.fingerprint, starts, problem.start().size());
  }
  shared.failures.open(options.out_dir + "/failures.log", std::ios::app);

  // Budgets are fixed per start, so the split does not depend on the thread count.
  std::vector<int> budget(starts, params.max_evaluations / starts);
  for (int s = 0; s < params.max_evaluations % starts; ++s) budget[s] += 1;

  // The runners see the (possibly overridden) budget through a problem copy's params.
  std::atomic<int> next{0};
  const int threads =
      std::max(1, std::min(starts, options.threads > 0
                                       ? options.threads
                                       : static_cast<int>(std::thread::hardware_concurrency())));
  auto worker = [&] {
    for (int s = next++; s < starts; s = next++) {
      StartRunner(problem, s, budget[s], shared).Run();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();

  Result result;
  for (auto& evals : shared.by_start) {
    result.history.insert(result.history.end(), evals.begin(), evals.end());
  }
  result.evaluations_computed = shared.computed;
  result.start_objective = shared.by_start[0].empty() ? 0.0 : shared.by_start[0][0].objective;
  // The best: lowest J; ties go to the earlier start and evaluation (thread-independent).
  result.best = *std::min_element(result.history.begin(), result.history.end(),
                                  [](const Evaluation& a, const Evaluation& b) {
                                    if (a.objective != b.objective) return a.objective < b.objective;
                                    if (a.start != b.start) return a.start < b.start;
                                    return a.index < b.index;
                                  });

  sim::WriteFileAtomic(options.out_dir + "/history.csv", HistoryCsv(problem, result.history));
  sim::WriteFileAtomic(options.out_dir + "/best.yaml",
                       "# Best parameters found by climbsim optimise; replay with\n"
                       "#   climbsim simulate best.yaml --out DIR\n" +
                           sim::ScenarioToYamlText(problem.ScenarioFor(result.best.x, 0)));
  std::string plot_warning;
  WriteConvergence(options.out_dir, problem, result.history, &plot_warning);
  result.wall_time_s = std::chrono::duration<double>(Clock::now() - t0).count();

  const Evaluation& first = shared.by_start[0].front();
  nlohmann::json best_params;
  for (size_t i = 0; i < result.best.x.size(); ++i) {
    best_params[problem.params().parameters[i].key] = result.best.x[i];
  }
  nlohmann::json summary{
      {"scenario", scenario_file},
      {"algorithm", params.algorithm},
      {"starts", starts},
      {"threads", threads},
      {"evaluations", result.history.size()},
      {"evaluations_computed", result.evaluations_computed},
      {"wall_time_s", result.wall_time_s},
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
      {"plot_warning", plot_warning},
      {"checkpoint_warning", shared.error}};
  sim::WriteFileAtomic(options.out_dir + "/summary.json", summary.dump(2) + "\n");
  folder.Commit();
  return result;
}

}  // namespace climbsim::optimise
