#include "experiments/case_pool.h"

#include <algorithm>
#include <chrono>

namespace climbsim::optimise::internal {

using Clock = std::chrono::steady_clock;

int CasePool::RunStep(int n, CaseFn fn, std::string* how, int* id) {
  auto step = std::make_shared<Step>();
  step->fn = std::move(fn);
  step->n = n;
  step->first_failure = n;
  step->decided = n == 0;
  step->done.assign(n, 0);
  step->how.resize(n);
  step->error.resize(n);
  step->record.wall_s.assign(n, 0.0);
  step->record.ran.assign(n, 0);
  step->record.failed.assign(n, 0);
  std::unique_lock<std::mutex> lock(mutex_);
  *id = static_cast<int>(steps_.size());
  steps_.push_back(step);
  for (int i = 0; i < n; ++i) queue_.emplace_back(step, i);
  changed_.notify_all();
  changed_.wait(lock, [&] { return step->decided; });
  const int first = step->first_failure;
  if (first < n) {
    if (step->error[first]) std::rethrow_exception(step->error[first]);
    *how = step->how[first];
  }
  return first;
}

void CasePool::Work(int w) {
  ModelCache cache;  // compiled models kept across this worker's cases
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    changed_.wait(lock, [&] { return closing_ || !queue_.empty(); });
    if (queue_.empty()) return;
    // The lowest case index of any step first (ties: the order queued): every verdict needs
    // its early cases, while a failure may drop the later ones.
    const auto next = std::min_element(queue_.begin(), queue_.end(),
                                       [](const auto& a, const auto& b) { return a.second < b.second; });
    const auto [step, i] = *next;
    queue_.erase(next);
    if (i > step->first_failure) continue;  // dropped: an earlier case failed
    lock.unlock();
    const auto t0 = Clock::now();
    bool survived = false;
    std::string how;
    std::exception_ptr error;
    try {
      survived = step->fn(i, &cache, &how);
    } catch (...) {
      error = std::current_exception();
    }
    const double wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
    lock.lock();
    busy_s_[w] += wall_s;
    Finish(*step, i, survived, std::move(how), error, wall_s);
  }
}

void CasePool::Finish(Step& step, int i, bool survived, std::string how,
                      std::exception_ptr error, double wall_s) {
  step.done[i] = 1;
  step.how[i] = std::move(how);
  step.error[i] = error;
  step.record.ran[i] = 1;
  step.record.wall_s[i] = wall_s;
  step.record.failed[i] = !survived || error;
  if (step.decided) return;  // unheeded: the step failed at an earlier case
  if (step.record.failed[i] && i < step.first_failure) step.first_failure = i;
  for (int j = 0; j < step.first_failure; ++j) {
    if (!step.done[j]) return;
  }
  step.decided = true;
  changed_.notify_all();
}

void CasePool::Close() {
  std::lock_guard<std::mutex> lock(mutex_);
  closing_ = true;
  changed_.notify_all();
}

}  // namespace climbsim::optimise::internal
