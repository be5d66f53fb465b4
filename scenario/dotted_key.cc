#include "scenario/dotted_key.h"

#include <cctype>
#include <charconv>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "common/common.h"
#include "scenario/archive.h"
#include "scenario/robot_key.h"
#include "scenario/scenario.h"

namespace climbsim::sim {
namespace {

// "a.b[1][2].c" → {a,{}}, {b,{1,2}}, {c,{}}.
struct Part {
  std::string key;
  std::vector<int> index;
};

// Built with append: GCC 12 warns falsely (-Wrestrict) on "'" + std::string + "'".
std::invalid_argument KeyError(std::string_view key, std::string_view what) {
  std::string m = "'";
  m.append(key).append("'").append(what);
  return std::invalid_argument(m);
}

std::vector<Part> Split(std::string_view key) {
  std::vector<Part> parts;
  size_t i = 0;
  while (i <= key.size()) {
    Part p;
    while (i < key.size() && key[i] != '.' && key[i] != '[') p.key += key[i++];
    if (p.key.empty()) throw KeyError(key, " is not a dotted key");
    while (i < key.size() && key[i] == '[') {
      const size_t close = key.find(']', i);
      if (close == std::string_view::npos) {
        throw KeyError(key, ": missing ']'");
      }
      int n = -1;
      auto r = std::from_chars(key.data() + i + 1, key.data() + close, n);
      if (r.ec != std::errc() || r.ptr != key.data() + close || n < 0) {
        throw KeyError(key, ": bad list index");
      }
      p.index.push_back(n);
      i = close + 1;
    }
    parts.push_back(std::move(p));
    if (i == key.size()) break;
    if (key[i] != '.') throw KeyError(key, " is not a dotted key");
    ++i;
  }
  return parts;
}

// A top-level key the file may give as a scalar, short for a map of one key ("scene: wall" is
// {name: wall}, "robot: gecko" is {preset: gecko}): setting a key under it writes the map out.
// A robot file's path has no keys to set.
void ExpandShorthand(YAML::Node root, const std::string& key) {
  static const std::pair<const char*, const char*> kShorthands[] = {{"scene", "name"},
                                                                    {"robot", "preset"}};
  if (!root.IsMap()) return;
  YAML::Node n = root[key];
  if (!n.IsDefined() || !n.IsScalar()) return;
  for (const auto& [top, inner] : kShorthands) {
    if (key != top) continue;
    const std::string value = n.Scalar();
    if (key == "robot" && IsRobotPath(value)) {
      throw std::invalid_argument("robot: the file's robot is an MJCF file (" + value +
                                  "); robot.* keys change a preset (robot: gecko) or a design");
    }
    YAML::Node map(YAML::NodeType::Map);
    map[inner] = value;
    root[key] = map;
  }
}

// Walks to the node a key names. With `create`, missing map keys are made (maps on the way,
// the last one null); list elements are never made: a tuned list must be written out.
YAML::Node Walk(YAML::Node root, std::string_view key, bool create) {
  const std::vector<Part> parts = Split(key);
  if (create && parts.size() > 1 && parts[0].index.empty()) ExpandShorthand(root, parts[0].key);
  YAML::Node cur;
  cur.reset(root);
  std::string done;
  for (size_t p = 0; p < parts.size(); ++p) {
    const Part& part = parts[p];
    done += (done.empty() ? "" : ".") + part.key;
    if (!cur.IsMap() && !(create && cur.IsNull())) {
      throw std::invalid_argument(done + ": the file has no map here");
    }
    YAML::Node next = cur[part.key];
    if (!next.IsDefined() || next.IsNull()) {
      if (!create || !part.index.empty()) {
        throw std::invalid_argument(
            done + " is not in the file" +
            (part.index.empty() ? "" : ": write the list out to tune one of its elements"));
      }
      if (p + 1 < parts.size()) cur[part.key] = YAML::Node(YAML::NodeType::Map);
      next.reset(cur[part.key]);
    }
    for (int n : part.index) {
      done.append("[").append(std::to_string(n)).append("]");
      if (!next.IsSequence() || n >= static_cast<int>(next.size())) {
        throw std::invalid_argument(done + " is not in the file");
      }
      YAML::Node element = next[n];
      next.reset(element);
    }
    cur.reset(next);
  }
  return cur;
}

void CollectKeys(const YAML::Node& n, const std::string& path, std::vector<std::string>* out) {
  if (n.IsMap()) {
    for (const auto& kv : n) {
      const std::string k = kv.first.Scalar();
      CollectKeys(kv.second, path.empty() ? k : path + "." + k, out);
    }
  } else if (n.IsSequence()) {
    for (size_t i = 0; i < n.size(); ++i) {
      CollectKeys(n[i], path + "[" + std::to_string(i) + "]", out);
    }
  } else if (!path.empty()) {
    out->push_back(path);
  }
}

// `inner` is `outer` or a key under it ("cpg.stride_rad[1]" is under "cpg.stride_rad" and
// under "cpg", not under "cpg.stride").
bool Under(std::string_view inner, std::string_view outer) {
  if (inner.substr(0, outer.size()) != outer) return false;
  return inner.size() == outer.size() || inner[outer.size()] == '.' ||
         inner[outer.size()] == '[';
}

// The value text as YAML: a flow list or map becomes its node; anything else stays the
// scalar text it is (so "1e-3" and "abc" reach the loader as the file would give them).
YAML::Node ValueNode(const std::string& value) {
  const size_t first = value.find_first_not_of(" \t");
  if (first != std::string::npos && (value[first] == '[' || value[first] == '{')) {
    try {
      return YAML::Load(value);
    } catch (const YAML::Exception& e) {
      throw std::invalid_argument("not a YAML list or map: " + e.msg);
    }
  }
  return YAML::Node(value);
}

std::vector<KeyOverride>& CommandLineKeysStorage() {
  static std::vector<KeyOverride> keys;
  return keys;
}

}  // namespace

void SetDottedKey(YAML::Node root, std::string_view key, double value) {
  // A key the file gives as text (cpg.gait: trot) takes no number.
  const YAML::Node n = Walk(root, key, /*create=*/true);
  if (n.IsDefined() && n.IsScalar()) {
    try {
      n.as<double>();
    } catch (const YAML::Exception&) {
      throw std::invalid_argument(std::string(key) + " holds text ('" + n.Scalar() +
                                  "'), not a number");
    }
  }
  SetDottedKeyText(root, key, ExactNumber(value));
}

void SetDottedKeyText(YAML::Node root, std::string_view key, const std::string& text) {
  YAML::Node n = Walk(root, key, /*create=*/true);
  if (n.IsDefined() && !n.IsNull() && !n.IsScalar()) {
    throw std::invalid_argument(std::string(key) + " is a list or a map, not a value");
  }
  n = text;
}

double GetDottedKey(const YAML::Node& root, std::string_view key) {
  YAML::Node n = Walk(YAML::Clone(root), key, /*create=*/false);
  try {
    return n.as<double>();
  } catch (const YAML::Exception&) {
    throw std::invalid_argument(std::string(key) + " is not a number");
  }
}


void SetDottedKeyNode(YAML::Node root, std::string_view key, const YAML::Node& value) {
  YAML::Node n = Walk(root, key, /*create=*/true);
  n = value;
}

YAML::Node GetDottedKeyNode(const YAML::Node& root, std::string_view key) {
  return YAML::Clone(Walk(YAML::Clone(root), key, /*create=*/false));
}

void RemoveDottedKey(YAML::Node root, std::string_view key) {
  Walk(YAML::Clone(root), key, /*create=*/false);  // throws when absent
  const size_t cut = key.find_last_of(".[");
  if (cut != std::string_view::npos && key[cut] == '[') {
    throw KeyError(key, ": a list item cannot be removed; set the whole list");
  }
  if (cut == std::string_view::npos) {
    root.remove(std::string(key));
    return;
  }
  YAML::Node parent = Walk(root, key.substr(0, cut), /*create=*/false);
  parent.remove(std::string(key.substr(cut + 1)));
}

std::vector<std::string> DottedKeys(const YAML::Node& root) {
  std::vector<std::string> keys;
  CollectKeys(root, "", &keys);
  return keys;
}

KeyOverride ParseKeyOverride(const std::string& text) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos) {
    throw InputError("--set " + text, 0, 0, "", "give KEY=VALUE (cpg.frequency_hz=0.8)");
  }
  KeyOverride o{text.substr(0, eq), text.substr(eq + 1)};
  try {
    Split(o.key);
  } catch (const std::invalid_argument& e) {
    throw InputError(o.Flag(), 0, 0, "", e.what());
  }
  return o;
}

void ApplyKeyOverrides(YAML::Node root, const std::vector<KeyOverride>& overrides,
                       const std::string& file) {
  if (overrides.empty()) return;
  for (const KeyOverride& o : overrides) {
    try {
      SetDottedKeyNode(root, o.key, ValueNode(o.value));
    } catch (const std::invalid_argument& e) {
      throw InputError(o.Flag(), 0, 0, "", std::string(e.what()) + " (in " + file + ")");
    }
  }
  try {
    ParseScenario(root, file);
  } catch (const InputError& e) {
    // The last override of a key wins, so it is the one to blame.
    for (auto o = overrides.rbegin(); o != overrides.rend(); ++o) {
      if (Under(e.key(), o->key) || Under(o->key, e.key())) {
        throw InputError(o->Flag(), 0, 0, e.key(), e.message());
      }
    }
    throw;
  }
}

void SetCommandLineKeys(std::vector<KeyOverride> overrides) {
  CommandLineKeysStorage() = std::move(overrides);
}

const std::vector<KeyOverride>& CommandLineKeys() { return CommandLineKeysStorage(); }

}  // namespace climbsim::sim
