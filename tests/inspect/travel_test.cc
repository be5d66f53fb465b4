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
  // No mesh file: the run folder's model.xml is this text, byte for byte.
  const sim::CarriedModel carried = sim::CarryMeshes(xml);
  EXPECT_TRUE(carried.meshes.empty());
  EXPECT_EQ(carried.xml, xml);
}

// A binary STL tetrahedron (MuJoCo 2.2.2 reads binary STL only): an 80-byte header, the
// triangle count, then per triangle a normal, three vertices (float32) and two spare bytes.
std::string TetrahedronStl(float size_m) {
  const float v[4][3] = {{0, 0, 0}, {size_m, 0, 0}, {0, size_m, 0}, {0, 0, size_m}};
  const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  std::string stl(80, ' ');
  const uint32_t count = 4;
  stl.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& f : faces) {
    const float normal[3] = {0, 0, 0};  // MuJoCo computes its own
    stl.append(reinterpret_cast<const char*>(normal), sizeof(normal));
    for (int k : f) stl.append(reinterpret_cast<const char*>(v[k]), sizeof(v[k]));
    stl.append(2, '\0');
  }
  return stl;
}

// The gecko with two mesh shells on its base, from two folders, the files of the same name
// (meshdir "parts", and "../more/shell.stl" from there): robot.xml in `dir`.
std::string MeshRobot(const std::string& dir) {
  climbsim::testing::WriteFile(dir + "/parts/shell.stl", TetrahedronStl(0.01f));
  climbsim::testing::WriteFile(dir + "/more/shell.stl", TetrahedronStl(0.02f));
  std::string xml = ReadFile(Source("mjcf/gecko.xml"));
  const std::string compiler = "<compiler angle=\"radian\" autolimits=\"true\"/>";
  const std::string head = "<geom name=\"head\" ";
  EXPECT_NE(xml.find(compiler), std::string::npos);
  EXPECT_NE(xml.find(head), std::string::npos);
  xml.replace(xml.find(compiler), compiler.size(),
              "<compiler angle=\"radian\" autolimits=\"true\" meshdir=\"parts\"/>\n"
              "  <asset><mesh name=\"shell\" file=\"shell.stl\"/>\n"
              "    <mesh name='shell_big' file='../more/shell.stl'/></asset>");
  xml.replace(xml.find(head), head.size(),
              "<geom name=\"shell\" type=\"mesh\" mesh=\"shell\" mass=\"0.0005\" contype=\"0\" "
              "conaffinity=\"0\"/>\n      <geom name=\"shell_big\" type=\"mesh\" "
              "mesh=\"shell_big\" mass=\"0.0005\" contype=\"0\" conaffinity=\"0\"/>\n      " +
                  head);
  return climbsim::testing::WriteFile(dir + "/robot.xml", xml);
}

// Without a meshdir: an absolute file, one relative to the working folder (as MuJoCo reads the
// composed model), the same file twice, a mesh in a comment and a default left as they are.
TEST(RunFolder, CarryMeshesWithoutAMeshdir) {
  const std::string xml =
      "<mujoco model=\"m\">\n  <!-- <mesh file=\"old.stl\"/> -->\n"
      "  <default><mesh scale=\"2 2 2\"/></default>\n"
      "  <asset><mesh name=\"a\" file=\"/abs/a&amp;b.stl\"/><mesh name=\"b\" file=\"parts/b.obj\"/>"
      "<mesh name=\"c\" file = '/abs/a&amp;b.stl'/></asset>\n</mujoco>\n";
  const sim::CarriedModel c = sim::CarryMeshes(xml);
  ASSERT_EQ(c.meshes.size(), 2u);
  EXPECT_EQ(c.meshes[0].source, "/abs/a&b.stl");
  EXPECT_EQ(c.meshes[0].name, "a&b.stl");
  EXPECT_EQ(c.meshes[1].source, (fs::current_path() / "parts/b.obj").string());
  EXPECT_EQ(c.meshes[1].name, "b.obj");
  EXPECT_EQ(c.xml,
            "<mujoco model=\"m\">\n  <compiler meshdir=\"meshes/\"/>\n"
            "  <!-- <mesh file=\"old.stl\"/> -->\n"
            "  <default><mesh scale=\"2 2 2\"/></default>\n"
            "  <asset><mesh name=\"a\" file=\"a&amp;b.stl\"/><mesh name=\"b\" file=\"b.obj\"/>"
            "<mesh name=\"c\" file = 'a&amp;b.stl'/></asset>\n</mujoco>\n");
}

// A custom robot with a meshdir: its run folder carries the meshes (meshes/, model.xml naming
// them relative to itself), so that the folder moved elsewhere, the original meshes deleted,
// still inspects and compiles.
TEST(RunFolder, ARunOfARobotWithMeshesCarriesThem) {
  const std::string robot_dir = TempDir() + "/mesh_robot";
  const std::string robot = MeshRobot(robot_dir);
  const std::string scenario = climbsim::testing::WriteFile(
      "mesh_robot.yaml", "robot: " + robot + "\nscene: floor\nduration_s: 0.3\n");
  const std::string run = TempDir() + "/mesh_run";
  auto r = RunClimbsim("simulate " + scenario + " --quiet --out " + run);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(ReadFile(run + "/meshes/shell.stl"), TetrahedronStl(0.01f));
  EXPECT_EQ(ReadFile(run + "/meshes/shell_2.stl"), TetrahedronStl(0.02f));
  const std::string model_xml = ReadFile(run + "/model.xml");
  EXPECT_NE(model_xml.find("<mesh name=\"shell\" file=\"shell.stl\"/>"), std::string::npos);
  EXPECT_NE(model_xml.find("<mesh name='shell_big' file='shell_2.stl'/>"), std::string::npos);
  EXPECT_EQ(model_xml.find("meshdir=\"" + robot_dir), std::string::npos) << model_xml;

  // The meshes as the run compiled them, from the robot's own folder.
  const auto ran = sim::CompileScenario(sim::LoadScenario(scenario));
  const std::vector<float> vertices(ran->model()->mesh_vert,
                                    ran->model()->mesh_vert + 3 * ran->model()->nmeshvert);
  ASSERT_EQ(ran->model()->nmesh, 2);

  const fs::path elsewhere =
      fs::temp_directory_path() / ("climbsim_travel_mesh_" + std::to_string(::getpid()));
  fs::remove_all(elsewhere);
  fs::create_directories(elsewhere);
  const std::string moved = (elsewhere / "run").string();
  fs::rename(run, moved);
  fs::remove_all(robot_dir);

  auto inspect = RunClimbsim("inspect " + moved);
  EXPECT_EQ(inspect.code, 0) << inspect.err;
  // From its file (as mujoco-compile loads it), and from its text through LoadRun.
  char error[1000] = "";
  mjModel* m = mj_loadXML((moved + "/model.xml").c_str(), nullptr, error, sizeof(error));
  ASSERT_NE(m, nullptr) << error;
  EXPECT_EQ(m->nmesh, 2);
  EXPECT_EQ(std::vector<float>(m->mesh_vert, m->mesh_vert + 3 * m->nmeshvert), vertices);
  mj_deleteModel(m);
  std::string compile_error;
  m = common::CompileMjcfString(sim::WithRunMeshes(ReadFile(moved + "/model.xml"), moved),
                                &compile_error);
  ASSERT_NE(m, nullptr) << compile_error;
  EXPECT_EQ(m->nmesh, 2);
  mj_deleteModel(m);
  EXPECT_EQ(inspect::LoadRun(moved).legs.size(), 4u);
  fs::remove_all(elsewhere);
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
