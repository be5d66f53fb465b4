// The scenario's `robot` key: a preset name, a file, or a design (a preset changed by keys).
// A design reads over its preset (a key not given keeps the preset's value), writes back
// whole (the resolved scenario reruns the same body), is listed by `climbsim keys` with the
// gecko's values, and its errors name the key's line.
#include <gtest/gtest.h>

#include "optimise/optimise.h"
#include "sim/sim.h"
#include "tests/common/scenario_error.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::Source;
using climbsim::testing::WriteFile;

// The design's keys as the resolved scenario writes them.
YAML::Node Keys(const RobotDesign& d) { return YamlWriteArchive::Write(d); }

std::string Text(const YAML::Node& n) {
  YAML::Emitter out;
  out << n;
  return out.c_str();
}

TEST(RobotKey, AScalarIsAPresetOrAFile) {
  const Scenario preset = LoadScenario(
      WriteFile("robot_preset.yaml", "robot: spider\nscene: floor\nduration_s: 0.01\n"));
  EXPECT_EQ(preset.robot, "spider");
  EXPECT_FALSE(preset.robot_design.has_value());
  ASSERT_TRUE(DesignOf(preset).has_value());
  EXPECT_EQ(Text(Keys(*DesignOf(preset))), Text(Keys(PresetDesign("spider"))));

  const Scenario file = LoadScenario(WriteFile(
      "robot_file.yaml",
      "robot: " + Source("mjcf/gecko.xml") + "\nscene: floor\nduration_s: 0.01\n"));
  EXPECT_FALSE(DesignOf(file).has_value());
  EXPECT_EQ(RobotMjcf(file), climbsim::testing::ReadFile(Source("mjcf/gecko.xml")));
}

// Every preset, changed by one key: the rest is the preset's, not RobotDesign's defaults.
TEST(RobotKey, AMapReadsOverItsPreset) {
  for (const std::string& preset : PresetNames()) {
    const Scenario s = LoadScenario(WriteFile(
        "robot_map_" + preset + ".yaml",
        "robot:\n  preset: " + preset + "\n  compliance: {knee: {travel_rad: 0.25}}\n"
        "scene: floor\nduration_s: 0.01\n"));
    ASSERT_TRUE(s.robot_design.has_value()) << preset;
    EXPECT_EQ(s.robot, preset);
    RobotDesign expected = PresetDesign(preset);
    EXPECT_NE(expected.compliance.knee.travel_rad, 0.25);
    expected.compliance.knee.travel_rad = 0.25;
    EXPECT_EQ(Text(Keys(*s.robot_design)), Text(Keys(expected))) << preset;
  }
}

TEST(RobotKey, TheResolvedScenarioRerunsTheSameDesign) {
  const Scenario s = LoadScenario(WriteFile(
      "robot_resolved.yaml",
      "robot: {preset: gecko_active, legs: {femur_m: 0.072}, pads: {size_m: 0.027}}\n"
      "scene: wall\n"
      "duration_s: 0.01\n"));
  const Scenario again =
      LoadScenario(WriteFile("robot_resolved_again.yaml", ScenarioToYamlText(s)));
  ASSERT_TRUE(again.robot_design.has_value());
  EXPECT_EQ(Text(Keys(*again.robot_design)), Text(Keys(*s.robot_design)));
  EXPECT_EQ(RobotMjcf(again), RobotMjcf(s));
  // A scalar stays a scalar.
  const Scenario plain = LoadScenario(
      WriteFile("robot_plain.yaml", "robot: gecko\nscene: floor\nduration_s: 0.01\n"));
  EXPECT_TRUE(climbsim::testing::Has(ScenarioToYamlText(plain), "robot: gecko\n"));
}

TEST(RobotKey, ErrorsNameTheKeyAndItsLine) {
  using climbsim::testing::ScenarioErrorOf;
  EXPECT_EQ(ScenarioErrorOf("robot_e1.yaml", "robot: snail\nscene: floor\nduration_s: 1\n"),
            "robot_e1.yaml:1:8: robot: no bundled robot 'snail' (gecko, gecko_active, "
            "gecko_ankle, spider, spider_active, spider_ankle, or a path to an MJCF robot "
            "file)");
  const std::string unknown = ScenarioErrorOf(
      "robot_e2.yaml", "robot:\n  preset: gecko\n  tial: {}\nscene: floor\nduration_s: 1\n");
  EXPECT_TRUE(climbsim::testing::Has(unknown, "robot_e2.yaml:3:")) << unknown;
  EXPECT_TRUE(climbsim::testing::Has(unknown, "robot.tial")) << unknown;
  const std::string range = ScenarioErrorOf(
      "robot_e3.yaml",
      "robot:\n  preset: gecko\n  tail:\n    length_m: 5\nscene: floor\nduration_s: 1\n");
  EXPECT_TRUE(climbsim::testing::Has(range, "robot_e3.yaml:4:15: robot.tail.length_m:"))
      << range;
  const std::string preset = ScenarioErrorOf(
      "robot_e4.yaml", "robot:\n  preset: snail\nscene: floor\nduration_s: 1\n");
  EXPECT_TRUE(climbsim::testing::Has(preset, "robot_e4.yaml:2:11: robot.preset:")) << preset;
  // In range, but the generator cannot build it: its refusal at the key's line.
  const std::string built = ScenarioErrorOf(
      "robot_e5.yaml",
      "robot:\n  preset: gecko\n  feet:\n    post_m: 0.002\nscene: floor\nduration_s: 1\n");
  EXPECT_TRUE(climbsim::testing::Has(built, "robot_e5.yaml:4:13: robot.feet.post_m: the post"))
      << built;
}

TEST(RobotKey, KeysListsTheDesignWithTheGeckosValues) {
  const RobotDesign gecko = PresetDesign("gecko");
  int design_rows = 0;
  for (const DocArchive::Row& row : ScenarioKeys()) {
    if (!row.key.starts_with("robot.")) continue;
    ++design_rows;
    if (row.key == "robot.preset") {
      EXPECT_EQ(row.default_value, "gecko");
    }
  }
  // Every key the design writes is listed (the writer and the lister walk one Serialize).
  int written = 0;
  const std::function<void(const YAML::Node&)> count = [&](const YAML::Node& n) {
    for (const auto& kv : n) {
      ++written;
      if (kv.second.IsMap()) count(kv.second);
    }
  };
  RobotDesign with_tail = gecko;
  with_tail.tail.emplace();
  with_tail.body.spine.emplace();  // optional blocks are listed too
  count(YamlWriteArchive::Write(with_tail));
  EXPECT_EQ(design_rows, written);
}

// robot.* keys on a scalar preset (sweep, optimise): the scalar becomes {preset: name, ...}.
TEST(RobotKey, DottedKeysTurnAScalarPresetIntoADesign) {
  YAML::Node root = YAML::Load("robot: spider\nscene: wall\nduration_s: 1\n");
  optimise::SetDottedKey(root, "robot.compliance.knee.travel_rad", 0.15);
  EXPECT_EQ(root["robot"]["preset"].Scalar(), "spider");
  EXPECT_EQ(optimise::GetDottedKey(root, "robot.compliance.knee.travel_rad"), 0.15);
  const Scenario s = ParseScenario(root, "dotted.yaml");
  ASSERT_TRUE(s.robot_design.has_value());
  EXPECT_EQ(s.robot_design->compliance.knee.travel_rad, 0.15);
  EXPECT_EQ(s.robot_design->compliance.hip_yaw.travel_rad,
            PresetDesign("spider").compliance.hip_yaw.travel_rad);
  optimise::SetDottedKey(root, "scene.incline_deg", 10);  // scene: wall → {name: wall, ...}
  EXPECT_EQ(root["scene"]["name"].Scalar(), "wall");

  YAML::Node file = YAML::Load("robot: models/my_robot.xml\nscene: wall\nduration_s: 1\n");
  try {
    optimise::SetDottedKey(file, "robot.tail.length_m", 0.15);
    ADD_FAILURE() << "a robot file took a design key";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(climbsim::testing::Has(e.what(), "MJCF file")) << e.what();
  }
}

}  // namespace
}  // namespace climbsim::sim
