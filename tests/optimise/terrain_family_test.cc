// The `terrain` family of `climbsim bench robustness`: a case sets scene.terrain.rms_m to the
// magnitude and draws rock seed k + 1 for seed case k; searched only when named; refused where
// the scenario sets terrain or bumps itself, or is not a plane scene.
#include <gtest/gtest.h>

#include <algorithm>

#include "experiments/experiments.h"
#include "optimise/disturbance.h"
#include "scenario/scenario.h"
#include "tests/common/test_util.h"

namespace climbsim::optimise {
namespace {

using climbsim::testing::Source;

TEST(TerrainFamily, CaseSetsRmsAndSeedNamedOnlyAndRefusals) {
  const sim::Scenario wall = sim::LoadScenario(Source("examples/gecko_wall.yaml"));
  const DisturbanceSetup u = MakeDisturbanceSetup(wall, RobustnessOptions{});
  EXPECT_EQ(CannotTakeFamily(u, "terrain"), "");
  for (int k : {0, 2}) {
    const sim::Scenario c = DisturbanceCase(u, "terrain", 0.0007, 0, k, 0);
    ASSERT_TRUE(c.scene.terrain.has_value());
    EXPECT_EQ(c.scene.terrain->rms_m, 0.0007);
    EXPECT_EQ(c.scene.terrain->seed, k + 1);
  }
  EXPECT_FALSE(DisturbanceCase(u, "terrain", 0.0, 0, 0, 0).scene.terrain.has_value());
  // Not in "all the scenario can take" (each rock run costs more): only when named.
  const auto all = RobustnessFamilies(wall);
  EXPECT_TRUE(std::none_of(all.begin(), all.end(), [](const auto& f) { return f.name == "terrain"; }));

  sim::Scenario rock = wall;
  rock.scene.terrain = sim::TerrainParams{};
  EXPECT_EQ(CannotTakeFamily(MakeDisturbanceSetup(rock, RobustnessOptions{}), "terrain"),
            "it sets scene.terrain itself (the search replaces it: remove it)");
  EXPECT_EQ(CannotTakeFamily(MakeDisturbanceSetup(rock, RobustnessOptions{}), "roughness"),
            "it sets scene.roughness or scene.terrain (bumps and rock do not combine)");
  sim::Scenario bumps = wall;
  bumps.scene.roughness = sim::RoughnessParams{};
  EXPECT_EQ(CannotTakeFamily(MakeDisturbanceSetup(bumps, RobustnessOptions{}), "terrain"),
            "it sets scene.roughness or scene.terrain (bumps and rock do not combine)");
  const sim::Scenario corner = sim::LoadScenario(Source("examples/gecko_floor_to_wall.yaml"));
  EXPECT_EQ(CannotTakeFamily(MakeDisturbanceSetup(corner, RobustnessOptions{}), "terrain"),
            "its scene 'floor_to_wall' is not a plane (floor, wall, ceiling, incline)");
}

}  // namespace
}  // namespace climbsim::optimise
