#include "optimise/comm.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <memory>
#include <thread>

#ifdef CLIMBSIM_MPI
#include <mpi.h>
#endif

namespace climbsim::optimise {

int DefaultThreads() {
  int local = 1;
  for (const char* v : {"OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS"}) {
    if (const char* s = std::getenv(v)) local = std::max(1, std::atoi(s));
  }
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()) / local);
}

#ifdef CLIMBSIM_MPI
bool BuiltWithMpi() { return true; }

namespace {

bool LaunchedByMpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE"}) {
    if (std::getenv(v) != nullptr) return true;
  }
  return false;
}

void Finalize() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) MPI_Finalize();
}

}  // namespace

Comm& Comm::World() {
  static Comm* world = [] {
    Comm* c = new Comm;
    if (LaunchedByMpi()) {
      int initialized = 0;
      MPI_Initialized(&initialized);
      if (!initialized) {
        // Worker threads never call MPI: only the thread that serves or asks for rollouts does.
        int provided = 0;
        MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
        std::atexit(Finalize);
      }
      MPI_Comm_rank(MPI_COMM_WORLD, &c->rank_);
      MPI_Comm_size(MPI_COMM_WORLD, &c->size_);
    }
    return c;
  }();
  return *world;
}

namespace {

// Waits for a non-blocking collective without spinning: a rank that finished its share early
// sleeps instead of taking a core from the ranks still computing (on shared or oversubscribed
// cores that matters; rollouts take seconds, so 1 ms of latency costs nothing).
void WaitQuietly(MPI_Request* request) {
  int done = 0;
  MPI_Test(request, &done, MPI_STATUS_IGNORE);
  while (!done) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    MPI_Test(request, &done, MPI_STATUS_IGNORE);
  }
}

}  // namespace

struct Comm::Pending {
  std::string buffer;
  MPI_Request request;
};

void Comm::Send(int to, int tag, std::string payload) {
  auto* p = new Pending{std::move(payload), MPI_REQUEST_NULL};
  MPI_Isend(p->buffer.data(), static_cast<int>(p->buffer.size()), MPI_CHAR, to, tag, MPI_COMM_WORLD,
            &p->request);
  sends_.push_back(p);
}

bool Comm::Poll(int* from, int* tag, std::string* payload) {
  // Delivered sends free their buffers.
  std::erase_if(sends_, [](Pending* p) {
    int done = 0;
    MPI_Test(&p->request, &done, MPI_STATUS_IGNORE);
    if (done) delete p;
    return done != 0;
  });
  int flag = 0;
  MPI_Status status;
  MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
  if (!flag) return false;
  int n = 0;
  MPI_Get_count(&status, MPI_CHAR, &n);
  payload->assign(static_cast<size_t>(n), '\0');
  MPI_Recv(payload->data(), n, MPI_CHAR, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD,
           MPI_STATUS_IGNORE);
  *from = status.MPI_SOURCE;
  *tag = status.MPI_TAG;
  return true;
}

void Comm::Drain() {
  for (Pending* p : sends_) {
    WaitQuietly(&p->request);
    delete p;
  }
  sends_.clear();
}

std::vector<std::string> Comm::AllGather(const std::string& mine) const {
  if (size_ == 1) return {mine};
  const int n = static_cast<int>(mine.size());
  std::vector<int> counts(size_), offsets(size_);
  MPI_Request request;
  MPI_Iallgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD, &request);
  WaitQuietly(&request);
  int total = 0;
  for (int r = 0; r < size_; ++r) {
    offsets[r] = total;
    total += counts[r];
  }
  std::string all(static_cast<size_t>(total), '\0');
  MPI_Iallgatherv(mine.data(), n, MPI_CHAR, all.data(), counts.data(), offsets.data(), MPI_CHAR,
                  MPI_COMM_WORLD, &request);
  WaitQuietly(&request);
  std::vector<std::string> out(size_);
  for (int r = 0; r < size_; ++r) out[r] = all.substr(offsets[r], counts[r]);
  return out;
}

#else  // one process

bool BuiltWithMpi() { return false; }

Comm& Comm::World() {
  static Comm world;
  return world;
}

std::vector<std::string> Comm::AllGather(const std::string& mine) const { return {mine}; }

struct Comm::Pending {};
void Comm::Send(int, int, std::string) {}
bool Comm::Poll(int*, int*, std::string*) { return false; }
void Comm::Drain() {}

#endif

}  // namespace climbsim::optimise
