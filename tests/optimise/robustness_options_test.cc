// `climbsim bench robustness` refuses, before any work and with exit code 2, a push time the
// pushes' schedule cannot keep (it was clamped silently) and a family the scenario cannot
// take (it gave an empty report and exit code 0), naming the family and why.
#include <gtest/gtest.h>

#include <filesystem>

#include "tests/common/test_util.h"

namespace {

using climbsim::testing::RunClimbsim;
using climbsim::testing::Source;
using climbsim::testing::TempDir;

// Little work if it were not refused: one seed, one phase, 0.3 s runs.
std::string Command(const std::string& example, const std::string& options,
                    const std::string& out) {
  return "bench robustness " + Source("examples/" + example) +
         " --duration 0.3 --seeds 1 --phases 1 " + options + " --out " + TempDir() + "/" + out;
}

TEST(RobustnessOptions, RefusesAPushTimeOutsideTheFirstThirdOfTheRun) {
  const auto late = RunClimbsim(
      Command("gecko_wall.yaml", "--families push_down --push-time 100", "robustness_late_push"));
  EXPECT_EQ(late.code, 2) << late.err;
  EXPECT_NE(late.err.find("--push-time: must be in [0, 0.1] s"), std::string::npos) << late.err;
  EXPECT_FALSE(std::filesystem::exists(TempDir() + "/robustness_late_push"));
  const auto negative = RunClimbsim(Command(
      "gecko_wall.yaml", "--families push_down --push-time -1", "robustness_negative_push"));
  EXPECT_EQ(negative.code, 2) << negative.err;
  EXPECT_NE(negative.err.find("got -1"), std::string::npos) << negative.err;
}

TEST(RobustnessOptions, RefusesAFamilyTheScenarioCannotTakeSayingWhy) {
  const struct {
    const char* example;
    const char* family;
    const char* why;
  } kCases[] = {
      {"gecko_ceiling_mujoco.yaml", "weak_patch", "its adhesion.model is 'mujoco', not bonds"},
      {"gecko_floor_to_wall.yaml", "roughness", "its scene 'floor_to_wall' is not a plane"},
      {"gecko_floor.yaml", "pad_failure", "it has no adhesion"},
  };
  for (const auto& c : kCases) {
    SCOPED_TRACE(c.family);
    const std::string out = std::string("robustness_cannot_") + c.family;
    const auto r = RunClimbsim(Command(c.example, std::string("--families ") + c.family, out));
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(std::string("--families: the scenario cannot take family '") + c.family +
                         "': " + c.why),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(std::filesystem::exists(TempDir() + "/" + out));
  }
}

}  // namespace
