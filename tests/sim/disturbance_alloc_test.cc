// The disturbances of `climbsim bench robustness` allocate nothing in the step loop: pad
// failures (StickyPad::Fail, events), weak patches (a hash per attach), bumps and a payload
// (model-level, set before the run), on the gecko climbing the wall.
#include <gtest/gtest.h>

#include <string_view>

#include "sim/sim.h"
#include "tests/common/alloc_counter.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

TEST(DisturbanceAllocation, StepLoopWithEveryDisturbanceAllocatesNothing) {
  const Scenario s = LoadScenario(climbsim::testing::WriteFile(
      "alloc_disturb.yaml",
      "robot: gecko\nduration_s: 3\npayload_kg: 0.02\nseed: 4\n"
      "scene:\n  name: wall\n  weak_patches: {fraction: 0.5, size_m: 0.02, coverage: 0.5}\n"
      "  roughness: {height_m: 0.002}\n"
      "outputs: {trajectory_rate_hz: 100}\n"
      "adhesion:\n  start_attached: true\n  initial_fraction: 0.9\n  buildup_time_s: 0.05\n"
      "  mu: 1.0\n  pad_failure_probability: 1\n  pad_failure_window_s: 0.05\n"
      "cpg:\n  gait: lateral_sequence\n  frequency_hz: 0.6\n  start_amplitude: 1\n"
      "  stride_m: 0.03\n  lift_m: 0.012\n  press_m: 0.002\n  lift_share: 0.25\n"
      "reflex: {spindle: {enabled: false}, gto: {enabled: false}}\n"
      "perturbations:\n  - {time_s: 1.0, impulse_ns: [0, 0, 0.01]}\n"
      "fall: {stop: false}\n"));  // every pad fails: the loop goes on past the fall
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  ASSERT_TRUE(sim.Step());
  bool ok = true;
  const auto counts = climbsim::testing::CountAllocations([&] {
    for (int i = 0; i < 2500; ++i) ok &= sim.Step();
  });
  EXPECT_TRUE(ok);
  EXPECT_EQ(counts.news, 0);
  EXPECT_EQ(counts.mallocs, 0);
  // The loop did meet the disturbances: at least one pad failed.
  int failures = 0;
  for (const Event& e : sim.events().rows()) {
    failures += std::string_view(e.kind) == "detach" && std::string_view(e.cause) == "failure";
  }
  EXPECT_GT(failures, 0);
}

}  // namespace
}  // namespace climbsim::sim
