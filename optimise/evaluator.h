// Inside `climbsim optimise` (not a public header): the queue that evaluates the starts'
// candidates. Each start runs its algorithm on its own thread and hands its next evaluations
// (one for NLopt, a generation for CMA-ES) to Evaluator::Submit, which blocks until they are
// evaluated. Their rollouts (each candidate times `objective.runs`) go to one queue, served
// first come first served to this process's worker threads and, under MPI, to the other
// ranks' workers as they ask for work (ranks.cc). No start waits for another's batch, so no
// core idles while a batch's slowest rollout finishes. A start's evaluations depend only on
// its own candidates and on the bound (start 0's first evaluation: batches after a start's
// first wait until it is known, as they would in lockstep rounds), so the history and
// best.yaml are the same bit for bit for any thread or process count.
#ifndef CLIMBSIM_OPTIMISE_EVALUATOR_H_
#define CLIMBSIM_OPTIMISE_EVALUATOR_H_

#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <limits>
#include <map>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "optimise/comm.h"
#include "optimise/optimise.h"

namespace climbsim::optimise::internal {

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

// One start's candidates handed to Submit, and their rollouts' costs as they come back.
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

// One rollout in the queue: run `run` of candidate `k` of `batch`.
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
             ModelCache& cache);

// An evaluation's J from its runs' costs (costs[0 .. runs - 1]): their mean or their worst.
double Aggregate(const Cost* costs, const sim::ObjectiveParams& o);

// An evaluation's J from all its rollouts' costs (costs[0 .. problem.rollouts() − 1]):
// Aggregate, plus each robustness case's penalty_mps when one of its disturbed runs does not
// survive by the bench's rule against its seed's baseline (or failed). Sets the evaluation's
// cases_failed and robustness_penalty.
double EvaluationCost(const Problem& problem, const Cost* costs, Evaluation* evaluation);

class Evaluator {
 public:
  Evaluator(const Problem& problem, Shared& shared, int threads, Comm& comm)
      : problem_(problem), shared_(shared), threads_(threads), comm_(comm),
        active_(problem.params().starts), batches_(problem.params().starts, 0),
        next_index_(problem.params().starts, 0) {}

  // A start's driver thread: evaluates `xs` (in [min, max] coordinates) and returns their
  // evaluations in order.
  std::vector<Evaluation> Submit(int start, std::vector<std::vector<double>> xs);

  // Thrown to a start's driver once the run stops (a checkpoint could not be written).
  struct Stopped : std::runtime_error {
    Stopped() : std::runtime_error("the run stopped") {}
  };

  // What stopped the run (null when nothing did); read after Serve returns.
  std::exception_ptr stop_error() const { return stop_error_; }

  // A start's driver is done (or failed: then the bound is released so no other start waits
  // for it).
  void Finish(int start);

  // Rank 0: runs this process's workers and serves the other ranks until every start has
  // finished, then stops them. Task 0 waits for the starts (or serves the other ranks), then
  // closes the queue; tasks 1.. are the workers. One thread per task, all at once. If serving
  // the ranks fails, the run stops: the workers drain the queue, and once none is left the
  // starts still waiting (for rollouts away on other ranks) are released.
  void Serve();

 private:
  // Under mutex_: queues the rollouts of `b` that the checkpoint does not serve.
  void Enqueue(Batch& b, double bound);
  // Under mutex_: the run stops (no more rollouts or writes); the first error is kept.
  void Stop(std::exception_ptr error);
  void Worker();

  // ranks.cc. Rank 0 with other ranks: a rank asks for up to n tasks when it has n idle
  // workers; it gets the queue's next tasks (or waits for some), sends their costs back, and
  // gets a stop when every start has finished.
  void ServeRanks();
  // Under mutex_: hands each asking rank the queue's next tasks, remembered in `away` by
  // id. Returns whether any were sent.
  bool SendTasks(std::vector<int>* wants, std::map<long, Task>* away, long* next_id);

  // Under mutex_: a rollout's cost is back.
  void Deliver(const Task& t, const Cost& c);
  // Under mutex_: every rollout of `b` is back. Aggregates each candidate's runs in run
  // order, records the evaluations, writes the checkpoint and wakes the start.
  void Complete(Batch& b);
  // Under mutex_: candidate k of `b` gets its J and counts from its runs' costs. Returns
  // whether one of its runs failed.
  bool RecordComputed(Batch& b, size_t k);
  // Under mutex_: once start 0's first evaluation is back, the bound later batches use.
  void SetBound();
  // Under mutex_: failures.log and checkpoint.json after a batch (rank 0).
  void WriteBatchFiles(bool failures, bool computed_any);

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

// ranks.cc. A rank other than 0: asks rank 0 for as many tasks as it has idle workers,
// computes them on its threads and sends their costs back, until rank 0 says stop.
void WorkForRankZero(const Problem& problem, int threads, Comm& comm);

}  // namespace climbsim::optimise::internal

#endif  // CLIMBSIM_OPTIMISE_EVALUATOR_H_
