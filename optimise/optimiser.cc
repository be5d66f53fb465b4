#include <sys/resource.h>

#include <nlopt.hpp>
#include <pagmo/algorithms/cmaes.hpp>
#include <pagmo/population.hpp>
#include <pagmo/problem.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <tuple>
#include <thread>

#include "optimise/checkpoint.h"
#include "optimise/comm.h"
#include "optimise/optimise.h"
#include "common/common.h"

namespace climbsim::optimise {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// CPU seconds (user + system) of this process so far, all threads.
double CpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + 1e-6 * u.ru_utime.tv_usec + u.ru_stime.tv_sec +
         1e-6 * u.ru_stime.tv_usec;
}

nlopt::algorithm Algorithm(const std::string& name) {
  static const std::map<std::string, nlopt::algorithm> k{
      {"LN_SBPLX", nlopt::LN_SBPLX},     {"LN_NELDERMEAD", nlopt::LN_NELDERMEAD},
      {"LN_BOBYQA", nlopt::LN_BOBYQA},   {"LN_COBYLA", nlopt::LN_COBYLA},
      {"GN_CRS2_LM", nlopt::GN_CRS2_LM}, {"GN_ISRES", nlopt::GN_ISRES},
      {"GN_ESCH", nlopt::GN_ESCH}};
  return k.at(name);
}

// What the starts share: their evaluations (for the checkpoint and the progress bar) and
// the evaluations a resumed run replays. Touched under the evaluator's lock.
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
  double bound = std::numeric_limits<double>::infinity();  // the evaluator's, once known
  std::set<std::pair<int, int>> replayed;  // (start, evaluation) served from the checkpoint
  std::string error;  // first checkpoint mismatch, reported after the run
  const std::function<void(double, double)>* progress = nullptr;
  // failures.log: what it held before (a resumed run's), then this run's failed rollouts
  // by start, evaluation and run, whatever order they finished in.
  std::string failures_path, failures_before;
  std::map<std::tuple<int, int, int>, std::string> failure_lines;
};

void WriteFailures(const Shared& s) {
  std::string text = s.failures_before;
  for (const auto& [where, what] : s.failure_lines) {
    const auto& [start, index, run] = where;
    text += "start " + std::to_string(start) + " evaluation " + std::to_string(index) + " run " +
            std::to_string(run) + ": " + what + "\n";
  }
  common::WriteFileAtomic(s.failures_path, text);
}

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

// ---- Batches of rollouts: rank 0 hands them out as workers free up ---------------------------
// Each start runs its algorithm on its own thread and hands its next evaluations (one for
// NLopt, a generation for CMA-ES) to Submit, which blocks until they are evaluated. Their
// rollouts (each candidate times `objective.runs`) go to one queue, served first come first
// served to this process's worker threads and, under MPI, to the other ranks' workers as they
// ask for work. No start waits for another's batch, so no core idles while a batch's slowest
// rollout finishes. A start's evaluations depend only on its own candidates and on the bound
// (start 0's first evaluation: batches after a start's first wait until it is known, as they
// would in lockstep rounds), so the history and best.yaml are the same bit for bit for any
// thread or process count.
struct Batch {
  int start = 0;
  int number = 0;  // this start's batch count before it
  std::vector<std::vector<double>> xs;
  std::vector<Evaluation> out;
  std::vector<int> index;      // per candidate: its evaluation number in the start
  std::vector<char> replayed;  // per candidate: served from the checkpoint
  std::vector<Cost> costs;     // per candidate and run: [k * runs + run]
  int pending = 0;             // rollouts not back yet
  bool done = false;
};

struct Task {
  Batch* batch = nullptr;
  size_t k = 0;
  int run = 0;
  double bound = 0.0;
};

// Message tags between rank 0 and the other ranks.
enum Tag : int { kAskTag = 1, kTasksTag = 2, kStopTag = 3, kCostsTag = 4 };

// Never throws: a bad candidate costs kFailedCost and is logged.
Cost Rollout(const Problem& problem, const std::vector<double>& x, int run, double bound,
             ModelCache& cache) {
  const auto t0 = Clock::now();
  Cost c;
  try {
    const sim::Scenario s = problem.ScenarioFor(x, run);
    sim::Simulation rollout(s, cache.For(s));
    c = RunRollout(rollout, problem.params().objective, bound);
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

// An evaluation's J from its runs' costs (costs[0 .. runs - 1]): their mean or their worst.
double Aggregate(const Cost* costs, const sim::ObjectiveParams& o) {
  double sum = 0.0, worst = -std::numeric_limits<double>::infinity();
  for (int run = 0; run < o.runs; ++run) {
    sum += costs[run].total;
    worst = std::max(worst, costs[run].total);
  }
  return o.aggregate == "worst" ? worst : sum / o.runs;
}

class Evaluator {
 public:
  Evaluator(const Problem& problem, Shared& shared, int threads, Comm& comm)
      : problem_(problem), shared_(shared), threads_(threads), comm_(comm),
        active_(problem.params().starts), batches_(problem.params().starts, 0),
        next_index_(problem.params().starts, 0) {}

  // A start's driver thread: evaluates `xs` (in [min, max] coordinates) and returns their
  // evaluations in order.
  std::vector<Evaluation> Submit(int start, std::vector<std::vector<double>> xs) {
    const sim::ObjectiveParams& o = problem_.params().objective;
    Batch b;
    b.start = start;
    b.xs = std::move(xs);
    std::unique_lock<std::mutex> lock(mutex_);
    if (stop_) throw Stopped();
    b.number = batches_[start]++;
    if (b.number > 0) changed_.wait(lock, [&] { return bound_known_; });
    const double bound = b.number > 0 ? bound_ : std::numeric_limits<double>::infinity();
    const size_t n = b.xs.size();
    b.out.resize(n);
    b.index.resize(n);
    b.replayed.assign(n, 0);
    b.costs.resize(n * o.runs);
    for (size_t k = 0; k < n; ++k) {
      b.index[k] = next_index_[start]++;
      const auto& rec = shared_.recorded[start];
      if (b.index[k] < static_cast<int>(rec.size())) {
        if (rec[b.index[k]].x == b.xs[k]) {
          b.out[k] = rec[b.index[k]];
          b.replayed[k] = 1;
          continue;
        }
        if (shared_.error.empty()) {
          shared_.error = "checkpoint.json does not match this run at start " +
                          std::to_string(start) + ", evaluation " + std::to_string(b.index[k]) +
                          ": evaluations from here are computed anew";
        }
      }
      for (int run = 0; run < o.runs; ++run) {
        queue_.push_back({&b, k, run, bound});
        ++b.pending;
      }
    }
    if (b.pending == 0) Complete(b);
    changed_.notify_all();
    changed_.wait(lock, [&] { return b.done || abandoned_; });
    if (stop_) throw Stopped();
    return std::move(b.out);
  }

  // Thrown to a start's driver once the run stops (a checkpoint could not be written).
  struct Stopped : std::runtime_error {
    Stopped() : std::runtime_error("the run stopped") {}
  };

  // What stopped the run (null when nothing did); read after Serve returns.
  std::exception_ptr stop_error() const { return stop_error_; }

  // A start's driver is done (or failed: then the bound is released so no other start waits
  // for it).
  void Finish(int start) {
    std::lock_guard<std::mutex> lock(mutex_);
    --active_;
    if (start == 0) bound_known_ = true;
    changed_.notify_all();
  }

  // Rank 0: runs this process's workers and serves the other ranks until every start has
  // finished, then stops them. Task 0 waits for the starts (or serves the other ranks), then
  // closes the queue; tasks 1.. are the workers. One thread per task, all at once. If serving
  // the ranks fails, the run stops: the workers drain the queue, and once none is left the
  // starts still waiting (for rollouts away on other ranks) are released.
  void Serve() {
    bool failed = false;
    common::ParallelFor(threads_ + 1, threads_ + 1, [&](int task) {
      if (task > 0) return Worker();
      std::exception_ptr error;
      try {
        if (comm_.size() == 1) {
          std::unique_lock<std::mutex> lock(mutex_);
          changed_.wait(lock, [&] { return active_ == 0; });
        } else {
          ServeRanks();
        }
      } catch (...) {
        error = std::current_exception();
      }
      std::lock_guard<std::mutex> lock(mutex_);
      if (error) Stop(error);
      failed = error != nullptr;
      closing_ = true;
      changed_.notify_all();
    });
    if (!failed) return;
    std::lock_guard<std::mutex> lock(mutex_);
    abandoned_ = true;
    changed_.notify_all();
  }

 private:
  // Under mutex_: the run stops (no more rollouts or writes); the first error is kept.
  void Stop(std::exception_ptr error) {
    stop_ = true;
    if (!stop_error_) stop_error_ = error;
  }

  void Worker() {
    ModelCache cache;  // compiled models kept across this worker's rollouts
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      changed_.wait(lock, [&] { return closing_ || !queue_.empty(); });
      if (queue_.empty()) return;
      const Task t = queue_.front();
      queue_.pop_front();
      if (stop_) {  // the run is over: the batch only needs its slots filled
        Cost stopped;
        stopped.failed = true;
        stopped.failure = "the run stopped";
        Deliver(t, stopped);
        continue;
      }
      lock.unlock();
      const Cost c = Rollout(problem_, t.batch->xs[t.k], t.run, t.bound, cache);
      lock.lock();
      Deliver(t, c);
    }
  }

  // Rank 0 with other ranks: a rank asks for up to n tasks when it has n idle workers; it gets
  // the queue's next tasks (or waits for some), sends their costs back, and gets a stop when
  // every start has finished.
  void ServeRanks() {
    std::vector<int> wants(comm_.size(), 0);
    std::vector<char> stopped(comm_.size(), 0);
    stopped[0] = 1;
    std::map<long, Task> away;  // tasks on other ranks, by id
    long next_id = 0;
    int from = 0, tag = 0;
    std::string payload;
    for (;;) {
      bool busy = false;
      while (comm_.Poll(&from, &tag, &payload)) {
        busy = true;
        if (tag == kAskTag) {
          wants[from] = std::stoi(payload);
        } else if (tag == kCostsTag) {
          std::lock_guard<std::mutex> lock(mutex_);
          for (const auto& entry : nlohmann::json::parse(payload)) {
            const auto it = away.find(entry[0].get<long>());
            const Task t = it->second;
            away.erase(it);
            Deliver(t, CostFromJson(entry[1]));
          }
        }
      }
      bool finished = false;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        for (int r = 1; r < comm_.size(); ++r) {
          if (wants[r] == 0 || queue_.empty()) continue;
          nlohmann::json tasks = nlohmann::json::array();
          for (; wants[r] > 0 && !queue_.empty(); --wants[r]) {
            const Task t = queue_.front();
            queue_.pop_front();
            away[next_id] = t;
            // JSON has no infinity: no bound travels as null.
            nlohmann::json bound = nullptr;
            if (std::isfinite(t.bound)) bound = t.bound;
            tasks.push_back({next_id++, t.batch->xs[t.k], t.run, bound});
          }
          wants[r] = 0;
          comm_.Send(r, kTasksTag, tasks.dump());
          busy = true;
        }
        finished = active_ == 0;
      }
      if (finished) {
        int running = 0;
        for (int r = 1; r < comm_.size(); ++r) {
          if (!stopped[r] && wants[r] > 0) {
            comm_.Send(r, kStopTag, "");
            stopped[r] = 1;
          }
          running += !stopped[r];
        }
        if (running == 0) break;
      }
      if (!busy) {
        std::unique_lock<std::mutex> lock(mutex_);
        changed_.wait_for(lock, std::chrono::milliseconds(1));
      }
    }
    comm_.Drain();
  }

  // Under mutex_: a rollout's cost is back.
  void Deliver(const Task& t, const Cost& c) {
    Batch& b = *t.batch;
    b.costs[t.k * problem_.params().objective.runs + t.run] = c;
    if (--b.pending == 0) Complete(b);
  }

  // Under mutex_: every rollout of `b` is back. Aggregates each candidate's runs in run
  // order, records the evaluations, writes the checkpoint and wakes the start.
  void Complete(Batch& b) {
    const sim::ObjectiveParams& o = problem_.params().objective;
    bool computed_any = false, failures = false;
    for (size_t k = 0; k < b.xs.size(); ++k) {
      Evaluation& e = b.out[k];
      if (!b.replayed[k]) {
        computed_any = true;
        e.x = b.xs[k];
        e.nominal = b.costs[k * o.runs];
        for (int run = 0; run < o.runs; ++run) {
          const Cost& c = b.costs[k * o.runs + run];
          if (c.failed) {
            ++e.failed_runs;
            failures = true;
            shared_.failure_lines[{b.start, b.index[k], run}] = c.failure;
          }
          e.wall_time_s += c.wall_time_s;
          shared_.rollouts += 1;
          shared_.stalled += c.early_stop == "stalled";
          shared_.bounded += c.early_stop == "bound";
          shared_.simulated_s += c.stop_time_s;
        }
        e.objective = Aggregate(&b.costs[k * o.runs], o);
      }
      e.start = b.start;
      e.index = b.index[k];
      if (b.replayed[k]) shared_.replayed.insert({b.start, e.index});
      shared_.by_start[b.start].push_back(e);
      shared_.done += 1;
      shared_.computed += !b.replayed[k];
      shared_.best = std::min(shared_.best, e.objective);
    }
    if (b.start == 0 && b.number == 0) {
      // The cost a rollout must beat to matter: the scenario as given. With `mean` over K
      // runs, one run may be as bad as K·B + (K−1)·v_max while the others at v_max bring
      // the mean under B.
      const Evaluation& first = shared_.by_start[0][0];
      if (!first.nominal.failed) {
        const double v = first.objective;
        bound_ = o.aggregate == "worst" ? v : o.runs * v + (o.runs - 1) * o.max_speed_mps;
        shared_.bound = bound_;
      }
      bound_known_ = true;
    }
    if (comm_.root() && !stop_) {
      // A worker's exception would end the process (std::terminate): a failed write stops the
      // run instead, the previous checkpoint kept (files are replaced whole), and the caller
      // gets the error.
      try {
        if (failures) WriteFailures(shared_);
        if (computed_any) WriteCheckpoint(shared_);
      } catch (...) {
        Stop(std::current_exception());
      }
    }
    if (shared_.progress && *shared_.progress && !stop_) {
      (*shared_.progress)(std::min(1.0, static_cast<double>(shared_.done) / shared_.total_budget),
                          shared_.best);
    }
    b.done = true;
    changed_.notify_all();
  }

  const Problem& problem_;
  Shared& shared_;
  const int threads_;
  Comm& comm_;
  std::mutex mutex_;
  std::condition_variable changed_;  // queue, batches, bound, active starts
  std::deque<Task> queue_;
  int active_;
  bool closing_ = false;
  bool stop_ = false;  // a checkpoint write failed: no more rollouts, no more writes
  std::exception_ptr stop_error_;
  bool abandoned_ = false;  // serving failed: batches with rollouts away are never completed
  bool bound_known_ = false;
  double bound_ = std::numeric_limits<double>::infinity();
  std::vector<int> batches_;
  std::vector<int> next_index_;
};

// A rank other than 0: asks rank 0 for as many tasks as it has idle workers, computes them on
// its threads and sends their costs back, until rank 0 says stop.
void WorkForRankZero(const Problem& problem, int threads, Comm& comm) {
  struct Local {
    long id;
    std::vector<double> x;
    int run;
    double bound;
  };
  std::mutex mutex;
  std::condition_variable cv;
  std::deque<Local> queue;
  nlohmann::json costs = nlohmann::json::array();
  int busy = 0;  // tasks received and not yet computed
  bool closing = false;
  const auto worker = [&] {
    ModelCache cache;
    std::unique_lock<std::mutex> lock(mutex);
    for (;;) {
      cv.wait(lock, [&] { return closing || !queue.empty(); });
      if (queue.empty()) return;
      const Local t = queue.front();
      queue.pop_front();
      lock.unlock();
      const Cost c = Rollout(problem, t.x, t.run, t.bound, cache);
      lock.lock();
      costs.push_back({t.id, CostToJson(c)});
      --busy;
    }
  };
  // Asks rank 0 for tasks while workers are idle, sends costs back, until told to stop.
  const auto talk = [&] {
    bool asked = false, stopped = false;
    int from = 0, tag = 0;
    std::string payload;
    for (;;) {
      std::string done;
      int idle = 0;
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (!costs.empty()) {
          done = costs.dump();
          costs = nlohmann::json::array();
        }
        idle = threads - busy;
      }
      if (!done.empty()) comm.Send(0, kCostsTag, done);
      if (stopped && idle == threads && done.empty()) break;
      if (!stopped && !asked && idle > 0) {
        comm.Send(0, kAskTag, std::to_string(idle));
        asked = true;
      }
      bool got = false;
      while (comm.Poll(&from, &tag, &payload)) {
        got = true;
        if (tag == kStopTag) {
          stopped = true;
        } else if (tag == kTasksTag) {
          asked = false;
          std::lock_guard<std::mutex> lock(mutex);
          for (const auto& t : nlohmann::json::parse(payload)) {
            queue.push_back(
                {t[0].get<long>(), t[1].get<std::vector<double>>(), t[2].get<int>(),
                 t[3].is_null() ? std::numeric_limits<double>::infinity() : t[3].get<double>()});
            ++busy;
          }
          cv.notify_all();
        }
      }
      if (!got && done.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  };
  const auto close = [&] {
    std::lock_guard<std::mutex> lock(mutex);
    closing = true;
    cv.notify_all();
  };
  // Task 0 talks to rank 0, tasks 1.. are the workers: one thread each, all at once. The
  // workers end once task 0 closes the queue, whether it ends or throws.
  common::ParallelFor(threads + 1, threads + 1, [&](int task) {
    if (task > 0) return worker();
    try {
      talk();
    } catch (...) {
      close();
      throw;
    }
    close();
  });
  comm.Drain();
}

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
  StartRunner(const Problem& problem, int start, int budget, Evaluator& rounds)
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
  Evaluator& rounds_;
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
  CmaesStart(const Problem& problem, int start, int budget, Evaluator& rounds)
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
  Evaluator& rounds_;
  const std::vector<double> lo_, hi_;
};

// A resumed run's best, when checkpoint.json served it, evaluated again here (its runs with
// the bound it had), so that the best reported is always a value this process computed. The
// checksum catches accidental damage only: a checkpoint edited with its checksum recomputed
// is refused here (InputError at the evaluation), as would one written by another build.
void RecheckReplayedBest(const Problem& problem, const Shared& shared, const Evaluation& best,
                         int threads) {
  if (shared.replayed.count({best.start, best.index}) == 0) return;
  const sim::ObjectiveParams& o = problem.params().objective;
  // A start's first batch (its evaluation 0) ran without the bound, later ones with it (Submit).
  const double bound = best.index == 0 ? std::numeric_limits<double>::infinity() : shared.bound;
  std::vector<Cost> costs(o.runs);
  ParallelRollouts(o.runs, threads, [&](int run, ModelCache& cache) {
    costs[run] = Rollout(problem, best.x, run, bound, cache);
  });
  const double j = Aggregate(costs.data(), o);
  if (j == best.objective) return;
  throw InputError(
      shared.checkpoint_path, 0, 0,
      "starts[" + std::to_string(best.start) + "][" + std::to_string(best.index) + "].objective",
      "the best evaluation it holds, J = " + sim::ExactNumber(best.objective) +
          ", computes to J = " + sim::ExactNumber(j) +
          " here: the checkpoint was edited or written by another build (its checksum guards "
          "against accidental damage, not edits); drop --resume (and use --force) to start over");
}

// Rank 0: tasks 0..starts-1 drive the starts (each catches its own error into `errors`, so
// every one starts), the last serves their rollouts; one thread each, all at once. Returns
// what stopped the run (a checkpoint not written), null when nothing did.
std::exception_ptr DriveStarts(const Problem& problem, const std::vector<int>& budget,
                               Shared& shared, int threads, Comm& comm,
                               std::vector<std::string>* errors) {
  const int starts = static_cast<int>(budget.size());
  Evaluator evaluator(problem, shared, threads, comm);
  common::ParallelFor(starts + 1, starts + 1, [&](int s) {
    if (s == starts) return evaluator.Serve();
    try {
      if (problem.params().algorithm == "cmaes") {
        CmaesStart(problem, s, budget[s], evaluator).Run();
      } else {
        StartRunner(problem, s, budget[s], evaluator).Run();
      }
    } catch (const std::exception& e) {
      (*errors)[s] = e.what();
    }
    evaluator.Finish(s);
  });
  return evaluator.stop_error();
}

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
      "data = 'convergence.csv'\n"  // gnuplot runs in `dir`
      "plot " + plots + "\n";
  *warning = common::RunGnuplot(dir, script, {"convergence.png"});
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

Result Optimise(const std::string& scenario_file, const Options& options,
                const std::function<void(double, double)>& progress) {
  const auto t0 = Clock::now();
  const double cpu0 = CpuSeconds();
  const Problem problem(scenario_file);
  sim::OptimiseParams params = problem.params();
  if (options.max_evaluations > 0) params.max_evaluations = options.max_evaluations;
  const int starts = params.starts;
  if (params.max_evaluations < starts) {
    throw InputError(scenario_file, 0, 0, "optimise.max_evaluations",
                     "must be at least the number of starts (" + std::to_string(starts) + ")");
  }

  Comm& comm = Comm::World();
  // The results folder: checked and locked by rank 0 before any rollout (sim/run_folder.h);
  // every rank learns whether it was refused, so that all stop together.
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
  shared.failures_path = options.out_dir + "/failures.log";
  if (comm.root()) {
    std::ifstream in(shared.failures_path);
    shared.failures_before.assign(std::istreambuf_iterator<char>(in), {});
    if (!fs::exists(shared.failures_path)) common::WriteFileAtomic(shared.failures_path, "");
  }

  // Budgets are fixed per start, so the split does not depend on the thread count.
  std::vector<int> budget(starts, params.max_evaluations / starts);
  for (int s = 0; s < params.max_evaluations % starts; ++s) budget[s] += 1;

  // Rank 0: each start drives its algorithm on its own thread; this thread serves their
  // rollouts to the workers (and to the other ranks). The other ranks only compute rollouts.
  const int threads = std::max(1, options.threads > 0 ? options.threads : DefaultThreads());
  std::vector<std::string> errors(starts);
  // What stopped the run (a checkpoint not written): rank 0's exception, its text for all.
  std::exception_ptr stop_error;
  std::string stopped;
  if (comm.root()) {
    stop_error = DriveStarts(problem, budget, shared, threads, comm, &errors);
    try {
      if (stop_error) std::rethrow_exception(stop_error);
    } catch (const std::exception& e) {
      stopped = e.what();
    }
  } else {
    WorkForRankZero(problem, threads, comm);
  }
  if (comm.size() > 1) {
    // Every rank returns the same result: rank 0's evaluations and counts, and its errors.
    nlohmann::json mine;
    if (comm.root()) {
      nlohmann::json by_start = nlohmann::json::array();
      for (const auto& evals : shared.by_start) {
        nlohmann::json list = nlohmann::json::array();
        for (const auto& e : evals) list.push_back(ToJson(e));
        by_start.push_back(list);
      }
      nlohmann::json replayed = nlohmann::json::array();
      for (const auto& [start, index] : shared.replayed) replayed.push_back({start, index});
      mine = {{"by_start", by_start},
              {"errors", errors},
              {"stopped", stopped},
              {"replayed", replayed},
              {"bound", std::isfinite(shared.bound) ? nlohmann::json(shared.bound)
                                                    : nlohmann::json(nullptr)},
              {"computed", shared.computed},
              {"rollouts", shared.rollouts},
              {"stalled", shared.stalled},
              {"bounded", shared.bounded},
              {"simulated_s", shared.simulated_s}};
    }
    const nlohmann::json all = nlohmann::json::parse(comm.AllGather(mine.dump())[0]);
    if (!comm.root()) {
      for (int s = 0; s < starts; ++s) {
        shared.by_start[s].clear();
        const auto& list = all["by_start"][s];
        for (size_t i = 0; i < list.size(); ++i) {
          shared.by_start[s].push_back(FromJson(list[i], s, static_cast<int>(i)));
        }
      }
      errors = all["errors"].get<std::vector<std::string>>();
      stopped = all["stopped"].get<std::string>();
      for (const auto& r : all["replayed"]) {
        shared.replayed.insert({r[0].get<int>(), r[1].get<int>()});
      }
      if (!all["bound"].is_null()) shared.bound = all["bound"].get<double>();
      shared.computed = all["computed"].get<int>();
      shared.rollouts = all["rollouts"].get<int>();
      shared.stalled = all["stalled"].get<int>();
      shared.bounded = all["bounded"].get<int>();
      shared.simulated_s = all["simulated_s"].get<double>();
    }
  }
  if (stop_error) std::rethrow_exception(stop_error);
  if (!stopped.empty()) throw std::runtime_error("rank 0 stopped: " + stopped);
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
  RecheckReplayedBest(problem, shared, result.best, threads);

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
  result.plot_warning = plot_warning;
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
      {"cpu_s_rank0", CpuSeconds() - cpu0},
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
