// One declaration per scenario key, walked from `climbsim keys` (the source of
// docs/scenario.md): the range it prints is the range the scenario reader enforces (a value
// just outside is refused at that key), the modules accept every value inside it (a bound
// builds a Simulation: no second, narrower range in a module), and the default it prints is
// the value a run resolves when the key is absent.
#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "experiments/experiments.h"
#include "sim/sim.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using testing::CliResult;
using testing::RunClimbsim;

struct KeyRow {
  std::string key, unit, def, allowed;
};

std::string Trim(const std::string& s) {
  const size_t a = s.find_first_not_of(' '), b = s.find_last_not_of(' ');
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// Rows "| `key` | unit | default | allowed | meaning |" of `climbsim keys`.
std::vector<KeyRow> KeyRows() {
  const CliResult r = RunClimbsim("keys");
  EXPECT_EQ(r.code, 0) << r.err;
  std::vector<KeyRow> rows;
  std::istringstream in(r.out);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("| `", 0) != 0) continue;
    const size_t key_end = line.find('`', 3);
    std::istringstream cells(line.substr(key_end + 1));
    std::string skip, unit, def, allowed;
    std::getline(cells, skip, '|');
    std::getline(cells, unit, '|');
    std::getline(cells, def, '|');
    std::getline(cells, allowed, '|');
    rows.push_back({line.substr(3, key_end - 3), Trim(unit), Trim(def), Trim(allowed)});
  }
  return rows;
}

std::optional<double> Number(const std::string& text) {
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size()) return std::nullopt;
  return v;
}

// The numeric range of an "allowed" cell ("in [0, 1]", "(0, 20]", "> 0", ">= 1", "<= 3").
struct Bounds {
  std::optional<double> lo, hi;
  bool lo_open = false, hi_open = false;
};
std::optional<Bounds> ParseBounds(std::string allowed) {
  if (allowed.rfind("required; ", 0) == 0) allowed = allowed.substr(10);
  Bounds b;
  if (allowed.rfind("in ", 0) == 0 && allowed.size() > 5) {
    const size_t comma = allowed.find(", ");
    if (comma == std::string::npos) return std::nullopt;
    b.lo_open = allowed[3] == '(';
    b.hi_open = allowed.back() == ')';
    b.lo = Number(allowed.substr(4, comma - 4));
    b.hi = Number(allowed.substr(comma + 2, allowed.size() - comma - 3));
    if (!b.lo || !b.hi) return std::nullopt;
    return b;
  }
  for (const char* op : {">= ", "> ", "<= ", "< "}) {
    if (allowed.rfind(op, 0) != 0) continue;
    const std::optional<double> v = Number(allowed.substr(std::string(op).size()));
    if (!v) return std::nullopt;
    if (op[0] == '>') {
      b.lo = v;
      b.lo_open = op[1] == ' ';
    } else {
      b.hi = v;
      b.hi_open = op[1] == ' ';
    }
    return b;
  }
  return std::nullopt;
}

// A scalar numeric key: its default is a number or "(see meaning)" (an optional number).
bool IsScalarNumber(const KeyRow& row) {
  return row.key.find("[]") == std::string::npos &&
         (Number(row.def).has_value() || row.def == "(see meaning)");
}

// A scenario with every optional block the keys live in: the floor-to-wall gecko (adhesion,
// cpg, reflex, transition, fall) with the wall gecko's optimise block.
YAML::Node BaseScenario() {
  const std::string dir = CLIMBSIM_SOURCE_DIR "/examples/";
  YAML::Node root = YAML::LoadFile(dir + "gecko_floor_to_wall.yaml");
  root["optimise"] = YAML::LoadFile(dir + "gecko_wall.yaml")["optimise"];
  root["duration_s"] = 0.5;
  if (root["scene"].IsScalar()) {  // the shorthand "scene: NAME" as a map, to set its keys
    YAML::Node scene(YAML::NodeType::Map);
    scene["name"] = root["scene"].Scalar();
    root["scene"] = scene;
  }
  return root;
}
const std::string kFile = CLIMBSIM_SOURCE_DIR "/examples/keys_declared_once.yaml";

std::string Text(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

// The reader's verdict on `key: value`: "" when accepted, else the key it refused.
std::string ReaderRefuses(const std::string& key, double value) {
  YAML::Node root = YAML::Clone(BaseScenario());
  optimise::SetDottedKeyText(root, key, Text(value));
  try {
    ParseScenario(root, kFile);
  } catch (const InputError& e) {
    return e.key().empty() ? std::string("(no key) ") + e.what() : e.key();
  }
  return "";
}

// Builds the run a value inside the range makes; "" when the modules accept it. Scene keys
// are tried on the incline, a plane scene where every one of them applies.
std::string ModulesRefuse(const std::string& key, double value) {
  YAML::Node root = YAML::Clone(BaseScenario());
  if (key.rfind("scene.", 0) == 0) {
    root["scene"]["name"] = "incline";
    root.remove("transition");  // a corner manoeuvre needs a corner
  }
  if (key.rfind("reflex.tail.", 0) == 0) {  // the tail reflex needs a robot with a tail
    root["robot"] = YAML::Load("{preset: gecko, tail: {yaw: true}}");
    root.remove("transition");  // which has no actuated ankles
  }
  optimise::SetDottedKeyText(root, key, Text(value));
  try {
    const Scenario s = ParseScenario(root, kFile);
    const auto model = CompileScenario(s);
    Simulation run(s, *model);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// Just past a bound: far enough that the table's six printed digits cannot hide it.
double Outside(double bound, bool below) {
  const double step = std::max(std::abs(bound) * 1e-3, 1e-6);
  return below ? bound - step : bound + step;
}

TEST(KeysDeclaredOnce, TheReaderRefusesAValueJustOutsideEachRangeAtItsKey) {
  int checked = 0;
  for (const KeyRow& row : KeyRows()) {
    if (!IsScalarNumber(row)) continue;
    const std::optional<Bounds> b = ParseBounds(row.allowed);
    if (!b) continue;
    if (b->lo) {
      EXPECT_EQ(ReaderRefuses(row.key, Outside(*b->lo, true)), row.key) << row.allowed;
      ++checked;
    }
    if (b->hi) {
      EXPECT_EQ(ReaderRefuses(row.key, Outside(*b->hi, false)), row.key) << row.allowed;
      ++checked;
    }
  }
  EXPECT_GT(checked, 200);
}

// Keys whose bound is refused by a rule that spans keys (the rule names why), not by a second
// range: the bound is still inside the key's own range.
const std::map<std::string, std::string> kRuleAtBound = {
    {"scene.roughness.size_m", "a bump's top is at most its grid pitch (spacing_m)"},
    {"scene.terrain.correlation_m", "at least two pitches of the height grid (grid_m)"},
    {"adhesion.min_bonds", "at most the bonds a pad has (grid_x * grid_y)"},
    {"optimise.max_evaluations", "at least one evaluation per start"},
    {"optimise.starts", "at most max_evaluations starts"},
    {"robot.body.hip_x_m", "pads of neighbouring legs must not overlap (robot.pads.size_m)"},
    {"robot.legs.count", "the scenario's gait is a 4-leg gait (cpg.gait)"},
    {"robot.feet.post_m", "longer than the pad is thick (robot.pads.thickness_m)"},
    {"robot.pads.foam_m", "leaves the adhesive's 0.5 mm of the pad (robot.pads.thickness_m)"},
    {"robot.legs.coxa_m", "pads of neighbouring legs must not overlap (robot.body.hip_x_m)"},
    {"robot.legs.tibia_inset_m", "pads of neighbouring legs must not overlap (robot.body.hip_x_m)"},
    {"robot.pads.size_m", "pads of neighbouring legs must not overlap (robot.body.hip_x_m)"},
    {"robot.legs.femur_rise_m", "the body stays above the surface (robot.legs.tibia_m)"},
    {"robot.body.spine.joint_x_m", "strictly between the hind and front hips (robot.body.hip_x_m)"},
    {"cpg.spine.amplitude_rad", "a robot with a spine (robot.body.spine)"},
    {"cpg.spine.phase_rad", "a robot with a spine (robot.body.spine)"},
};

TEST(KeysDeclaredOnce, TheModulesAcceptEveryClosedBoundOfEachRange) {
  int checked = 0;
  for (const KeyRow& row : KeyRows()) {
    if (!IsScalarNumber(row) || kRuleAtBound.count(row.key)) continue;
    const std::optional<Bounds> b = ParseBounds(row.allowed);
    if (!b) continue;
    for (const auto& [bound, open] : {std::pair{b->lo, b->lo_open}, std::pair{b->hi, b->hi_open}}) {
      if (!bound || open) continue;
      EXPECT_EQ(ModulesRefuse(row.key, *bound), "") << row.key << " = " << *bound;
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(KeysDeclaredOnce, TheDocumentedDefaultIsTheResolvedValueOfEveryAbsentKey) {
  const YAML::Node base = BaseScenario();
  const YAML::Node resolved = ScenarioToYaml(ParseScenario(base, kFile));
  int checked = 0;
  for (const KeyRow& row : KeyRows()) {
    const std::optional<double> def = Number(row.def);
    if (!def || row.key.find("[]") != std::string::npos) continue;
    bool given = true;
    try {
      optimise::GetDottedKey(base, row.key);
    } catch (const std::exception&) {
      given = false;
    }
    if (given) continue;
    double value = 0;
    try {
      value = optimise::GetDottedKey(resolved, row.key);
    } catch (const std::exception& e) {
      continue;  // a block the base does not enable (scene.roughness): not resolved
    }
    EXPECT_NEAR(value, *def, 1e-5 * std::max(1.0, std::abs(*def))) << row.key;
    ++checked;
  }
  EXPECT_GT(checked, 120);
}

}  // namespace
}  // namespace climbsim::sim
