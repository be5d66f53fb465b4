#include "optimise/schedule.h"

#include <algorithm>
#include <cstdio>
#include <deque>
#include <limits>

namespace climbsim::optimise {
namespace {

struct BatchState {
  std::vector<char> done, dropped;
  int first_failure = std::numeric_limits<int>::max();
  bool decided = false;
};

struct Running {
  double end_s;
  int worker, chain, batch, job;
};

class Simulator {
 public:
  Simulator(const Schedule& s, int workers) : s_(s), free_(std::max(1, workers), 1) {
    result_.busy_s.assign(free_.size(), 0.0);
    state_.resize(s.chains.size());
    next_.assign(s.chains.size(), 0);
    for (size_t c = 0; c < s.chains.size(); ++c) {
      for (const ScheduleBatch& b : s.chains[c]) {
        state_[c].push_back({std::vector<char>(b.jobs.size(), 0),
                             std::vector<char>(b.jobs.size(), 0)});
      }
    }
  }

  ScheduleResult Run() {
    std::vector<int> all(s_.chains.size());
    for (size_t c = 0; c < all.size(); ++c) all[c] = static_cast<int>(c);
    Release(all);
    for (;;) {
      StartJobs();
      if (running_.empty()) break;
      const double t = std::min_element(running_.begin(), running_.end(),
                                         [](const Running& a, const Running& b) {
                                           return a.end_s < b.end_s;
                                         })->end_s;
      now_s_ = t;
      std::vector<int> ready;  // chains whose next batch may be released now
      for (size_t i = 0; i < running_.size();) {
        if (running_[i].end_s != t) {
          ++i;
          continue;
        }
        const Running r = running_[i];
        running_.erase(running_.begin() + static_cast<long>(i));
        free_[r.worker] = 1;
        Finish(r, &ready);
      }
      std::sort(ready.begin(), ready.end());
      Release(ready);
    }
    result_.makespan_s = now_s_;
    return result_;
  }

 private:
  bool Gated(int chain, int batch) const {
    return s_.gate_chain >= 0 && chain != s_.gate_chain && batch >= s_.gated_from_batch &&
           !state_[s_.gate_chain].empty() && !state_[s_.gate_chain][0].decided;
  }

  // Queues the next batch of each chain in `chains` (in that order) unless the gate holds it.
  void Release(const std::vector<int>& chains) {
    for (int c : chains) {
      const int b = next_[c];
      if (b >= static_cast<int>(s_.chains[c].size())) continue;
      if (Gated(c, b)) {
        waiting_.push_back(c);
        continue;
      }
      ++next_[c];
      for (size_t j = 0; j < s_.chains[c][b].jobs.size(); ++j) {
        queue_.push_back({c, b, static_cast<int>(j)});
      }
      // An empty batch is decided at once.
      if (s_.chains[c][b].jobs.empty()) Decide(c, b, nullptr);
    }
  }

  void StartJobs() {
    for (size_t w = 0; w < free_.size() && !queue_.empty(); ++w) {
      if (!free_[w]) continue;
      while (!queue_.empty()) {
        auto next = queue_.begin();
        if (s_.lowest_index_first) {
          next = std::min_element(queue_.begin(), queue_.end(),
                                  [](const Queued& a, const Queued& b) { return a.job < b.job; });
        }
        const auto [c, b, j] = *next;
        queue_.erase(next);
        if (state_[c][b].dropped[j]) continue;
        const double d = s_.chains[c][b].jobs[j].duration_s;
        running_.push_back({now_s_ + d, static_cast<int>(w), c, b, j});
        free_[w] = 0;
        result_.busy_s[w] += d;
        result_.work_s += d;
        ++result_.jobs_run;
        break;
      }
    }
  }

  void Finish(const Running& r, std::vector<int>* ready) {
    const ScheduleBatch& batch = s_.chains[r.chain][r.batch];
    BatchState& st = state_[r.chain][r.batch];
    st.done[r.job] = 1;
    if (st.decided) return;  // an unheeded job after the batch's failure
    if (batch.stop_at_failure && batch.jobs[r.job].fails && r.job < st.first_failure) {
      st.first_failure = r.job;
      for (size_t j = r.job + 1; j < batch.jobs.size(); ++j) st.dropped[j] = !st.done[j];
    }
    const size_t need = std::min<size_t>(batch.jobs.size(), st.first_failure);
    for (size_t j = 0; j < need; ++j) {
      if (!st.done[j]) return;
    }
    Decide(r.chain, r.batch, ready);
  }

  void Decide(int chain, int batch, std::vector<int>* ready) {
    state_[chain][batch].decided = true;
    std::vector<int> now = {chain};
    if (chain == s_.gate_chain && batch == 0) {
      now.insert(now.end(), waiting_.begin(), waiting_.end());
      waiting_.clear();
    }
    if (ready) {
      ready->insert(ready->end(), now.begin(), now.end());
    } else {
      std::sort(now.begin(), now.end());
      Release(now);
    }
  }

  struct Queued {
    int chain, batch, job;
  };
  const Schedule& s_;
  std::vector<char> free_;
  std::vector<std::vector<BatchState>> state_;
  std::vector<int> next_;
  std::vector<int> waiting_;
  std::deque<Queued> queue_;
  std::vector<Running> running_;
  double now_s_ = 0.0;
  ScheduleResult result_;
};

}  // namespace

ScheduleResult SimulateSchedule(const Schedule& schedule, int workers) {
  return Simulator(schedule, workers).Run();
}

std::vector<double> PredictedSpeedups(const Schedule& schedule, const std::vector<int>& cores) {
  const double one_s = SimulateSchedule(schedule, 1).makespan_s;
  std::vector<double> out;
  for (int n : cores) {
    const double n_s = SimulateSchedule(schedule, n).makespan_s;
    out.push_back(n_s > 0 ? one_s / n_s : 1.0);
  }
  return out;
}

std::string SpeedupLine(const Schedule& schedule) {
  const std::vector<int> cores = {2, 4, 8, 16};
  const std::vector<double> x = PredictedSpeedups(schedule, cores);
  std::string out;
  char buf[64];
  for (size_t i = 0; i < cores.size(); ++i) {
    std::snprintf(buf, sizeof(buf), "%s%d: %.2fx", i ? ", " : "", cores[i], x[i]);
    out += buf;
  }
  return out;
}

}  // namespace climbsim::optimise
