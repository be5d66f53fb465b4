// The spine (robot/spine.h): the plate split at the joint into the base and base_hind, each
// half's mass its share of the plate's length, the hind legs under base_hind, a hinge about z
// with the catalogue servo's figures, and the refusals naming their key.
#include <gtest/gtest.h>

#include <mujoco/mujoco.h>

#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>

#include "robot/design.h"
#include "robot/servos.h"
#include "tests/mjcf/design_refusal.h"

namespace climbsim::sim {
namespace {

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;

ModelPtr Compile(const RobotDesign& d) {
  const std::string text = GenerateRobotMjcf(d);
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  mj_makeEmptyFileVFS(&vfs, "robot.xml", static_cast<int>(text.size()));
  std::memcpy(vfs.filedata[vfs.nfile - 1], text.data(), text.size());
  char error[1000] = "";
  ModelPtr m(mj_loadXML("robot.xml", &vfs, error, sizeof(error)));
  mj_deleteVFS(&vfs);
  EXPECT_NE(m, nullptr) << error;
  return m;
}

RobotDesign Spined(double joint_x_m) {
  RobotDesign d = PresetDesign("gecko");
  d.body.spine = SpineDesign{};
  d.body.spine->joint_x_m = joint_x_m;
  return d;
}

using mjcf_test::Refusal;

TEST(DesignSpine, PlateSplitAtTheJointByLength) {
  const RobotDesign d = Spined(0.01);
  ModelPtr m = Compile(d);
  ASSERT_NE(m, nullptr);
  const int base = mj_name2id(m.get(), mjOBJ_BODY, "base");
  const int hind = mj_name2id(m.get(), mjOBJ_BODY, "base_hind");
  ASSERT_GE(hind, 0);
  EXPECT_EQ(m->body_parentid[hind], base);
  const int front_geom = mj_name2id(m.get(), mjOBJ_GEOM, "base");
  const int hind_geom = mj_name2id(m.get(), mjOBJ_GEOM, "base_hind");
  // 0.1 m plate split at x = 0.01: 0.04 m ahead (0.4 of the mass), 0.06 m behind (0.6).
  EXPECT_NEAR(m->geom_size[3 * front_geom], 0.02, 1e-12);
  EXPECT_NEAR(m->geom_size[3 * hind_geom], 0.03, 1e-12);
  const ServoModel& servo = *FindServo(d.body.spine->servo);
  const double yaw_servo_kg = FindServo(d.servos.hip_yaw)->mass_kg;
  EXPECT_NEAR(m->body_mass[hind], 0.6 * d.body.mass_kg + servo.mass_kg + 2 * yaw_servo_kg, 1e-9)
      << "hind plate, spine servo and the two hind yaw servo cases";
  // The plate's two halves span it: front edge at +0.05, hind edge at -0.05 in qpos0.
  mjData* data = mj_makeData(m.get());
  mj_kinematics(m.get(), data);
  EXPECT_NEAR(data->geom_xpos[3 * front_geom] + m->geom_size[3 * front_geom] -
                  data->xpos[3 * base],
              0.05, 1e-12);
  EXPECT_NEAR(data->geom_xpos[3 * hind_geom] - m->geom_size[3 * hind_geom] - data->xpos[3 * base],
              -0.05, 1e-12);
  // Every pad stands where it stands without the spine.
  ModelPtr rigid = Compile(PresetDesign("gecko"));
  mjData* rigid_data = mj_makeData(rigid.get());
  mj_kinematics(rigid.get(), rigid_data);
  for (const char* leg : {"LF_pad", "RF_pad", "LH_pad", "RH_pad"}) {
    const int a = mj_name2id(m.get(), mjOBJ_BODY, leg), b = mj_name2id(rigid.get(), mjOBJ_BODY, leg);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(data->xpos[3 * a + k], rigid_data->xpos[3 * b + k], 1e-12) << leg;
  }
  mj_deleteData(rigid_data);
  mj_deleteData(data);
}

TEST(DesignSpine, HindLegsHangFromTheHindHalf) {
  ModelPtr m = Compile(Spined(0.0));
  ASSERT_NE(m, nullptr);
  const int base = mj_name2id(m.get(), mjOBJ_BODY, "base");
  const int hind = mj_name2id(m.get(), mjOBJ_BODY, "base_hind");
  for (const char* leg : {"LF", "RF"})
    EXPECT_EQ(m->body_parentid[mj_name2id(m.get(), mjOBJ_BODY, (std::string(leg) + "_coxa").c_str())],
              base);
  for (const char* leg : {"LH", "RH"})
    EXPECT_EQ(m->body_parentid[mj_name2id(m.get(), mjOBJ_BODY, (std::string(leg) + "_coxa").c_str())],
              hind);
  EXPECT_EQ(mj_name2id(m.get(), mjOBJ_JOINT, "root"), 0) << "the base keeps the free joint";
}

TEST(DesignSpine, YawHingeWithTheCatalogueServo) {
  RobotDesign d = Spined(0.0);
  d.body.spine->servo = "hs65hb";
  d.body.spine->range_rad = 0.6;
  ModelPtr m = Compile(d);
  ASSERT_NE(m, nullptr);
  const int j = mj_name2id(m.get(), mjOBJ_JOINT, "spine_yaw");
  ASSERT_GE(j, 0);
  EXPECT_EQ(m->jnt_type[j], mjJNT_HINGE);
  EXPECT_EQ(m->jnt_bodyid[j], mj_name2id(m.get(), mjOBJ_BODY, "base_hind"));
  EXPECT_EQ(m->jnt_axis[3 * j + 2], 1.0);
  EXPECT_EQ(m->jnt_range[2 * j], -0.6);
  EXPECT_EQ(m->jnt_range[2 * j + 1], 0.6);
  const int a = mj_name2id(m.get(), mjOBJ_ACTUATOR, "spine_yaw");
  ASSERT_GE(a, 0);
  EXPECT_EQ(m->actuator_trnid[2 * a], j);
  const ServoModel& s = *FindServo("hs65hb");
  EXPECT_EQ(m->actuator_forcerange[2 * a + 1], s.stall_torque_nm);
  EXPECT_EQ(m->actuator_gainprm[mjNGAIN * a], s.kp_nm_per_rad);
}

TEST(DesignSpine, RefusalsNameTheirKey) {
  // The gecko's hips at +-0.045 m: a joint at or behind the hind hips cannot be built.
  EXPECT_NE(Refusal(Spined(-0.045)).find("robot.body.spine.joint_x_m"), std::string::npos);
  EXPECT_EQ(Refusal(Spined(-0.044)), "");
  RobotDesign d = Spined(0.0);
  d.body.spine->servo = "sg9000";
  EXPECT_NE(Refusal(d).find("robot.body.spine.servo"), std::string::npos);
}

TEST(DesignSpine, AbsentSpineChangesNothing) {
  EXPECT_EQ(GenerateRobotMjcf(PresetDesign("gecko")).find("spine"), std::string::npos);
  EXPECT_NE(GenerateRobotMjcf(Spined(0.0)).find("Keys changed from the preset: body.spine"),
            std::string::npos);
}

}  // namespace
}  // namespace climbsim::sim
