#include "sim/world.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>
#include <utility>

#include "adhesion/adhesion.h"
#include "sim/terrain.h"

namespace climbsim::sim {
namespace {

// A path as an XML attribute value: & < > " and ' as entities (a folder may be named so).
std::string XmlAttribute(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// The value of `name="..."` in the first <compiler> element of an MJCF text, "" when none.
std::string CompilerAttribute(const std::string& text, const std::string& name) {
  for (size_t at = text.find("<compiler"); at != std::string::npos;
       at = text.find("<compiler", at + 1)) {
    const size_t end = text.find('>', at);
    const std::string element = text.substr(at, end == std::string::npos ? end : end - at);
    for (const char quote : {'"', '\''}) {
      const size_t key = element.find(" " + name + "=" + quote);
      if (key == std::string::npos) continue;
      const size_t from = key + name.size() + 3;
      const size_t to = element.find(quote, from);
      if (to != std::string::npos) return element.substr(from, to - from);
    }
  }
  return "";
}

// MuJoCo 2.2.2 resolves a relative meshdir and texturedir (and mesh files without one) against
// the top file's folder, which for the composed model is the working folder. A robot file
// outside the bundled folder gets them resolved against its own folder instead: a <compiler>
// after its include (the last one wins), with absolute paths.
std::string RobotAssetDirs(const std::string& robot_file) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(robot_file).parent_path();
  std::error_code ec;
  if (dir.empty() || fs::equivalent(dir, fs::path(MjcfDir()), ec)) return "";
  std::ifstream in(robot_file, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string attributes;
  for (const char* name : {"meshdir", "texturedir"}) {
    const fs::path given = CompilerAttribute(text, name);
    const fs::path resolved = given.is_absolute() ? given : (dir / given).lexically_normal();
    std::string value = resolved.string();
    if (!value.empty() && value.back() != '/') value += '/';
    attributes += std::string(" ") + name + "=\"" + XmlAttribute(value) + "\"";
  }
  return "  <compiler" + attributes + "/>\n";
}

std::string ReadMjcfFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// An attribute value with XML's five entities decoded (a folder may hold & or quotes).
std::string XmlUnescape(const std::string& text) {
  static const std::pair<const char*, char> kEntities[] = {
      {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
  std::string out;
  for (size_t i = 0; i < text.size();) {
    bool done = false;
    for (const auto& [entity, c] : kEntities) {
      if (text.compare(i, std::strlen(entity), entity) == 0) {
        out += c;
        i += std::strlen(entity);
        done = true;
        break;
      }
    }
    if (!done) out += text[i++];
  }
  return out;
}

// Index just past the comments, processing instructions and blanks before position i.
size_t SkipProlog(const std::string& xml, size_t i) {
  while (i < xml.size()) {
    if (std::isspace(static_cast<unsigned char>(xml[i]))) {
      ++i;
    } else if (xml.compare(i, 4, "<!--") == 0) {
      const size_t end = xml.find("-->", i + 4);
      i = end == std::string::npos ? xml.size() : end + 3;
    } else if (xml.compare(i, 2, "<?") == 0) {
      const size_t end = xml.find("?>", i + 2);
      i = end == std::string::npos ? xml.size() : end + 2;
    } else {
      break;
    }
  }
  return i;
}

// The children of an MJCF text's <mujoco> root, as written (`name` names it in messages).
std::string RootChildren(const std::string& xml, const std::string& path) {
  const size_t open = SkipProlog(xml, 0);
  if (xml.compare(open, 7, "<mujoco") != 0) {
    throw std::runtime_error(path + ": the root element is not <mujoco>");
  }
  const size_t open_end = xml.find('>', open);
  if (open_end == std::string::npos) throw std::runtime_error(path + ": unterminated <mujoco>");
  if (xml[open_end - 1] == '/') return "";  // <mujoco/>
  const size_t close = xml.rfind("</mujoco>");
  if (close == std::string::npos || close < open_end) {
    throw std::runtime_error(path + ": no </mujoco>");
  }
  return xml.substr(open_end + 1, close - open_end - 1);
}

// The children of an MJCF file's <mujoco> root, with its own includes expanded in turn
// (MuJoCo splices an included file's root children in place of the <include>).
std::string IncludedChildren(const std::string& path, int depth) {
  if (depth > 16) throw std::runtime_error("includes nested too deep at " + path);
  return ExpandIncludes(RootChildren(ReadMjcfFile(path), path),
                        std::filesystem::path(path).parent_path().string(), depth + 1);
}

// The composed model around the robot's part (an <include> of its file, or a generated
// robot's root children spliced in as ExpandIncludes would splice them).
std::string Compose(const std::string& robot_part, const std::string& scene_file,
                    const MjcfAdditions& add) {
  std::string xml = "<mujoco model=\"climbsim\">\n";
  xml += "  <include file=\"" + XmlAttribute(scene_file) + "\"/>\n";
  xml += robot_part;
  xml += add.top;
  if (!add.worldbody.empty()) xml += "  <worldbody>\n" + add.worldbody + "  </worldbody>\n";
  if (!add.contact.empty()) xml += "  <contact>\n" + add.contact + "  </contact>\n";
  if (!add.equality.empty()) xml += "  <equality>\n" + add.equality + "  </equality>\n";
  if (!add.actuator.empty()) xml += "  <actuator>\n" + add.actuator + "  </actuator>\n";
  if (!add.sensor.empty()) xml += "  <sensor>\n" + add.sensor + "  </sensor>\n";
  xml += "</mujoco>\n";
  return xml;
}

// Where each element <tag ...> of an MJCF text starts and ends (just past its '>'), comments
// left out.
std::vector<std::pair<size_t, size_t>> Elements(const std::string& xml, const std::string& tag) {
  std::vector<std::pair<size_t, size_t>> out;
  const std::string open = "<" + tag;
  for (size_t at = 0; at < xml.size();) {
    if (xml.compare(at, 4, "<!--") == 0) {
      const size_t end = xml.find("-->", at + 4);
      at = end == std::string::npos ? xml.size() : end + 3;
      continue;
    }
    const char next = at + open.size() < xml.size() ? xml[at + open.size()] : '\0';
    if (xml.compare(at, open.size(), open) != 0 ||
        !(std::isspace(static_cast<unsigned char>(next)) || next == '/' || next == '>')) {
      ++at;
      continue;
    }
    const size_t close = xml.find('>', at);
    if (close == std::string::npos) break;
    out.emplace_back(at, close + 1);
    at = close + 1;
  }
  return out;
}

// Where the value of attribute `name` of one element's text starts, and its length (as
// written, entities and all); npos when the element has none.
std::pair<size_t, size_t> FindAttribute(const std::string& element, const std::string& name) {
  for (size_t key = element.find(name); key != std::string::npos;
       key = element.find(name, key + 1)) {
    if (key == 0 || !std::isspace(static_cast<unsigned char>(element[key - 1]))) continue;
    size_t q = element.find_first_not_of(" \t\r\n", key + name.size());
    if (q == std::string::npos || element[q] != '=') continue;
    q = element.find_first_not_of(" \t\r\n", q + 1);
    if (q == std::string::npos || (element[q] != '"' && element[q] != '\'')) continue;
    const size_t end = element.find(element[q], q + 1);
    if (end == std::string::npos) break;
    return {q + 1, end - q - 1};
  }
  return {std::string::npos, 0};
}

// `file`'s name, or stem_2.ext, stem_3.ext ... when another file took it.
std::string UniqueName(const std::filesystem::path& file, std::set<std::string>* taken) {
  std::string name = file.filename().string();
  for (int k = 2; taken->count(name) > 0; ++k) {
    name = file.stem().string() + "_" + std::to_string(k) + file.extension().string();
  }
  taken->insert(name);
  return name;
}

}  // namespace

std::string ExpandIncludes(const std::string& xml, const std::string& base_dir, int depth) {
  // A plain scan (no std::regex: GCC 12 warns falsely inside it under the sanitizers):
  // comments are copied as they are, every <include file="..."/> is replaced.
  std::string out;
  size_t last = 0;
  for (size_t at = 0; at < xml.size();) {
    if (xml.compare(at, 4, "<!--") == 0) {
      const size_t end = xml.find("-->", at + 4);
      at = end == std::string::npos ? xml.size() : end + 3;
      continue;
    }
    const bool include = xml.compare(at, 8, "<include") == 0 && at + 8 < xml.size() &&
                         std::isspace(static_cast<unsigned char>(xml[at + 8]));
    if (!include) {
      ++at;
      continue;
    }
    const size_t close = xml.find('>', at);
    if (close == std::string::npos) throw std::runtime_error("unterminated <include");
    const std::string element = xml.substr(at, close + 1 - at);
    size_t key = element.find("file");
    while (key != std::string::npos &&
           !std::isspace(static_cast<unsigned char>(element[key - 1]))) {
      key = element.find("file", key + 1);
    }
    size_t q = key == std::string::npos ? key : element.find_first_not_of(" \t\r\n", key + 4);
    if (q != std::string::npos && element[q] == '=') {
      q = element.find_first_not_of(" \t\r\n", q + 1);
    } else {
      q = std::string::npos;
    }
    if (q == std::string::npos || (element[q] != '"' && element[q] != '\'')) {
      throw std::runtime_error("an <include> without file=\"...\": " + element);
    }
    const size_t q_end = element.find(element[q], q + 1);
    if (q_end == std::string::npos) throw std::runtime_error("unterminated file= in " + element);
    std::filesystem::path file = XmlUnescape(element.substr(q + 1, q_end - q - 1));
    if (file.is_relative() && !base_dir.empty()) file = std::filesystem::path(base_dir) / file;
    const std::string name = file.lexically_normal().string();
    out.append(xml, last, at - last);
    // The markers name the file only: model.xml holds no path of the machine it ran on.
    const std::string base = std::filesystem::path(name).filename().string();
    out += "<!-- climbsim: begin of " + base + " -->";
    out += IncludedChildren(name, depth);
    out += "<!-- climbsim: end of " + base + " -->";
    at = last = close + 1;
  }
  out.append(xml, last, std::string::npos);
  return out;
}

bool CustomNumeric(const mjModel* m, const char* name, int size, double* out) {
  const int id = mj_name2id(m, mjOBJ_NUMERIC, name);
  if (id < 0 || m->numeric_size[id] < size) return false;
  for (int i = 0; i < size; ++i) out[i] = m->numeric_data[m->numeric_adr[id] + i];
  return true;
}

std::string ComposeMjcf(const std::string& robot_file, const std::string& scene_file,
                        const MjcfAdditions& add) {
  return Compose("  <include file=\"" + XmlAttribute(robot_file) + "\"/>\n" +
                     RobotAssetDirs(robot_file),
                 scene_file, add);
}

std::string RobotMjcf(const Scenario& s) {
  const std::optional<RobotDesign> design = DesignOf(s);
  if (!design) return ReadMjcfFile(RobotFile(s));
  try {
    return GenerateRobotMjcf(*design);
  } catch (const std::invalid_argument& e) {
    throw ScenarioError(s, "robot", e.what());  // ParseScenario placed a design's refusals
  }
}

std::string ComposeScenarioMjcf(const Scenario& s, const MjcfAdditions& add) {
  if (!DesignOf(s)) return ComposeMjcf(RobotFile(s), SceneFile(s), add);
  // Marked as the preset's file would be: a preset's model.xml reads as it did from its file.
  const std::string name = s.robot + (s.robot_design ? " design" : ".xml");
  return Compose("  <!-- climbsim: begin of " + name + " -->" +
                     RootChildren(RobotMjcf(s), name) + "<!-- climbsim: end of " + name +
                     " -->\n",
                 SceneFile(s), add);
}

std::unique_ptr<CompiledModel> CompiledModel::Build(const Scenario& s,
                                                    const MjcfAdditions& additions) {
  std::unique_ptr<CompiledModel> c(new CompiledModel());
  std::string error;
  // Self-contained: what is compiled here is what the run folder's model.xml holds. A file
  // that cannot be read is reported at the robot key (its file and the scenario's line).
  try {
    c->xml_ = ExpandIncludes(ComposeScenarioMjcf(s, additions), "");
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw ScenarioError(s, "robot", e.what());
  }
  c->model_ = common::CompileMjcfString(c->xml_, &error);
  if (c->model_ == nullptr) {
    throw ScenarioError(s, "robot", "MuJoCo cannot load the model: " + error);
  }
  mjModel* m = c->model_;

  // The scene's own gravity and travel direction; the scenario's options apply per World.
  c->scene_.gravity = Eigen::Vector3d(m->opt.gravity[0], m->opt.gravity[1], m->opt.gravity[2]);
  double v[3];
  if (CustomNumeric(m, "climbsim_travel", 3, v))
    c->scene_.travel = Eigen::Vector3d(v[0], v[1], v[2]);
  if (CustomNumeric(m, "climbsim_spawn", 3, v)) {
    for (int i = 0; i < 3; ++i) c->spawn_offset_[i] = v[i];
  }

  // Robot contract (robot/robot.h); its messages name the robot key's file.
  try {
    c->robot_ = ReadRobot(m);
  } catch (const std::invalid_argument& e) {
    throw ScenarioError(s, "robot", e.what());
  }
  const RobotInfo& r = c->robot_;

  // Spawn: the robot file's base position moved by the scene's offset.
  for (int i = 0; i < 3; ++i) m->qpos0[r.root_qpos_adr + i] += c->spawn_offset_[i];
  FillTerrain(s, r, m);  // scene.terrain's heights (MJCF cannot carry them in MuJoCo 2.2.2)
  return c;
}

CompiledModel::~CompiledModel() {
  if (model_ != nullptr) mj_deleteModel(model_);
}

PhysicsParams PhysicsOf(const mjModel* m) {
  PhysicsParams p;
  p.timestep_s = m->opt.timestep;
  p.integrator = m->opt.integrator == mjINT_EULER ? "euler"
                 : m->opt.integrator == mjINT_RK4 ? "rk4"
                                                  : "implicit";
  p.solver_iterations = m->opt.iterations;
  p.solver_tolerance = m->opt.tolerance;
  p.noslip_iterations = m->opt.noslip_iterations;
  p.cone = m->opt.cone == mjCONE_ELLIPTIC ? "elliptic" : "pyramidal";
  p.impratio = m->opt.impratio;
  return p;
}

World::World(const CompiledModel& compiled, const Scenario& s)
    : compiled_(compiled), model_(mj_copyModel(nullptr, compiled.model())) {
  mjModel* m = model_;
  // Physics options: a key the scenario gives wins over the scene file's <option>.
  const PhysicsParams& p = s.physics;
  if (p.timestep_s) m->opt.timestep = *p.timestep_s;
  if (p.integrator) {
    m->opt.integrator = *p.integrator == "euler" ? mjINT_EULER
                        : *p.integrator == "rk4" ? mjINT_RK4
                                                 : mjINT_IMPLICIT;
  }
  if (p.solver_iterations) m->opt.iterations = *p.solver_iterations;
  if (p.solver_tolerance) m->opt.tolerance = *p.solver_tolerance;
  if (p.noslip_iterations) m->opt.noslip_iterations = *p.noslip_iterations;
  if (p.cone) m->opt.cone = *p.cone == "elliptic" ? mjCONE_ELLIPTIC : mjCONE_PYRAMIDAL;
  if (p.impratio) m->opt.impratio = *p.impratio;

  // Incline: rotate the scene's gravity about y so that uphill stays +x.
  gravity_ = compiled.scene().gravity;
  if (s.scene.name == "incline") {
    const double a = s.scene.incline_deg.value_or(30.0) * M_PI / 180.0;
    gravity_ = gravity_.norm() * Eigen::Vector3d(-std::sin(a), 0.0, -std::cos(a));
    for (int i = 0; i < 3; ++i) m->opt.gravity[i] = gravity_[i];
  }
  // Another body's gravity: the scene's direction (down, -z, for a scene without gravity).
  if (const std::optional<double> g = s.scene.GravityMagnitude()) {
    const Eigen::Vector3d down =
        gravity_.norm() > 0 ? Eigen::Vector3d(gravity_.normalized()) : Eigen::Vector3d(0, 0, -1);
    gravity_ = *g * down;
    for (int i = 0; i < 3; ++i) m->opt.gravity[i] = gravity_[i];
  }

  // Initial pose: the scenario's offset and yaw about +z, on this run's copy only.
  const int adr = compiled.robot().root_qpos_adr;
  if (adr >= 0) {
    double* q = m->qpos0 + adr;
    for (int i = 0; i < 3; ++i) q[i] += s.initial.offset_m[i];
    const double half_yaw = 0.5 * s.initial.yaw_deg * M_PI / 180.0;
    const double yaw_quat[4] = {std::cos(half_yaw), 0.0, 0.0, std::sin(half_yaw)};
    double rotated[4];
    mju_mulQuat(rotated, yaw_quat, q + 3);
    mju_copy4(q + 3, rotated);
  }
  // Payload: on the base body, spread like its own mass.
  const int base = compiled.robot().base_body;
  const bool payload = s.payload_kg > 0.0 && base >= 0;
  if (payload) {
    const double k = (m->body_mass[base] + s.payload_kg) / m->body_mass[base];
    m->body_mass[base] *= k;
    for (int i = 0; i < 3; ++i) m->body_inertia[3 * base + i] *= k;
  }
  data_ = mj_makeData(m);
  if (payload) mj_setConst(m, data_);
}

void World::MarkStart() {
  start_qpos_.assign(data_->qpos, data_->qpos + model_->nq);  // sized once: no allocation after
}

std::string World::Xml() const {
  const mjModel* m = model_;
  auto numbers = [](const double* v, int n) {
    std::string s;
    char buf[32];
    for (int i = 0; i < n; ++i) {
      if (i) s += ' ';
      // Shortest text that reads back as the same double.
      s.append(buf, std::to_chars(buf, buf + sizeof(buf), v[i]).ptr);
    }
    return s;
  };
  const char* integrator = m->opt.integrator == mjINT_EULER ? "Euler"
                           : m->opt.integrator == mjINT_RK4 ? "RK4"
                                                            : "implicit";
  std::string run =
      "  <!-- climbsim: this run's values (the scenario's physics options win over the files';\n"
      "       key climbsim_start is the state the run started from) -->\n";
  run += "  <option timestep=\"" + numbers(&m->opt.timestep, 1) + "\" gravity=\"" +
         numbers(m->opt.gravity, 3) + "\" integrator=\"" + integrator + "\" iterations=\"" +
         std::to_string(m->opt.iterations) + "\" tolerance=\"" + numbers(&m->opt.tolerance, 1) +
         "\" noslip_iterations=\"" + std::to_string(m->opt.noslip_iterations) + "\" cone=\"" +
         (m->opt.cone == mjCONE_ELLIPTIC ? "elliptic" : "pyramidal") + "\" impratio=\"" +
         numbers(&m->opt.impratio, 1) + "\"/>\n";
  const std::vector<double>& q =
      start_qpos_.empty() ? std::vector<double>(m->qpos0, m->qpos0 + m->nq) : start_qpos_;
  run += "  <keyframe>\n    <key name=\"climbsim_start\" qpos=\"" +
         numbers(q.data(), m->nq) + "\"/>\n  </keyframe>\n";
  std::string xml = compiled_.xml();
  const size_t close = xml.rfind("</mujoco>");
  xml.insert(close == std::string::npos ? xml.size() : close, run);
  return xml;
}

World::~World() {
  mj_deleteData(data_);
  mj_deleteModel(model_);
}

CarriedModel CarryMeshes(const std::string& xml) {
  namespace fs = std::filesystem;
  // What MuJoCo 2.2.2 reads: the last meshdir given + file (the file alone when absolute; the
  // composed model's own folder is the working folder), without its folders under strippath.
  const std::vector<std::pair<size_t, size_t>> compilers = Elements(xml, "compiler");
  std::string meshdir;
  bool strip = false;
  for (const auto& [begin, end] : compilers) {
    const std::string element = xml.substr(begin, end - begin);
    const auto [dir_at, dir_size] = FindAttribute(element, "meshdir");
    if (dir_at != std::string::npos) meshdir = XmlUnescape(element.substr(dir_at, dir_size));
    const auto [strip_at, strip_size] = FindAttribute(element, "strippath");
    if (strip_at != std::string::npos) strip = element.substr(strip_at, strip_size) == "true";
  }
  CarriedModel carried{xml, {}};
  std::vector<std::tuple<size_t, size_t, std::string>> edits;  // at, size, new value
  std::map<std::string, std::string> name_of;                  // source -> name in meshes/
  std::set<std::string> taken;
  for (const auto& [begin, end] : Elements(xml, "mesh")) {
    const std::string element = xml.substr(begin, end - begin);
    const auto [at, size] = FindAttribute(element, "file");
    if (at == std::string::npos) continue;  // vertices given inline
    fs::path file = XmlUnescape(element.substr(at, size));
    if (strip) file = file.filename();
    const fs::path source =
        (file.is_absolute() ? file : fs::absolute(fs::path(meshdir) / file)).lexically_normal();
    const auto [it, fresh] = name_of.emplace(source.string(), "");
    if (fresh) {
      it->second = UniqueName(file, &taken);
      carried.meshes.push_back({source.string(), it->second});
    }
    edits.emplace_back(begin + at, size, XmlAttribute(it->second));
  }
  if (carried.meshes.empty()) return carried;  // the text as it was, byte for byte
  for (const auto& [begin, end] : compilers) {
    const auto [at, size] = FindAttribute(xml.substr(begin, end - begin), "meshdir");
    if (at != std::string::npos) edits.emplace_back(begin + at, size, std::string(kRunMeshDir));
  }
  // Back to front, so that the positions before each edit hold.
  std::sort(edits.begin(), edits.end(),
            [](const auto& a, const auto& b) { return std::get<0>(a) > std::get<0>(b); });
  for (const auto& [at, size, value] : edits) carried.xml.replace(at, size, value);
  if (meshdir.empty()) {
    const std::vector<std::pair<size_t, size_t>> root = Elements(carried.xml, "mujoco");
    const size_t after = root.empty() ? 0 : root.front().second;
    carried.xml.insert(after, "\n  <compiler meshdir=\"" + std::string(kRunMeshDir) + "\"/>");
  }
  return carried;
}

std::string WithRunMeshes(const std::string& xml, const std::string& run_dir) {
  std::error_code ec;
  const std::filesystem::path meshes = std::filesystem::path(run_dir) / kRunMeshDir;
  if (!std::filesystem::is_directory(meshes, ec)) return xml;
  const std::string dir = std::filesystem::absolute(meshes, ec).string();
  std::string out = xml;
  const size_t close = out.rfind("</mujoco>");
  // MuJoCo takes the last meshdir given.
  out.insert(close == std::string::npos ? out.size() : close,
             "  <compiler meshdir=\"" + XmlAttribute(dir) + "\"/>\n");
  return out;
}

}  // namespace climbsim::sim
