// The spine (robot.body.spine) driven by the CPG (cpg.spine): on the floor its servo follows
// the commanded sine; a spine held straight (amplitude 0) walks as the rigid body does; and
// cpg.spine on a rigid robot is refused at its line.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/sim.h"
#include "tests/common/scenario_error.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::WriteFile;

// gecko_floor.yaml's gait on a robot `robot`, with `spine` appended to the cpg block.
std::string Floor(const std::string& robot, const std::string& spine, double duration_s) {
  return "robot: " + robot + "\nscene: floor\nduration_s: " + std::to_string(duration_s) +
         "\ncpg:\n  gait: trot\n  frequency_hz: 1.0\n  stride_rad: [0.35, 0.0, 0.0]\n"
         "  lift_rad: [0.0, 0.4, 0.3]\n" +
         spine;
}

// The hs35hd's lag behind a 0.3 rad, 1 Hz sine (1.9 rad/s at its peak): 0.044 rad measured.
constexpr double kSpineTolRad = 0.06;
// A straight spine against the rigid body in 10 s on the floor: 0.6831 and 0.6829 m measured
// (0.03 %); the hinge is as stiff as the servo's kp, so the bound is 2 %.
constexpr double kDistanceShare = 0.02;

const char* kSpined = "{preset: gecko, body: {spine: {joint_x_m: 0.0}}}";

RunResult RunText(const std::string& name, const std::string& text) {
  const Scenario s = LoadScenario(WriteFile(name, text));
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  return sim.Run();
}

TEST(Spine, ServoFollowsTheCommandedSine) {
  const double amplitude_rad = 0.3;
  const Scenario s = LoadScenario(WriteFile(
      "spine_sine.yaml", Floor(kSpined, "  spine: {amplitude_rad: 0.3, phase_rad: 0.5}\n", 4)));
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  const RobotInfo& robot = sim.world().robot();
  ASSERT_GE(robot.spine_actuator, 0);
  double max_ctrl = 0, max_q = 0, max_error = 0;
  while (sim.world().data()->time < 4.0 && sim.Step()) {
    const mjData* d = sim.world().data();
    if (d->time < 1.0) continue;  // one stride to settle
    const double ctrl = d->ctrl[robot.spine_actuator], q = d->qpos[robot.spine_qpos_adr];
    max_ctrl = std::max(max_ctrl, std::abs(ctrl));
    max_q = std::max(max_q, std::abs(q));
    max_error = std::max(max_error, std::abs(q - ctrl));
  }
  // The command reaches its amplitude (sampled every step at 1 Hz: within 0.1 %).
  EXPECT_NEAR(max_ctrl, amplitude_rad, 1e-3 * amplitude_rad);
  // The servo follows within kSpineTolRad of the command.
  EXPECT_LE(max_error, kSpineTolRad);
  EXPECT_GE(max_q, amplitude_rad - kSpineTolRad);
}

// A spine held straight by its servo (amplitude 0, or no cpg.spine) walks as the rigid body
// does: the same robot but for a hinge between the halves stiffened by the servo's kp.
TEST(Spine, HeldStraightWalksAsTheRigidBody) {
  const RunResult rigid = RunText("spine_rigid.yaml", Floor("gecko", "", 10));
  const RunResult zero =
      RunText("spine_zero.yaml", Floor(kSpined, "  spine: {amplitude_rad: 0.0}\n", 10));
  const RunResult undriven = RunText("spine_undriven.yaml", Floor(kSpined, "", 10));
  ASSERT_TRUE(rigid.stable && zero.stable && undriven.stable);
  // Amplitude 0 writes ctrl 0, what an undriven servo holds: the same run to the bit.
  EXPECT_EQ(zero.distance_m, undriven.distance_m);
  EXPECT_NEAR(zero.distance_m, rigid.distance_m, kDistanceShare * rigid.distance_m);
}

TEST(Spine, RefusedOnARigidBody) {
  const std::string error = climbsim::testing::ScenarioErrorOf(
      "spine_refused.yaml", Floor("gecko", "  spine: {amplitude_rad: 0.2}\n", 1));
  EXPECT_NE(error.find("spine_refused.yaml:9:"), std::string::npos) << error;
  EXPECT_NE(error.find("cpg.spine: the robot has no spine"), std::string::npos) << error;
}

}  // namespace
}  // namespace climbsim::sim
