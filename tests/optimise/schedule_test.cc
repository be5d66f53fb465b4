// The schedule simulation (optimise/schedule.h) against closed forms: equal jobs take
// ceil(n/k) rounds, a long job bounds the makespan, chains serialise, a failure drops the
// jobs queued after it, and the gate holds later batches.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "optimise/schedule.h"

namespace climbsim::optimise {
namespace {

ScheduleBatch Batch(const std::vector<double>& durations, bool stop_at_failure = false,
                    int failing = -1) {
  ScheduleBatch b;
  b.stop_at_failure = stop_at_failure;
  for (size_t j = 0; j < durations.size(); ++j) {
    b.jobs.push_back({durations[j], static_cast<int>(j) == failing});
  }
  return b;
}

TEST(Schedule, EqualJobsTakeCeilNOverKRounds) {
  for (int n : {1, 5, 16, 27, 40}) {
    for (int k : {1, 2, 3, 4, 8, 16}) {
      Schedule s;
      s.chains = {{Batch(std::vector<double>(n, 1.5))}};
      const ScheduleResult r = SimulateSchedule(s, k);
      EXPECT_DOUBLE_EQ(r.makespan_s, 1.5 * std::ceil(static_cast<double>(n) / k))
          << n << " jobs, " << k << " workers";
      EXPECT_DOUBLE_EQ(r.work_s, 1.5 * n);
      EXPECT_EQ(r.jobs_run, n);
      double busy = 0.0;
      for (double b : r.busy_s) busy += b;
      EXPECT_DOUBLE_EQ(busy, r.work_s);
    }
  }
}

TEST(Schedule, OneLongJobBoundsTheMakespan) {
  // A 10 s job first, then 20 jobs of 1 s: on 4 workers the other three finish the short ones
  // in ceil(20/3) = 7 s, so the long job decides; on 1 worker the sum does.
  std::vector<double> d(21, 1.0);
  d[0] = 10.0;
  Schedule s;
  s.chains = {{Batch(d)}};
  EXPECT_DOUBLE_EQ(SimulateSchedule(s, 4).makespan_s, 10.0);
  EXPECT_DOUBLE_EQ(SimulateSchedule(s, 1).makespan_s, 30.0);
  // Queued last, the long job starts after the short ones: 5 rounds of 4, then it.
  std::rotate(d.begin(), d.begin() + 1, d.end());
  s.chains = {{Batch(d)}};
  EXPECT_DOUBLE_EQ(SimulateSchedule(s, 4).makespan_s, 15.0);
  // Longest first is the better order, and the speed-up says so.
  EXPECT_NEAR(PredictedSpeedups(s, {4})[0], 2.0, 1e-12);
}

TEST(Schedule, ChainsSerialiseAndRunSideBySide) {
  // A chain of 5 one-job batches takes the sum whatever the workers; 3 such chains on 3
  // workers take as long as one.
  std::vector<ScheduleBatch> chain;
  for (double d : {1.0, 2.0, 3.0, 4.0, 5.0}) chain.push_back(Batch({d}));
  Schedule s;
  s.chains = {chain};
  for (int k : {1, 2, 16}) EXPECT_DOUBLE_EQ(SimulateSchedule(s, k).makespan_s, 15.0);
  s.chains = {chain, chain, chain};
  EXPECT_DOUBLE_EQ(SimulateSchedule(s, 3).makespan_s, 15.0);
  EXPECT_DOUBLE_EQ(SimulateSchedule(s, 1).makespan_s, 45.0);
  // A barrier: two batches of 3 equal jobs on 2 workers take 2 + 2 rounds, not 3.
  s.chains = {{Batch({1, 1, 1}), Batch({1, 1, 1})}};
  EXPECT_DOUBLE_EQ(SimulateSchedule(s, 2).makespan_s, 4.0);
}

TEST(Schedule, AFailureDropsTheQueuedJobsAfterIt) {
  // Job 1 of 4 fails. One worker runs 0 and 1, and the batch is decided: 2 s, then the next
  // batch's 1 s job.
  Schedule s;
  s.chains = {{Batch({1, 1, 1, 1}, true, 1), Batch({1})}};
  ScheduleResult r = SimulateSchedule(s, 1);
  EXPECT_DOUBLE_EQ(r.makespan_s, 3.0);
  EXPECT_EQ(r.jobs_run, 3);
  // Four workers start all four; the batch is decided at 1 s, the next batch's job runs
  // beside the unheeded ones; the makespan counts every running job.
  s.chains = {{Batch({1, 1, 3, 3}, true, 1), Batch({1})}};
  r = SimulateSchedule(s, 4);
  EXPECT_EQ(r.jobs_run, 5);
  EXPECT_DOUBLE_EQ(r.makespan_s, 3.0);
  // Two workers: jobs 0 and 1 run; 1 fails, 2 and 3 are dropped; the next batch runs at 1 s.
  r = SimulateSchedule(s, 2);
  EXPECT_EQ(r.jobs_run, 3);
  EXPECT_DOUBLE_EQ(r.makespan_s, 2.0);
  // Without stop_at_failure every job runs and the batch waits for all.
  s.chains = {{Batch({1, 1, 3, 3}, false, 1), Batch({1})}};
  EXPECT_DOUBLE_EQ(SimulateSchedule(s, 4).makespan_s, 4.0);
}

TEST(Schedule, LowestIndexFirstRunsFewerJobsThatAFailureDrops) {
  // Two chains' batches of four 1 s jobs; chain 0's job 0 fails. First come first served,
  // two workers start chain 0's jobs 0 and 1, and job 1 is wasted; lowest index first, they
  // start both job 0s, and chain 0's jobs 1-3 are dropped before they start.
  Schedule s;
  s.chains = {{Batch({1, 1, 1, 1}, true, 0)}, {Batch({1, 1, 1, 1})}};
  EXPECT_EQ(SimulateSchedule(s, 2).jobs_run, 6);
  s.lowest_index_first = true;
  EXPECT_EQ(SimulateSchedule(s, 2).jobs_run, 5);
  EXPECT_DOUBLE_EQ(SimulateSchedule(s, 2).makespan_s, 3.0);
  // One worker runs what the in-order loop runs, whatever the rule.
  EXPECT_EQ(SimulateSchedule(s, 1).jobs_run, 5);
  s.lowest_index_first = false;
  EXPECT_EQ(SimulateSchedule(s, 1).jobs_run, 5);
  EXPECT_DOUBLE_EQ(SimulateSchedule(s, 1).makespan_s, 5.0);
}

TEST(Schedule, TheGateHoldsLaterBatches) {
  // Chain 0's first batch (4 s) gates every other chain's batches: chain 1's 1 s job waits
  // although a worker is free, then both second batches run side by side.
  Schedule s;
  s.chains = {{Batch({4}), Batch({2})}, {Batch({1}), Batch({2})}};
  s.gate_chain = 0;
  s.gated_from_batch = 0;
  EXPECT_DOUBLE_EQ(SimulateSchedule(s, 2).makespan_s, 7.0);  // 4, then 1 beside 2, then 2
  s.gated_from_batch = 1;  // the optimiser's rule: a start's first batch is free
  EXPECT_DOUBLE_EQ(SimulateSchedule(s, 2).makespan_s, 6.0);  // 4 beside 1; then 2 and 2
}

}  // namespace
}  // namespace climbsim::optimise
