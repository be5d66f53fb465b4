// Counts every heap allocation of the test program: all global operator new forms and, on
// glibc without sanitizers, malloc/calloc/realloc (what Eigen and MuJoCo's C code call).
// Link the target climbsim_test_alloc_counter into a test executable to use it; the
// replacement applies to the whole program, so keep such tests in their own executable.
#ifndef CLIMBSIM_TESTS_COMMON_ALLOC_COUNTER_H_
#define CLIMBSIM_TESTS_COMMON_ALLOC_COUNTER_H_

namespace climbsim::testing {

struct AllocationCounts {
  long news = 0;     // operator new calls
  long mallocs = 0;  // malloc, calloc, realloc calls (0 when not countable)
  long total() const { return news + mallocs; }
};

AllocationCounts AllocationsSoFar();
// True when malloc itself is counted (glibc, no AddressSanitizer).
bool MallocIsCounted();

// Allocations made while `body` runs.
template <class Body>
AllocationCounts CountAllocations(Body&& body) {
  const AllocationCounts before = AllocationsSoFar();
  body();
  const AllocationCounts after = AllocationsSoFar();
  return {after.news - before.news, after.mallocs - before.mallocs};
}

}  // namespace climbsim::testing

#endif  // CLIMBSIM_TESTS_COMMON_ALLOC_COUNTER_H_
