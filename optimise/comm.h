// Internal to optimise/: the processes of an MPI run (mpirun -np N climbsim ...). Rank 0 runs
// the optimisation and hands rollouts to the other ranks as they ask for work (Send, Poll);
// a collective (AllGather) shares what every rank must know. Built without CLIMBSIM_MPI, or
// started without mpirun, it is one process of one rank and does nothing. Only the thread
// that called World() first may call Send, Poll, Drain and AllGather.
#ifndef CLIMBSIM_OPTIMISE_COMM_H_
#define CLIMBSIM_OPTIMISE_COMM_H_

#include <string>
#include <vector>

namespace climbsim::optimise {

// Threads per process by default: this machine's cores shared by the ranks it runs.
int DefaultThreads();

class Comm {
 public:
  // The processes of this run. Initialises MPI on first use when the process was started
  // by an MPI launcher (it looks for OMPI_COMM_WORLD_SIZE, PMIX_RANK or PMI_SIZE), and
  // finalises it at exit.
  static Comm& World();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }

  // Each rank's `mine`, in rank order, on every rank. A rank that arrives first sleeps
  // (1 ms polls) rather than spinning on a core.
  std::vector<std::string> AllGather(const std::string& mine) const;

  // Point to point, never blocking: Send queues `payload` for rank `to` with `tag` (the
  // buffer is kept until MPI has delivered it); Poll returns one message that has arrived,
  // from any rank with any tag, or false when none has (it also moves queued sends on);
  // Drain waits, in 1 ms polls, until every queued send has been delivered.
  void Send(int to, int tag, std::string payload);
  bool Poll(int* from, int* tag, std::string* payload);
  void Drain();

 private:
  struct Pending;
  Comm() = default;
  std::vector<Pending*> sends_;
  int rank_ = 0;
  int size_ = 1;
};

}  // namespace climbsim::optimise

#endif  // CLIMBSIM_OPTIMISE_COMM_H_
