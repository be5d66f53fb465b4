// Inside bench robustness (not a public header): the cases of many searches' current steps,
// side by side. Each search runs on its own driver thread and hands one step's cases (a
// magnitude's seeds × push phases) to CasePool::RunStep, which blocks until the step is
// decided; the cases of all steps go to one queue, served to the pool's workers (one model
// cache each) lowest case index first, ties in the order queued: the cases every verdict
// needs run before those a failure may drop. A step stops at its first failing case in case
// order: once case i fails and every case before it is done, the step is decided, and its
// cases still queued after i are dropped (those running finish unheeded). The verdict and
// the failing case are those of the cases run one by one in order, for any worker count.
#ifndef CLIMBSIM_EXPERIMENTS_CASE_POOL_H_
#define CLIMBSIM_EXPERIMENTS_CASE_POOL_H_

#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "experiments/experiments.h"

namespace climbsim::optimise::internal {

// Whether case i survives (why not in *how). Must not hold references to a driver's stack:
// a dropped step's running cases outlive its RunStep.
using CaseFn = std::function<bool(int i, ModelCache* cache, std::string* how)>;

class CasePool {
 public:
  explicit CasePool(int workers) : busy_s_(workers, 0.0) {}

  // Runs cases [0, n) of one step; returns the first failing case (n when all survive), its
  // `how`, and in *id the step's number for Record. A case's exception, when it is the first
  // failure, is rethrown here.
  int RunStep(int n, CaseFn fn, std::string* how, int* id);

  // Step `id`'s cases as they ran (for the schedule simulation); complete once the workers
  // have returned.
  RobustnessStepRecord Record(int id) const { return steps_[id]->record; }

  // Worker w's loop, until Close and an empty queue. Call from `workers` threads.
  void Work(int w);
  // No more steps: the workers return once the queue is empty.
  void Close();

  // Each worker's time inside cases so far (read after the workers returned).
  const std::vector<double>& busy_s() const { return busy_s_; }

 private:
  struct Step {
    CaseFn fn;
    int n = 0;
    int first_failure = 0;  // n until a case fails
    bool decided = false;
    std::vector<char> done;
    std::vector<std::string> how;
    std::vector<std::exception_ptr> error;
    RobustnessStepRecord record;
  };
  // Under mutex_: case i of `step` is back.
  void Finish(Step& step, int i, bool survived, std::string how, std::exception_ptr error,
              double wall_s);

  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::pair<std::shared_ptr<Step>, int>> queue_;
  bool closing_ = false;
  std::vector<double> busy_s_;
  std::vector<std::shared_ptr<Step>> steps_;
};

}  // namespace climbsim::optimise::internal

#endif  // CLIMBSIM_EXPERIMENTS_CASE_POOL_H_
