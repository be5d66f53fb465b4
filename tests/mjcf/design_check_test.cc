// Designs the generator refuses (std::invalid_argument naming the key path), the presets'
// values inside their keys' ranges, and a key change reaching the generated text.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "keys/keys.h"
#include "robot/design.h"

namespace climbsim::sim {
namespace {

// The message of the std::invalid_argument GenerateRobotMjcf throws; "" when none.
std::string Refusal(const RobotDesign& d) {
  try {
    GenerateRobotMjcf(d);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(DesignCheck, PresetsAreInsideTheirKeysRanges) {
  for (const std::string& name : PresetNames())
    EXPECT_NO_THROW(keys::Validate(PresetDesign(name), "robot")) << name;
}

TEST(DesignCheck, UnknownPresetNamesThePresets) {
  EXPECT_THROW(PresetDesign("lizard"), std::invalid_argument);
}

TEST(DesignCheck, UnknownServoNamesItsKey) {
  RobotDesign d = PresetDesign("gecko");
  d.servos.knee = "sg9000";
  EXPECT_EQ(Refusal(d).rfind("robot.servos.knee: unknown servo 'sg9000'", 0), 0u) << Refusal(d);
  d = PresetDesign("spider_ankle");
  d.ankles.tilt_servo = "x";
  EXPECT_EQ(Refusal(d).rfind("robot.ankles.tilt_servo:", 0), 0u) << Refusal(d);
}

TEST(DesignCheck, PostShorterThanThePadIsRefused) {
  RobotDesign d = PresetDesign("gecko");
  d.feet.post_m = d.pads.thickness_m;
  EXPECT_EQ(Refusal(d).rfind("robot.feet.post_m:", 0), 0u) << Refusal(d);
  d.feet.post_m = d.pads.thickness_m + 0.001;
  EXPECT_EQ(Refusal(d), "");
}

// Gecko pads sit 0.09 m apart along x (hips at +-0.045): a 0.09 m pad would touch its
// neighbour, 0.089 m does not.
TEST(DesignCheck, OverlappingPadsAreRefused) {
  RobotDesign d = PresetDesign("gecko");
  d.pads.size_m = 0.0901;
  EXPECT_EQ(Refusal(d).rfind("robot.pads.size_m: the pads of LF and LH overlap", 0), 0u)
      << Refusal(d);
  d.pads.size_m = 0.089;
  EXPECT_EQ(Refusal(d), "");
}

TEST(DesignCheck, LegCountIsFourOrSix) {
  RobotDesign d = PresetDesign("spider");
  d.legs.count = 5;
  EXPECT_EQ(Refusal(d).rfind("robot.legs.count:", 0), 0u) << Refusal(d);
}

TEST(DesignCheck, AKeyChangesTheGeneratedRobot) {
  RobotDesign d = PresetDesign("gecko");
  d.legs.femur_m = 0.072;
  const std::string text = GenerateRobotMjcf(d);
  EXPECT_NE(text.find("<body name=\"LF_tibia\" pos=\"0 0.072 0\">"), std::string::npos) << text;
  EXPECT_EQ(GenerateRobotMjcf(PresetDesign("gecko")).find("0.072"), std::string::npos);
}

}  // namespace
}  // namespace climbsim::sim
