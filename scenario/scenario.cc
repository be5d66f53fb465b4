#include "scenario/scenario.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "scenario/dotted_key.h"

namespace climbsim::sim {
namespace {

namespace fs = std::filesystem;

bool IsPath(const std::string& s) { return IsRobotPath(s); }

// A path in the file is relative to the file's folder, so scenarios can travel with models.
std::string Absolute(const std::string& path, const std::string& scenario_file) {
  fs::path p(path);
  if (p.is_absolute()) return p.lexically_normal().string();
  return fs::absolute(fs::path(scenario_file).parent_path() / p).lexically_normal().string();
}

// fs::exists without the exception: a name the system refuses (too long, a component that is
// not a folder) is a file that is not there, and the loader says so with the key's place.
bool Exists(const std::string& path) {
  std::error_code error;
  return fs::exists(path, error);
}

const std::vector<std::string>& BuiltinScenes() {
  static const std::vector<std::string> k{"floor",         "wall",
                                          "ceiling",       "incline",
                                          "floor_to_wall", "floor_to_wall_fillet",
                                          "wall_to_ceiling", "wall_to_top"};
  return k;
}

// A generator's refusal "robot.legs.femur_m: why" as an InputError at that key's line (the
// nearest enclosing key the file gives when it does not give this one).
InputError DesignError(const Scenario& s, const std::string& what) {
  const size_t colon = what.find(": ");
  std::string key = colon == std::string::npos ? "robot" : what.substr(0, colon);
  const std::string why = colon == std::string::npos ? what : what.substr(colon + 2);
  if (key != "robot" && !key.starts_with("robot.")) key = "robot." + key;
  std::string place = key;
  while (!s.places.contains(place) && place.rfind('.') != std::string::npos) {
    place.resize(place.rfind('.'));
  }
  const auto it = s.places.find(place);
  const SourcePlace at = it == s.places.end() ? SourcePlace{} : it->second;
  return InputError(s.source_file, at.line, at.column, key, why);
}

// The robot exists before anything runs: a file is there, a name is a preset, a design
// builds.
void CheckRobot(Scenario* s, const std::string& file) {
  if (IsPath(s->robot)) {
    s->robot = Absolute(s->robot, file);
    if (!Exists(s->robot)) throw ScenarioError(*s, "robot", "file not found: " + s->robot);
    return;
  }
  if (!s->robot_design) {
    const std::vector<std::string> presets = PresetNames();
    std::string names;
    for (const auto& p : presets) names += (names.empty() ? "" : ", ") + p;
    if (std::find(presets.begin(), presets.end(), s->robot) == presets.end()) {
      throw ScenarioError(*s, "robot", "no bundled robot '" + s->robot + "' (" + names +
                                           ", or a path to an MJCF robot file)");
    }
    return;
  }
  try {
    GenerateRobotMjcf(*s->robot_design);
  } catch (const std::invalid_argument& e) {
    throw DesignError(*s, e.what());
  }
}

}  // namespace

std::vector<std::string> GravityBodies() {
  std::vector<std::string> names;
  for (const SurfaceGravity& g : kSurfaceGravity) names.emplace_back(g.body);
  return names;
}

std::string_view GravityBodiesDoc() {
  static const std::string doc = [] {
    std::string d = "gravity's magnitude as a body's surface gravity (";
    const char* separator = "";
    for (const SurfaceGravity& g : kSurfaceGravity) {
      char value[32];
      std::snprintf(value, sizeof value, "%g", g.m_s2);
      d += separator + std::string(g.body) + " " + value;
      separator = ", ";
    }
    return d + " m/s^2), along the scene's own direction; absent: the scene's (9.81)";
  }();
  return doc;
}

std::optional<double> SceneParams::GravityMagnitude() const {
  if (gravity_m_s2) return gravity_m_s2;
  if (!gravity) return std::nullopt;
  for (const SurfaceGravity& g : kSurfaceGravity) {
    if (g.body == *gravity) return g.m_s2;
  }
  return std::nullopt;  // the reader refuses other names
}

namespace {
std::string& PackageMjcfDir() {
  static std::string dir;
  return dir;
}
}  // namespace

void SetPackageMjcfDir(const char* dir) { PackageMjcfDir() = dir; }

std::string MjcfDir() {
  if (const char* env = std::getenv("CLIMBSIM_MJCF_DIR"); env != nullptr && *env != '\0') {
    return env;
  }
  // An installed package: the folder its climbsimConfig.cmake registered.
  if (!PackageMjcfDir().empty()) return PackageMjcfDir();
  std::error_code ec;
  if (std::filesystem::is_directory(CLIMBSIM_DEFAULT_MJCF_DIR, ec))
    return CLIMBSIM_DEFAULT_MJCF_DIR;
  // An installed climbsim tool: PREFIX/bin/climbsim → PREFIX/share/climbsim/mjcf.
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const std::filesystem::path installed = exe.parent_path().parent_path() / "share/climbsim/mjcf";
    if (std::filesystem::is_directory(installed, ec)) return installed.string();
  }
  return CLIMBSIM_DEFAULT_MJCF_DIR;
}

std::string RobotFile(const Scenario& s) {
  return IsPath(s.robot) ? s.robot : MjcfDir() + "/" + s.robot + ".xml";
}

std::optional<RobotDesign> DesignOf(const Scenario& s) {
  if (s.robot_design) return s.robot_design;
  if (IsPath(s.robot)) return std::nullopt;
  return PresetDesign(s.robot);
}

std::string SceneFile(const Scenario& s) {
  return IsPath(s.scene.name) ? s.scene.name : MjcfDir() + "/scenes/" + s.scene.name + ".xml";
}

InputError ScenarioError(const Scenario& s, const std::string& key, const std::string& message) {
  auto it = s.places.find(key);
  const SourcePlace place = it == s.places.end() ? SourcePlace{} : it->second;
  return InputError(s.source_file, place.line, place.column, key, message);
}

Scenario ParseScenario(const YAML::Node& root, const std::string& file) {
  // A tree from YAML::Load (Python, the fuzzer, tests) gets LoadYamlFile's bounds too: an
  // alias bomb would otherwise cost every later walk of the tree.
  CheckYamlShape(root, file);
  Scenario s;
  s.source_file = file;
  YamlReadArchive archive(YamlMap(root, file, ""), &s.places);
  archive.Read(&s);

  // Model files must exist before anything runs.
  CheckRobot(&s, file);
  if (IsPath(s.scene.name)) {
    s.scene.name = Absolute(s.scene.name, file);
  } else {
    bool known = false;
    std::string names;
    for (const auto& b : BuiltinScenes()) {
      known |= b == s.scene.name;
      names += (names.empty() ? "" : ", ") + b;
    }
    if (!known) {
      throw ScenarioError(s, "scene.name",
                          "no bundled scene '" + s.scene.name + "' (" + names + ")");
    }
  }
  if (!Exists(SceneFile(s))) {
    throw ScenarioError(s, "scene.name", "file not found: " + SceneFile(s));
  }
  if (s.scene.name == "incline") {
    if (!s.scene.incline_deg) s.scene.incline_deg = 30.0;
  } else if (s.scene.incline_deg) {
    throw ScenarioError(s, "scene.incline_deg", "applies to the incline scene only");
  }
  // A push that starts after the end of the run would silently never happen.
  for (size_t i = 0; i < s.perturbations.size(); ++i) {
    if (s.perturbations[i].time_s >= s.duration_s) {
      throw ScenarioError(s, "perturbations[" + std::to_string(i) + "].time_s",
                          "must be before the end of the run (duration_s " +
                              ExactNumber(s.duration_s) + " s), got " +
                              ExactNumber(s.perturbations[i].time_s));
    }
  }
  return s;
}

Scenario LoadScenario(const std::string& path) {
  if (!Exists(path)) throw InputError(path, 0, 0, "", "scenario file not found");
  return ParseScenario(LoadYamlFile(path), path);
}

YAML::Node ScenarioToYaml(const Scenario& scenario) {
  return YamlWriteArchive::Write(scenario);
}

std::string ScenarioToYamlText(const Scenario& scenario) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << ScenarioToYaml(scenario);
  std::string head = "# Resolved scenario: every key, defaults filled in.\n";
  for (const KeyOverride& o : CommandLineKeys()) head += "# with " + o.Flag() + "\n";
  return head + out.c_str() + "\n";
}

std::vector<DocArchive::Row> ScenarioKeys() { return DocArchive::List<Scenario>(); }

std::string ScenarioKeysMarkdown() {
  std::string out = "| key | unit | default | allowed | meaning |\n|---|---|---|---|---|\n";
  for (const auto& r : ScenarioKeys()) {
    out += "| `" + r.key + "` | " + r.unit + " | " + r.default_value + " | " + r.allowed +
           " | " + r.doc + " |\n";
  }
  return out;
}

}  // namespace climbsim::sim
