#include "optimise/evaluator.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "common/common.h"
#include "optimise/checkpoint.h"
#include "optimise/disturbance.h"

namespace climbsim::optimise::internal {
namespace {

using Clock = std::chrono::steady_clock;

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

}  // namespace

Cost Rollout(const Problem& problem, const std::vector<double>& x, int run, double bound,
             ModelCache& cache) {
  const auto t0 = Clock::now();
  Cost c;
  try {
    const sim::Scenario s = problem.ScenarioFor(x, run);
    sim::Simulation rollout(s, cache.For(s));
    if (run < problem.params().objective.runs) {
      c = RunRollout(rollout, problem.params().objective, bound);
    } else {
      // A robustness run: to its end or its fall, as the bench runs it; no J of its own.
      const sim::RunResult r = rollout.Run();
      c.stable = r.stable;
      if (!r.stable) c.failure = r.failure;
      c.fell = r.fell;
      c.fall_time_s = r.fall_time_s;
      c.distance_m = r.distance_m;
      c.stop_time_s = r.sim_time_s;
    }
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

double Aggregate(const Cost* costs, const sim::ObjectiveParams& o) {
  double sum = 0.0, worst = -std::numeric_limits<double>::infinity();
  for (int run = 0; run < o.runs; ++run) {
    sum += costs[run].total;
    worst = std::max(worst, costs[run].total);
  }
  return o.aggregate == "worst" ? worst : sum / o.runs;
}

double EvaluationCost(const Problem& problem, const Cost* costs, Evaluation* e) {
  const sim::ObjectiveParams& o = problem.params().objective;
  const auto& rollouts = problem.robustness_rollouts();
  std::vector<char> failed(o.robustness.size(), 0);
  std::vector<double> baseline_m;  // of the current case, per seed
  for (size_t i = 0; i < rollouts.size(); ++i) {
    const Problem::RobustnessRollout& r = rollouts[i];
    const Cost& c = costs[o.runs + i];
    if (r.baseline) {
      if (r.seed == 0) baseline_m.clear();
      baseline_m.push_back(c.distance_m);
      continue;
    }
    sim::RunResult run;
    run.stable = c.stable;
    run.failure = c.failure;
    run.fell = c.fell;
    run.fall_time_s = c.fall_time_s;
    run.distance_m = c.distance_m;
    if (c.failed || !SurvivedRun(run, baseline_m[r.seed], nullptr)) failed[r.case_index] = 1;
  }
  e->cases_failed = 0;
  e->robustness_penalty = 0.0;
  for (size_t k = 0; k < failed.size(); ++k) {
    if (!failed[k]) continue;
    ++e->cases_failed;
    e->robustness_penalty += o.robustness[k].penalty_mps;
  }
  return Aggregate(costs, o) + e->robustness_penalty;
}

std::vector<Evaluation> Evaluator::Submit(int start, std::vector<std::vector<double>> xs) {
  Batch b;
  b.start = start;
  b.xs = std::move(xs);
  std::unique_lock<std::mutex> lock(mutex_);
  if (stop_) throw Stopped();
  b.number = batches_[start]++;
  if (b.number > 0) changed_.wait(lock, [&] { return bound_known_; });
  Enqueue(b, b.number > 0 ? bound_ : std::numeric_limits<double>::infinity());
  if (b.pending == 0) Complete(b);
  changed_.notify_all();
  changed_.wait(lock, [&] { return b.done || abandoned_; });
  if (stop_) throw Stopped();
  return std::move(b.out);
}

void Evaluator::Enqueue(Batch& b, double bound) {
  const int runs = problem_.rollouts();
  const size_t n = b.xs.size();
  b.out.resize(n);
  b.index.resize(n);
  b.replayed.assign(n, 0);
  b.costs.resize(n * runs);
  for (size_t k = 0; k < n; ++k) {
    b.index[k] = next_index_[b.start]++;
    const auto& rec = shared_.recorded[b.start];
    if (b.index[k] < static_cast<int>(rec.size())) {
      if (rec[b.index[k]].x == b.xs[k]) {
        b.out[k] = rec[b.index[k]];
        b.replayed[k] = 1;
        continue;
      }
      if (shared_.error.empty()) {
        shared_.error = "checkpoint.json does not match this run at start " +
                        std::to_string(b.start) + ", evaluation " + std::to_string(b.index[k]) +
                        ": evaluations from here are computed anew";
      }
    }
    for (int run = 0; run < runs; ++run) {
      queue_.push_back({&b, k, run, bound});
      ++b.pending;
    }
  }
}

void Evaluator::Finish(int start) {
  std::lock_guard<std::mutex> lock(mutex_);
  --active_;
  if (start == 0) bound_known_ = true;
  changed_.notify_all();
}

void Evaluator::Serve() {
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

void Evaluator::Stop(std::exception_ptr error) {
  stop_ = true;
  if (!stop_error_) stop_error_ = error;
}

void Evaluator::Worker() {
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

void Evaluator::Deliver(const Task& t, const Cost& c) {
  Batch& b = *t.batch;
  b.costs[t.k * problem_.rollouts() + t.run] = c;
  if (--b.pending == 0) Complete(b);
}

void Evaluator::Complete(Batch& b) {
  bool computed_any = false, failures = false;
  for (size_t k = 0; k < b.xs.size(); ++k) {
    Evaluation& e = b.out[k];
    if (!b.replayed[k]) {
      computed_any = true;
      failures = RecordComputed(b, k) || failures;
    }
    e.start = b.start;
    e.index = b.index[k];
    if (b.replayed[k]) shared_.replayed.insert({b.start, e.index});
    shared_.by_start[b.start].push_back(e);
    shared_.done += 1;
    shared_.computed += !b.replayed[k];
    shared_.best = std::min(shared_.best, e.objective);
  }
  if (b.start == 0 && b.number == 0) SetBound();
  if (comm_.root() && !stop_) WriteBatchFiles(failures, computed_any);
  if (shared_.progress && *shared_.progress && !stop_) {
    (*shared_.progress)(std::min(1.0, static_cast<double>(shared_.done) / shared_.total_budget),
                        shared_.best);
  }
  b.done = true;
  changed_.notify_all();
}

bool Evaluator::RecordComputed(Batch& b, size_t k) {
  const int runs = problem_.rollouts();
  Evaluation& e = b.out[k];
  bool failures = false;
  e.x = b.xs[k];
  e.nominal = b.costs[k * runs];
  for (int run = 0; run < runs; ++run) {
    const Cost& c = b.costs[k * runs + run];
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
  e.objective = EvaluationCost(problem_, &b.costs[k * runs], &e);
  return failures;
}

void Evaluator::SetBound() {
  const sim::ObjectiveParams& o = problem_.params().objective;
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

void Evaluator::WriteBatchFiles(bool failures, bool computed_any) {
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

}  // namespace climbsim::optimise::internal
