// Helpers for the MJCF model tests. They use MuJoCo alone (no climbsim code): the models
// must load and behave in plain MuJoCo, which is part of their contract (mjcf/README.md).
#ifndef CLIMBSIM_TESTS_MJCF_MJCF_TEST_UTIL_H_
#define CLIMBSIM_TESTS_MJCF_MJCF_TEST_UTIL_H_

#include <mujoco/mujoco.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace climbsim::mjcf_test {

// Root of the source tree (holds mjcf/).
inline std::filesystem::path SourceDir() { return std::filesystem::path(CLIMBSIM_SOURCE_DIR); }
inline std::filesystem::path MjcfDir() { return SourceDir() / "mjcf"; }

inline const std::vector<std::string>& RobotNames() {
  static const std::vector<std::string> kRobots = {"gecko", "spider"};
  return kRobots;
}
// The robots with active-release feet (the same robots with a short foot post: mjcf/README.md,
// "Active-release feet"). No viewer files of their own.
inline const std::vector<std::string>& VariantNames() {
  static const std::vector<std::string> kVariants = {"gecko_active", "spider_active"};
  return kVariants;
}
// Every robot file: the robots, their variants and their options.
inline const std::vector<std::string>& AllRobotNames() {
  static const std::vector<std::string> kAll = {"gecko",        "spider",      "gecko_active",
                                                "spider_active", "gecko_ankle", "spider_ankle"};
  return kAll;
}
// Options of the robots (mjcf/README.md, "Actuated ankles"): a robot file plus one servo per
// leg. They compose with every scene but have no viewer files.
inline const std::vector<std::string>& OptionRobotNames() {
  static const std::vector<std::string> kOptions = {"gecko_ankle", "spider_ankle"};
  return kOptions;
}
inline const std::vector<std::string>& SceneNames() {
  static const std::vector<std::string> kScenes = {"floor",           "wall",
                                                   "ceiling",         "incline",
                                                   "floor_to_wall",   "floor_to_wall_fillet",
                                                   "wall_to_ceiling", "wall_to_top"};
  return kScenes;
}
inline std::filesystem::path RobotFile(const std::string& robot) {
  return MjcfDir() / (robot + ".xml");
}
inline std::filesystem::path SceneFile(const std::string& scene) {
  return MjcfDir() / "scenes" / (scene + ".xml");
}

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

// Loads an MJCF file. On failure returns null and puts MuJoCo's message in *error; on
// success *error holds whatever MuJoCo wrote (warnings), normally "".
inline ModelPtr Load(const std::filesystem::path& path, std::string* error) {
  std::array<char, 1024> buffer{};
  mjModel* m = mj_loadXML(path.c_str(), nullptr, buffer.data(), static_cast<int>(buffer.size()));
  *error = buffer.data();
  return ModelPtr(m);
}

// A robot file held in memory (a generated design, tests/mjcf/design_robots.cc) under this
// robot name; nullptr: the robot is mjcf/<robot>.xml. Each test executable defines it.
const std::string* RobotText(const std::string& robot);

// The top file that the simulator generates: the scene and the robot included by absolute
// path (a robot held in memory by its bare name, from the VFS), then `extra`
// (equality/sensor/actuator sections) verbatim.
inline std::string TopFileXml(const std::string& robot, const std::string& scene,
                              const std::string& extra) {
  const std::string robot_file = RobotText(robot) ? robot + ".xml" : RobotFile(robot).string();
  return "<mujoco model=\"" + robot + "_" + scene + "\">\n" + "  <include file=\"" +
         SceneFile(scene).string() + "\"/>\n" + "  <include file=\"" + robot_file + "\"/>\n" +
         extra + "</mujoco>\n";
}

// Compiles MJCF held in memory: `files` (name, text) go into a MuJoCo VFS under bare names and
// the first is the top file; an <include> of another's name reads it from the VFS, any other
// include from the file system. Nothing is written to disk. *error as for Load.
inline ModelPtr LoadFromMemory(const std::vector<std::pair<std::string, std::string>>& files,
                               std::string* error) {
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  for (const auto& [name, text] : files) {
    if (mj_makeEmptyFileVFS(vfs.get(), name.c_str(), static_cast<int>(text.size())) != 0) {
      mj_deleteVFS(vfs.get());
      *error = "VFS full";
      return nullptr;
    }
    std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), name.c_str())], text.data(), text.size());
  }
  std::array<char, 1024> buffer{};
  mjModel* m = mj_loadXML(files.front().first.c_str(), vfs.get(), buffer.data(),
                          static_cast<int>(buffer.size()));
  mj_deleteVFS(vfs.get());
  *error = buffer.data();
  return ModelPtr(m);
}

// Loads the composed model. The top file goes into a MuJoCo VFS under a bare name: MuJoCo
// 2.2.2 prefixes every include path with the directory of the top file, even an absolute
// one, so a top file written to /some/dir/top.xml cannot include /abs/path/robot.xml. A
// VFS file name has no directory, and the includes are then read from the file system.
inline ModelPtr LoadComposed(const std::string& robot, const std::string& scene,
                             const std::string& extra, std::string* error) {
  std::vector<std::pair<std::string, std::string>> files = {
      {robot + "_" + scene + ".xml", TopFileXml(robot, scene, extra)}};
  if (const std::string* text = RobotText(robot)) files.emplace_back(robot + ".xml", *text);
  return LoadFromMemory(files, error);
}

// The robot file alone: mjcf/<robot>.xml, or the text RobotText holds.
inline ModelPtr LoadRobot(const std::string& robot, std::string* error) {
  if (const std::string* text = RobotText(robot))
    return LoadFromMemory({{robot + ".xml", *text}}, error);
  return Load(RobotFile(robot), error);
}

inline std::string Name(const mjModel* m, mjtObj type, int id) {
  const char* name = mj_id2name(m, type, id);
  return name ? std::string(name) : std::string();
}

// The custom text `name` (without its trailing NUL), or "" when absent.
inline std::string CustomText(const mjModel* m, const std::string& name) {
  const int id = mj_name2id(m, mjOBJ_TEXT, name.c_str());
  if (id < 0) return "";
  return std::string(m->text_data + m->text_adr[id]);
}

// Leg names from the custom text climbsim_legs ("LF RF LH RH").
inline std::vector<std::string> LegNames(const mjModel* m) {
  std::vector<std::string> legs;
  std::string text = CustomText(m, "climbsim_legs");
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find(' ', start);
    if (end == std::string::npos) end = text.size();
    if (end > start) legs.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return legs;
}

// The custom numeric `name` as a vector (empty when absent).
inline std::vector<double> CustomNumeric(const mjModel* m, const std::string& name) {
  const int id = mj_name2id(m, mjOBJ_NUMERIC, name.c_str());
  if (id < 0) return {};
  return std::vector<double>(m->numeric_data + m->numeric_adr[id],
                             m->numeric_data + m->numeric_adr[id] + m->numeric_size[id]);
}

// Total mass of every body except the world (kg).
inline double RobotMass(const mjModel* m) {
  double mass = 0;
  for (int b = 1; b < m->nbody; ++b) mass += m->body_mass[b];
  return mass;
}

// Lowest z (world) of the 8 corners of a box geom, from the current mjData kinematics.
inline double BoxLowestZ(const mjModel* m, const mjData* d, int geom) {
  const mjtNum* size = m->geom_size + 3 * geom;
  const mjtNum* pos = d->geom_xpos + 3 * geom;
  const mjtNum* mat = d->geom_xmat + 9 * geom;
  double lowest = 1e300;
  for (int corner = 0; corner < 8; ++corner) {
    const double local[3] = {(corner & 1 ? 1 : -1) * size[0], (corner & 2 ? 1 : -1) * size[1],
                             (corner & 4 ? 1 : -1) * size[2]};
    const double z = pos[2] + mat[6] * local[0] + mat[7] * local[1] + mat[8] * local[2];
    lowest = std::min(lowest, z);
  }
  return lowest;
}

// Sum of MuJoCo's warning counters (bad qacc, too many contacts, ...).
inline int WarningCount(const mjData* d) {
  int count = 0;
  for (int i = 0; i < mjNWARNING; ++i) count += d->warning[i].number;
  return count;
}

}  // namespace climbsim::mjcf_test

#endif  // CLIMBSIM_TESTS_MJCF_MJCF_TEST_UTIL_H_
