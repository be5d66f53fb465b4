// The model contract of mjcf/README.md, checked on each robot file alone (the robots of
// robots_under_test.h): names, joint and actuator types, servo figures, pad geometry, masses,
// the neutral pose and the one sign convention for every leg.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "mjcf_test_util.h"
#include "robots_under_test.h"

namespace climbsim::mjcf_test {
namespace {

class MjcfContract : public testing::TestWithParam<RobotSpec> {
 protected:
  void SetUp() override {
    std::string error;
    m_ = LoadRobot(GetParam().robot, &error);
    ASSERT_NE(m_, nullptr) << error;
    d_.reset(mj_makeData(m_.get()));
    mj_kinematics(m_.get(), d_.get());
  }
  int Id(mjtObj type, const std::string& name) const {
    return mj_name2id(m_.get(), type, name.c_str());
  }
  // World position of site `name` with the joint `joint` set to `angle` (all others 0).
  std::array<double, 3> SiteWithJoint(const std::string& name, const std::string& joint,
                                      double angle) {
    mj_resetData(m_.get(), d_.get());
    d_->qpos[m_->jnt_qposadr[Id(mjOBJ_JOINT, joint)]] = angle;
    mj_kinematics(m_.get(), d_.get());
    const mjtNum* p = d_->site_xpos + 3 * Id(mjOBJ_SITE, name);
    return {p[0], p[1], p[2]};
  }
  // Horizontal separation (m) of two horizontal box pads from the current kinematics, by
  // the separating-axis test on their footprints (> 0: apart by at least that much).
  double PadSeparation(int a, int b) const {
    double best = -1e300;
    for (int g : {a, b}) {
      for (int axis = 0; axis < 2; ++axis) {
        // Footprint axis `axis` of geom g in world xy (column of geom_xmat).
        const double ux = d_->geom_xmat[9 * g + axis], uy = d_->geom_xmat[9 * g + 3 + axis];
        double extent = 0;
        for (int h : {a, b}) {
          for (int k = 0; k < 2; ++k) {
            extent += m_->geom_size[3 * h + k] *
                      std::abs(d_->geom_xmat[9 * h + k] * ux + d_->geom_xmat[9 * h + 3 + k] * uy);
          }
        }
        const double centre = (d_->geom_xpos[3 * a] - d_->geom_xpos[3 * b]) * ux +
                              (d_->geom_xpos[3 * a + 1] - d_->geom_xpos[3 * b + 1]) * uy;
        best = std::max(best, std::abs(centre) - extent);
      }
    }
    return best;
  }
  ModelPtr m_;
  DataPtr d_;
};

TEST_P(MjcfContract, LegsAreListedInCustomText) { EXPECT_EQ(LegNames(m_.get()), GetParam().legs); }

TEST_P(MjcfContract, RootIsBaseWithFreeJointNamedRoot) {
  const int base = Id(mjOBJ_BODY, "base");
  ASSERT_EQ(base, 1) << "base must be the first body below the world";
  EXPECT_EQ(m_->body_parentid[base], 0);
  const int root = Id(mjOBJ_JOINT, "root");
  ASSERT_GE(root, 0);
  EXPECT_EQ(m_->jnt_type[root], mjJNT_FREE);
  EXPECT_EQ(m_->jnt_bodyid[root], base);
  // No <option> in robot files: the defaults remain (the scene sets them).
  EXPECT_EQ(m_->opt.timestep, 0.002);
}

TEST_P(MjcfContract, TotalMassInDocumentedRange) {
  const double mass = RobotMass(m_.get());
  EXPECT_GE(mass, GetParam().mass_min_kg);
  EXPECT_LE(mass, GetParam().mass_max_kg);
}

// Each actuated joint is a hinge driven by a <position> servo of the same name, with
// ctrlrange = joint range, force limited to the stall torque, damping = stall torque /
// no-load speed (so that the saturated servo runs at the data-sheet speed) and armature.
TEST_P(MjcfContract, ActuatedJointsAreLimitedPositionServos) {
  const RobotSpec& spec = GetParam();
  int actuated = 0;
  for (const auto& leg : spec.legs) {
    for (const std::string joint_name : {"_hip_yaw", "_hip_pitch", "_knee"}) {
      const std::string name = leg + joint_name;
      const int j = Id(mjOBJ_JOINT, name);
      ASSERT_GE(j, 0) << name;
      EXPECT_EQ(m_->jnt_type[j], mjJNT_HINGE) << name;
      EXPECT_TRUE(m_->jnt_limited[j]) << name;
      const int a = Id(mjOBJ_ACTUATOR, name);
      ASSERT_GE(a, 0) << name;
      ++actuated;
      EXPECT_EQ(m_->actuator_trntype[a], mjTRN_JOINT) << name;
      EXPECT_EQ(m_->actuator_trnid[2 * a], j) << name;
      // <position>: gain kp, bias (0, -kp, 0).
      const double kp = m_->actuator_gainprm[mjNGAIN * a];
      EXPECT_GT(kp, 0) << name;
      EXPECT_EQ(m_->actuator_biasprm[mjNBIAS * a + 1], -kp) << name;
      EXPECT_TRUE(m_->actuator_ctrllimited[a]) << name;
      EXPECT_EQ(m_->actuator_ctrlrange[2 * a], m_->jnt_range[2 * j]) << name;
      EXPECT_EQ(m_->actuator_ctrlrange[2 * a + 1], m_->jnt_range[2 * j + 1]) << name;
      EXPECT_TRUE(m_->actuator_forcelimited[a]) << name;
      EXPECT_EQ(m_->actuator_forcerange[2 * a], -spec.stall_torque_nm) << name;
      EXPECT_EQ(m_->actuator_forcerange[2 * a + 1], spec.stall_torque_nm) << name;
      const int dof = m_->jnt_dofadr[j];
      // 2 % covers rounding the damping to the figures written in the file.
      EXPECT_NEAR(m_->dof_damping[dof] * spec.no_load_speed_rad_s, spec.stall_torque_nm,
                  0.02 * spec.stall_torque_nm)
          << name;
      EXPECT_GT(m_->dof_armature[dof], 0) << name;
      // The gait needs +-0.4 rad of yaw and 0.5 rad of lift inside the range.
      EXPECT_LE(m_->jnt_range[2 * j], -0.4) << name;
      EXPECT_GE(m_->jnt_range[2 * j + 1], 0.5) << name;
    }
  }
  const int tilts = GetParam().tilt_stall_torque_nm > 0 ? static_cast<int>(spec.legs.size()) : 0;
  EXPECT_EQ(m_->nu, actuated + tilts + spec.body_actuators)
      << "no other actuators in a robot file";
}

// The ankle option: a hinge L_ankle_tilt about the pad's y axis, first in the pad body (so
// it turns the pad and the passive ankle after it), with +-1.7 rad of travel and a position
// servo of the documented stall torque and speed. The plain robots have no tilt joint.
TEST_P(MjcfContract, AnkleTiltServosOnlyInTheOption) {
  const RobotSpec& spec = GetParam();
  for (const auto& leg : spec.legs) {
    const std::string name = leg + "_ankle_tilt";
    const int j = Id(mjOBJ_JOINT, name);
    if (spec.tilt_stall_torque_nm == 0) {
      EXPECT_LT(j, 0) << name;
      continue;
    }
    ASSERT_GE(j, 0) << name;
    EXPECT_EQ(m_->jnt_type[j], mjJNT_HINGE) << name;
    const int pad_body = Id(mjOBJ_BODY, leg + "_pad");
    EXPECT_EQ(m_->jnt_bodyid[j], pad_body) << name;
    EXPECT_EQ(m_->body_jntadr[pad_body], j) << name << ": first joint of the pad body";
    EXPECT_EQ(m_->jnt_axis[3 * j + 1], 1.0) << name;
    EXPECT_TRUE(m_->jnt_limited[j]) << name;
    EXPECT_EQ(m_->jnt_range[2 * j], -1.7) << name;
    EXPECT_EQ(m_->jnt_range[2 * j + 1], 1.7) << name;
    const int a = Id(mjOBJ_ACTUATOR, name);
    ASSERT_GE(a, 0) << name;
    EXPECT_EQ(m_->actuator_trnid[2 * a], j) << name;
    const double kp = m_->actuator_gainprm[mjNGAIN * a];
    EXPECT_GT(kp, 0) << name;
    EXPECT_EQ(m_->actuator_biasprm[mjNBIAS * a + 1], -kp) << name;
    EXPECT_EQ(m_->actuator_ctrlrange[2 * a], m_->jnt_range[2 * j]) << name;
    EXPECT_EQ(m_->actuator_ctrlrange[2 * a + 1], m_->jnt_range[2 * j + 1]) << name;
    EXPECT_TRUE(m_->actuator_forcelimited[a]) << name;
    EXPECT_EQ(m_->actuator_forcerange[2 * a + 1], spec.tilt_stall_torque_nm) << name;
    const int dof = m_->jnt_dofadr[j];
    EXPECT_NEAR(m_->dof_damping[dof] * spec.tilt_no_load_speed_rad_s, spec.tilt_stall_torque_nm,
                0.02 * spec.tilt_stall_torque_nm)
        << name;
    EXPECT_GT(m_->dof_armature[dof], 0) << name;
    // The servo's case is a named geom of the documented servo mass class.
    EXPECT_GE(Id(mjOBJ_GEOM, leg + "_tilt_servo"), 0) << name;
  }
}

// Passive ankle: three hinges (pitch, roll, yaw: a compliant ball joint, as the seed's
// spheres) with stiffness, damping and springref 0, not actuated, in the pad body; site
// L_ankle at the joint centre.
TEST_P(MjcfContract, AnklesArePassiveSprings) {
  for (const auto& leg : GetParam().legs) {
    const int pad_body = Id(mjOBJ_BODY, leg + "_pad");
    ASSERT_GE(pad_body, 0) << leg;
    const int site = Id(mjOBJ_SITE, leg + "_ankle");
    ASSERT_GE(site, 0) << leg;
    EXPECT_EQ(m_->site_bodyid[site], pad_body) << leg;
    for (const std::string suffix : {"_ankle_pitch", "_ankle_roll", "_ankle_yaw"}) {
      const int j = Id(mjOBJ_JOINT, leg + suffix);
      ASSERT_GE(j, 0) << leg + suffix;
      EXPECT_EQ(m_->jnt_type[j], mjJNT_HINGE);
      EXPECT_EQ(m_->jnt_bodyid[j], pad_body);
      EXPECT_GT(m_->jnt_stiffness[j], 0);
      EXPECT_GT(m_->dof_damping[m_->jnt_dofadr[j]], 0);
      EXPECT_EQ(m_->qpos_spring[m_->jnt_qposadr[j]], 0.0) << "springref 0";
      for (int a = 0; a < m_->nu; ++a) EXPECT_NE(m_->actuator_trnid[2 * a], j);
      // Ankle joint centre = site L_ankle (xanchor is the world joint position).
      for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(d_->xanchor[3 * j + i], d_->site_xpos[3 * site + i], 1e-12);
      }
    }
  }
}

// Pad: body L_pad holding exactly one box geom L_pad of the documented size and mass,
// colliding with scene geoms, with a soft contact and polymer-on-hard-surface friction
// that win over the scene's (priority).
TEST_P(MjcfContract, PadsAreFlatBoxesWithSoftFrictionalContact) {
  const RobotSpec& spec = GetParam();
  for (const auto& leg : spec.legs) {
    const int body = Id(mjOBJ_BODY, leg + "_pad");
    const int g = Id(mjOBJ_GEOM, leg + "_pad");
    ASSERT_GE(g, 0) << leg;
    EXPECT_EQ(m_->geom_bodyid[g], body);
    // The pad is the body's only colliding geom (the foot post is visual).
    int colliding = 0;
    for (int k = 0; k < m_->body_geomnum[body]; ++k) {
      const int gk = m_->body_geomadr[body] + k;
      colliding += m_->geom_contype[gk] != 0 || m_->geom_conaffinity[gk] != 0;
    }
    EXPECT_EQ(colliding, 1) << "the pad geom is the pad body's only colliding geom";
    EXPECT_EQ(m_->geom_type[g], mjGEOM_BOX);
    EXPECT_NEAR(2 * m_->geom_size[3 * g], spec.pad_side_m, 1e-9);
    EXPECT_NEAR(2 * m_->geom_size[3 * g + 1], spec.pad_side_m, 1e-9);
    EXPECT_NEAR(2 * m_->geom_size[3 * g + 2], spec.pad_thickness_m, 1e-9);
    EXPECT_GE(m_->body_mass[body], spec.pad_mass_min_kg);
    EXPECT_LE(m_->body_mass[body], spec.pad_mass_max_kg);
    // Collides with scene geoms (contype 1, conaffinity 2).
    EXPECT_TRUE((m_->geom_contype[g] & 2) || (m_->geom_conaffinity[g] & 1));
    EXPECT_GT(m_->geom_priority[g], 0);
    EXPECT_GE(m_->geom_solref[mjNREF * g], 0.01);  // time constant (s): spongy
    EXPECT_LE(m_->geom_solref[mjNREF * g], 0.02);
    EXPECT_GE(m_->geom_friction[3 * g], 0.5);  // polymer pad on glass/metal
    EXPECT_LE(m_->geom_friction[3 * g], 1.5);
  }
}

// Self-collision off, scene collision on: no pair of robot geoms can collide, and every
// geom that collides at all collides with a scene geom (contype 1, conaffinity 2).
TEST_P(MjcfContract, RobotGeomsCollideWithSceneOnly) {
  int colliding = 0;
  for (int a = 0; a < m_->ngeom; ++a) {
    const bool with_scene = (m_->geom_contype[a] & 2) || (m_->geom_conaffinity[a] & 1);
    const bool any = m_->geom_contype[a] || m_->geom_conaffinity[a];
    EXPECT_EQ(with_scene, any) << Name(m_.get(), mjOBJ_GEOM, a);
    colliding += with_scene;
    for (int b = a + 1; b < m_->ngeom; ++b) {
      EXPECT_FALSE((m_->geom_contype[a] & m_->geom_conaffinity[b]) ||
                   (m_->geom_contype[b] & m_->geom_conaffinity[a]))
          << Name(m_.get(), mjOBJ_GEOM, a) << " x " << Name(m_.get(), mjOBJ_GEOM, b);
    }
  }
  // Body and legs collide with the scene too, not only the pads.
  EXPECT_GT(colliding, static_cast<int>(GetParam().legs.size()) * 3);
}

// In qpos0 every pad is flat, its bottom face 0.5 mm above z = 0, and site L_pad_face sits
// at the centroid of that face with z = pad normal (+z world) and x along the pad width
// (+x world, the robot's forward direction).
TEST_P(MjcfContract, NeutralPoseHasFlatPadsHalfAMillimetreAboveThePlane) {
  for (const auto& leg : GetParam().legs) {
    const int g = Id(mjOBJ_GEOM, leg + "_pad");
    const int face = Id(mjOBJ_SITE, leg + "_pad_face");
    ASSERT_GE(face, 0) << leg;
    EXPECT_EQ(m_->site_bodyid[face], Id(mjOBJ_BODY, leg + "_pad"));
    EXPECT_NEAR(BoxLowestZ(m_.get(), d_.get(), g), 0.0005, 1e-6) << leg;
    const mjtNum* gm = d_->geom_xmat + 9 * g;
    EXPECT_NEAR(gm[8], 1.0, 1e-9) << leg << ": pad z axis is world +z";
    const mjtNum* sm = d_->site_xmat + 9 * face;
    EXPECT_NEAR(sm[0], 1.0, 1e-9) << leg << ": face x axis is world +x";
    EXPECT_NEAR(sm[8], 1.0, 1e-9) << leg << ": face z axis is world +z";
    const mjtNum* sp = d_->site_xpos + 3 * face;
    const mjtNum* gp = d_->geom_xpos + 3 * g;
    EXPECT_NEAR(sp[0], gp[0], 1e-9);
    EXPECT_NEAR(sp[1], gp[1], 1e-9);
    EXPECT_NEAR(sp[2], gp[2] - m_->geom_size[3 * g + 2], 1e-9) << "centroid of the bottom face";
  }
}

// One sign convention for every leg: +0.2 rad of hip_yaw moves the pad forward, +0.2 rad
// of hip_pitch or knee lifts it, to first order (-0.2 rad moves it the other way), and
// left and right legs mirror each other exactly. The minimum sizes come from the leg
// geometry in the README: yaw radius >= 0.05 m gives >= 10 mm, the hip-pitch lever
// >= 0.046 m gives >= 9 mm, the inward lean of the tibia gives >= 3 mm at the knee.
TEST_P(MjcfContract, PositiveAnglesMovePadForwardOrUpOnEveryLeg) {
  struct Case {
    std::string joint;
    int axis;      // 0: x (forward), 2: z (up)
    double min_m;  // at +0.2 rad
  };
  const std::vector<Case> cases = {
      {"_hip_yaw", 0, 0.009}, {"_hip_pitch", 2, 0.008}, {"_knee", 2, 0.003}};
  for (const auto& leg : GetParam().legs) {
    const std::string site = leg + "_pad_face";
    for (const auto& c : cases) {
      const auto p0 = SiteWithJoint(site, leg + c.joint, 0.0);
      const auto plus = SiteWithJoint(site, leg + c.joint, 0.2);
      const auto minus = SiteWithJoint(site, leg + c.joint, -0.2);
      EXPECT_GT(plus[c.axis] - p0[c.axis], c.min_m) << leg + c.joint;
      EXPECT_LT(minus[c.axis] - p0[c.axis], 0.0) << leg + c.joint;
      if (c.axis == 0) {
        EXPECT_NEAR(plus[2], p0[2], 1e-9) << leg + c.joint << ": yaw keeps the pad height";
      }
    }
  }
  // Mirror symmetry: the right leg of each pair moves like the left with y negated.
  for (const auto& left : GetParam().legs) {
    if (left[0] != 'L') continue;
    const std::string right = "R" + left.substr(1);
    for (const auto& c : cases) {
      const auto l0 = SiteWithJoint(left + "_pad_face", left + c.joint, 0.0);
      const auto l1 = SiteWithJoint(left + "_pad_face", left + c.joint, 0.2);
      const auto r0 = SiteWithJoint(right + "_pad_face", right + c.joint, 0.0);
      const auto r1 = SiteWithJoint(right + "_pad_face", right + c.joint, 0.2);
      EXPECT_NEAR(l1[0] - l0[0], r1[0] - r0[0], 1e-9) << left << c.joint;
      EXPECT_NEAR(l1[1] - l0[1], -(r1[1] - r0[1]), 1e-9) << left << c.joint;
      EXPECT_NEAR(l1[2] - l0[2], r1[2] - r0[2], 1e-9) << left << c.joint;
    }
  }
}

// A useful stride with the gait's angles: hip_yaw from -0.35 to +0.35 rad moves every pad
// at least 3.5 cm forward (README: 3.8 cm gecko, 4.0-4.6 cm spider), and 0.4 rad of hip
// pitch lifts it at least 1.5 cm (gecko 2.1 cm), clear of a small step.
TEST_P(MjcfContract, GaitAnglesGiveSeveralCentimetresOfStrideAndLift) {
  for (const auto& leg : GetParam().legs) {
    const std::string site = leg + "_pad_face";
    const auto back = SiteWithJoint(site, leg + "_hip_yaw", -0.35);
    const auto front = SiteWithJoint(site, leg + "_hip_yaw", 0.35);
    EXPECT_GE(front[0] - back[0], 0.035) << leg;
    const auto p0 = SiteWithJoint(site, leg + "_hip_pitch", 0.0);
    const auto up = SiteWithJoint(site, leg + "_hip_pitch", 0.4);
    EXPECT_GE(up[2] - p0[2], 0.015) << leg;
  }
}

// Robot geoms do not collide with each other, so the geometry must keep neighbouring pads
// apart: two neighbouring legs of a side swung towards each other by the gait's 0.4 rad of
// hip yaw leave at least 5 mm between their pads (README).
TEST_P(MjcfContract, NeighbouringPadsStayApartAtGaitYawAngles) {
  const auto& legs = GetParam().legs;
  for (size_t i = 0; i + 1 < legs.size(); ++i) {
    // Legs are listed front to back per side (gecko: LF RF LH RH, spider: L1 L2 L3 R1 R2 R3).
    const std::string front = legs[i];
    std::string back;
    for (size_t k = i + 1; k < legs.size(); ++k) {
      if (legs[k][0] == front[0]) {
        back = legs[k];
        break;
      }
    }
    if (back.empty()) continue;
    mj_resetData(m_.get(), d_.get());
    d_->qpos[m_->jnt_qposadr[Id(mjOBJ_JOINT, front + "_hip_yaw")]] = -0.4;
    d_->qpos[m_->jnt_qposadr[Id(mjOBJ_JOINT, back + "_hip_yaw")]] = 0.4;
    mj_kinematics(m_.get(), d_.get());
    const int a = Id(mjOBJ_GEOM, front + "_pad"), b = Id(mjOBJ_GEOM, back + "_pad");
    EXPECT_GE(PadSeparation(a, b), 0.005) << front << " vs " << back;
  }
}

INSTANTIATE_TEST_SUITE_P(Robots, MjcfContract, testing::ValuesIn(ContractRobots()),
                         [](const testing::TestParamInfo<RobotSpec>& info) {
                           return info.param.robot;
                         });

}  // namespace
}  // namespace climbsim::mjcf_test
