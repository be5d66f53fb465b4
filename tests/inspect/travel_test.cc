// Run folders travel: model.xml is the model that ran, self-contained (no include, the
// welds and sensors climbsim added are in it), so a copy of the folder elsewhere inspects,
// plots and renders, and MuJoCo's own mujoco-compile loads it.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

#include "inspect/inspect.h"
#include "sim/sim.h"
#include "tests/common/test_util.h"
#include "tests/inspect/inspect_test_util.h"

namespace climbsim {
namespace {

using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsim;
using climbsim::testing::Source;
using climbsim::testing::TempDir;
namespace fs = std::filesystem;

// A short climb written by `climbsim simulate`, then moved to a folder of its own elsewhere.
std::string MovedRun() {
  const std::string run = TempDir() + "/travel_src/run";
  const std::string scenario = climbsim::testing::WriteFile(
      "travel.yaml", std::regex_replace(ReadFile(Source("examples/gecko_wall.yaml")),
                                        std::regex("duration_s: [0-9.]+"), "duration_s: 1.5"));
  auto r = RunClimbsim("simulate " + scenario + " --quiet --out " + run);
  EXPECT_EQ(r.code, 0) << r.err;
  const fs::path elsewhere =
      fs::temp_directory_path() / ("climbsim_travel_" + std::to_string(::getpid()));
  fs::remove_all(elsewhere);
  fs::create_directories(elsewhere);
  const std::string moved = (elsewhere / "run").string();
  fs::rename(run, moved);  // the original is gone
  return moved;
}

TEST(RunFolder, ModelXmlIsSelfContainedAndTheModelThatRan) {
  const std::string s_path = Source("examples/gecko_wall.yaml");
  const sim::Scenario s = sim::LoadScenario(s_path);
  auto model = sim::CompileScenario(s);
  sim::Simulation run(s, *model);
  const std::string xml = run.world().Xml();
  EXPECT_EQ(xml.find("<include"), std::string::npos);
  EXPECT_NE(xml.find("<weld"), std::string::npos) << "the pads' welds climbsim adds";
  std::string error;
  mjModel* m = common::CompileMjcfString(xml, &error);
  ASSERT_NE(m, nullptr) << error;
  const mjModel* ran = run.world().model();
  EXPECT_EQ(m->nq, ran->nq);
  EXPECT_EQ(m->nbody, ran->nbody);
  EXPECT_EQ(m->ngeom, ran->ngeom);
  EXPECT_EQ(m->neq, ran->neq);
  EXPECT_EQ(m->nu, ran->nu);
  EXPECT_EQ(m->nsensor, ran->nsensor);
  EXPECT_EQ(m->opt.timestep, ran->opt.timestep);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(m->opt.gravity[k], ran->opt.gravity[k]);
  EXPECT_EQ(m->opt.cone, ran->opt.cone);
  EXPECT_EQ(m->opt.impratio, ran->opt.impratio);
  // The keyframe holds the state the run started from, bit for bit.
  ASSERT_EQ(m->nkey, 1);
  for (int i = 0; i < m->nq; ++i) EXPECT_EQ(m->key_qpos[i], run.world().data()->qpos[i]) << i;
  mj_deleteModel(m);
}

// Includes are expanded recursively (a nested one resolves against its own file's folder),
// with either quote, XML entities in the path, and a prolog before <mujoco>.
TEST(RunFolder, IncludesExpandRecursivelyWithEntitiesAndQuotes) {
  const std::string dir = TempDir() + "/a&b";
  climbsim::testing::WriteFile(
      dir + "/robot.xml",
      "<?xml version=\"1.0\"?>\n<!-- a <mujoco> in a comment -->\n<mujoco model=\"r\">\n"
      "  <include file='parts/body.xml'/>\n</mujoco>\n");
  climbsim::testing::WriteFile(dir + "/parts/body.xml",
                               "<mujoco><worldbody><body name=\"base\"><freejoint name=\"root\"/>"
                               "<geom type=\"sphere\" size=\"0.1\"/></body></worldbody></mujoco>");
  const std::string top = "<mujoco model=\"t\">\n  <include file=\"" + TempDir() +
                          "/a&amp;b/robot.xml\"/>\n</mujoco>\n";
  const std::string xml = sim::ExpandIncludes(top, "");
  EXPECT_EQ(xml.find("<include"), std::string::npos) << xml;
  EXPECT_NE(xml.find("begin of robot.xml"), std::string::npos);
  EXPECT_NE(xml.find("begin of body.xml"), std::string::npos);
  EXPECT_EQ(xml.find("<?xml"), std::string::npos);
  std::string error;
  mjModel* m = common::CompileMjcfString(xml, &error);
  ASSERT_NE(m, nullptr) << error;
  EXPECT_EQ(m->nbody, 2);
  mj_deleteModel(m);
  try {
    sim::ExpandIncludes("<mujoco><include file=\"missing.xml\"/></mujoco>", dir);
    ADD_FAILURE() << "a missing include must throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/missing.xml"), std::string::npos) << e.what();
  }
}

TEST(RunFolder, AMovedRunInspectsPlotsRendersAndCompiles) {
  const std::string run = MovedRun();
  EXPECT_EQ(ReadFile(run + "/model.xml").find(CLIMBSIM_SOURCE_DIR), std::string::npos)
      << "no path into the checkout";

  auto inspect = RunClimbsim("inspect " + run);
  EXPECT_EQ(inspect.code, 0) << inspect.err;
  EXPECT_NE(inspect.out.find("LF"), std::string::npos) << inspect.out;

  auto plots = RunClimbsim("inspect " + run + " --plots");
  EXPECT_EQ(plots.code, 0) << plots.err;
  int pngs = 0;
  for (const auto& e : fs::recursive_directory_iterator(run))
    pngs += e.path().extension() == ".png";
  EXPECT_GT(pngs, 0);

  const std::string still = run + "/still.png";
  auto render = RunClimbsim("render " + run + " --at 1 --out " + still +
                            " --width 160 --height 120 --quality reduced");
  EXPECT_EQ(render.code, 0) << render.err;
  EXPECT_GT(fs::file_size(still), 1000u);

  ASSERT_EQ(std::system("command -v mujoco-compile >/dev/null 2>&1"), 0)
      << "mujoco-compile not installed (scripts/setup.sh installs libmujoco-samples)";
  const std::string mjb = TempDir() + "/travel.mjb";
  const std::string cmd = "cd " + fs::temp_directory_path().string() + " && mujoco-compile " + run +
                          "/model.xml " + mjb + " > " + TempDir() + "/compile.log 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << ReadFile(TempDir() + "/compile.log");
  EXPECT_GT(fs::file_size(mjb), 1000u);
}

}  // namespace
}  // namespace climbsim
