// The step loop allocates nothing once started: every operator new and malloc of the
// program is counted (tests/common/alloc_counter) while a scenario with effects steps.
#include <gtest/gtest.h>

#include "sim/sim.h"
#include "tests/common/alloc_counter.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

TEST(SimulationAllocation, CounterIsLive) {
  const auto counts = climbsim::testing::CountAllocations([] {
    auto* v = new std::vector<double>(16);
    // Through a volatile pointer the allocation cannot be elided.
    std::vector<double>* volatile keep = v;
    delete keep;
  });
  EXPECT_GE(counts.news, 1);
}

TEST(SimulationAllocation, StepLoopAllocatesNothing) {
  const Scenario s = LoadScenario(climbsim::testing::WriteFile("alloc.yaml",
                          "robot: spider\nscene: floor\nduration_s: 2\n"
                          "cpg:\n  gait: tripod\n  stepper: dopri5\n"
                          "outputs:\n  trajectory_rate_hz: 200\n"));
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  ASSERT_TRUE(sim.Step());  // the first call may size lazily-sized buffers
  bool ok = true;
  const auto counts = climbsim::testing::CountAllocations([&] {
    for (int i = 0; i < 1500; ++i) ok &= sim.Step();
  });
  EXPECT_TRUE(ok);
  EXPECT_EQ(counts.news, 0);
  EXPECT_EQ(counts.mallocs, 0);
}

}  // namespace
}  // namespace climbsim::sim
