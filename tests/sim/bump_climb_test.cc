// Bumps with partial contact: a pad set over a bump's edge bonds only where it touches, and a
// wall robot that kept such a landing fell (docs/climbing.md, "Bumps with partial contact").
// reflex.regrip.min_touched_share lets such a landing go and places the foot again. The case
// is `climbsim bench robustness examples/gecko_wall.yaml --families roughness`'s seed 2 at
// its first failing height before the re-place: LF landed touching 71 % of its face, the next
// legs lifted, and LF tore at 9.0 s.
#include <gtest/gtest.h>

#include <string>

#include "optimise/disturbance.h"
#include "sim/sim.h"
#include "tests/common/run_scenario.h"
#include "tests/common/survives_case.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::RunScenario;
using climbsim::testing::Source;
using climbsim::testing::SurvivesCase;

RunResult RunBumpCase(double min_touched_share, std::string* events) {
  Scenario base = LoadScenario(Source("examples/gecko_wall.yaml"));
  base.reflex->regrip.min_touched_share = min_touched_share;
  const optimise::DisturbanceSetup u = optimise::MakeDisturbanceSetup(base, {});
  return RunScenario(optimise::DisturbanceCase(u, "roughness", 0.000533, 0, 2, 0), events);
}

TEST(RoughClimb, GeckoReplacesAPartlyTouchingLandingAndClimbsWhereItFell) {
  ASSERT_GT(LoadScenario(Source("examples/gecko_wall.yaml")).reflex->regrip.min_touched_share,
            0.8);
  std::string events;
  const RunResult kept = RunBumpCase(0.0, &events);
  EXPECT_TRUE(kept.fell) << "the partly touching landing kept: LF tears";
  EXPECT_EQ(events.find("partial_contact"), std::string::npos);
  const RunResult replaced = RunBumpCase(0.9, &events);
  ASSERT_TRUE(replaced.stable) << replaced.failure;
  EXPECT_FALSE(replaced.fell) << "fell at " << replaced.fall_time_s;
  EXPECT_NE(events.find("regrip,partial_contact"), std::string::npos);
  // The undisturbed climb is 0.176 m in 10 s; the bench counts half of it as survived.
  EXPECT_GE(replaced.distance_m, 0.12);
}

// Foam in the pad's backing (robot.pads.foam_m) lets a face over a bump bond around it: the
// co-designed gecko's first failing case on bumps (the bench's seed case 2 at 1.48 mm, seeds
// 0-2: it fell at 7.66 s with rigid pads) is climbed with the example's 1.5 mm of foam.
TEST(RoughClimb, FoamedPadsClimbBumpsWhereRigidOnesFell) {
  Scenario foam = LoadScenario(Source("examples/gecko_designed.yaml"));
  ASSERT_TRUE(foam.robot_design.has_value());
  ASSERT_EQ(foam.robot_design->pads.foam_m, 0.0015);
  Scenario rigid = foam;
  rigid.robot_design->pads.foam_m = 0.0;
  std::string how;
  EXPECT_FALSE(SurvivesCase(rigid, "roughness", 0.0014835, 2, 0, &how)) << "rigid pads";
  EXPECT_TRUE(SurvivesCase(foam, "roughness", 0.0014835, 2, 0, &how)) << how;
}

}  // namespace
}  // namespace climbsim::sim
