// `climbsim model SCENARIO --out FILE [--scene]`: the robot file alone (MuJoCo loads it),
// the design's mass and servos on the terminal; an earlier unedited output is replaced, any
// other file refused (exit 2).
#include <mujoco/mujoco.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/common/test_util.h"

namespace {

using climbsim::testing::CliResult;
using climbsim::testing::Has;
using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsimArgs;
using climbsim::testing::Source;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

// The total mass of the bodies MuJoCo loads from `path`; -1 when it refuses the file.
double LoadedMass(const std::string& path) {
  char error[1000] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, error, sizeof(error));
  EXPECT_NE(m, nullptr) << path << ": " << error;
  if (m == nullptr) return -1;
  double mass = 0;
  for (int b = 1; b < m->nbody; ++b) mass += m->body_mass[b];
  mj_deleteModel(m);
  return mass;
}

// The number after "mass" in the verb's output.
double PrintedMass(const std::string& out) {
  const size_t at = out.find("mass");
  return at == std::string::npos ? -1 : std::stod(out.substr(out.find_first_of("0123456789", at)));
}

TEST(ModelCli, WritesTheRobotAloneWithItsMassAndServos) {
  const std::string out = TempDir() + "/model_gecko.xml";
  const CliResult r =
      RunClimbsimArgs({"model", Source("examples/gecko_wall.yaml"), "--out", out});
  ASSERT_EQ(r.code, 0) << r.err;
  // The printed mass is the loaded file's, to the 4 decimals printed.
  EXPECT_NEAR(PrintedMass(r.out), LoadedMass(out), 6e-5) << r.out;
  EXPECT_TRUE(Has(r.out, "servos          12")) << r.out;
  // The robot alone: no scene (the wall's geoms are not in it).
  EXPECT_FALSE(Has(ReadFile(out), "climbsim: begin of wall.xml"));

  const std::string scene = TempDir() + "/model_gecko_scene.xml";
  const CliResult s =
      RunClimbsimArgs({"model", Source("examples/gecko_wall.yaml"), "--out", scene, "--scene"});
  ASSERT_EQ(s.code, 0) << s.err;
  EXPECT_TRUE(Has(ReadFile(scene), "climbsim: begin of wall.xml"));
  EXPECT_TRUE(Has(ReadFile(scene), "climbsim_start"));
  EXPECT_GT(LoadedMass(scene), 0);
}

TEST(ModelCli, ADesignsMassIsItsParts) {
  const std::string plain = TempDir() + "/model_plain.xml";
  const std::string tail = TempDir() + "/model_tail.xml";
  const std::string scenario = WriteFile(
      "model_tail.yaml",
      "robot: {preset: gecko, legs: {femur_mass_kg: 0.0035}}\nscene: wall\n"
      "duration_s: 1\n");
  const CliResult a = RunClimbsimArgs({"model", Source("examples/gecko_wall.yaml"), "--out", plain});
  const CliResult b = RunClimbsimArgs({"model", scenario, "--out", tail});
  ASSERT_EQ(a.code, 0) << a.err;
  ASSERT_EQ(b.code, 0) << b.err;
  EXPECT_TRUE(Has(b.out, "(a design)")) << b.out;
  // Four femurs 2 g heavier than the preset's 1.5 g.
  EXPECT_NEAR(LoadedMass(tail) - LoadedMass(plain), 4 * 0.002, 1e-9);
  EXPECT_NEAR(PrintedMass(b.out), LoadedMass(tail), 6e-5) << b.out;
}

TEST(ModelCli, ReplacesItsOwnFileOnlyWhileUnedited) {
  const std::string out = TempDir() + "/model_again.xml";
  const std::vector<std::string> args = {"model", Source("examples/gecko_wall.yaml"), "--out",
                                         out};
  ASSERT_EQ(RunClimbsimArgs(args).code, 0);
  EXPECT_EQ(RunClimbsimArgs(args).code, 0) << "its own, unedited file";
  std::ofstream(out, std::ios::app) << "<!-- a user's note -->\n";
  const CliResult edited = RunClimbsimArgs(args);
  EXPECT_EQ(edited.code, 2);
  EXPECT_TRUE(Has(edited.err, "--out")) << edited.err;
  EXPECT_TRUE(Has(ReadFile(out), "a user's note")) << "the edited file is kept";

  const std::string foreign = WriteFile("model_foreign.xml", "<mujoco/>\n");
  const CliResult r = RunClimbsimArgs({"model", Source("examples/gecko_wall.yaml"), "--out",
                                       foreign});
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(ReadFile(foreign), "<mujoco/>\n");
}

// In a run folder the file is recorded as climbsim's: the run's --force takes it.
TEST(ModelCli, AFileInARunFolderIsRecordedAsClimbsims) {
  const std::string run = TempDir() + "/model_run";
  const std::string scenario =
      WriteFile("model_run.yaml", "robot: gecko\nscene: floor\nduration_s: 0.05\n");
  ASSERT_EQ(RunClimbsimArgs({"simulate", scenario, "--out", run, "--quiet"}).code, 0);
  const std::vector<std::string> model = {"model", scenario, "--out", run + "/robot.xml"};
  ASSERT_EQ(RunClimbsimArgs(model).code, 0);
  ASSERT_EQ(RunClimbsimArgs(model).code, 0);
  EXPECT_TRUE(Has(ReadFile(run + "/.climbsim-run"), "robot.xml"));
  const CliResult again =
      RunClimbsimArgs({"simulate", scenario, "--out", run, "--quiet", "--force"});
  EXPECT_EQ(again.code, 0) << again.err;
  // Never over a run's data.
  EXPECT_EQ(RunClimbsimArgs({"model", scenario, "--out", run + "/model.xml"}).code, 2);
}

TEST(ModelCli, ABadDesignIsBadInputAtItsLine) {
  const std::string scenario = WriteFile(
      "model_bad.yaml", "robot:\n  preset: gecko\n  tail: {length_m: 9}\nscene: wall\n"
                        "duration_s: 1\n");
  const std::string out = TempDir() + "/model_bad.xml";
  const CliResult r = RunClimbsimArgs({"model", scenario, "--out", out});
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "model_bad.yaml:3:")) << r.err;
  EXPECT_TRUE(Has(r.err, "robot.tail.length_m")) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
