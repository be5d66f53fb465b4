// All pads letting go at once on a wall: the gecko hangs on its four start-attached pads
// (examples/gecko_wall_hold.yaml), every pad is released at t = 1 s, the robot falls, and the
// run goes on to its end without a warning or a non-finite number.
#include <gtest/gtest.h>

#include <cstdio>

#include "sim/adhesion_effect.h"
#include "sim/sim.h"
#include "tests/hard/hard_util.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::RootSpeedMps;
using climbsim::testing::Source;
using climbsim::testing::StateFinite;
using climbsim::testing::WarningsRaised;

TEST(HardLetGo, AllPadsReleasedAtOnceOnTheWallTheRobotFallsAndTheRunEndsCleanly) {
  Scenario s = LoadScenario(Source("examples/gecko_wall_hold.yaml"));
  s.duration_s = 3.0;  // 1 s hanging, 2 s falling
  s.fall.stop = false;  // simulate on through the fall (the default ends the run there)
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  AdhesionEffect* adhesion = FindAdhesion(sim.effects());
  ASSERT_NE(adhesion, nullptr);
  const mjModel* m = sim.world().model();
  const mjData* d = sim.world().data();
  const int root_dof = sim.world().robot().root_dof_adr;
  const double g = sim.world().gravity().norm();

  // Hanging: 1 s, every pad attached throughout.
  while (d->time < 1.0 - 1e-9) ASSERT_TRUE(sim.Step()) << sim.result().failure;
  for (int p = 0; p < adhesion->pad_count(); ++p) ASSERT_TRUE(adhesion->pad(p).attached()) << p;
  ASSERT_FALSE(sim.result().fell);
  const double release_s = d->time;
  const double speed_at_release = RootSpeedMps(d, root_dof);

  // All at once, between two steps (adhesion_effect.h: the release acts in the next mj_step).
  for (int p = 0; p < adhesion->pad_count(); ++p) ASSERT_TRUE(adhesion->RequestRelease(p)) << p;

  // Falling: no pad may hold again (nothing presses a pad onto a wall), the state stays
  // finite, and the base is never faster than a free fall from rest at the release: the
  // robot gains speed from gravity alone (the servos move the legs, not the centre of mass,
  // and the wall's friction only brakes). 0.1 m/s of slack covers the base moving against
  // its own legs' swing as they relax.
  bool finite = true;
  double worst_excess_mps = -1e9;
  while (sim.result().stable && sim.world().data()->time < s.duration_s - 1e-9) {
    if (!sim.Step()) break;
    finite = finite && StateFinite(m, d);
    const double free_fall_mps = speed_at_release + g * (d->time - release_s);
    worst_excess_mps = std::max(worst_excess_mps, RootSpeedMps(d, root_dof) - free_fall_mps);
  }
  const RunResult r = sim.Run();  // nothing left to step: totals and distance
  ASSERT_TRUE(r.stable) << r.failure;
  EXPECT_EQ(r.steps, 3000) << "the run goes on to its end after the fall";
  EXPECT_TRUE(finite);
  EXPECT_EQ(WarningsRaised(d), "");
  EXPECT_LT(worst_excess_mps, 0.1);
  for (int p = 0; p < adhesion->pad_count(); ++p) {
    EXPECT_FALSE(adhesion->pad(p).attached()) << p;
    EXPECT_EQ(adhesion->pad(p).counts().detach_released, 1) << p;
    EXPECT_EQ(adhesion->pad(p).counts().attach, 1) << p << ": only the start attachment";
  }
  const nlohmann::json summary = sim.Summary();
  EXPECT_EQ(summary["fell"], true);
  EXPECT_EQ(summary["stable"], true);
  // The fall (base 0.1 m below its highest point) comes within sqrt(2·0.1/g) = 0.14 s of free
  // fall; sliding along the wall can only slow it. 0.5 s is generous.
  EXPECT_GT(r.fall_time_s, release_s);
  EXPECT_LT(r.fall_time_s, release_s + 0.5);
  // Down the wall (gravity along −x, the travel direction +x): at least the free-fall drop
  // of the 2 s, less friction. 10 m is half of g·t²/2 = 19.6 m.
  EXPECT_LT(r.distance_at_end_m, -10.0);
  // distance_m is the distance up to the fall: the base dropped fall.drop_m (0.1 m) down
  // the wall, plus at most one step of a 1.4 m/s fall.
  EXPECT_LT(r.distance_m, -0.1 + 1e-3);
  EXPECT_GT(r.distance_m, -0.12);
  std::printf(
      "released at %.3f s, fell at %.3f s, %.2f m down the wall by %.1f s, worst "
      "speed over free fall %.4f m/s\n",
      release_s, r.fall_time_s, -r.distance_at_end_m, r.sim_time_s, worst_excess_mps);
}

}  // namespace
}  // namespace climbsim::sim
