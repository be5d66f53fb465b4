#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "common/common.h"

namespace climbsim::common {

void ParallelFor(int count, int threads, const std::function<void(int task)>& task) {
  if (count <= 0) return;
  std::atomic<int> next{0};
  std::atomic<bool> failed{false};
  std::mutex mutex;  // guards the first error only; never taken by a task that succeeds
  int error_task = count;
  std::exception_ptr error;
  // The failure flag is read before an index is taken, never after: every index taken runs.
  // Indices are taken in order, so the tasks that ran are 0..k for some k, and the lowest
  // task that throws among them is the lowest that throws at all (the same error for any
  // thread count, when tasks are deterministic).
  auto worker = [&] {
    while (!failed.load()) {
      const int t = next++;
      if (t >= count) return;
      try {
        task(t);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (t < error_task) {
          error_task = t;
          error = std::current_exception();
        }
        failed = true;
      }
    }
  };
  const int n = std::clamp(threads, 1, count);
  std::vector<std::thread> pool;
  pool.reserve(n - 1);
  for (int k = 1; k < n; ++k) pool.emplace_back(worker);
  worker();
  for (auto& th : pool) th.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace climbsim::common
