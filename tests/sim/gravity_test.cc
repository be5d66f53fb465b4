// scene.gravity / scene.gravity_m_s2: another body's surface gravity, along the scene's own
// direction. Earth's changes nothing; a magnitude is what the robot falls with.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/sim.h"
#include "tests/common/scenario_error.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::ScenarioErrorOf;
using climbsim::testing::Source;
using climbsim::testing::WriteFile;

Eigen::Vector3d GravityOf(const std::string& text) {
  const Scenario s = LoadScenario(WriteFile("gravity.yaml", text));
  const auto model = CompileScenario(s);
  Simulation run(s, *model);
  const mjModel* m = run.world().model();
  const Eigen::Vector3d g(m->opt.gravity[0], m->opt.gravity[1], m->opt.gravity[2]);
  EXPECT_EQ(g, run.world().gravity());  // what steps is what the run reports
  return g;
}

TEST(Gravity, BodiesScaleTheSceneGravityAlongItsDirection) {
  const Eigen::Vector3d moon = GravityOf("robot: gecko\nscene: {name: floor, gravity: moon}\n"
                                         "duration_s: 0.01\n");
  EXPECT_NEAR(moon.z(), -1.62, 1e-12);
  EXPECT_NEAR(moon.head<2>().norm(), 0.0, 1e-12);
  // The incline keeps its tilt: 30 deg by default, downhill along -x.
  const Eigen::Vector3d mars = GravityOf(
      "robot: gecko\nscene: {name: incline, gravity: mars}\nduration_s: 0.01\n");
  EXPECT_NEAR(mars.norm(), 3.72, 1e-12);
  EXPECT_NEAR(mars.x(), -3.72 * std::sin(M_PI / 6), 1e-12);
  EXPECT_NEAR(mars.z(), -3.72 * std::cos(M_PI / 6), 1e-12);
  const Eigen::Vector3d given = GravityOf(
      "robot: gecko\nscene: {name: wall, gravity_m_s2: 0.5}\nduration_s: 0.01\n");
  const Eigen::Vector3d earth_wall =
      GravityOf("robot: gecko\nscene: wall\nduration_s: 0.01\n");
  EXPECT_NEAR((given - 0.5 * earth_wall.normalized()).norm(), 0.0, 1e-12);
}

TEST(Gravity, EarthIsTheScenesOwnBitForBit) {
  const auto run = [](const std::string& scene) {
    const std::string text = "robot: gecko\nscene: " + scene +
                             "\nduration_s: 0.3\ncpg: {}\nadhesion: {}\n";
    const Scenario s = LoadScenario(WriteFile("earth.yaml", text));
    const auto model = CompileScenario(s);
    Simulation sim(s, *model);
    sim.Run();
    const mjData* d = sim.world().data();
    return std::vector<double>(d->qpos, d->qpos + sim.world().model()->nq);
  };
  EXPECT_EQ(run("wall"), run("{name: wall, gravity: earth}"));
}

// Before the feet touch, the robot's centre of mass falls with the key's gravity, whatever
// its servos do (internal forces do not move the centre of mass).
TEST(Gravity, TheCentreOfMassFallsWithTheGivenGravity) {
  const Scenario s = LoadScenario(
      WriteFile("drop.yaml", "robot: gecko\nscene: {name: floor, gravity: moon}\n"
                             "duration_s: 0.05\ninitial: {offset_m: [0, 0, 0.05]}\n"));
  const auto model = CompileScenario(s);
  Simulation sim(s, *model);
  const mjModel* m = sim.world().model();
  const mjData* d = sim.world().data();
  const int root = mj_name2id(m, mjOBJ_BODY, "base");
  ASSERT_GE(root, 0);
  // Three samples n steps apart: for a constant acceleration, semi-implicit Euler (Euler and
  // implicit alike: gravity is constant) gives a second difference of exactly g (n h)^2,
  // whatever the velocity at the first sample.
  ASSERT_TRUE(sim.Step());  // subtree_com is computed from the first step on
  const int n = 10;
  double z[3];
  for (double& zi : z) {
    zi = d->subtree_com[3 * root + 2];
    for (int i = 0; i < n; ++i) ASSERT_TRUE(sim.Step());
  }
  ASSERT_EQ(d->ncon, 0);  // still in the air
  const double h = m->opt.timestep;
  const double expected = 1.62 * (n * h) * (n * h);
  EXPECT_NEAR(2 * z[1] - z[0] - z[2], expected, 1e-3 * expected);
}

TEST(Gravity, RefusesBothKeysAndUnknownBodies) {
  EXPECT_EQ(ScenarioErrorOf("both.yaml", "robot: gecko\nscene: {name: wall, gravity: moon, "
                                         "gravity_m_s2: 1.0}\nduration_s: 1\n"),
            "both.yaml:2:50: scene.gravity_m_s2: give gravity or gravity_m_s2, not both");
  const std::string pluto = ScenarioErrorOf(
      "pluto.yaml", "robot: gecko\nscene: {name: wall, gravity: pluto}\nduration_s: 1\n");
  EXPECT_NE(pluto.find("scene.gravity"), std::string::npos) << pluto;
  EXPECT_NE(pluto.find("earth, mars, moon, ceres, eros"), std::string::npos) << pluto;
  const std::string zero = ScenarioErrorOf(
      "zero.yaml", "robot: gecko\nscene: {name: wall, gravity_m_s2: 0}\nduration_s: 1\n");
  EXPECT_NE(zero.find("scene.gravity_m_s2: must be in [0.0001, 20]"), std::string::npos) << zero;
}

// The examples of both robots in other worlds, 8 s of each: they climb or walk and stay on.
RunResult RunFor(Scenario s, double duration_s) {
  s.duration_s = duration_s;
  s.outputs.trajectory_rate_hz = 0.0;
  const auto model = CompileScenario(s);
  Simulation sim(s, *model);
  return sim.Run();
}

TEST(Gravity, BothRobotsClimbTheMoonsWallAndWalkErossFloor) {
  Scenario gecko_moon = LoadScenario(Source("examples/gecko_moon_wall.yaml"));
  Scenario spider_eros = LoadScenario(Source("examples/spider_eros_floor.yaml"));
  Scenario spider_moon = LoadScenario(Source("examples/spider_wall.yaml"));
  spider_moon.scene.gravity = "moon";
  Scenario gecko_eros = LoadScenario(Source("examples/gecko_wall.yaml"));
  gecko_eros.scene.name = "floor";
  gecko_eros.scene.gravity = "eros";
  for (const Scenario* s : {&gecko_moon, &spider_moon, &gecko_eros, &spider_eros}) {
    const RunResult r = RunFor(*s, 8.0);
    EXPECT_TRUE(r.stable) << s->robot << " " << *s->scene.gravity << ": " << r.failure;
    EXPECT_FALSE(r.fell) << s->robot << " " << *s->scene.gravity << ": " << r.fall_cause;
    EXPECT_GT(r.distance_m, 0.08) << s->robot << " " << *s->scene.gravity;
  }
}

// A gecko trotting without adhesive pads: on Earth's floor it walks; on Eros's its feet push
// it off the ground, and the run ends when nothing of it has touched the floor for
// fall.airborne_s (it drifts upward: no drop would ever say so).
TEST(Gravity, ARobotPushedOffASmallBodyHasLeftTheSurface) {
  Scenario s = LoadScenario(Source("examples/gecko_floor.yaml"));
  const RunResult earth = RunFor(s, 4.0);
  EXPECT_FALSE(earth.fell) << earth.fall_cause;
  s.scene.gravity = "eros";
  const RunResult eros = RunFor(s, 4.0);
  ASSERT_TRUE(eros.fell);
  EXPECT_STREQ(eros.fall_cause, "left_surface");
  EXPECT_GT(eros.fall_time_s, s.fall.airborne_s);
}

}  // namespace
}  // namespace climbsim::sim
