// What N cores would make of recorded work: a schedule simulation that follows the rules of
// climbsim's rollout queues, so that a two-core machine can judge a design for sixteen.
//
// The work is chains of batches (a start's generations in `optimise`, a search's bisection
// steps in `bench robustness`). A batch's jobs enter one first-come-first-served queue when
// the batch is released: the chain's first batch at time 0, each later one when the batch
// before it is decided. A gate delays batches until one batch of one chain is decided
// (optimise: a start's batches after its first wait for start 0's first evaluation, the
// bound; bench robustness: every search waits for the undisturbed runs). N identical workers
// take the queue's front (or its lowest job index) whenever they are free. A batch that stops at a failure (a
// bisection step: "every case survives") is decided once a job fails and every job before
// it is done; its jobs still queued after the failure are dropped, the ones running finish
// unheeded. Jobs run for their recorded durations; the simulation itself costs microseconds.
//
//   Schedule s;
//   s.chains = {{{{{1.0}, {2.0}, {1.0}}}}};  // one chain, one batch of three jobs
//   const ScheduleResult r = SimulateSchedule(s, 2);  // r.makespan_s == 2.0
#ifndef CLIMBSIM_OPTIMISE_SCHEDULE_H_
#define CLIMBSIM_OPTIMISE_SCHEDULE_H_

#include <string>
#include <vector>

namespace climbsim::optimise {

struct ScheduleJob {
  double duration_s = 0.0;
  bool fails = false;  // only read in a batch that stops at a failure
};

struct ScheduleBatch {
  std::vector<ScheduleJob> jobs;  // in queue order
  bool stop_at_failure = false;
};

struct Schedule {
  std::vector<std::vector<ScheduleBatch>> chains;  // each chain's batches, in order
  // The gate: batches from gated_from_batch on (of every chain other than gate_chain) wait
  // until batch 0 of gate_chain is decided; -1: no gate.
  int gate_chain = -1;
  int gated_from_batch = 0;
  // The queue serves the lowest job index of any queued batch first (ties: the order
  // queued), as bench robustness's case pool does: the cases every verdict needs before the
  // ones a failure may drop. false: first come first served.
  bool lowest_index_first = false;
};

struct ScheduleResult {
  double makespan_s = 0.0;           // until the last job ends (a dropped one never starts)
  double work_s = 0.0;               // the jobs that ran, summed
  std::vector<double> busy_s;        // per worker
  int jobs_run = 0;
};

// N >= 1 workers. Ties (jobs released at the same instant) queue in chain order.
ScheduleResult SimulateSchedule(const Schedule& schedule, int workers);

// The predicted speed-up on each of `cores` against one worker: makespan(1) / makespan(N).
std::vector<double> PredictedSpeedups(const Schedule& schedule, const std::vector<int>& cores);

// "2: 1.98x, 4: 3.9x, ..." for the cores {2, 4, 8, 16}, as the benches print it.
std::string SpeedupLine(const Schedule& schedule);

}  // namespace climbsim::optimise

#endif  // CLIMBSIM_OPTIMISE_SCHEDULE_H_
