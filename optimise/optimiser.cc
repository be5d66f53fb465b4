#include <nlopt.hpp>
#include <pagmo/algorithms/cmaes.hpp>
#include <pagmo/population.hpp>
#include <pagmo/problem.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <sstream>
#include <thread>

#include "optimise/comm.h"
#include "optimise/optimise.h"
#include "common/common.h"

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

nlohmann::json CostToJson(const Cost& c) {
  return {{"total", c.total},
          {"speed_mps", c.speed_mps},
          {"fall_penalty", c.fall_penalty},
          {"overload_penalty", c.overload_penalty},
          {"energy_penalty", c.energy_penalty},
          {"failed", c.failed},
          {"failure", c.failure},
          {"early_stop", c.early_stop},
          {"stop_time_s", c.stop_time_s},
          {"wall_time_s", c.wall_time_s}};
}

Cost CostFromJson(const nlohmann::json& n) {
  Cost c;
  c.total = n.at("total").get<double>();
  c.speed_mps = n.at("speed_mps").get<double>();
  c.fall_penalty = n.at("fall_penalty").get<double>();
  c.overload_penalty = n.at("overload_penalty").get<double>();
  c.energy_penalty = n.at("energy_penalty").get<double>();
  c.failed = n.at("failed").get<bool>();
  c.failure = n.at("failure").get<std::string>();
  // Absent from checkpoints written before early stopping.
  c.early_stop = n.value("early_stop", std::string());
  c.stop_time_s = n.value("stop_time_s", 0.0);
  c.wall_time_s = n.value("wall_time_s", 0.0);
  return c;
}

nlohmann::json ToJson(const Evaluation& e) {
  return {{"x", e.x},
          {"objective", e.objective},
          {"nominal", CostToJson(e.nominal)},
          {"failed_runs", e.failed_runs},
          {"wall_time_s", e.wall_time_s}};
}

Evaluation FromJson(const nlohmann::json& j, int start, int index) {
  Evaluation e;
  e.start = start;
  e.index = index;
  e.x = j.at("x").get<std::vector<double>>();
  e.objective = j.at("objective").get<double>();
  e.nominal = CostFromJson(j.at("nominal"));
  e.failed_runs = j.at("failed_runs").get<int>();
  e.wall_time_s = j.at("wall_time_s").get<double>();
  return e;
}

// What the starts share: their evaluations (for the checkpoint and the progress bar) and
// the evaluations a resumed run replays. Touched only by the thread that runs the rounds.
struct Shared {
  std::vector<std::vector<Evaluation>> by_start;
  std::vector<std::vector<Evaluation>> recorded;
  std::string checkpoint_path;
  std::string fingerprint;
  int total_budget = 0;
  int done = 0;
  int computed = 0;
  int rollouts = 0, stalled = 0, bounded = 0;
  double simulated_s = 0.0;
  double best = std::numeric_limits<double>::infinity();
  std::string error;  // first checkpoint mismatch, reported after the run
  const std::function<void(double, double)>* progress = nullptr;
  std::ofstream failures;  // rank 0 only
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
  common::WriteFileAtomic(s.checkpoint_path, j.dump() + "\n");
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


// ---- Rounds --------------------------------------------------------------------------------
// Each start runs its algorithm on its own thread and hands its next evaluations (one for
// NLopt, a generation for CMA-ES) to Submit, which blocks. When every start still running
// has handed in its batch, the thread that called Serve evaluates the round: the rollouts of
// all batches, in start order, spread over the MPI ranks (rollout i on rank i mod N) and,
// within a rank, over its threads. A round holds exactly one batch of each running start, so
// every start sees the same evaluations whatever the thread or process count.
struct Request {
  int start = 0;
  std::vector<std::vector<double>> xs;
  std::vector<Evaluation> out;
  bool done = false;
};

class Rounds {
 public:
  explicit Rounds(int starts) : active_(starts) {}

  std::vector<Evaluation> Submit(int start, std::vector<std::vector<double>> xs) {
    Request r;
    r.start = start;
    r.xs = std::move(xs);
    std::unique_lock<std::mutex> lock(mutex_);
    pending_.push_back(&r);
    main_.notify_all();
    starts_.wait(lock, [&] { return r.done; });
    return std::move(r.out);
  }

  void Finish() {
    std::lock_guard<std::mutex> lock(mutex_);
    --active_;
    main_.notify_all();
  }

  void Serve(const std::function<void(std::vector<Request*>&)>& evaluate) {
    for (;;) {
      std::vector<Request*> batch;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        main_.wait(lock, [&] { return static_cast<int>(pending_.size()) == active_; });
        if (active_ == 0) return;
        batch.swap(pending_);
      }
      std::sort(batch.begin(), batch.end(),
                [](const Request* a, const Request* b) { return a->start < b->start; });
      evaluate(batch);
      {
        std::lock_guard<std::mutex> lock(mutex_);
        for (Request* r : batch) r->done = true;
      }
      starts_.notify_all();
    }
  }

 private:
  std::mutex mutex_;
  std::condition_variable main_, starts_;
  int active_;
  std::vector<Request*> pending_;
};

// Evaluates rounds: replays recorded evaluations, runs the others' rollouts on this rank's
// share and exchanges the shares.
class RoundEvaluator {
 public:
  RoundEvaluator(const Problem& problem, Shared& shared, int threads, const Comm& comm)
      : problem_(problem), shared_(shared), threads_(threads), comm_(comm), caches_(threads),
        next_index_(problem.params().starts, 0) {}

  void operator()(std::vector<Request*>& batch) {
    const sim::ObjectiveParams& o = problem_.params().objective;
    struct Item {
      Request* request;
      size_t k;
      int index;
      bool replayed;
    };
    std::vector<Item> items;
    for (Request* r : batch) {
      r->out.resize(r->xs.size());
      for (size_t k = 0; k < r->xs.size(); ++k) {
        const int index = next_index_[r->start]++;
        bool replayed = false;
        const auto& rec = shared_.recorded[r->start];
        if (index < static_cast<int>(rec.size())) {
          if (rec[index].x == r->xs[k]) {
            r->out[k] = rec[index];
            replayed = true;
          } else if (shared_.error.empty()) {
            shared_.error = "checkpoint.json does not match this run at start " +
                            std::to_string(r->start) + ", evaluation " + std::to_string(index) +
                            ": evaluations from here are computed anew";
          }
        }
        items.push_back({r, k, index, replayed});
      }
    }

    // The rollouts to compute, in a fixed order: item, then run.
    struct Task {
      size_t item;
      int run;
    };
    std::vector<Task> tasks;
    for (size_t i = 0; i < items.size(); ++i) {
      if (items[i].replayed) continue;
      for (int run = 0; run < o.runs; ++run) tasks.push_back({i, run});
    }
    // The cost a rollout must beat to matter: the scenario as given (start 0's first
    // evaluation), known from the first round on. With `mean` over K runs, one run may be
    // as bad as K·B + (K−1)·v_max while the others at v_max bring the mean under B.
    double bound = std::numeric_limits<double>::infinity();
    if (!shared_.by_start[0].empty() && !shared_.by_start[0][0].nominal.failed) {
      const double b = shared_.by_start[0][0].objective;
      bound = o.aggregate == "worst" ? b : o.runs * b + (o.runs - 1) * o.max_speed_mps;
    }

    std::vector<Cost> costs(tasks.size());
    std::vector<size_t> mine;
    for (size_t t = 0; t < tasks.size(); ++t) {
      if (static_cast<int>(t % comm_.size()) == comm_.rank()) mine.push_back(t);
    }
    std::atomic<size_t> next{0};
    auto worker = [&](int slot) {
      for (size_t m = next++; m < mine.size(); m = next++) {
        const Task& task = tasks[mine[m]];
        costs[mine[m]] = Rollout(items[task.item].request->xs[items[task.item].k], task.run,
                                 bound, caches_[slot]);
      }
    };
    const int n = std::max(1, std::min<int>(threads_, static_cast<int>(mine.size())));
    std::vector<std::thread> pool;
    for (int k = 1; k < n; ++k) pool.emplace_back(worker, k);
    worker(0);
    for (auto& th : pool) th.join();
    if (comm_.size() > 1) {
      nlohmann::json local = nlohmann::json::array();
      for (size_t t : mine) local.push_back({t, CostToJson(costs[t])});
      for (const std::string& part : comm_.AllGather(local.dump())) {
        for (const auto& entry : nlohmann::json::parse(part)) {
          costs[entry[0].get<size_t>()] = CostFromJson(entry[1]);
        }
      }
    }

    // Aggregate each computed item's runs, in run order.
    std::vector<double> sum(items.size(), 0.0),
        worst(items.size(), -std::numeric_limits<double>::infinity());
    for (size_t t = 0; t < tasks.size(); ++t) {
      const Item& it = items[tasks[t].item];
      Evaluation& e = it.request->out[it.k];
      const Cost& c = costs[t];
      if (tasks[t].run == 0) {
        e.x = it.request->xs[it.k];
        e.nominal = c;
      }
      if (c.failed) {
        ++e.failed_runs;
        if (comm_.root()) {
          shared_.failures << "start " << it.request->start << " evaluation " << it.index
                           << " run " << tasks[t].run << ": " << c.failure << "\n";
        }
      }
      sum[tasks[t].item] += c.total;
      worst[tasks[t].item] = std::max(worst[tasks[t].item], c.total);
      e.wall_time_s += c.wall_time_s;
      shared_.rollouts += 1;
      shared_.stalled += c.early_stop == "stalled";
      shared_.bounded += c.early_stop == "bound";
      shared_.simulated_s += c.stop_time_s;
    }
    if (comm_.root()) shared_.failures.flush();
    for (size_t i = 0; i < items.size(); ++i) {
      Evaluation& e = items[i].request->out[items[i].k];
      if (!items[i].replayed) e.objective = o.aggregate == "worst" ? worst[i] : sum[i] / o.runs;
      e.start = items[i].request->start;
      e.index = items[i].index;
      shared_.by_start[e.start].push_back(e);
      shared_.done += 1;
      shared_.computed += !items[i].replayed;
      shared_.best = std::min(shared_.best, e.objective);
    }
    if (comm_.root() && !tasks.empty()) WriteCheckpoint(shared_);
    if (shared_.progress && *shared_.progress) {
      (*shared_.progress)(std::min(1.0, static_cast<double>(shared_.done) / shared_.total_budget),
                          shared_.best);
    }
  }

 private:
  // Never throws: a bad candidate costs kFailedCost and is logged.
  Cost Rollout(const std::vector<double>& x, int run, double bound, ModelCache& cache) {
    const auto t0 = Clock::now();
    Cost c;
    try {
      const sim::Scenario s = problem_.ScenarioFor(x, run);
      sim::Simulation rollout(s, cache.For(s));
      c = RunRollout(rollout, problem_.params().objective, bound);
    } catch (const std::exception& ex) {
      c = Cost{};
      c.failed = true;
      c.failure = ex.what();
      c.total = kFailedCost;
    }
    if (!std::isfinite(c.total)) {
      c.failed = true;
      c.failure = "the cost is not finite";
      c.total = kFailedCost;
    }
    c.wall_time_s = std::chrono::duration<double>(Clock::now() - t0).count();
    return c;
  }

  const Problem& problem_;
  Shared& shared_;
  const int threads_;
  const Comm& comm_;
  std::vector<ModelCache> caches_;  // one per worker slot, kept across rounds
  std::vector<int> next_index_;
};

// The first point of a start, in [0, 1] coordinates: start 0 at the given values, start s
// drawn uniformly in the bounds with a seed from `seed` and s.
std::vector<double> StartPoint(const Problem& problem, int start) {
  const sim::OptimiseParams& p = problem.params();
  const std::vector<double> lo = problem.lower(), hi = problem.upper();
  std::vector<double> x0 = problem.start();
  if (start > 0) {
    std::mt19937_64 rng(Fnv1a("start") ^ (static_cast<uint64_t>(p.seed) << 20) ^ start);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (size_t i = 0; i < x0.size(); ++i) x0[i] = lo[i] + u(rng) * (hi[i] - lo[i]);
  }
  std::vector<double> u0(x0.size());
  for (size_t i = 0; i < x0.size(); ++i) u0[i] = (x0[i] - lo[i]) / (hi[i] - lo[i]);
  return u0;
}

// One start with NLopt: its own NLopt object and seed; evaluations in a fixed order.
class StartRunner {
 public:
  StartRunner(const Problem& problem, int start, int budget, Rounds& rounds)
      : problem_(problem), start_(start), budget_(budget), rounds_(rounds),
        lo_(problem.lower()), hi_(problem.upper()) {}

  void Run() {
    const sim::OptimiseParams& p = problem_.params();
    // NLopt's random numbers are per thread, and each start has its own thread.
    nlopt::srand(static_cast<unsigned long>(p.seed) * 1000003ul + start_);
    const std::vector<double> u0 = StartPoint(problem_, start_);
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

  double Objective(const std::vector<double>& u) {
    std::vector<double> x(u.size());
    for (size_t i = 0; i < u.size(); ++i) {
      x[i] = lo_[i] + std::clamp(u[i], 0.0, 1.0) * (hi_[i] - lo_[i]);
    }
    const Evaluation e = rounds_.Submit(start_, {x}).front();
    ++count_;
    if (e.objective < best_f_) {
      best_f_ = e.objective;
      best_u_ = u;
    }
    return e.objective;
  }

  const Problem& problem_;
  const int start_;
  const int budget_;
  Rounds& rounds_;
  const std::vector<double> lo_, hi_;
  int count_ = 0;
  double best_f_ = std::numeric_limits<double>::infinity();
  std::vector<double> best_u_;
};

// ---- CMA-ES ----------------------------------------------------------------------------------
// pagmo's cmaes samples a generation and evaluates it one candidate after the other inside
// evolve(). To evaluate a generation in parallel, each generation is run twice: a copy of the
// algorithm (same state, same random engine) evolves with a problem that only records the
// points it is asked for; those are evaluated as one batch; then the algorithm itself
// evolves with a problem that serves the costs, checking that it asks for the same points
// bit for bit.
struct Oracle {
  bool recording = true;
  std::vector<std::vector<double>> asked;
  std::vector<double> answers;
  size_t next = 0;
};

struct CmaesProblem {
  std::shared_ptr<Oracle> oracle;
  unsigned dimension = 1;

  pagmo::vector_double fitness(const pagmo::vector_double& u) const {
    Oracle& o = *oracle;
    if (o.recording) {
      o.asked.push_back(u);
      return {0.0};
    }
    if (o.next >= o.answers.size() || o.asked[o.next] != u) {
      throw std::logic_error("cmaes asked for a point it had not sampled");
    }
    return {o.answers[o.next++]};
  }
  std::pair<pagmo::vector_double, pagmo::vector_double> get_bounds() const {
    return {pagmo::vector_double(dimension, 0.0), pagmo::vector_double(dimension, 1.0)};
  }
};

class CmaesStart {
 public:
  CmaesStart(const Problem& problem, int start, int budget, Rounds& rounds)
      : problem_(problem), start_(start), budget_(budget), rounds_(rounds),
        lo_(problem.lower()), hi_(problem.upper()) {}

  void Run() {
    const sim::OptimiseParams& p = problem_.params();
    const unsigned n = static_cast<unsigned>(lo_.size());
    const std::vector<double> u0 = StartPoint(problem_, start_);
    const double f0 = rounds_.Submit(start_, {ToX(u0)}).front().objective;
    int count = 1;
    const unsigned lambda =
        p.population > 0 ? static_cast<unsigned>(p.population)
                         : std::max(5u, 4u + static_cast<unsigned>(std::floor(3.0 * std::log(n))));
    auto oracle = std::make_shared<Oracle>();
    const unsigned seed = static_cast<unsigned>(p.seed) * 1000003u + static_cast<unsigned>(start_);
    pagmo::population pop(pagmo::problem(CmaesProblem{oracle, n}), 0u, seed);
    // The first mean is the population's best: λ copies of the start point, its cost known.
    for (unsigned i = 0; i < lambda; ++i) pop.push_back(u0, {f0});
    // One generation per evolve(), the state kept between calls (memory), candidates clipped
    // to the bounds; ftol is off (the copies of the start tie), xtol in shares of the range.
    pagmo::cmaes cma(1u, -1, -1, -1, -1, p.sigma0, 0.0, p.xtol_rel, true, true, seed);
    while (count + static_cast<int>(lambda) <= budget_) {
      oracle->recording = true;
      oracle->asked.clear();
      const pagmo::cmaes probe = cma;
      probe.evolve(pop);
      if (oracle->asked.empty()) break;  // the step fell under xtol
      std::vector<std::vector<double>> xs;
      for (const auto& u : oracle->asked) xs.push_back(ToX(u));
      const std::vector<Evaluation> evals = rounds_.Submit(start_, xs);
      oracle->answers.clear();
      for (const Evaluation& e : evals) oracle->answers.push_back(e.objective);
      oracle->recording = false;
      oracle->next = 0;
      pop = cma.evolve(pop);
      count += static_cast<int>(lambda);
    }
  }

 private:
  std::vector<double> ToX(const std::vector<double>& u) const {
    std::vector<double> x(u.size());
    for (size_t i = 0; i < u.size(); ++i) {
      x[i] = lo_[i] + std::clamp(u[i], 0.0, 1.0) * (hi_[i] - lo_[i]);
    }
    return x;
  }

  const Problem& problem_;
  const int start_;
  const int budget_;
  Rounds& rounds_;
  const std::vector<double> lo_, hi_;
};

std::string HistoryCsv(const Problem& problem, const std::vector<Evaluation>& history) {
  std::string out = "evaluation,start";
  for (const auto& p : problem.params().parameters) out += "," + p.key;
  out += ",objective,speed_mps,fall_penalty_mps,overload_penalty_mps,energy_penalty_mps,"
         "failed_runs,early_stop,wall_time_s\n";
  for (const Evaluation& e : history) {
    out += std::to_string(e.index) + "," + std::to_string(e.start);
    for (double v : e.x) out += "," + sim::ExactNumber(v);
    out += "," + sim::ExactNumber(e.objective) + "," + sim::ExactNumber(e.nominal.speed_mps) +
           "," + sim::ExactNumber(e.nominal.fall_penalty) + "," +
           sim::ExactNumber(e.nominal.overload_penalty) + "," +
           sim::ExactNumber(e.nominal.energy_penalty) + "," + std::to_string(e.failed_runs) +
           "," + e.nominal.early_stop + "," + sim::ExactNumber(e.wall_time_s) + "\n";
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
      "data = " + common::GnuplotQuote(dir + "/convergence.csv") + "\n"
      "plot " + plots + "\n";
  *warning = common::RunGnuplot(script, {dir + "/convergence.png"});
}

}  // namespace

int ProcessRank() { return Comm::World().rank(); }
int ProcessCount() { return Comm::World().size(); }

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

  const Comm& comm = Comm::World();
  // The results folder: checked and locked by rank 0 before any rollout (sim/run_folder.h);
  // every rank learns whether it was refused, so that all stop together.
  std::optional<sim::RunFolder> folder;
  std::string refused;
  if (comm.root()) {
    try {
      folder.emplace(sim::RunFolder::Live(
          options.out_dir,
          {.made_by = "optimise", .force = options.force, .inputs = {scenario_file}},
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
  const std::string resolved = sim::ScenarioToYamlText(problem.scenario());
  if (comm.root()) {
    fs::create_directories(options.out_dir);
    common::WriteFileAtomic(options.out_dir + "/scenario.yaml", resolved);
  }

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
  if (comm.root()) shared.failures.open(options.out_dir + "/failures.log", std::ios::app);

  // Budgets are fixed per start, so the split does not depend on the thread count.
  std::vector<int> budget(starts, params.max_evaluations / starts);
  for (int s = 0; s < params.max_evaluations % starts; ++s) budget[s] += 1;

  // Each start drives its algorithm on its own thread; this thread evaluates the rounds.
  const int threads = std::max(1, options.threads > 0 ? options.threads : DefaultThreads());
  Rounds rounds(starts);
  std::vector<std::string> errors(starts);
  std::vector<std::thread> drivers;
  for (int s = 0; s < starts; ++s) {
    drivers.emplace_back([&, s] {
      try {
        if (params.algorithm == "cmaes") {
          CmaesStart(problem, s, budget[s], rounds).Run();
        } else {
          StartRunner(problem, s, budget[s], rounds).Run();
        }
      } catch (const std::exception& e) {
        errors[s] = e.what();
      }
      rounds.Finish();
    });
  }
  RoundEvaluator evaluate(problem, shared, threads, comm);
  rounds.Serve(std::ref(evaluate));
  for (auto& t : drivers) t.join();
  for (int s = 0; s < starts; ++s) {
    if (!errors[s].empty()) {
      throw std::runtime_error("start " + std::to_string(s) + ": " + errors[s]);
    }
  }

  Result result;
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

  result.rollouts_computed = shared.rollouts;
  result.rollouts_stalled = shared.stalled;
  result.rollouts_bounded = shared.bounded;
  result.simulated_s = shared.simulated_s;
  result.processes = comm.size();
  if (!comm.root()) {
    result.wall_time_s = std::chrono::duration<double>(Clock::now() - t0).count();
    return result;
  }
  common::WriteFileAtomic(options.out_dir + "/history.csv", HistoryCsv(problem, result.history));
  common::WriteFileAtomic(options.out_dir + "/best.yaml",
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
      {"processes", comm.size()},
      {"rollouts_computed", result.rollouts_computed},
      {"rollouts_stopped_stalled", result.rollouts_stalled},
      {"rollouts_stopped_bound", result.rollouts_bounded},
      {"simulated_s", result.simulated_s},
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
  common::WriteFileAtomic(options.out_dir + "/summary.json", summary.dump(2) + "\n");
  folder->Commit();
  return result;
}

}  // namespace climbsim::optimise
