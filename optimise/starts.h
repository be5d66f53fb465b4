// Inside `climbsim optimise` (not a public header): the starts' drivers.
#ifndef CLIMBSIM_OPTIMISE_STARTS_H_
#define CLIMBSIM_OPTIMISE_STARTS_H_

#include <exception>
#include <string>
#include <vector>

#include "optimise/comm.h"
#include "optimise/evaluator.h"
#include "optimise/optimise.h"

namespace climbsim::optimise::internal {

// Rank 0: tasks 0..starts-1 drive the starts (each catches its own error into `errors`, so
// every one starts), the last serves their rollouts; one thread each, all at once. Returns
// what stopped the run (a checkpoint not written), null when nothing did.
std::exception_ptr DriveStarts(const Problem& problem, const std::vector<int>& budget,
                               Shared& shared, int threads, Comm& comm,
                               std::vector<std::string>* errors);

}  // namespace climbsim::optimise::internal

#endif  // CLIMBSIM_OPTIMISE_STARTS_H_
