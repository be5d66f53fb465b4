// `bench speed --versus` (experiments/bench_speed.h) on the step loop: both sides are real runs
// of their own settings; the same settings give the same run bit for bit. Apart from
// simulation_test.cc, so that the step loop's tests link the sim module alone (the sanitized
// tree, tests/sanitize/run_asan.sh, builds no more than they need).
#include <gtest/gtest.h>

#include "experiments/bench_speed.h"
#include "sim/sim.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

// Both sides run interleaved; the same settings on both sides give the same run bit for bit
// (only the clock differs).
TEST(BenchSpeedCompare, RunsBothSettingsAndTheSameSettingsGiveTheSameRun) {
  Scenario a = LoadScenario(climbsim::testing::Source("examples/gecko_floor.yaml"));
  Scenario b = a;
  b.physics.integrator = "implicit";
  b.physics.cone = "elliptic";
  const SpeedComparison c = BenchSpeedCompare(a, b, 0.2, 2);
  ASSERT_EQ(c.a.steps_per_s.size(), 2u);
  ASSERT_EQ(c.b.steps_per_s.size(), 2u);
  EXPECT_EQ(c.a.steps, 200);
  EXPECT_EQ(c.b.steps, 200);
  EXPECT_GT(c.a.median_steps_per_s, 0.0);
  EXPECT_DOUBLE_EQ(c.ratio, c.a.median_steps_per_s / c.b.median_steps_per_s);
  // Different physics, different runs (cone and integrator both change the trot).
  EXPECT_NE(c.a.distance_m, c.b.distance_m);
  const SpeedComparison same = BenchSpeedCompare(a, a, 0.2, 1);
  EXPECT_EQ(same.a.distance_m, same.b.distance_m);
  EXPECT_EQ(same.a.distance_m, c.a.distance_m);
}

// The profile takes the clock's own lap off each part once per call: mj_step once a step,
// every effect at most twice (BeforeStep, AfterStep), and no part below 0.
TEST(BenchSpeed, ProfileTakesTheClocksOwnLapOffEachPart) {
  const Scenario s = LoadScenario(climbsim::testing::Source("examples/gecko_wall.yaml"));
  const SpeedReport r = BenchSpeed(s, 0.2, 1);
  ASSERT_EQ(r.profiled_steps, 200);
  // Two clock reads and a sum: more than nothing, far less than a microsecond.
  EXPECT_GT(r.clock_lap_s, 0.0);
  EXPECT_LT(r.clock_lap_s, 1e-6);
  const double one_lap_a_step = r.profiled_steps * r.clock_lap_s;
  EXPECT_NEAR(r.mj_step_with_clock_s - r.mj_step_s, one_lap_a_step, 1e-12);
  ASSERT_GE(r.effect_s.size(), 3u);  // adhesion, the controller, the trajectory
  double effects = 0.0;
  for (const auto& e : r.effect_s) {
    EXPECT_GE(e.second, 0.0) << e.first;
    effects += e.second;
  }
  EXPECT_LT(effects, r.effects_with_clock_s - one_lap_a_step + 1e-12);
  EXPECT_GE(effects,
            r.effects_with_clock_s - 2.0 * r.effect_s.size() * one_lap_a_step - 1e-12);
  EXPECT_GE(r.monitor_s, 0.0);
}

}  // namespace
}  // namespace climbsim::sim
