// Every MJCF file loads in plain MuJoCo, every robot composes with every scene the way the
// simulator composes them, and every scene holds the gravity, surfaces and custom data that
// mjcf/README.md promises.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "mjcf_test_util.h"

namespace climbsim::mjcf_test {
namespace {

std::vector<std::string> AllMjcfFiles() {
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(MjcfDir())) {
    if (entry.is_regular_file() && entry.path().extension() == ".xml") {
      files.push_back(std::filesystem::relative(entry.path(), MjcfDir()).string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

// The file set is what the README lists: 2 robots, their 2 options, 8 scenes, one viewer file
// per robot and scene.
TEST(MjcfFiles, TheDocumentedFilesExist) {
  std::set<std::string> files;
  for (const auto& f : AllMjcfFiles()) files.insert(f);
  for (const auto& robot : RobotNames()) {
    EXPECT_TRUE(files.count(robot + ".xml")) << robot;
    for (const auto& scene : SceneNames()) {
      EXPECT_TRUE(files.count("view/" + robot + "_" + scene + ".xml")) << robot << " " << scene;
    }
  }
  for (const auto& variant : VariantNames()) EXPECT_TRUE(files.count(variant + ".xml")) << variant;
  for (const auto& robot : OptionRobotNames()) EXPECT_TRUE(files.count(robot + ".xml")) << robot;
  for (const auto& scene : SceneNames()) EXPECT_TRUE(files.count("scenes/" + scene + ".xml"));
  EXPECT_EQ(files.size(), 2u + 2u + 2u + 8u + 16u) << "a file was added or removed: update the README";
}

std::vector<std::string> Lines(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The active-release variants are their robot line for line, but for the header comment and
// these lines: the model name, the foot post and the pad (its height below the ankle, its
// mass), the face site, and the base's default height with its comment. So a change to a
// robot that is not carried into its variant fails here.
TEST(MjcfVariants, ActiveFeetDifferOnlyInTheFeet) {
  for (const auto& [robot, variant] : std::vector<std::pair<std::string, std::string>>{
           {"gecko", "gecko_active"}, {"spider", "spider_active"}}) {
    const std::vector<std::string> base = Lines(RobotFile(robot));
    std::vector<std::string> var = Lines(RobotFile(variant));
    // Drop the variant's own header paragraph (up to the robot's first comment line).
    const auto first = std::find(var.begin() + 1, var.end(), base[1]);
    ASSERT_NE(first, var.end()) << variant;
    var.erase(var.begin() + 1, first);
    ASSERT_EQ(var.size(), base.size()) << variant;
    const std::vector<std::string> allowed = {"<mujoco model=", "_post", "_pad\"", "mass=\"",
                                              "_pad_face", "name=\"base\"", "foot post",
                                              "below the ankle", "peel lever", "(mjcf/README.md,",
                                              "force taken at its top", "the pad face 0.0", "Visual only",
                                              "+ 0.0005 = "};
    int differing = 0;
    for (size_t i = 0; i < base.size(); ++i) {
      if (base[i] == var[i]) continue;
      ++differing;
      const bool ok = std::any_of(allowed.begin(), allowed.end(), [&](const std::string& a) {
        return var[i].find(a) != std::string::npos;
      });
      EXPECT_TRUE(ok) << variant << ":" << i + 1 << " differs from " << robot << ": " << var[i];
    }
    EXPECT_GT(differing, 10) << variant;  // the feet did change
  }
}

class MjcfFileLoads : public testing::TestWithParam<std::string> {};

// Each file is a complete <mujoco> document: robots alone (they fall in space), scenes
// alone, and the viewer files (relative includes). MuJoCo must report no error at all.
TEST_P(MjcfFileLoads, WithoutError) {
  std::string error;
  ModelPtr m = Load(MjcfDir() / GetParam(), &error);
  ASSERT_NE(m, nullptr) << error;
  EXPECT_EQ(error, "");
}

INSTANTIATE_TEST_SUITE_P(AllFiles, MjcfFileLoads, testing::ValuesIn(AllMjcfFiles()),
                         [](const testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

// What the simulator adds after the two includes: an inactive weld per pad for adhesion,
// force/torque sensors at each ankle site and MuJoCo's adhesion actuator (the baseline).
std::string SimulatorLikeExtras(const std::vector<std::string>& legs) {
  std::ostringstream equality, sensor, actuator;
  for (const auto& leg : legs) {
    equality << "    <weld name=\"" << leg << "_bond\" body1=\"" << leg
             << "_pad\" active=\"false\"/>\n";
    sensor << "    <force name=\"" << leg << "_ankle_force\" site=\"" << leg << "_ankle\"/>\n"
           << "    <torque name=\"" << leg << "_ankle_torque\" site=\"" << leg << "_ankle\"/>\n";
    actuator << "    <adhesion name=\"" << leg << "_adhesion\" body=\"" << leg
             << "_pad\" ctrlrange=\"0 1\" gain=\"1\"/>\n";
  }
  return "  <equality>\n" + equality.str() + "  </equality>\n  <sensor>\n" + sensor.str() +
         "  </sensor>\n  <actuator>\n" + actuator.str() + "  </actuator>\n";
}

using RobotScene = std::tuple<std::string, std::string>;
class MjcfComposition : public testing::TestWithParam<RobotScene> {};

// Robot x scene composes with the simulator's extra sections and steps cleanly: no name
// clashes (defaults, assets, custom), the options are the scene's, and 0.2 s of free
// motion gives finite states and no MuJoCo warnings.
TEST_P(MjcfComposition, LoadsAndStepsWithSimulatorSections) {
  const auto& [robot, scene] = GetParam();
  std::string error;
  ModelPtr alone = Load(RobotFile(robot), &error);
  ASSERT_NE(alone, nullptr) << error;
  const std::vector<std::string> legs = LegNames(alone.get());
  ASSERT_FALSE(legs.empty());

  ModelPtr m = LoadComposed(robot, scene, SimulatorLikeExtras(legs), &error);
  ASSERT_NE(m, nullptr) << error;
  EXPECT_EQ(error, "");

  // Robot actuators (3 per leg, 4 with the ankle option) first, then the simulator's
  // adhesion actuators.
  EXPECT_EQ(m->nu, alone->nu + static_cast<int>(legs.size()));
  EXPECT_EQ(alone->nu,
            static_cast<int>((robot.find("_ankle") != std::string::npos ? 4 : 3) * legs.size()));
  EXPECT_EQ(m->neq, static_cast<int>(legs.size()));
  EXPECT_EQ(m->nsensor, static_cast<int>(2 * legs.size()));
  EXPECT_EQ(m->opt.timestep, 0.001) << "timestep comes from the scene only";
  EXPECT_EQ(LegNames(m.get()), legs);
  EXPECT_EQ(CustomNumeric(m.get(), "climbsim_travel").size(), 3u);
  EXPECT_GE(mj_name2id(m.get(), mjOBJ_BODY, "base"), 0);

  DataPtr d(mj_makeData(m.get()));
  for (int i = 0; i < 200; ++i) mj_step(m.get(), d.get());
  EXPECT_EQ(WarningCount(d.get()), 0);
  for (int i = 0; i < m->nq; ++i) ASSERT_TRUE(std::isfinite(d->qpos[i]));
}

INSTANTIATE_TEST_SUITE_P(AllPairs, MjcfComposition,
                         testing::Combine(testing::ValuesIn(RobotNames()),
                                          testing::ValuesIn(SceneNames())),
                         [](const testing::TestParamInfo<RobotScene>& info) {
                           return std::get<0>(info.param) + "_" + std::get<1>(info.param);
                         });
INSTANTIATE_TEST_SUITE_P(OptionPairs, MjcfComposition,
                         testing::Combine(testing::ValuesIn(OptionRobotNames()),
                                          testing::ValuesIn(SceneNames())),
                         [](const testing::TestParamInfo<RobotScene>& info) {
                           return std::get<0>(info.param) + "_" + std::get<1>(info.param);
                         });

struct SceneSpec {
  std::string scene;
  std::array<double, 3> gravity;  // m/s^2
  std::vector<std::string> surfaces;
  std::array<double, 3> travel;
};
void PrintTo(const SceneSpec& spec, std::ostream* os) { *os << spec.scene; }

class MjcfScene : public testing::TestWithParam<SceneSpec> {};

// Gravity, timestep, friction cone, named surfaces and travel direction, as documented. The
// incline's default is 30 deg: 9.81 (-sin 30, 0, -cos 30) = (-4.905, 0, -8.49571).
TEST_P(MjcfScene, HasDocumentedGravitySurfacesAndTravel) {
  const SceneSpec& spec = GetParam();
  std::string error;
  ModelPtr m = Load(SceneFile(spec.scene), &error);
  ASSERT_NE(m, nullptr) << error;
  EXPECT_EQ(m->opt.timestep, 0.001);
  EXPECT_EQ(m->opt.integrator, mjINT_EULER);  // as accurate as implicit here, 2x faster
  if (spec.scene == "floor") {
    // Gravity along the normal: no creep to stop, and pyramidal cones halve the solver's time.
    EXPECT_EQ(m->opt.cone, mjCONE_PYRAMIDAL);
  } else {
    // Elliptic cones with impratio 10 keep MuJoCo's soft-friction creep small (README).
    EXPECT_EQ(m->opt.cone, mjCONE_ELLIPTIC);
    EXPECT_EQ(m->opt.impratio, 10.0);
  }
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(m->opt.gravity[i], spec.gravity[i], 1e-5) << i;
  EXPECT_NEAR(
      std::sqrt(m->opt.gravity[0] * m->opt.gravity[0] + m->opt.gravity[1] * m->opt.gravity[1] +
                m->opt.gravity[2] * m->opt.gravity[2]),
      9.81, 1e-5);
  for (const auto& surface : spec.surfaces) {
    const int g = mj_name2id(m.get(), mjOBJ_GEOM, surface.c_str());
    ASSERT_GE(g, 0) << surface;
    EXPECT_EQ(m->geom_bodyid[g], 0) << surface << " must be static";
    // Scene bits: contype 1 / conaffinity 2 (robot geoms are contype 2 / conaffinity 1).
    EXPECT_EQ(m->geom_contype[g], 1) << surface;
    EXPECT_EQ(m->geom_conaffinity[g], 2) << surface;
  }
  // Every geom in a scene is a named surface: robots must find them by name.
  for (int g = 0; g < m->ngeom; ++g) EXPECT_NE(Name(m.get(), mjOBJ_GEOM, g), "") << g;
  const auto travel = CustomNumeric(m.get(), "climbsim_travel");
  ASSERT_EQ(travel.size(), 3u);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(travel[i], spec.travel[i]) << i;
  // The main surface is the plane z = 0 with normal +z, big enough to walk on (>= 4 m); at an
  // outer corner it must end, so there it is the top face of an axis-aligned box.
  const int plane = mj_name2id(m.get(), mjOBJ_GEOM, spec.surfaces[0].c_str());
  EXPECT_EQ(m->geom_quat[4 * plane], 1.0);
  EXPECT_GE(m->geom_size[3 * plane], 2.0);
  EXPECT_GE(m->geom_size[3 * plane + 1], 2.0);
  if (spec.scene == "wall_to_top") {
    EXPECT_EQ(m->geom_type[plane], mjGEOM_BOX);
    EXPECT_NEAR(m->geom_pos[3 * plane + 2] + m->geom_size[3 * plane + 2], 0.0, 1e-12);
  } else {
    EXPECT_EQ(m->geom_type[plane], mjGEOM_PLANE);
    EXPECT_EQ(m->geom_pos[3 * plane + 2], 0.0);
  }
}

INSTANTIATE_TEST_SUITE_P(
    AllScenes, MjcfScene,
    testing::Values(SceneSpec{"floor", {0, 0, -9.81}, {"floor"}, {1, 0, 0}},
                    SceneSpec{"wall", {-9.81, 0, 0}, {"wall"}, {1, 0, 0}},
                    SceneSpec{"ceiling", {0, 0, 9.81}, {"ceiling"}, {1, 0, 0}},
                    SceneSpec{"incline", {-4.905, 0, -8.49571}, {"incline"}, {1, 0, 0}},
                    SceneSpec{"floor_to_wall", {0, 0, -9.81}, {"floor", "wall"}, {1, 0, 1}},
                    SceneSpec{"floor_to_wall_fillet",
                              {0, 0, -9.81},
                              {"floor", "wall", "fillet0", "fillet17"},
                              {1, 0, 1}},
                    SceneSpec{"wall_to_ceiling", {-9.81, 0, 0}, {"wall", "ceiling"}, {1, 0, 1}},
                    SceneSpec{"wall_to_top", {-9.81, 0, 0}, {"wall", "top"}, {1, 0, -1}}),
    [](const testing::TestParamInfo<SceneSpec>& info) { return info.param.scene; });

// The two corners of issue 17, both with gravity along -x (up the wall is +x) and the robot
// spawned on the wall at x = 0, 0.30 m before the corner. Wall to ceiling: the ceiling's
// underside is the plane x = 0.30 facing -x (down), reaching at least 1 m out from the wall.
// Wall to top: the wall's face z = 0 ends at x = 0.30, where the top, the plane x = 0.30 facing
// +x (up), runs at least 1 m back behind the wall; the top's block starts right under the
// wall's thin slab, so no pad on the wall plane touches "top".
TEST(MjcfCorners, CornerAtThirtyCentimetresUpTheWall) {
  auto box = [](const mjModel* m, const char* name) {
    const int g = mj_name2id(m, mjOBJ_GEOM, name);
    EXPECT_GE(g, 0) << name;
    EXPECT_EQ(m->geom_type[g], mjGEOM_BOX) << name;
    EXPECT_EQ(m->geom_quat[4 * g], 1.0) << name;
    std::array<double, 6> lo_hi{};
    for (int k = 0; k < 3; ++k) {
      lo_hi[k] = m->geom_pos[3 * g + k] - m->geom_size[3 * g + k];
      lo_hi[3 + k] = m->geom_pos[3 * g + k] + m->geom_size[3 * g + k];
    }
    return lo_hi;  // x_lo, y_lo, z_lo, x_hi, y_hi, z_hi
  };
  std::string error;
  ModelPtr w2c = Load(SceneFile("wall_to_ceiling"), &error);
  ASSERT_NE(w2c, nullptr) << error;
  const auto ceiling = box(w2c.get(), "ceiling");
  EXPECT_NEAR(ceiling[0], 0.30, 1e-12);  // underside
  EXPECT_LE(ceiling[2], 0.0);            // from the wall...
  EXPECT_GE(ceiling[5], 1.0);            // ...1 m out
  EXPECT_GE(ceiling[4] - ceiling[1], 1.0);
  ModelPtr w2t = Load(SceneFile("wall_to_top"), &error);
  ASSERT_NE(w2t, nullptr) << error;
  const auto wall = box(w2t.get(), "wall");
  const auto top = box(w2t.get(), "top");
  EXPECT_NEAR(wall[3], 0.30, 1e-12);    // the wall ends at the edge...
  EXPECT_NEAR(top[3], 0.30, 1e-12);     // ...where the top's face is
  EXPECT_NEAR(top[5], wall[2], 1e-12);  // right under the wall's slab...
  EXPECT_GE(top[5], -0.005);            // ...at most 5 mm from the edge...
  EXPECT_LE(top[2], -1.0);              // ...1 m back
  EXPECT_LE(wall[0], -2.0);             // a wall long enough to climb
  for (const mjModel* m : {w2c.get(), w2t.get()}) {
    const auto spawn = CustomNumeric(m, "climbsim_spawn");
    ASSERT_EQ(spawn.size(), 3u);
    EXPECT_EQ(spawn[0], 0.0);
  }
}

// The floor-to-wall wall: a box whose -x face is the plane x = 0.30, at least 1 m tall from
// the floor up, wide enough (>= 1 m) that a robot cannot walk around it; spawn at x = 0.
TEST(MjcfFloorToWall, WallFaceAtThirtyCentimetresAndOneMetreTall) {
  std::string error;
  ModelPtr m = Load(SceneFile("floor_to_wall"), &error);
  ASSERT_NE(m, nullptr) << error;
  const int wall = mj_name2id(m.get(), mjOBJ_GEOM, "wall");
  ASSERT_GE(wall, 0);
  ASSERT_EQ(m->geom_type[wall], mjGEOM_BOX);
  EXPECT_EQ(m->geom_quat[4 * wall], 1.0) << "axis-aligned box";
  const mjtNum* pos = m->geom_pos + 3 * wall;
  const mjtNum* size = m->geom_size + 3 * wall;
  EXPECT_NEAR(pos[0] - size[0], 0.30, 1e-12);
  EXPECT_LE(pos[2] - size[2], 0.0);
  EXPECT_GE(pos[2] + size[2], 1.0);
  EXPECT_GE(2 * size[1], 1.0);
  const auto spawn = CustomNumeric(m.get(), "climbsim_spawn");
  ASSERT_EQ(spawn.size(), 3u);
  EXPECT_EQ(spawn[0], 0.0);
  EXPECT_EQ(spawn[1], 0.0);
  EXPECT_EQ(spawn[2], 0.0);
}

}  // namespace
}  // namespace climbsim::mjcf_test
