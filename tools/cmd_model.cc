// climbsim model SCENARIO --out FILE [--scene]: the scenario's robot as one MJCF file (the
// generated robot of a preset or a design; with --scene, the whole model a run of it steps),
// and the design's mass and servos on the terminal.
#include <unistd.h>

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include "common/common.h"
#include "common/run_folder.h"
#include "robot/servos.h"
#include "sim/sim.h"
#include "tools/commands.h"

namespace climbsim::tools {
namespace {

// The first line of a file this verb writes: it names the scenario and holds the FNV-1a 64
// hash of the rest, so a later `climbsim model` knows the file as its own, unedited, and may
// replace it; any other file is the user's.
constexpr const char* kHeader = "<!-- climbsim model: ";

std::string HashText(std::string_view text) {
  char hex[17];
  std::snprintf(hex, sizeof(hex), "%016" PRIx64, common::Fnv1a64(text));
  return hex;
}

std::string WithHeader(const std::string& body, const std::string& scenario_path) {
  return std::string(kHeader) + "from " + scenario_path + ", fnv1a64 " + HashText(body) +
         " of what follows -->\n" + body;
}

// True when `path` holds what WithHeader wrote, unedited.
bool MadeByModel(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  const size_t eol = s.find('\n');
  if (!s.starts_with(kHeader) || eol == std::string::npos) return false;
  const std::string first = s.substr(0, eol);
  const size_t at = first.find("fnv1a64 ");
  return at != std::string::npos && first.compare(at + 8, 16, HashText(s.substr(eol + 1))) == 0;
}

// Refuses what CheckFileOutput refuses (through RunFolderAdditions, which records the file
// in a run folder's marker when --out lies in one), except an earlier output of this verb,
// which it may replace (`additions` stays empty then).
void CheckModelOutput(const std::string& out,
                      std::optional<sim::RunFolderAdditions>* additions) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_regular_file(fs::symlink_status(out, ec)) && MadeByModel(out)) {
    // A run's data file never holds the header, so it never gets here. In a run folder the
    // marker recorded it (with its hash) the first time: the additions accept and update it.
    const fs::path folder = fs::absolute(out, ec).parent_path();
    if (fs::exists(folder / sim::kRunMarker, ec)) {
      additions->emplace(std::vector<std::string>{out}, "--out");
    } else if (::access(folder.c_str(), W_OK | X_OK) != 0) {
      throw InputError(out, 0, 0, "--out", "cannot be written: its folder is not writable");
    }
    return;
  }
  if (fs::exists(fs::symlink_status(out, ec)) && !fs::is_directory(out, ec) &&
      !fs::is_symlink(fs::symlink_status(out, ec))) {
    throw InputError(out, 0, 0, "--out",
                     "exists, and is not a file climbsim model wrote (or it was edited since): "
                     "climbsim never overwrites a file it did not make; remove it or give "
                     "another name");
  }
  additions->emplace(std::vector<std::string>{out}, "--out");
}

// "8 x Hitec HS-35HD (stall 0.088 N·m)": the robot's servos grouped by catalogue part (a
// servo whose force limit is no catalogue part's stall torque: by its force limit).
void PrintServos(const mjModel* m) {
  std::map<std::string, int> count;
  for (int a = 0; a < m->nu; ++a) {
    if (m->actuator_trntype[a] != mjTRN_JOINT) continue;
    const double stall = m->actuator_forcerange[2 * a + 1];
    std::string part;
    for (const sim::ServoModel& s : sim::ServoCatalogue()) {
      if (std::abs(s.stall_torque_nm - stall) <= 1e-9 * s.stall_torque_nm) {
        part = std::string(s.part) + " (" + std::string(s.name) + ")";
      }
    }
    char text[160];
    std::snprintf(text, sizeof(text), "%s, stall %.4g N·m",
                  part.empty() ? "not in the catalogue" : part.c_str(), stall);
    ++count[text];
  }
  int total = 0;
  for (const auto& [what, n] : count) total += n;
  std::printf("  servos          %d\n", total);
  for (const auto& [what, n] : count) std::printf("    %2d x %s\n", n, what.c_str());
}

void RunModel(const std::string& scenario_path, const std::string& out, bool scene) {
  const sim::Scenario s = sim::LoadScenario(scenario_path);
  std::optional<sim::RunFolderAdditions> additions;
  CheckModelOutput(out, &additions);
  const auto model = sim::CompileScenario(s);
  std::string body;
  if (scene) {
    const sim::Simulation run(s, *model);  // the starting pose, as a run's model.xml has it
    body = run.world().Xml();
  } else {
    body = sim::RobotMjcf(s);
  }
  const std::filesystem::path folder = std::filesystem::absolute(out).parent_path();
  std::filesystem::create_directories(folder);  // as the run folders' verbs make theirs
  common::WriteFileAtomic(out, WithHeader(body, scenario_path));
  if (additions) additions->Commit();
  std::printf("climbsim model: %s%s\n", s.robot.c_str(), s.robot_design ? " (a design)" : "");
  std::printf("  mass            %.4f kg\n", model->robot().mass_kg);
  PrintServos(model->model());
  std::printf("  wrote           %s (%s; mujoco-simulate %s opens it)\n", out.c_str(),
              scene ? "robot, scene and climbsim's additions" : "the robot alone", out.c_str());
}

}  // namespace

void AddModelCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "model", "Write the scenario's robot (a preset, a design or a file) as one MJCF file");
  static std::string scenario_path, out;
  static bool scene = false;
  cmd->add_option("scenario", scenario_path, "scenario file (YAML; the robot key)")->required();
  AddSetOption(cmd);
  cmd->add_option("--out", out,
                  "the MJCF file to write: new, or an unedited one climbsim model wrote")
      ->required();
  cmd->add_flag("--scene", scene,
                "write the model a run steps (robot, scene, climbsim's welds, sensors and "
                "actuators, the starting pose) instead of the robot alone");
  cmd->footer(
      "Example:\n  climbsim model examples/gecko_wall.yaml --out gecko_wall_robot.xml\n"
      "  mujoco-simulate gecko_wall_robot.xml   (MuJoCo's viewer opens it)");
  cmd->callback([] { RunModel(scenario_path, out, scene); });
}

}  // namespace climbsim::tools
