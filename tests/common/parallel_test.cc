// common::ParallelFor: every task runs once, and a task's exception reaches the caller (the
// lowest failing task's, after the running tasks have finished), for any thread count.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "common/common.h"

namespace climbsim::common {
namespace {

const int kThreads[] = {1, 2, 4, 8};

TEST(ParallelFor, RunsEveryTaskExactlyOnce) {
  for (int threads : kThreads) {
    std::vector<std::atomic<int>> runs(257);
    ParallelFor(257, threads, [&](int t) { ++runs[t]; });
    for (int t = 0; t < 257; ++t) EXPECT_EQ(runs[t].load(), 1) << threads << " threads, task " << t;
  }
}

TEST(ParallelFor, OneThreadOrFewerRunsOnTheCallerInOrder) {
  for (int threads : {1, 0, -3}) {
    std::vector<int> order;
    const std::thread::id caller = std::this_thread::get_id();
    ParallelFor(5, threads, [&](int t) {
      EXPECT_EQ(std::this_thread::get_id(), caller);
      order.push_back(t);
    });
    EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3, 4})) << threads << " threads";
  }
}

std::string ErrorOf(int count, int threads, const std::function<void(int)>& task) {
  try {
    ParallelFor(count, threads, task);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(ParallelFor, ATasksExceptionReachesTheCaller) {
  for (int threads : kThreads) {
    const std::string e = ErrorOf(20, threads, [](int t) {
      if (t == 13) throw std::runtime_error("task 13 failed");
    });
    EXPECT_EQ(e, "task 13 failed") << threads << " threads";
  }
}

// Task 3 throws last in time (it waits first); task 7 throws at once. The error is task 3's.
TEST(ParallelFor, TheLowestFailingTaskWinsWhateverFinishesFirst) {
  for (int threads : kThreads) {
    const std::string e = ErrorOf(10, threads, [](int t) {
      if (t == 3) {
        std::this_thread::sleep_for(std::chrono::milliseconds(30));
        throw std::runtime_error("task 3");
      }
      if (t >= 7) throw std::runtime_error("task " + std::to_string(t));
    });
    EXPECT_EQ(e, "task 3") << threads << " threads";
  }
}

// Every task below the failing one has run, and none is still running when the call returns;
// with one thread nothing after the failing task starts.
TEST(ParallelFor, TasksBeforeTheFailureRunAndNoneOutlivesTheCall) {
  for (int threads : kThreads) {
    std::vector<std::atomic<int>> ran(200);
    std::atomic<int> running{0};
    const std::string e = ErrorOf(200, threads, [&](int t) {
      ++running;
      ran[t] = 1;
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      --running;
      if (t == 40) throw std::runtime_error("task 40");
    });
    EXPECT_EQ(e, "task 40");
    EXPECT_EQ(running.load(), 0) << threads << " threads";
    for (int t = 0; t <= 40; ++t) EXPECT_EQ(ran[t].load(), 1) << threads << " threads, task " << t;
    if (threads == 1) {
      for (int t = 41; t < 200; ++t) EXPECT_EQ(ran[t].load(), 0) << "task " << t;
    }
  }
}

TEST(ParallelFor, NoTasksIsANoOp) {
  int calls = 0;
  ParallelFor(0, 4, [&](int) { ++calls; });
  ParallelFor(-1, 4, [&](int) { ++calls; });
  EXPECT_EQ(calls, 0);
}

}  // namespace
}  // namespace climbsim::common
