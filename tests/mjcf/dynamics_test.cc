// The robots standing and holding on in plain MuJoCo: stable standing with ctrl = 0 under
// both integrators, statics of the contact forces, and servos strong enough to hold the
// robot on a wall, a ceiling and an incline with only the stance legs of the gait attached.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "mjcf_test_util.h"
#include "robots_under_test.h"

namespace climbsim::mjcf_test {
namespace {

std::string IntegratorName(int integrator) {
  return integrator == mjINT_EULER ? "Euler" : integrator == mjINT_IMPLICIT ? "implicit" : "RK4";
}

ModelPtr LoadOrFail(const std::string& robot, const std::string& scene, const std::string& extra) {
  std::string error;
  ModelPtr m = LoadComposed(robot, scene, extra, &error);
  EXPECT_NE(m, nullptr) << error;
  EXPECT_EQ(error, "");
  return m;
}

// Number of contacts between geom `a` and geom `b`, in either order.
int ContactsBetween(const mjData* d, int a, int b) {
  int n = 0;
  for (int c = 0; c < d->ncon; ++c) {
    const mjContact& con = d->contact[c];
    n += (con.geom1 == a && con.geom2 == b) || (con.geom1 == b && con.geom2 == a);
  }
  return n;
}

bool StateIsFinite(const mjModel* m, const mjData* d) {
  for (int i = 0; i < m->nq; ++i) {
    if (!std::isfinite(d->qpos[i])) return false;
  }
  for (int i = 0; i < m->nv; ++i) {
    if (!std::isfinite(d->qvel[i])) return false;
  }
  return true;
}

using RobotIntegrator = std::tuple<std::string, int>;
class MjcfStanding : public testing::TestWithParam<RobotIntegrator> {};

// The standing robot, all ctrl = 0, on the floor scene at 1 ms: 5 s with finite state, no
// MuJoCo warning, base height within 5 mm of its settled value (taken at 0.5 s: the 0.5 mm
// drop and the servo sag settle in < 0.2 s), no creep (< 1 mm horizontally), and at the
// end every pad in full contact (a box on a plane gives 4 contact points; the adhesion
// model needs >= 3) with its bottom within 1 mm of the plane z = 0.
TEST_P(MjcfStanding, StaysStillForFiveSecondsWithCtrlZero) {
  const auto& [robot, integrator] = GetParam();
  ModelPtr m = LoadOrFail(robot, "floor", "");
  ASSERT_NE(m, nullptr);
  m->opt.integrator = integrator;
  ASSERT_EQ(m->opt.timestep, 0.001);
  DataPtr d(mj_makeData(m.get()));
  const int base = mj_name2id(m.get(), mjOBJ_BODY, "base");
  const double x0 = d->qpos[0], y0 = d->qpos[1];

  double settled_z = 0, max_dev = 0, max_creep = 0;
  const int steps = 5000;
  for (int i = 1; i <= steps; ++i) {
    mj_step(m.get(), d.get());
    ASSERT_TRUE(StateIsFinite(m.get(), d.get())) << "t = " << d->time;
    const double z = d->xpos[3 * base + 2];
    if (i == 500) settled_z = z;
    if (i >= 500) {
      max_dev = std::max(max_dev, std::abs(z - settled_z));
      max_creep = std::max(max_creep, std::hypot(d->qpos[0] - x0, d->qpos[1] - y0));
    }
  }
  EXPECT_EQ(WarningCount(d.get()), 0);
  EXPECT_LE(max_dev, 0.005);
  EXPECT_LE(max_creep, 0.001);

  const int floor = mj_name2id(m.get(), mjOBJ_GEOM, "floor");
  for (const auto& leg : LegNames(m.get())) {
    const int pad = mj_name2id(m.get(), mjOBJ_GEOM, (leg + "_pad").c_str());
    EXPECT_GE(ContactsBetween(d.get(), pad, floor), 3) << leg;
    const double bottom = BoxLowestZ(m.get(), d.get(), pad);
    EXPECT_LE(std::abs(bottom), 0.001) << leg;
  }
}

INSTANTIATE_TEST_SUITE_P(RobotsAndIntegrators, MjcfStanding,
                         testing::Combine(testing::ValuesIn(StandingRobots()),
                                          testing::Values(int{mjINT_EULER}, int{mjINT_IMPLICIT})),
                         [](const testing::TestParamInfo<RobotIntegrator>& info) {
                           return std::get<0>(info.param) + "_" +
                                  IntegratorName(std::get<1>(info.param));
                         });

class MjcfStatics : public testing::TestWithParam<std::string> {};

// Statics: after 2 s of standing, the normal contact forces (mj_contactForce, contact
// frame) summed over all contacts with the floor carry the weight m g to within 1 %. The
// robot is then quasi-static: what still moves is the slow (time constant ~0.9 s)
// relaxation of internal forces through MuJoCo's soft friction, |qvel| < 1e-3, whose
// inertial forces are far below 1 % of the weight.
TEST_P(MjcfStatics, FloorNormalForcesCarryTheWeight) {
  ModelPtr m = LoadOrFail(GetParam(), "floor", "");
  ASSERT_NE(m, nullptr);
  DataPtr d(mj_makeData(m.get()));
  for (int i = 0; i < 2000; ++i) mj_step(m.get(), d.get());
  for (int i = 0; i < m->nv; ++i) ASSERT_LT(std::abs(d->qvel[i]), 1e-3) << "not at rest, dof " << i;

  const int floor = mj_name2id(m.get(), mjOBJ_GEOM, "floor");
  double normal_sum = 0;
  for (int c = 0; c < d->ncon; ++c) {
    const mjContact& con = d->contact[c];
    if (con.geom1 != floor && con.geom2 != floor) continue;
    mjtNum force[6];
    mj_contactForce(m.get(), d.get(), c, force);
    normal_sum += force[0];
  }
  const double weight = RobotMass(m.get()) * 9.81;
  EXPECT_NEAR(normal_sum, weight, 0.01 * weight);
}

INSTANTIATE_TEST_SUITE_P(Robots, MjcfStatics, testing::ValuesIn(StandingRobots()),
                         [](const testing::TestParamInfo<std::string>& info) {
                           return info.param;
                         });

class MjcfFriction : public testing::TestWithParam<std::string> {};

// Pad friction holds a standing robot (ctrl = 0, no adhesion) on the 30 deg incline:
// tan 30 deg = 0.577 is above the surface's own friction (0.5, which would let it slide at
// 0.66 m/s^2, 2 m in 2.5 s) and below the pads' 1.0. MuJoCo's soft friction still creeps;
// with the scenes' elliptic cones and impratio 10 the measured creep is 0.36 mm/s (gecko)
// and 0.32 mm/s (spider), so after the first 0.5 s the base slides less than 2 mm in 2.5 s.
TEST_P(MjcfFriction, StandsOnThirtyDegreeInclineByPadFriction) {
  ModelPtr m = LoadOrFail(GetParam(), "incline", "");
  ASSERT_NE(m, nullptr);
  DataPtr d(mj_makeData(m.get()));
  double x_settled = 0;
  for (int i = 1; i <= 3000; ++i) {
    mj_step(m.get(), d.get());
    if (i == 500) x_settled = d->qpos[0];
  }
  EXPECT_GT(d->qpos[0] - x_settled, -0.002);
  EXPECT_EQ(WarningCount(d.get()), 0);
}

GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(MjcfFriction);  // no design runs it
INSTANTIATE_TEST_SUITE_P(Robots, MjcfFriction, testing::ValuesIn(InclineRobots()),
                         [](const testing::TestParamInfo<std::string>& info) {
                           return info.param;
                         });

class MjcfHold : public testing::TestWithParam<HoldCase> {};

// Servo strength: with only the stance legs of the gait attached (gecko trot pair LF+RH,
// spider tripod L1+R2+L3; welds stand in for the adhesion) and the swing legs lifted by
// 0.4 rad of hip pitch, the robot hangs on the wall, the ceiling and the 30 deg incline.
// After 2 s no servo exceeds the share of its stall torque the README states ("torque
// margin": 2 for the gecko, 1.7 for the spider on the wall, whose free ankle yaw leaves the
// in-plane load to the hip-yaw servos), the
// body has moved less than 15 mm (servo sag and the pitch-back about the stance pads'
// passive ankles, README) and MuJoCo reports nothing.
TEST_P(MjcfHold, StanceLegsHoldTheRobotWithinTorqueMargin) {
  const HoldCase& c = GetParam();
  std::ostringstream welds;
  welds << "  <equality>\n";
  for (const auto& leg : c.stance) welds << "    <weld body1=\"" << leg << "_pad\"/>\n";
  welds << "  </equality>\n";
  ModelPtr m = LoadOrFail(c.robot, c.scene, welds.str());
  ASSERT_NE(m, nullptr);
  DataPtr d(mj_makeData(m.get()));
  for (const auto& leg : LegNames(m.get())) {
    if (std::find(c.stance.begin(), c.stance.end(), leg) != c.stance.end()) continue;
    const int a = mj_name2id(m.get(), mjOBJ_ACTUATOR, (leg + "_hip_pitch").c_str());
    ASSERT_GE(a, 0);
    d->ctrl[a] = 0.4;
  }
  const std::array<double, 3> p0 = {d->qpos[0], d->qpos[1], d->qpos[2]};
  for (int i = 0; i < 2000; ++i) {
    mj_step(m.get(), d.get());
    ASSERT_TRUE(StateIsFinite(m.get(), d.get()));
  }
  // Steady state: the servo torques after the swing legs and the body have settled.
  double max_ratio = 0;
  std::string worst;
  for (int a = 0; a < m->nu; ++a) {
    const double ratio = std::abs(d->actuator_force[a]) / m->actuator_forcerange[2 * a + 1];
    if (ratio > max_ratio) {
      max_ratio = ratio;
      worst = Name(m.get(), mjOBJ_ACTUATOR, a);
    }
  }
  const double moved = std::hypot(d->qpos[0] - p0[0], d->qpos[1] - p0[1], d->qpos[2] - p0[2]);
  // Body tilt: angle between the base z axis and the surface normal (world +z).
  const double tilt = std::acos(std::clamp(d->xmat[9 * 1 + 8], -1.0, 1.0));
  std::printf("%s on %s: max servo torque %.2f of stall (%s), body moved %.1f mm, tilt %.3f rad\n",
              c.robot.c_str(), c.scene.c_str(), max_ratio, worst.c_str(), 1e3 * moved, tilt);
  EXPECT_LE(max_ratio, c.max_torque_ratio) << worst;
  EXPECT_LT(moved, 0.015);
  EXPECT_EQ(WarningCount(d.get()), 0);
}

INSTANTIATE_TEST_SUITE_P(StanceSets, MjcfHold, testing::ValuesIn(HoldCases()),
                         [](const testing::TestParamInfo<HoldCase>& info) {
                           return info.param.robot + "_" + info.param.scene;
                         });

}  // namespace
}  // namespace climbsim::mjcf_test
