// The tail (robot/tail.h) on a generated gecko: ReadRobot's ids, the tip on the surface in
// qpos0, the mass added = its parts; and the tail reflex (reflex.tail) on versus off on the
// same pad-failure cases of examples/gecko_tail_peel.yaml and examples/gecko_tail.yaml.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>

#include "robot/design.h"
#include "robot/robot.h"
#include "robot/servos.h"
#include "sim/sim.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::Source;
using climbsim::testing::TempDir;

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;

ModelPtr Compile(const RobotDesign& design, const std::string& name) {
  const std::string path = TempDir() + "/" + name + ".xml";
  std::ofstream(path) << GenerateRobotMjcf(design);
  char error[1000] = "";
  ModelPtr m(mj_loadXML(path.c_str(), nullptr, error, sizeof error));
  EXPECT_TRUE(m) << error;
  return m;
}

RobotDesign GeckoWithTail(const TailDesign& tail) {
  RobotDesign d = PresetDesign("gecko");
  d.tail = tail;
  return d;
}

// The tip's lowest point in qpos0 stands rest_gap_m above the plane z = 0 (1 µm), whatever the
// tail's length, segments and yaw.
TEST(Tail, TipRestsOnTheSurfaceInQpos0) {
  for (const auto& [length_m, segments, yaw, gap_m] :
       {std::tuple{0.15, 1, false, 0.0}, {0.08, 2, false, 0.0}, {0.25, 3, true, 0.004}}) {
    TailDesign t;
    t.length_m = length_m;
    t.segments = segments;
    t.yaw = yaw;
    t.rest_gap_m = gap_m;
    ModelPtr m = Compile(GeckoWithTail(t), "tip");
    ASSERT_TRUE(m);
    mjData* d = mj_makeData(m.get());
    mj_forward(m.get(), d);
    const RobotInfo r = ReadRobot(m.get());
    const double tip_bottom_m = d->site_xpos[3 * r.tail.tip_site + 2] - t.tip_radius_m;
    EXPECT_NEAR(tip_bottom_m, gap_m, 1e-6) << length_m << " m, " << segments << " segments";
    // And the tip is behind the body's rear edge.
    EXPECT_LT(d->site_xpos[3 * r.tail.tip_site], -0.05 - 0.5 * length_m);
    mj_deleteData(d);
  }
}

// ReadRobot: the tail's ids (yaw −1 without a yaw servo), every id −1 without a tail; the
// tail's geoms collide with the scene only (contype 2, conaffinity 1).
TEST(Tail, ReadRobotFindsTheTailsIds) {
  ModelPtr plain = Compile(PresetDesign("gecko"), "plain");
  ASSERT_TRUE(plain);
  const RobotInfo p = ReadRobot(plain.get());
  EXPECT_FALSE(p.tail.present());
  EXPECT_EQ(p.tail.pitch_actuator, -1);
  EXPECT_EQ(p.tail.tip_site, -1);
  for (bool yaw : {false, true}) {
    TailDesign t;
    t.yaw = yaw;
    ModelPtr m = Compile(GeckoWithTail(t), "ids");
    ASSERT_TRUE(m);
    const RobotInfo r = ReadRobot(m.get());
    ASSERT_TRUE(r.tail.present());
    EXPECT_EQ(r.tail.pitch_joint, mj_name2id(m.get(), mjOBJ_JOINT, "tail_pitch"));
    EXPECT_EQ(r.tail.pitch_actuator, mj_name2id(m.get(), mjOBJ_ACTUATOR, "tail_pitch"));
    EXPECT_EQ(m->actuator_trnid[2 * r.tail.pitch_actuator], r.tail.pitch_joint);
    EXPECT_EQ(r.tail.tip_geom, mj_name2id(m.get(), mjOBJ_GEOM, "tail_tip"));
    EXPECT_EQ(r.tail.yaw_actuator >= 0, yaw);
    EXPECT_EQ(m->nu, plain->nu + (yaw ? 2 : 1));
    EXPECT_EQ(r.legs.size(), 4u);
    // The servo as the catalogue has it: force limit = stall torque, kp.
    const ServoModel* s = FindServo(t.servo);
    EXPECT_EQ(m->actuator_forcerange[2 * r.tail.pitch_actuator + 1], s->stall_torque_nm);
    EXPECT_EQ(m->actuator_gainprm[mjNGAIN * r.tail.pitch_actuator], s->kp_nm_per_rad);
    for (int g = 0; g < m->ngeom; ++g) {
      if (m->geom_bodyid[g] != r.base_body && m->body_parentid[m->geom_bodyid[g]] == 0) continue;
      const char* n = mj_id2name(m.get(), mjOBJ_GEOM, g);
      if (n == nullptr || std::string(n).rfind("tail", 0) != 0) continue;
      EXPECT_EQ(m->geom_contype[g], 2) << n;
      EXPECT_EQ(m->geom_conaffinity[g], 1) << n;
    }
  }
}

// The mass the tail adds is its parts' sum: servo(s) from the catalogue, rod and tip.
TEST(Tail, MassAddedIsThePartsSum) {
  ModelPtr plain = Compile(PresetDesign("gecko"), "plain_mass");
  ASSERT_TRUE(plain);
  for (const std::string servo : {"hs35hd", "sg90"}) {
    TailDesign t;
    t.servo = servo;
    t.yaw = servo == "sg90";
    t.mass_kg = 0.002;
    t.tip_mass_kg = 0.001;
    ModelPtr m = Compile(GeckoWithTail(t), "mass");
    ASSERT_TRUE(m);
    const double added = m->body_subtreemass[1] - plain->body_subtreemass[1];
    const double parts = FindServo(servo)->mass_kg * (t.yaw ? 2 : 1) + 0.002 + 0.001;
    EXPECT_NEAR(added, parts, 1e-12) << servo;
    EXPECT_NEAR(TailMassKg(t), parts, 1e-15) << servo;
  }
}

// A tail that cannot reach the surface, or a servo not in the catalogue, is refused naming
// the key.
TEST(Tail, RefusesATailThatCannotReachTheSurface) {
  TailDesign t;
  t.length_m = 0.04;  // the gecko's base stands 0.055 m above the surface
  try {
    GenerateRobotMjcf(GeckoWithTail(t));
    FAIL() << "a 0.04 m tail was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("robot.tail.length_m"), std::string::npos) << e.what();
  }
  t = TailDesign{};
  t.servo = "nope";
  EXPECT_THROW(GenerateRobotMjcf(GeckoWithTail(t)), std::invalid_argument);
}

struct Outcome {
  RunResult result;
  nlohmann::json summary;
  std::string events;
};

// An example as `bench robustness` runs its pad_failure case of seed 0 at `probability`
// (10 s, a fall ends the run).
Scenario PadFailureScenario(const char* example, double probability) {
  Scenario s = LoadScenario(Source(example));
  s.duration_s = 10;
  s.fall.stop = true;
  s.outputs.trajectory_rate_hz = 0;
  s.adhesion->pad_failure_probability = probability;
  return s;
}

// The tail stays at rest: no trigger presses it.
void NeverPress(reflex::TailReflexParams* tail) {
  tail->on_front_pad_loss = false;
  tail->pitch_threshold_rad = 1.0;  // never reached
}

Outcome RunCase(const Scenario& s) {
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  Outcome o;
  o.result = sim.Run();
  o.summary = sim.Summary();
  o.events = sim.EventsCsv();
  return o;
}

// examples/gecko_tail_peel.yaml's case at probability 0.035, with the tail held `rest_rad` off
// the wall, and pressed or not.
Outcome PadFailureCase(double rest_rad, bool press) {
  Scenario s = PadFailureScenario("examples/gecko_tail_peel.yaml", 0.035);
  s.reflex->tail->rest_rad = rest_rad;
  if (!press) NeverPress(&*s.reflex->tail);
  return RunCase(s);
}

// The same failing front pad (LF, at 1.62 s and again at 4.21 s) with the tail held
// 0.3 rad clear of the wall: without the press the gecko falls; pressed, it climbs on.
TEST(TailReflex, PressOnPadFailureSavesWhatAClearTailCannot) {
  const Outcome off = PadFailureCase(-0.3, false);
  const Outcome on = PadFailureCase(-0.3, true);
  ASSERT_TRUE(on.result.stable && off.result.stable);
  EXPECT_TRUE(off.result.fell);
  EXPECT_FALSE(on.result.fell) << "fell at " << on.result.fall_time_s;
  EXPECT_GT(on.result.distance_m, 0.15);
  EXPECT_EQ(off.summary["reflex"]["tail"]["presses"], 0);
  EXPECT_GE(on.summary["reflex"]["tail"]["presses"], 1);
  // Every press is logged on the pad "tail" with its trigger, and released afterwards.
  int presses = 0, releases = 0;
  for (const auto& e : climbsim::testing::ParseEvents(on.events)) {
    if (e.pad != "tail") continue;
    presses += e.event == "tail_press";
    releases += e.event == "tail_release";
    if (e.event == "tail_press") {
      EXPECT_TRUE(e.cause == "front_pad_lost" || e.cause.rfind("pitch=", 0) == 0) << e.cause;
    }
  }
  EXPECT_EQ(presses, on.summary["reflex"]["tail"]["presses"]);
  EXPECT_GE(releases, presses - 1);
}

// examples/gecko_tail.yaml, the tail on the active-release gecko, at probability 0.1: LF fails
// in stance at 1.445 s, again at 3.588 s, and RF at 9.538 s (without the tail LF at 1.440 s:
// the tail's light press at rest moves the gait by a few ms). `tail` false takes the tail off
// the robot and its reflex off (gecko_wall_active.yaml); `press` false leaves the tail resting
// on the wall.
Outcome ActiveTailCase(bool tail, bool press) {
  Scenario s = PadFailureScenario("examples/gecko_tail.yaml", 0.1);
  if (!tail) {
    s.robot_design->tail.reset();
    s.reflex->tail.reset();
  } else if (!press) {
    NeverPress(&*s.reflex->tail);
  }
  return RunCase(s);
}

// The first pad that fails outright: its detach event (t -1 and no pad when none fails).
climbsim::testing::EventRow FirstFailure(const std::string& events) {
  for (const auto& e : climbsim::testing::ParseEvents(events)) {
    if (e.event == "detach" && e.cause == "failure") return e;
  }
  climbsim::testing::EventRow none;
  none.t = -1.0;
  return none;
}

// The same front pad fails at the same time (within 10 ms) with and without the tail; without
// it the two pads of the other side are twisted off and the gecko falls, with it the gecko
// climbs on. Pressed, the tail keeps the nose's turn off the wall under half the resting tail's
// and the climb longer (docs/climbing.md, "Tail").
TEST(TailReflex, ActiveGeckoWithTheTailSurvivesThePadLossThatDropsItWithout) {
  const Outcome none = ActiveTailCase(false, false);
  const Outcome resting = ActiveTailCase(true, false);
  const Outcome pressed = ActiveTailCase(true, true);
  ASSERT_TRUE(none.result.stable && resting.result.stable && pressed.result.stable);
  const auto first_none = FirstFailure(none.events);
  const auto first_pressed = FirstFailure(pressed.events);
  EXPECT_NEAR(first_none.t, 1.44, 1e-9);
  EXPECT_EQ(first_none.pad, "LF_pad");
  EXPECT_EQ(first_pressed.pad, first_none.pad);
  EXPECT_NEAR(first_pressed.t, first_none.t, 0.01);
  EXPECT_TRUE(none.result.fell);
  EXPECT_FALSE(pressed.result.fell) << "fell at " << pressed.result.fall_time_s;
  EXPECT_GT(pressed.result.distance_m, 0.15);
  EXPECT_EQ(resting.summary["reflex"]["tail"]["presses"], 0);
  EXPECT_GE(pressed.summary["reflex"]["tail"]["presses"], 2);
  const double pitch_pressed = pressed.summary["reflex"]["tail"]["max_pitch_rad"];
  const double pitch_resting = resting.summary["reflex"]["tail"]["max_pitch_rad"];
  EXPECT_LT(pitch_pressed, 0.5 * pitch_resting) << pitch_pressed << " vs " << pitch_resting;
  EXPECT_GT(pressed.result.distance_m, resting.result.distance_m + 0.03);
}

// Held 0.1 rad clear (tip ~14 mm off the wall), the unpressed tail catches the body too, later:
// the press keeps the nose's largest turn off the wall smaller and the climb longer.
TEST(TailReflex, PressBoundsThePitchOfAClearTail) {
  const Outcome off = PadFailureCase(-0.1, false);
  const Outcome on = PadFailureCase(-0.1, true);
  ASSERT_FALSE(on.result.fell);
  const double pitch_on = on.summary["reflex"]["tail"]["max_pitch_rad"];
  const double pitch_off = off.summary["reflex"]["tail"]["max_pitch_rad"];
  EXPECT_LT(pitch_on, 0.8 * pitch_off) << pitch_on << " vs " << pitch_off;
  EXPECT_GT(on.result.distance_m, off.result.distance_m + 0.02);
}

// An adhesive tip (robot.tail.tip: adhesive) is a sticky pad: the body tail_pad with one box
// of pad_size_m square whose face lies on the surface in qpos0 (rest_gap_m 0), on a sleeve
// (slide along x with the keys' spring and travel); ReadRobot finds it, a ball tip has none.
TEST(Tail, AdhesiveTipIsAPadOnASleeve) {
  TailDesign t;
  t.tip = "adhesive";
  t.pad_size_m = 0.03;
  ModelPtr m = Compile(GeckoWithTail(t), "adhesive");
  ASSERT_TRUE(m);
  const RobotInfo r = ReadRobot(m.get());
  ASSERT_GE(r.tail.pad_body, 0);
  EXPECT_EQ(r.tail.pad_body, mj_name2id(m.get(), mjOBJ_BODY, "tail_pad"));
  const int g = r.tail.tip_geom;
  EXPECT_EQ(m->geom_type[g], mjGEOM_BOX);
  EXPECT_EQ(m->geom_bodyid[g], r.tail.pad_body);
  EXPECT_NEAR(2 * m->geom_size[3 * g], 0.03, 1e-12);
  EXPECT_NEAR(2 * m->geom_size[3 * g + 1], 0.03, 1e-12);
  mjData* d = mj_makeData(m.get());
  mj_forward(m.get(), d);
  const double face_z_m = d->geom_xpos[3 * g + 2] - m->geom_size[3 * g + 2];
  EXPECT_NEAR(face_z_m, 0.0, 1e-6);
  mj_deleteData(d);
  const int slide = mj_name2id(m.get(), mjOBJ_JOINT, "tail_slide");
  ASSERT_GE(slide, 0);
  EXPECT_EQ(m->jnt_type[slide], mjJNT_SLIDE);
  EXPECT_EQ(m->jnt_stiffness[slide], t.slide_stiffness_n_per_m);
  EXPECT_EQ(m->jnt_range[2 * slide + 1], t.slide_travel_m);
  ModelPtr ball = Compile(GeckoWithTail(TailDesign{}), "ball");
  EXPECT_EQ(ReadRobot(ball.get()).tail.pad_body, -1);
}

// The adhesive tip grips only while the reflex presses: on the pad-failure case of
// PadFailureCase (LF fails in stance at 1.56 s and 4.19 s) with the tip adhesive and the press
// held 0.3 s, the tail pad attaches after each tail_press and is released (detach "released")
// by the tail_release that ends it, and the gecko climbs on; with the press off it never bonds
// after the start (where it lets go at once).
TEST(TailReflex, AdhesiveTipBondsOnlyWhilePressed) {
  for (bool press : {true, false}) {
    Scenario s = LoadScenario(Source("examples/gecko_tail_peel.yaml"));
    s.robot_design->tail->tip = "adhesive";
    s.duration_s = 5;
    s.outputs.trajectory_rate_hz = 0;
    s.adhesion->pad_failure_probability = 0.035;
    s.reflex->tail->hold_s = 0.3;  // a shorter press (docs/climbing.md, "Tail")
    if (!press) NeverPress(&*s.reflex->tail);
    auto model = CompileScenario(s);
    Simulation sim(s, *model);
    const RunResult result = sim.Run();
    if (press) {
      EXPECT_FALSE(result.fell) << "fell at " << result.fall_time_s;
    }
    bool pressing = false, attached = false;
    int bonds = 0, releases = 0;
    for (const auto& e : climbsim::testing::ParseEvents(sim.EventsCsv())) {
      if (e.pad == "tail") pressing = e.event == "tail_press";
      if (e.pad != "tail_pad" || e.t == 0.0) continue;
      if (e.event == "attach") {
        EXPECT_TRUE(pressing) << "attached unpressed at " << e.t;
        attached = true;
        ++bonds;
      }
      if (e.event == "detach") {
        attached = false;
        releases += e.cause == "released";
      }
      // A release ends every bond that the press's end finds.
      if (!pressing) {
        EXPECT_FALSE(attached) << e.t;
      }
    }
    if (press) {
      EXPECT_EQ(bonds, 2);
      EXPECT_EQ(releases, 2);
    } else {
      EXPECT_EQ(bonds, 0);
    }
  }
}

// examples/gecko_tail_peel.yaml designs the robot these tests check: the gecko preset with the
// default tail and nothing else changed.
TEST(Tail, ExampleDesignsTheTestedRobot) {
  const Scenario s = ParseScenario(YAML::LoadFile(Source("examples/gecko_tail_peel.yaml")),
                                   Source("examples/gecko_tail_peel.yaml"));
  ASSERT_TRUE(s.robot_design.has_value());
  EXPECT_EQ(GenerateRobotMjcf(*s.robot_design), GenerateRobotMjcf(GeckoWithTail(TailDesign{})));
}

}  // namespace
}  // namespace climbsim::sim
