// Step never allocates: every global operator new (and, on glibc without sanitizers, every
// malloc, which is what Eigen and C code call) is counted (tests/common/alloc_counter) while
// the networks step. Its own executable: the counting replaces them for the whole program.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "cpg/cpg.h"
#include "tests/cpg/test_util.h"
#include "tests/common/alloc_counter.h"

namespace climbsim::cpg {
namespace {

void* volatile g_sink = nullptr;  // a stored allocation cannot be elided
using climbsim::testing::AllocationCounts;
using Counts = AllocationCounts;

template <class Body>
Counts Count(Body body) {
  return climbsim::testing::CountAllocations(body);
}

TEST(CpgAllocation, CounterSeesAllocations) {
  // The hooks are live: a vector's buffer is one operator new and (glibc) one malloc.
  const Counts counts = Count([] {
    auto* v = new std::vector<double>(16);
    g_sink = v;  // volatile: the allocation cannot be elided
    delete v;
  });
  EXPECT_GE(counts.news, 1);
  if (climbsim::testing::MallocIsCounted()) {
    EXPECT_GE(counts.mallocs, 1);
  }
}

TEST(CpgAllocation, StepNeverAllocatesForAnyStepperOrNetwork) {
  for (bool hopf : {false, true}) {
    for (int legs : {4, 6}) {
      for (Stepper stepper : {Stepper::kEuler, Stepper::kRk4, Stepper::kDopri5}) {
        const std::string what = std::string(hopf ? "Hopf" : "Phase") + " legs " +
                                 std::to_string(legs) + " stepper " +
                                 std::to_string(static_cast<int>(stepper));
        std::unique_ptr<OscillatorNetwork> network = testing::MakeGaitNetwork(hopf, legs, stepper);
        std::vector<double> feedback(legs, 0.0);
        // "Better never": even the first Step, before any warm-up, allocates nothing.
        const Counts first = Count([&] { network->Step(1e-3, feedback); });
        EXPECT_EQ(first.news, 0) << what;
        EXPECT_EQ(first.mallocs, 0) << what;
        // 1000 Steps after that one, with feedback that changes every step (Dopri5 then
        // re-evaluates its derivative) and, every tenth step, none at all.
        const Counts steady = Count([&] {
          for (int k = 0; k < 1000; ++k) {
            for (int i = 0; i < legs; ++i) feedback[i] = 0.1 * ((k + i) % 7) - 0.3;
            if (k % 10 == 0) {
              network->Step(1e-3, {});
            } else {
              network->Step(1e-3, feedback);
            }
            // What the simulator reads after a step.
            for (int i = 0; i < legs; ++i) {
              const LegCommand c =
                  ShapeLeg(LegShape{}, network->phase_rad()[i], network->amplitude()[i]);
              feedback[i] += TegotaeFeedback(0.0, 1.0, c.progress);
            }
          }
        });
        EXPECT_EQ(steady.news, 0) << what;
        EXPECT_EQ(steady.mallocs, 0) << what;
        EXPECT_EQ(network->status(), StepStatus::kOk) << what;
        EXPECT_EQ(network->stats().steps, 1001) << what;
      }
    }
  }
}

}  // namespace
}  // namespace climbsim::cpg
