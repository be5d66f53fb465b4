#include "scenario/scenario.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>

namespace climbsim::sim {
namespace {

namespace fs = std::filesystem;

bool IsPath(const std::string& s) {
  return s.find('/') != std::string::npos || s.ends_with(".xml");
}

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

}  // namespace

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
  if (IsPath(s.robot)) s.robot = Absolute(s.robot, file);
  if (!Exists(RobotFile(s))) {
    throw ScenarioError(s, "robot",
                        IsPath(s.robot) ? "file not found: " + s.robot
                                        : "no bundled robot '" + s.robot +
                                              "' (gecko, spider) at " + RobotFile(s));
  }
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
  return std::string("# Resolved scenario: every key, defaults filled in.\n") + out.c_str() +
         "\n";
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
