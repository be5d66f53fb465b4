// bench robustness's case pool (experiments/case_pool.h): a step's verdict, its failing case
// and its `how` are those of the cases run one by one in order, for any worker count; cases
// queued after a failure are dropped; an exception counts only when it is the first failure.
#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <chrono>
#include <stdexcept>
#include <thread>

#include "common/common.h"
#include "experiments/case_pool.h"

namespace climbsim::optimise::internal {
namespace {

struct StepOutcome {
  int first = -1;
  std::string how, error;
  RobustnessStepRecord record;
};

// Runs `steps` (each a CaseFn over n cases) on `workers` workers, one driver per step.
std::vector<StepOutcome> RunSteps(int workers, int n, const std::vector<CaseFn>& steps) {
  CasePool pool(workers);
  std::vector<StepOutcome> out(steps.size());
  std::vector<int> ids(steps.size(), 0);
  common::ParallelFor(workers + 1, workers + 1, [&](int task) {
    if (task > 0) return pool.Work(task - 1);
    common::ParallelFor(static_cast<int>(steps.size()), static_cast<int>(steps.size()),
                        [&](int s) {
                          try {
                            out[s].first = pool.RunStep(n, steps[s], &out[s].how, &ids[s]);
                          } catch (const std::exception& e) {
                            out[s].error = e.what();
                          }
                        });
    pool.Close();
  });
  for (size_t s = 0; s < steps.size(); ++s) out[s].record = pool.Record(ids[s]);
  return out;
}

// Case i sleeps a little (later cases shorter, so that they finish first) and fails when
// `fails(i)`; throws when `throws(i)`.
CaseFn Cases(std::function<bool(int)> fails, std::function<bool(int)> throws) {
  return [fails, throws](int i, ModelCache*, std::string* how) {
    std::this_thread::sleep_for(std::chrono::milliseconds(12 - i));
    if (throws(i)) throw std::runtime_error("case " + std::to_string(i) + " threw");
    if (fails(i)) *how = "case " + std::to_string(i) + " fell";
    return !fails(i);
  };
}

TEST(CasePool, TheVerdictIsTheInOrderOneForAnyWorkerCount) {
  const auto never = [](int) { return false; };
  const std::vector<CaseFn> steps = {
      Cases(never, never),                                     // all survive
      Cases([](int i) { return i == 2 || i == 5; }, never),    // 2 fails first
      Cases([](int i) { return i >= 6; }, never),              // the last two fail
      Cases([](int i) { return i == 1; }, [](int i) { return i == 4; }),  // 4 throws after 1
      Cases(never, [](int i) { return i == 3; }),              // 3 throws: rethrown
  };
  for (int workers : {1, 2, 5, 8}) {
    const std::vector<StepOutcome> r = RunSteps(workers, 8, steps);
    EXPECT_EQ(r[0].first, 8) << workers;
    EXPECT_EQ(r[1].first, 2) << workers;
    EXPECT_EQ(r[1].how, "case 2 fell");
    EXPECT_EQ(r[2].first, 6);
    EXPECT_EQ(r[2].how, "case 6 fell");
    EXPECT_EQ(r[3].first, 1);
    EXPECT_EQ(r[3].how, "case 1 fell");
    EXPECT_EQ(r[3].error, "");
    EXPECT_EQ(r[4].error, "case 3 threw");
    // Every case before the first failure ran; with one worker nothing after it did.
    for (int i = 0; i <= 2; ++i) EXPECT_TRUE(r[1].record.ran[i]) << workers << " " << i;
    for (int i = 0; i < 8; ++i) EXPECT_TRUE(r[0].record.ran[i]);
    if (workers == 1) {
      for (int i = 3; i < 8; ++i) EXPECT_FALSE(r[1].record.ran[i]) << i;
    }
  }
}

TEST(CasePool, CasesOfOneStepRunSideBySide) {
  // Four cases that each wait until four are running at once: they finish only on four
  // workers or more (a pool that ran a step's cases one by one would never get there).
  std::atomic<int> running{0};
  const CaseFn meet = [&](int, ModelCache*, std::string*) {
    ++running;
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (running.load() < 4 && std::chrono::steady_clock::now() < until) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return running.load() >= 4;
  };
  const std::vector<StepOutcome> r = RunSteps(4, 4, {meet});
  EXPECT_EQ(r[0].first, 4);
  for (double w : r[0].record.wall_s) EXPECT_GT(w, 0.0);
}

TEST(CasePool, TheLowestCaseIndexOfAnyStepRunsFirst) {
  // One worker. Step A's case 0 holds the worker until step B is queued; then B's case 0
  // runs before A's cases 1 and 2, and B's case 1 after A's case 1 (ties: the order queued).
  CasePool pool(1);
  std::mutex mutex;
  std::vector<std::string> order;
  std::atomic<bool> a0_started{false}, b_queued{false};
  std::atomic<int> drivers_done{0};
  const auto note = [&](const std::string& what) {
    std::lock_guard<std::mutex> lock(mutex);
    order.push_back(what);
  };
  const auto wait_for = [](const std::atomic<bool>& flag) {
    while (!flag.load()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  };
  const CaseFn a = [&](int i, ModelCache*, std::string*) {
    if (i == 0) {
      a0_started = true;
      wait_for(b_queued);
      std::this_thread::sleep_for(std::chrono::milliseconds(200));  // B's RunStep queues
    }
    note("A" + std::to_string(i));
    return true;
  };
  const CaseFn b = [&](int i, ModelCache*, std::string*) {
    note("B" + std::to_string(i));
    return true;
  };
  common::ParallelFor(3, 3, [&](int task) {
    if (task == 0) return pool.Work(0);
    std::string how;
    int id = 0;
    if (task == 1) {
      pool.RunStep(3, a, &how, &id);
    } else {
      wait_for(a0_started);  // A's cases are queued
      b_queued = true;
      pool.RunStep(2, b, &how, &id);
    }
    if (++drivers_done == 2) pool.Close();
  });
  EXPECT_EQ(order, (std::vector<std::string>{"A0", "B0", "A1", "B1", "A2"}));
}

}  // namespace
}  // namespace climbsim::optimise::internal
