// Servo margins (sim/servo_margin.h): the gait's stance sets, the holding torque of a known
// mass on a known lever, how a payload scales it on a robot, and `simulate --strict`.
#include "sim/servo_margin.h"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sim/sim.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::CliResult;
using climbsim::testing::Has;
using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsim;
using climbsim::testing::Source;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

TEST(ServoMargin, StanceSetsOfTheGaits) {
  // Trot (LF 0, RF ½, LH ½, RH 0; D = ½): the two diagonal pairs, then all four.
  EXPECT_EQ(GaitStanceSets({0, 0.5, 0.5, 0}, 0.5),
            (std::vector<std::vector<int>>{{1, 2}, {0, 3}, {0, 1, 2, 3}}));
  // Lateral sequence (LF ¼, RF ¾, LH 0, RH ½; D = ¾): each leg off in turn.
  EXPECT_EQ(GaitStanceSets({0.25, 0.75, 0, 0.5}, 0.75),
            (std::vector<std::vector<int>>{{0, 1, 3}, {1, 2, 3}, {0, 1, 2}, {0, 2, 3}, {0, 1, 2, 3}}));
  // Tripod: L1 L3 R2 and L2 R1 R3.
  EXPECT_EQ(GaitStanceSets({0, 0.5, 0, 0.5, 0, 0.5}, 0.5),
            (std::vector<std::vector<int>>{{1, 3, 5}, {0, 2, 4}, {0, 1, 2, 3, 4, 5}}));
}

// A 50 g mass 0.1 m out on a horizontal arm, a position servo at its hinge: the holding torque
// is m·g·L·cos(sag) with sag = m·g·L/kp.
TEST(ServoMargin, KnownMassOnKnownLever) {
  const char* xml = R"(<mujoco><option gravity="0 0 -9.81" timestep="0.001"/>
    <worldbody><body name="arm"><joint name="j" type="hinge" axis="0 1 0" damping="0.05"/>
      <geom type="sphere" size="0.005" pos="0.1 0 0" mass="0.05"/></body></worldbody>
    <actuator><position name="j" joint="j" kp="20" forcelimited="true" forcerange="-1 1"/>
    </actuator></mujoco>)";
  char error[500] = "";
  mjModel* m = mj_loadXML(WriteFile("lever.xml", xml).c_str(), nullptr, error, sizeof error);
  ASSERT_NE(m, nullptr) << error;
  mjData* d = mj_makeData(m);
  const std::vector<double> f = SettledActuatorForces(m, d, {}, {}, {}, 3000);
  const double mgl = 0.05 * 9.81 * 0.1;
  EXPECT_NEAR(f[0], mgl * std::cos(mgl / 20.0), 1e-3 * mgl);
  mj_deleteData(d);
  mj_deleteModel(m);
}

// The gecko standing on the floor on all four pads, with 0, m and 2m on its base (m its own
// mass): statics are linear in the load, so each servo's holding torque rises by the same step
// twice (within 2 %), and the report names the stance set (all four: no cpg) and the mass.
TEST(ServoMargin, HoldingTorqueIsLinearInThePayload) {
  Scenario s = LoadScenario(Source("examples/gecko_floor.yaml"));
  s.cpg.reset();
  std::vector<ServoMargins> margins;
  for (double times : {0.0, 1.0, 2.0}) {
    s.payload_kg = times * 0.1025;
    margins.push_back(MeasureServoMargins(s));
  }
  EXPECT_NEAR(margins[2].mass_kg, 3 * 0.1025, 1e-9);
  ASSERT_EQ(margins[0].stance_sets,
            (std::vector<std::vector<std::string>>{{"LF", "RF", "LH", "RH"}}));
  ASSERT_EQ(margins[0].servos.size(), 12u);
  for (size_t i = 0; i < 12; ++i) {
    EXPECT_DOUBLE_EQ(margins[0].servos[i].rated_torque_nm, 0.039);
    if (margins[0].servos[i].name.find("hip_pitch") == std::string::npos) continue;
    const double step1 = margins[1].servos[i].holding_torque_nm - margins[0].servos[i].holding_torque_nm;
    const double step2 = margins[2].servos[i].holding_torque_nm - margins[1].servos[i].holding_torque_nm;
    EXPECT_GT(step1, 1e-3) << margins[0].servos[i].name;
    EXPECT_NEAR(step2 / step1, 1.0, 0.02) << margins[0].servos[i].name;
  }
}

std::string WallWithPayload(const std::string& name, double payload_kg) {
  std::string yaml = ReadFile(Source("examples/gecko_wall.yaml"));
  yaml.replace(yaml.find("duration_s: 20"), 14, "duration_s: 0.05");
  yaml += "payload_kg: " + std::to_string(payload_kg) + "\n";
  return WriteFile(name, yaml);
}

// 0.1 kg on the gecko's back puts its hip-yaw servos over their rating on the wall: a warning
// and the report in summary.json; with --strict, exit 2 before the run (no run folder).
TEST(ServoMargin, StrictRefusesAnOverloadedDesignBeforeTheRun) {
  const std::string heavy = WallWithPayload("heavy_wall.yaml", 0.1);
  const std::string dir = TempDir() + "/heavy_run";
  const CliResult warned = RunClimbsim("simulate " + heavy + " --out " + dir + " --quiet");
  EXPECT_EQ(warned.code, 0) << warned.err;
  EXPECT_TRUE(Has(warned.err, "warning: servo LF_hip_yaw 1")) << warned.err;
  const nlohmann::json j = nlohmann::json::parse(ReadFile(dir + "/summary.json"));
  EXPECT_FALSE(j["servo_margins"]["overloaded"].empty());
  EXPECT_NEAR(j["servo_margins"]["mass_kg"].get<double>(), 0.2025, 1e-9);

  const std::string strict_dir = TempDir() + "/heavy_strict";
  const CliResult refused = RunClimbsim("simulate " + heavy + " --out " + strict_dir + " --strict");
  EXPECT_EQ(refused.code, 2);
  EXPECT_TRUE(Has(refused.err, "error: servo LF_hip_yaw 1")) << refused.err;
  EXPECT_FALSE(std::filesystem::exists(strict_dir));

  const std::string light = WallWithPayload("light_wall.yaml", 0.0);
  const CliResult ok = RunClimbsim("simulate " + light + " --out " + TempDir() +
                                   "/light_strict --strict --quiet");
  EXPECT_EQ(ok.code, 0) << ok.err;
}

}  // namespace
}  // namespace climbsim::sim
