// Designs the generator refuses (std::invalid_argument naming the key path), the presets'
// values inside their keys' ranges, and a key change reaching the generated text.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "keys/keys.h"
#include "robot/design.h"
#include "robot/generate.h"
#include "robot/mjcf_dom.h"
#include "tests/mjcf/design_refusal.h"

namespace climbsim::sim {
namespace {

using mjcf_test::Refusal;

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

// The foam lies inside the pad's thickness and leaves the adhesive its 0.5 mm.
TEST(DesignCheck, FoamLeavingNoRoomForTheAdhesiveIsRefused) {
  RobotDesign d = PresetDesign("gecko");  // 2 mm pads
  d.pads.foam_m = 0.0016;
  EXPECT_EQ(Refusal(d).rfind("robot.pads.foam_m:", 0), 0u) << Refusal(d);
  d.pads.foam_m = 0.0015;
  EXPECT_EQ(Refusal(d), "");
}

// Foam adds its own mass (100 kg/m^3 over the pad's face) and tells adhesion how much more
// relief the faces follow (half its thickness); no foam leaves the preset's text as it was.
TEST(DesignCheck, FoamAddsItsMassAndItsConformance) {
  RobotDesign d = PresetDesign("gecko");
  d.pads.foam_m = 0.0015;
  const std::string text = GenerateRobotMjcf(d);
  EXPECT_NE(text.find("<numeric name=\"climbsim_pad_conform_m\" data=\"0.00075\"/>"),
            std::string::npos)
      << text;
  const double mass_kg = d.pads.mass_kg + 100.0 * d.pads.size_m * d.pads.size_m * 0.0015;
  EXPECT_NEAR(generate::PadMassKg(d.pads), mass_kg, 1e-15);
  EXPECT_NE(text.find("mass=\"" + MjcfNumber(mass_kg) + "\""), std::string::npos) << text;
  const std::string preset = GenerateRobotMjcf(PresetDesign("gecko"));
  EXPECT_EQ(preset.find("climbsim_pad_conform_m"), std::string::npos);
  EXPECT_NE(preset.find("mass=\"" + MjcfNumber(PresetDesign("gecko").pads.mass_kg) + "\""),
            std::string::npos);
}

// Gecko pads sit 0.09 m apart along x (hips at +-0.045): a 0.09 m pad would touch its
// neighbour in the neutral pose.
TEST(DesignCheck, OverlappingPadsAreRefused) {
  RobotDesign d = PresetDesign("gecko");
  d.pads.size_m = 0.0901;
  EXPECT_EQ(Refusal(d).rfind("robot.pads.size_m: the pads of LF and LH overlap", 0), 0u)
      << Refusal(d);
}

// Swung towards each other by 0.4 rad of hip yaw, the gecko's LF and LH pads (reach r = coxa +
// femur - inset = 0.05632 m) have centres 0.09 - 2 r sin 0.4 = 0.046136 m apart, each square
// turned 0.4 rad; on a pad's own edge normal the gap is 0.046136 cos 0.4 - s/2 (1 + cos 0.8 +
// sin 0.8) = 0.042494 - 1.207031 s: 0.25 mm for s = 35 mm, -0.11 mm for 35.3 mm.
TEST(DesignCheck, PadsMeetingAtTheGaitsHipYawAreRefused) {
  RobotDesign d = PresetDesign("gecko");
  d.pads.size_m = 0.035;
  EXPECT_EQ(Refusal(d), "");
  d.pads.size_m = 0.0353;
  EXPECT_EQ(Refusal(d).rfind("robot.body.hip_x_m: the pads of LF and LH overlap by 0.11 mm", 0), 0u)
      << Refusal(d);
  // A 0.09 m femur overlaps by 9.2 mm with the hips 0.09 m apart, clears by 9.2 mm at 0.11 m.
  d = PresetDesign("gecko");
  d.legs.femur_m = 0.09;
  EXPECT_EQ(Refusal(d).rfind("robot.body.hip_x_m: the pads of LF and LH overlap by 9.2 mm", 0), 0u)
      << Refusal(d);
  d.body.hip_x_m = 0.055;
  EXPECT_EQ(Refusal(d), "");
}

// The gecko's plate (10 mm thick) is 0.05509 - 0.005 = 50.09 mm above the surface; a femur
// rising 49.1 mm leaves 0.99 mm, 49 mm leaves 1.09 mm.
TEST(DesignCheck, BodyOnTheSurfaceIsRefused) {
  RobotDesign d = PresetDesign("gecko");
  d.legs.femur_rise_m = 0.0491;
  EXPECT_EQ(Refusal(d).rfind("robot.legs.tibia_m: the body's underside would stand 0.99 mm", 0), 0u)
      << Refusal(d);
  d.legs.femur_rise_m = 0.049;
  EXPECT_EQ(Refusal(d), "");
}

TEST(DesignCheck, JointRangeWithoutTheNeutralPoseIsRefused) {
  RobotDesign d = PresetDesign("spider");
  d.legs.knee_range_rad = {0.1, 1.2};
  EXPECT_EQ(Refusal(d),
            "robot.legs.knee_range_rad: [0.1 1.2] must hold 0, the neutral pose, "
            "inside its ends");
  d.legs.knee_range_rad = {1.0, -1.0};
  EXPECT_EQ(Refusal(d).rfind("robot.legs.knee_range_rad:", 0), 0u) << Refusal(d);
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
  // The header names the changed key; a preset's names none.
  EXPECT_NE(text.find("  Keys changed from the preset: legs.femur_m 0.072.\n"), std::string::npos);
  EXPECT_EQ(GenerateRobotMjcf(PresetDesign("gecko")).find("Keys changed"), std::string::npos);
}

// The keys where a design differs from its preset, in declaration order.
TEST(DesignCheck, ChangedKeysListsWhatDiffersFromThePreset) {
  for (const std::string& name : PresetNames())
    EXPECT_EQ(ChangedKeys(PresetDesign(name)), std::vector<std::string>{}) << name;
  RobotDesign d = PresetDesign("spider");
  d.pads.size_m = 0.03;
  d.legs.knee_range_rad[1] = 1.1;
  d.servos.knee = "hs82mg";
  d.feet.release = "active";
  EXPECT_EQ(ChangedKeys(d),
            (std::vector<std::string>{"legs.knee_range_rad[1] 1.1", "pads.size_m 0.03",
                                      "feet.release active", "servos.knee hs82mg"}));
}

// Numbers in the files people read: plain unless the exponent form is 3+ characters shorter,
// sums rounded back to the drawing's figures.
TEST(MjcfNumber, PlainFormUnlessMuchLonger) {
  EXPECT_EQ(MjcfNumber(0.0002), "0.0002");
  EXPECT_EQ(MjcfNumber(0.00025), "0.00025");
  EXPECT_EQ(MjcfNumber(3e-5), "3e-5");
  EXPECT_EQ(MjcfNumber(1e-6), "1e-6");
  EXPECT_EQ(MjcfNumber(-1.5e-7), "-1.5e-7");
  EXPECT_EQ(MjcfNumber(20000), "20000");
  EXPECT_EQ(MjcfNumber(2e6), "2e6");
  EXPECT_EQ(MjcfNumber(1e22), "1e22");
  EXPECT_EQ(MjcfNumber(-0.0), "0");
  EXPECT_EQ(MjcfNumber(0.03759 + 0.017 + 0.0005), "0.05509");
}

// Every value with at most 12 significant digits reads back as the same double.
TEST(MjcfNumber, ReadsBackAsTheSameDouble) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> mantissa(1.0, 10.0);
  std::uniform_int_distribution<int> exponent(-12, 8), digits(1, 12);
  for (int i = 0; i < 20000; ++i) {
    char text[64];
    std::snprintf(text, sizeof text, "%.*ge%d", digits(random) - 1, mantissa(random),
                  exponent(random));
    const double v = std::strtod(text, nullptr);
    ASSERT_EQ(std::strtod(MjcfNumber(v).c_str(), nullptr), v) << text << " -> " << MjcfNumber(v);
    ASSERT_EQ(std::strtod(MjcfNumber(-v).c_str(), nullptr), -v) << text;
  }
}

}  // namespace
}  // namespace climbsim::sim
