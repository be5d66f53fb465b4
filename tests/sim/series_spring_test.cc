// Series-elastic legs (robot/compliance.h): the spring joint the generator adds, how it
// deflects under a known torque (with and without a preload), what it does to a push on the
// wall, and that the shipped example designs the robot tested here.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>
#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "robot/compliance.h"
#include "robot/design.h"
#include "robot/leg_chain.h"
#include "robot/robot.h"
#include "sim/sim.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::ReadFile;
using climbsim::testing::Source;
using climbsim::testing::SplitCsv;
using climbsim::testing::WriteFile;

// The preloaded hip-yaw spring of examples/gecko_compliant.yaml.
ComplianceDesign ExampleDesign() {
  ComplianceDesign d;
  d.hip_yaw = {.stiffness_nm_per_rad = 0.2, .damping_nms_per_rad = 0.005, .travel_rad = 0.15,
               .preload_nm = 0.04};
  return d;
}

// The example's foot post (the gecko preset's is 17 mm).
constexpr double kExamplePostM = 0.01;

// A symmetric hip-yaw spring (no preload), the best of those without one.
ComplianceDesign SymmetricDesign() {
  ComplianceDesign d;
  d.hip_yaw = {.stiffness_nm_per_rad = 0.6, .damping_nms_per_rad = 0.002, .travel_rad = 0.2};
  return d;
}

// The gecko preset with these springs, as the generator writes it, plus `extra` (a <mujoco>
// document whose children are appended).
std::string CompliantGecko(const ComplianceDesign& design, const std::string& extra = "") {
  RobotDesign robot = PresetDesign("gecko");
  robot.compliance = design;
  const std::string xml = GenerateRobotMjcf(robot);
  if (extra.empty()) return xml;
  tinyxml2::XMLDocument doc, part;
  EXPECT_EQ(doc.Parse(xml.c_str()), tinyxml2::XML_SUCCESS);
  EXPECT_EQ(part.Parse(extra.c_str()), tinyxml2::XML_SUCCESS);
  for (auto* c = part.RootElement()->FirstChildElement(); c; c = c->NextSiblingElement()) {
    doc.RootElement()->InsertEndChild(c->DeepClone(&doc));
  }
  tinyxml2::XMLPrinter printer;
  doc.Print(&printer);
  return printer.CStr();
}

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;

ModelPtr Compile(const std::string& xml, const std::string& name) {
  const std::string path = WriteFile(name, xml);
  char error[1000] = "";
  ModelPtr m(mj_loadXML(path.c_str(), nullptr, error, sizeof error));
  EXPECT_NE(m, nullptr) << error;
  EXPECT_STREQ(error, "");
  return m;
}

TEST(SeriesSpring, SpringJointHasTheKeysValuesAndTheContractHolds) {
  const ModelPtr m = Compile(CompliantGecko(ExampleDesign()), "spring_gecko.xml");
  ASSERT_NE(m, nullptr);
  const RobotInfo robot = ReadRobot(m.get());
  ASSERT_EQ(robot.legs.size(), 4u);
  for (int leg = 0; leg < 4; ++leg) {
    const LegInfo& l = robot.legs[leg];
    const int servo = l.joint[0];
    const int j = mj_name2id(m.get(), mjOBJ_JOINT, SpringJointName(l.name + "_hip_yaw").c_str());
    ASSERT_GE(j, 0) << l.name;
    EXPECT_EQ(j, servo + 1);  // right after the servo, in the same body, same axis and anchor
    EXPECT_EQ(m->jnt_bodyid[j], m->jnt_bodyid[servo]);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(m->jnt_axis[3 * j + k], m->jnt_axis[3 * servo + k]);
      EXPECT_EQ(m->jnt_pos[3 * j + k], m->jnt_pos[3 * servo + k]);
    }
    EXPECT_EQ(m->jnt_stiffness[j], 0.2);
    EXPECT_EQ(m->dof_damping[m->jnt_dofadr[j]], 0.005);
    EXPECT_EQ(m->dof_armature[m->jnt_dofadr[j]], 0.0);
    EXPECT_EQ(m->jnt_range[2 * j], 0.0);  // preloaded: one way only, from its stop at 0
    EXPECT_EQ(m->jnt_range[2 * j + 1], 0.15);
    EXPECT_DOUBLE_EQ(m->qpos_spring[m->jnt_qposadr[j]], -0.04 / 0.2);
    // The servo keeps its armature and back-EMF damping; the actuator still drives it.
    EXPECT_EQ(m->dof_armature[m->jnt_dofadr[servo]], 3e-5);
    EXPECT_EQ(m->dof_damping[m->jnt_dofadr[servo]], 0.0075);
    EXPECT_EQ(m->actuator_trnid[2 * l.actuator[0]], servo);
    EXPECT_EQ(LegChain::Problem(m.get(), robot, leg), "") << l.name;
    // No spring where the design asks for none.
    EXPECT_LT(mj_name2id(m.get(), mjOBJ_JOINT, (l.name + "_knee_spring").c_str()), 0);
  }
  EXPECT_EQ(m->njnt, 1 + 4 * (3 + 3 + 1));
}

struct Deflection {
  double spring_rad, servo_rad, servo_kp;
};

// Statics: the base held, no gravity, a torque τ about LF's hip-yaw axis on its coxa, 4 s to
// settle. Servo and spring are in series, so each carries τ.
Deflection UnderTorque(const ComplianceDesign& design, double torque_nm) {
  const std::string hold =
      "<mujoco><option gravity=\"0 0 0\"/><equality><weld body1=\"base\"/></equality></mujoco>";
  const ModelPtr m = Compile(CompliantGecko(design, hold), "spring_static.xml");
  if (!m) return {};
  mjData* d = mj_makeData(m.get());
  const int coxa = mj_name2id(m.get(), mjOBJ_BODY, "LF_coxa");
  const int servo = mj_name2id(m.get(), mjOBJ_JOINT, "LF_hip_yaw");
  const int spring = mj_name2id(m.get(), mjOBJ_JOINT, "LF_hip_yaw_spring");
  mj_forward(m.get(), d);
  for (int k = 0; k < 3; ++k) {  // the axis in the world (the base at rest, aligned)
    d->xfrc_applied[6 * coxa + 3 + k] = torque_nm * m->jnt_axis[3 * servo + k];
  }
  for (int i = 0; i < 4000; ++i) mj_step(m.get(), d);
  const Deflection out{d->qpos[m->jnt_qposadr[spring]], d->qpos[m->jnt_qposadr[servo]],
                       m->actuator_gainprm[mjNGAIN * mj_name2id(m.get(), mjOBJ_ACTUATOR,
                                                                 "LF_hip_yaw")]};
  mj_deleteData(d);
  return out;
}

// The spring turns τ/k, the servo τ/kp.
TEST(SeriesSpring, KnownTorqueDeflectsTheSpringByTorqueOverStiffness) {
  const double torque_nm = 0.02;  // below the servo's 0.078 N·m limit, 0.033 rad of 0.2 travel
  const Deflection q = UnderTorque(SymmetricDesign(), torque_nm);
  EXPECT_NEAR(q.spring_rad, torque_nm / 0.6, 0.02 * torque_nm / 0.6);
  EXPECT_NEAR(q.servo_rad, torque_nm / q.servo_kp, 0.02 * torque_nm / q.servo_kp);
}

// A preloaded spring: below the preload it stays on its stop (the servo alone gives), above
// it turns by (τ - preload)/k.
TEST(SeriesSpring, PreloadedSpringMovesOnlyBeyondThePreload) {
  ComplianceDesign design;
  const double k = 0.2, preload_nm = 0.045;
  design.hip_yaw = {.stiffness_nm_per_rad = k, .damping_nms_per_rad = 0.005, .travel_rad = 0.15,
                    .preload_nm = preload_nm};
  const Deflection below = UnderTorque(design, 0.9 * preload_nm);
  // Unpreloaded, the same spring would turn 0.2 rad (past its travel): on the stop it turns
  // less than 1 % of that (the stop is a soft constraint).
  EXPECT_NEAR(below.spring_rad, 0.0, 0.01 * 0.9 * preload_nm / k);
  EXPECT_NEAR(below.servo_rad, 0.9 * preload_nm / below.servo_kp, 0.02 * below.servo_rad);
  const double torque_nm = 0.06;  // (0.06 - 0.045)/0.2 = 0.075 rad of the 0.15 travel
  const Deflection above = UnderTorque(design, torque_nm);
  EXPECT_NEAR(above.spring_rad, (torque_nm - preload_nm) / k, 0.03 * (torque_nm - preload_nm) / k);
  EXPECT_NEAR(above.servo_rad, torque_nm / above.servo_kp, 0.02 * torque_nm / above.servo_kp);
  // A negative preload gives the other way only: a positive torque leaves it on its stop.
  design.hip_yaw.preload_nm = -preload_nm;
  EXPECT_NEAR(UnderTorque(design, torque_nm).spring_rad, 0.0, 0.01 * 0.9 * preload_nm / k);
  EXPECT_NEAR(UnderTorque(design, -torque_nm).spring_rad, -(torque_nm - preload_nm) / k,
              0.03 * (torque_nm - preload_nm) / k);
}

// The peak pad load (|(fn, fx, fy)|, largest pad) within 60 ms of a 10 ms push down the wall.
double PeakPadLoadAfterPush(const std::string& robot, double push_ns) {
  std::string yaml = ReadFile(Source("examples/gecko_wall.yaml"));
  yaml.replace(yaml.find("robot: gecko"), 12, "robot: " + robot);
  yaml.replace(yaml.find("duration_s: 20"), 14, "duration_s: 1.6");
  yaml += "outputs: {trajectory_rate_hz: 1000}\nperturbations:\n  - {time_s: 1.5, impulse_ns: [" +
          std::to_string(-push_ns) + ", 0, 0]}\n";
  const Scenario s = ParseScenario(YAML::Load(yaml), Source("examples/gecko_wall.yaml"));
  const auto model = CompileScenario(s);
  Simulation run(s, *model);
  run.Run();
  std::istringstream in(run.TrajectoryCsv());
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> head = SplitCsv(line);
  double peak = 0.0;
  while (std::getline(in, line)) {
    const std::vector<std::string> row = SplitCsv(line);
    const double t = std::stod(row[0]);
    if (t < 1.5 || t > 1.56) continue;
    for (size_t c = 0; c + 2 < head.size(); ++c) {
      if (head[c].size() < 9 || head[c].compare(head[c].size() - 9, 9, "_pad_fn_n") != 0) continue;
      peak = std::max(peak, std::hypot(std::stod(row[c]), std::stod(row[c + 1]),
                                       std::stod(row[c + 2])));
    }
  }
  return peak;
}

// The push the stiff gecko cannot take (0.03 N·s): the springs let the body move against them
// instead of handing the push to the pads within a few ms.
TEST(SeriesSpring, PushDownTheWallLoadsThePadsLessWithSprings) {
  const double stiff = PeakPadLoadAfterPush("gecko", 0.03);
  const double symmetric =
      PeakPadLoadAfterPush(WriteFile("spring_sym.xml", CompliantGecko(SymmetricDesign())), 0.03);
  const double preloaded =
      PeakPadLoadAfterPush(WriteFile("spring_pre.xml", CompliantGecko(ExampleDesign())), 0.03);
  std::printf("peak pad load after a 0.03 N s push: stiff %.3f N, symmetric springs %.3f N, "
              "preloaded %.3f N\n", stiff, symmetric, preloaded);
  EXPECT_LT(symmetric, 0.9 * stiff);  // measured: 1.25 N against 1.53 N
  EXPECT_LT(preloaded, 0.9 * stiff);  // measured: 1.28 N
}

// A 10 ms push down the wall on examples/gecko_compliant.yaml (seed 0), 10 s, a fall ends
// the run; `edit` changes the scenario first.
template <class Edit>
RunResult CompliantPushCase(double push_ns, double time_s, Edit edit) {
  Scenario s = LoadScenario(Source("examples/gecko_compliant.yaml"));
  s.duration_s = 10;
  s.fall.stop = true;
  s.outputs.trajectory_rate_hz = 0;
  PushParams push;
  push.time_s = time_s;
  push.impulse_ns = {-push_ns, 0, 0};
  s.perturbations.push_back(push);
  edit(s);
  const auto model = CompileScenario(s);
  Simulation run(s, *model);
  return run.Run();
}

// The example as it was before its short post: 17 mm post, 0.045 N·m preload, the default peel.
void EarlierDesign(Scenario& s) {
  s.robot_design->feet.post_m = 0.017;
  s.robot_design->compliance.hip_yaw.preload_nm = 0.045;
  s.reflex->peel = reflex::PeelParams{};
}

// The earlier design's springs let the push (0.0284 N·s at 3.75 s, the case that ended it)
// through to the body, which pitches about the hind feet and tears a front pad off the wall; a
// tail on the wall holds that pitch (measured: without the tail it falls at 3.96 s, with it it
// climbs 0.151 m). With the tail the payload, weak-patch and bump margins fall below the stiff
// gecko's (docs/climbing.md).
TEST(SeriesSpring, TheTailHoldsThePitchTheSpringsLetThrough) {
  const RunResult without = CompliantPushCase(0.0284, 3.75, EarlierDesign);
  const RunResult with = CompliantPushCase(0.0284, 3.75, [](Scenario& s) {
    EarlierDesign(s);
    s.robot_design->tail = TailDesign{};
    s.reflex->tail = reflex::TailReflexParams{};  // rest_rad 0, press_rad 0.3, as gecko_tail_peel
  });
  EXPECT_TRUE(without.fell);
  EXPECT_FALSE(with.fell) << "fell at " << with.fall_time_s;
  EXPECT_GT(with.distance_m, 0.12);
}

// The example's edge push (0.0508 N·s, 2.1 times the stiff gecko's) at 3.33 s, as LF has just
// landed and RH is being peeled: the short post and the springs together carry it; without
// either it falls (measured: 3.49 s without the springs, 3.54 s with the 17 mm post).
TEST(SeriesSpring, TheShortPostAndTheSpringsTogetherCarryTheEdgePush) {
  const RunResult shipped = CompliantPushCase(0.0508, 10.0 / 3, [](Scenario&) {});
  const RunResult stiff = CompliantPushCase(0.0508, 10.0 / 3, [](Scenario& s) {
    s.robot_design->compliance.hip_yaw.stiffness_nm_per_rad = 0;
  });
  const RunResult long_post = CompliantPushCase(0.0508, 10.0 / 3, [](Scenario& s) {
    s.robot_design->feet.post_m = 0.017;
  });
  EXPECT_FALSE(shipped.fell) << "fell at " << shipped.fall_time_s;
  EXPECT_GT(shipped.distance_m, 0.12);
  EXPECT_TRUE(stiff.fell);
  EXPECT_TRUE(long_post.fell);
}

// examples/gecko_compliant.yaml designs the robot these tests check: the gecko preset with
// ExampleDesign's springs and the short post, nothing else changed.
TEST(SeriesSpring, ExampleDesignsTheTestedRobot) {
  const Scenario s = ParseScenario(YAML::LoadFile(Source("examples/gecko_compliant.yaml")),
                                   Source("examples/gecko_compliant.yaml"));
  ASSERT_TRUE(s.robot_design.has_value());
  RobotDesign expected = PresetDesign("gecko");
  expected.compliance = ExampleDesign();
  expected.feet.post_m = kExamplePostM;
  EXPECT_EQ(GenerateRobotMjcf(*s.robot_design), GenerateRobotMjcf(expected));
}

}  // namespace
}  // namespace climbsim::sim
