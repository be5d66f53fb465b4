// The MPI side of the evaluator: rank 0 serves the queue's rollouts to the other ranks
// (Evaluator::ServeRanks), which compute them on their threads (WorkForRankZero).
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <limits>
#include <mutex>
#include <thread>

#include "common/common.h"
#include "optimise/checkpoint.h"
#include "optimise/evaluator.h"

namespace climbsim::optimise::internal {
namespace {

// A task as a rank other than 0 holds it: what rank 0 sent.
struct RemoteTask {
  long id;
  std::vector<double> x;
  int run;
  double bound;
};

// A rank other than 0: one thread talks to rank 0, the others compute the tasks it got.
class RankWorker {
 public:
  RankWorker(const Problem& problem, int threads, Comm& comm)
      : problem_(problem), threads_(threads), comm_(comm) {}

  // Task 0 talks to rank 0, tasks 1.. are the workers: one thread each, all at once. The
  // workers end once task 0 closes the queue, whether it ends or throws.
  void Run() {
    common::ParallelFor(threads_ + 1, threads_ + 1, [&](int task) {
      if (task > 0) return Worker();
      try {
        Talk();
      } catch (...) {
        Close();
        throw;
      }
      Close();
    });
    comm_.Drain();
  }

 private:
  void Worker() {
    ModelCache cache;
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      cv_.wait(lock, [&] { return closing_ || !queue_.empty(); });
      if (queue_.empty()) return;
      const RemoteTask t = queue_.front();
      queue_.pop_front();
      lock.unlock();
      const Cost c = Rollout(problem_, t.x, t.run, t.bound, cache);
      lock.lock();
      costs_.push_back({t.id, CostToJson(c)});
      --busy_;
    }
  }

  // Asks rank 0 for tasks while workers are idle, sends costs back, until told to stop.
  void Talk() {
    bool asked = false, stopped = false;
    for (;;) {
      std::string done;
      int idle = 0;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!costs_.empty()) {
          done = costs_.dump();
          costs_ = nlohmann::json::array();
        }
        idle = threads_ - busy_;
      }
      if (!done.empty()) comm_.Send(0, kCostsTag, done);
      if (stopped && idle == threads_ && done.empty()) break;
      if (!stopped && !asked && idle > 0) {
        comm_.Send(0, kAskTag, std::to_string(idle));
        asked = true;
      }
      const bool got = Receive(&asked, &stopped);
      if (!got && done.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }

  // Takes rank 0's messages: tasks (queued for the workers) or stop. Returns whether any came.
  bool Receive(bool* asked, bool* stopped) {
    int from = 0, tag = 0;
    std::string payload;
    bool got = false;
    while (comm_.Poll(&from, &tag, &payload)) {
      got = true;
      if (tag == kStopTag) {
        *stopped = true;
      } else if (tag == kTasksTag) {
        *asked = false;
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& t : nlohmann::json::parse(payload)) {
          queue_.push_back(
              {t[0].get<long>(), t[1].get<std::vector<double>>(), t[2].get<int>(),
               t[3].is_null() ? std::numeric_limits<double>::infinity() : t[3].get<double>()});
          ++busy_;
        }
        cv_.notify_all();
      }
    }
    return got;
  }

  void Close() {
    std::lock_guard<std::mutex> lock(mutex_);
    closing_ = true;
    cv_.notify_all();
  }

  const Problem& problem_;
  const int threads_;
  Comm& comm_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<RemoteTask> queue_;
  nlohmann::json costs_ = nlohmann::json::array();
  int busy_ = 0;  // tasks received and not yet computed
  bool closing_ = false;
};

}  // namespace

void Evaluator::ServeRanks() {
  std::vector<int> wants(comm_.size(), 0);
  std::vector<char> stopped(comm_.size(), 0);
  stopped[0] = 1;
  std::map<long, Task> away;  // tasks on other ranks, by id
  long next_id = 0;
  int from = 0, tag = 0;
  std::string payload;
  for (;;) {
    bool busy = false;
    while (comm_.Poll(&from, &tag, &payload)) {
      busy = true;
      if (tag == kAskTag) {
        wants[from] = std::stoi(payload);
      } else if (tag == kCostsTag) {
        std::lock_guard<std::mutex> lock(mutex_);
        for (const auto& entry : nlohmann::json::parse(payload)) {
          const auto it = away.find(entry[0].get<long>());
          const Task t = it->second;
          away.erase(it);
          Deliver(t, CostFromJson(entry[1]));
        }
      }
    }
    bool finished = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      busy = SendTasks(&wants, &away, &next_id) || busy;
      finished = active_ == 0;
    }
    // Every start has finished: each rank that asks again gets a stop.
    if (finished) {
      int running = 0;
      for (int r = 1; r < comm_.size(); ++r) {
        if (!stopped[r] && wants[r] > 0) {
          comm_.Send(r, kStopTag, "");
          stopped[r] = 1;
        }
        running += !stopped[r];
      }
      if (running == 0) break;
    }
    if (!busy) {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait_for(lock, std::chrono::milliseconds(1));
    }
  }
  comm_.Drain();
}

bool Evaluator::SendTasks(std::vector<int>* wants, std::map<long, Task>* away, long* next_id) {
  bool sent = false;
  for (int r = 1; r < comm_.size(); ++r) {
    int& want = (*wants)[r];
    if (want == 0 || queue_.empty()) continue;
    nlohmann::json tasks = nlohmann::json::array();
    for (; want > 0 && !queue_.empty(); --want) {
      const Task t = queue_.front();
      queue_.pop_front();
      (*away)[*next_id] = t;
      // JSON has no infinity: no bound travels as null.
      nlohmann::json bound = nullptr;
      if (std::isfinite(t.bound)) bound = t.bound;
      tasks.push_back({(*next_id)++, t.batch->xs[t.k], t.run, bound});
    }
    want = 0;
    comm_.Send(r, kTasksTag, tasks.dump());
    sent = true;
  }
  return sent;
}

void WorkForRankZero(const Problem& problem, int threads, Comm& comm) {
  RankWorker(problem, threads, comm).Run();
}

}  // namespace climbsim::optimise::internal
