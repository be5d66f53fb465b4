// An alias bomb (anchors whose aliases repeat a list of aliases, level after level) is a few
// hundred bytes that expand to 10^12 values: every walk of the tree must be bounded, so the
// file is refused as bad input (exit code 2, with its place) in milliseconds, not hours.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "scenario/scenario.h"
#include "scenario/yaml_reader.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::CliResult;
using climbsim::testing::RunClimbsimArgs;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

// A valid walk, then `levels` lists of ten: level 0 ten numbers, level k ten aliases of k-1.
std::string AliasBomb(int levels) {
  std::string text =
      "robot: gecko\nscene: floor\nduration_s: 1\n"
      "cpg: {gait: trot, frequency_hz: 1.0}\n"
      "bomb:\n  - &l0 [0, 1, 2, 3, 4, 5, 6, 7, 8, 9]\n";
  for (int k = 1; k < levels; ++k) {
    const std::string prev = "*l" + std::to_string(k - 1);
    text += "  - &l" + std::to_string(k) + " [";
    for (int i = 0; i < 10; ++i) text += (i ? ", " : "") + prev;
    text += "]\n";
  }
  return text;
}

double SecondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

TEST(YamlBounds, AnAliasBombIsRefusedAtLoadInUnderASecond) {
  const std::string text = AliasBomb(12);
  ASSERT_LT(text.size(), 1000u);
  const std::string file = WriteFile("bomb.yaml", text);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    LoadYamlFile(file);
    FAIL() << "the bomb loaded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bomb.yaml:"), std::string::npos) << e.what();
    EXPECT_EQ(e.key().rfind("bomb[", 0), 0u) << e.key();
    EXPECT_NE(e.message().find("expands to more than 100000 values"), std::string::npos)
        << e.message();
  }
  EXPECT_LT(SecondsSince(t0), 1.0);
  // A modest use of aliases (four levels, 2·10^4 values) is within the bound.
  EXPECT_NO_THROW(CheckYamlShape(YAML::Load(AliasBomb(4) + "extra: *l3\n"), "modest.yaml"));
}

// Trees read by other means (Python's scenario_from_yaml, the fuzzer) meet the same bound.
TEST(YamlBounds, ParseScenarioBoundsATreeFromYamlLoad) {
  const auto t0 = std::chrono::steady_clock::now();
  try {
    ParseScenario(YAML::Load(AliasBomb(12)), TempDir() + "/bomb.yaml");
    FAIL() << "the bomb parsed";
  } catch (const InputError& e) {
    EXPECT_NE(e.message().find("expands to more than"), std::string::npos) << e.what();
  }
  EXPECT_LT(SecondsSince(t0), 1.0);
}

TEST(YamlBounds, TheCliRefusesTheBombWithExitCodeTwo) {
  const std::string file = WriteFile("bomb_cli.yaml", AliasBomb(12));
  const auto t0 = std::chrono::steady_clock::now();
  const CliResult r = RunClimbsimArgs({"simulate", file, "--out", TempDir() + "/bomb_run"});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("bomb_cli.yaml:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("expands to more than 100000 values"), std::string::npos) << r.err;
  EXPECT_LT(SecondsSince(t0), 5.0);  // the process's start and MuJoCo's, not the bomb
}

}  // namespace
}  // namespace climbsim::sim
