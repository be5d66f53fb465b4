// The step loop allocates nothing once started: every operator new and malloc of the
// program is counted (tests/common/alloc_counter) while a scenario with effects steps.
#include <gtest/gtest.h>

#include "sim/sim.h"
#include "tests/common/alloc_counter.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

// Builds the scenario's simulation, takes a first step (which may size lazily-sized buffers),
// then steps `steps` times counting every allocation; each step must succeed.
void ExpectStepsAllocateNothing(const Scenario& s, int steps) {
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  ASSERT_TRUE(sim.Step());
  bool ok = true;
  const auto counts = climbsim::testing::CountAllocations([&] {
    for (int i = 0; i < steps; ++i) ok &= sim.Step();
  });
  EXPECT_TRUE(ok);
  EXPECT_EQ(counts.news, 0);
  EXPECT_EQ(counts.mallocs, 0);
}

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
  ExpectStepsAllocateNothing(s, 1500);
}

// The climbing example with every reflex on (spindle, GTO with its utilisation channels and
// load sharing across the legs, stance compliance setting the servos' kp), the adhesion
// effect's utilisation and the trajectory's utilisation columns: still nothing allocated per
// step.
TEST(SimulationAllocation, ClimbingReflexesAllocateNothing) {
  std::string text =
      climbsim::testing::ReadFile(climbsim::testing::Source("examples/gecko_wall.yaml"));
  text.replace(text.find("reflex:\n"), 8, "reflex:\n  compliance: {enabled: true}\n");
  text.replace(text.find("  gto:\n"), 8, "  gto:\n    share: {gain_per_s: 30, threshold: 0.2}\n");
  const Scenario s = LoadScenario(climbsim::testing::WriteFile("alloc_climb.yaml", text));
  ASSERT_TRUE(s.reflex.has_value());
  ASSERT_TRUE(s.reflex->spindle.enabled && s.reflex->gto.enabled && s.reflex->compliance.enabled);
  ASSERT_GT(s.reflex->gto.share.gain_per_s, 0.0);
  ASSERT_TRUE(s.reflex->gto.posture.enabled);
  ExpectStepsAllocateNothing(s, 2000);  // a peel, a swing and a landing
}

// The directional gait (examples/gecko_wall_directional.yaml): force tracking of each pad's
// gripping shear, the landing's settle and drag, and the release's contact delay, over two
// seconds (releases and landings of two legs): nothing allocated per step.
TEST(SimulationAllocation, DirectionalGaitAllocatesNothing) {
  const Scenario s = LoadScenario(
      climbsim::testing::Source("examples/gecko_wall_directional.yaml"));
  ASSERT_TRUE(s.reflex.has_value());
  ASSERT_EQ(s.reflex->gto.share.mode, climbsim::reflex::SharingMode::kForceTracking);
  ASSERT_GT(s.reflex->landing.settle_s, 0.0);
  ExpectStepsAllocateNothing(s, 2000);
}

// Under the ceiling the pads grip in different directions: the targets' vector sum and the
// least grasp run on every tick (2 s: the first release and landing).
TEST(SimulationAllocation, DirectionalCeilingGaitAllocatesNothing) {
  const Scenario s = LoadScenario(
      climbsim::testing::Source("examples/gecko_ceiling_directional.yaml"));
  ASSERT_TRUE(s.reflex.has_value());
  ASSERT_EQ(s.reflex->gto.share.mode, climbsim::reflex::SharingMode::kForceTracking);
  ASSERT_GT(s.reflex->gto.share.min_grip_n, 0.0);
  ExpectStepsAllocateNothing(s, 2000);
}

}  // namespace
}  // namespace climbsim::sim
