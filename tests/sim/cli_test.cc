// The climbsim executable as a user meets it: exit codes, messages, help, and that bad input
// leaves an existing run directory as it was.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/common/test_util.h"

namespace {

using climbsim::testing::CliResult;
using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsim;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;


TEST(Cli, BadScenarioExitsTwoAndKeepsTheRunDirectory) {
  const std::string dir = TempDir() + "/kept_run";
  std::filesystem::create_directories(dir);
  WriteFile("kept_run/summary.json", "{\"from\": \"an earlier run\"}\n");
  const std::string bad = WriteFile("bad_cli.yaml", "robot: gecko\nscene: floor\nduration_s: -1\n");
  const CliResult r = RunClimbsim("simulate " + bad + " --out " + dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, bad + ":3:13: duration_s: must be in (0, 1000000], got -1\n");
  EXPECT_EQ(ReadFile(dir + "/summary.json"), "{\"from\": \"an earlier run\"}\n");
}

TEST(Cli, MissingScenarioFileExitsTwo) {
  const CliResult r = RunClimbsim("simulate /nonexistent/x.yaml --out " + TempDir() + "/never");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "/nonexistent/x.yaml: scenario file not found\n");
  EXPECT_FALSE(std::filesystem::exists(TempDir() + "/never"));
}

TEST(Cli, UnknownOptionExitsTwo) {
  EXPECT_EQ(RunClimbsim("simulate --frobnicate").code, 2);
  EXPECT_EQ(RunClimbsim("no-such-verb").code, 2);
}

TEST(Cli, HelpEndsWithAnExampleThatRuns) {
  for (const std::string verb : {"", "simulate ", "keys "}) {
    const CliResult r = RunClimbsim(verb + "--help");
    EXPECT_EQ(r.code, 0) << verb;
    const size_t at = r.out.rfind("Example:\n  climbsim ");
    ASSERT_NE(at, std::string::npos) << verb << r.out;
  }
  // The examples shown are real: the simulate example's scenario file exists.
  EXPECT_TRUE(std::filesystem::exists(climbsim::testing::Source("examples/gecko_floor.yaml")));
}

TEST(Cli, SimulatePrintsTheSummaryAndWritesTheRun) {
  const std::string scenario = WriteFile("cli_ok.yaml",
                                         "robot: gecko\nscene: floor\nduration_s: 0.2\n"
                                         "cpg:\n  gait: trot\n");
  const std::string dir = TempDir() + "/cli_ok_run";
  const CliResult r = RunClimbsim("simulate " + scenario + " --out " + dir);
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("distance"), std::string::npos);
  const auto summary = nlohmann::json::parse(ReadFile(dir + "/summary.json"));
  EXPECT_EQ(summary["steps"], 200);
  EXPECT_EQ(summary["effects"], nlohmann::json::array({"cpg", "trajectory"}));
}


TEST(Cli, BenchSpeedVersusComparesTwoSettingsAndRejectsABadKey) {
  const std::string scenario = climbsim::testing::Source("examples/gecko_floor.yaml");
  const CliResult r =
      RunClimbsim("bench speed " + scenario +
                  " --duration 0.1 --repetitions 1 --versus physics.integrator=implicit");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("B   physics.integrator=implicit"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("A runs "), std::string::npos) << r.out;
  const CliResult bad = RunClimbsim("bench speed " + scenario + " --versus physics.integrator");
  EXPECT_EQ(bad.code, 2) << bad.err;
  EXPECT_NE(bad.err.find("expected KEY=VALUE"), std::string::npos) << bad.err;
  const CliResult wrong =
      RunClimbsim("bench speed " + scenario + " --versus physics.integrator=verlet");
  EXPECT_EQ(wrong.code, 2) << wrong.err;
  EXPECT_NE(wrong.err.find("physics.integrator: must be one of"), std::string::npos)
      << wrong.err;
}

// `bench speed --profile-from`: the profile covers the steps from that time on (0.1 s of a
// 0.25 s run at 1 ms: the last 150 steps), and a window that starts at or after the end is
// refused before anything runs.
TEST(Cli, BenchSpeedProfilesFromAGivenTime) {
  const std::string scenario = climbsim::testing::Source("examples/gecko_floor.yaml");
  const CliResult r = RunClimbsim("bench speed " + scenario +
                                  " --duration 0.25 --repetitions 1 --profile-from 0.1");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("profile of the full scenario from 0.1 s (150 steps;"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("(less the profile's own clock, "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("(with the clock left in: all effects "), std::string::npos) << r.out;
  const CliResult late =
      RunClimbsim("bench speed " + scenario + " --duration 0.25 --profile-from 0.25");
  EXPECT_EQ(late.code, 2) << late.err;
  EXPECT_NE(late.err.find("--profile-from"), std::string::npos) << late.err;
  EXPECT_EQ(late.out.find("steps/s"), std::string::npos) << late.out;
}

}  // namespace
