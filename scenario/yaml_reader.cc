#include "scenario/yaml_reader.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "scenario/dotted_key.h"

namespace climbsim::sim {
namespace {

// What a node holds, for "expected a number, got a list".
std::string Shape(const YAML::Node& n) {
  if (n.IsSequence()) return "a list";
  if (n.IsMap()) return "a map";
  if (n.IsNull()) return "nothing";
  return "'" + n.Scalar() + "'";
}

}  // namespace

std::string ExactNumber(double v) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof(buf), v);
  return std::string(buf, r.ptr);
}

namespace {

// A walk of the tree as its readers see it: an alias is its anchor's node again, so each
// alias counts its whole subtree once more (12 levels of ten aliases are 10^12 nodes from a
// 900-byte file). Every list and map at most kMaxYamlListLength long, at most 64 deep, and
// at most kMaxYamlNodes nodes in all, counted as expanded; the walk stops at the first excess.
class ShapeCheck {
 public:
  explicit ShapeCheck(const std::string& file) : file_(file) {}

  void Walk(const YAML::Node& n, const std::string& key, int depth) {
    if (++nodes_ > kMaxYamlNodes) {
      Fail(n, key,
           "the file expands to more than " + std::to_string(kMaxYamlNodes) +
               " values (aliases repeat their anchor's whole content; a scenario holds a few "
               "hundred)");
    }
    // These two name no key, as they always have (tests and users match the messages).
    if (depth > 64) Fail(n, "", "nested more than 64 levels deep");
    if (!n.IsSequence() && !n.IsMap()) return;
    if (n.size() > kMaxYamlListLength) {
      Fail(n, "",
           std::string(n.IsMap() ? "a map of " : "a list of ") + std::to_string(n.size()) +
               (n.IsMap() ? " keys" : " items") + "; at most " +
               std::to_string(kMaxYamlListLength) + " are allowed");
    }
    size_t i = 0;
    for (const auto& item : n) {
      if (n.IsSequence()) {
        Walk(item, key + "[" + std::to_string(i++) + "]", depth + 1);
        continue;
      }
      const std::string k = key.empty() ? item.first.Scalar() : key + "." + item.first.Scalar();
      Walk(item.first, k, depth + 1);  // a key may be an alias too
      Walk(item.second, k, depth + 1);
    }
  }

 private:
  [[noreturn]] void Fail(const YAML::Node& n, const std::string& key, const std::string& what) {
    throw InputError(file_, n.Mark().line + 1, n.Mark().column + 1, key, what);
  }

  const std::string& file_;
  size_t nodes_ = 0;
};

}  // namespace

YAML::Node LoadYamlFile(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) throw InputError(path, 0, 0, "", "file not found");
  if (fs::is_directory(st)) {
    throw InputError(path, 0, 0, "", "is a folder, not a scenario file (give the .yaml file)");
  }
  // A file or a pipe (read up to the bound); a device never ends (/dev/zero) or waits.
  if (!fs::is_regular_file(st) && !fs::is_fifo(st)) {
    throw InputError(path, 0, 0, "", "is not a regular file (a device?); give a .yaml file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, 0, "", "cannot open file");
  // Read at most the bound and one byte more: a huge file is refused without reading it all.
  std::string text;
  char buf[65536];
  while (in && text.size() <= kMaxYamlFileBytes) {
    in.read(buf, sizeof(buf));
    text.append(buf, static_cast<size_t>(in.gcount()));
  }
  YAML::Node root = LoadYamlText(text, path);
  // Every scenario file a verb reads takes the command line's --set (none elsewhere).
  ApplyKeyOverrides(root, CommandLineKeys(), path);
  return root;
}

YAML::Node LoadYamlText(const std::string& text, const std::string& path) {
  if (text.size() > kMaxYamlFileBytes) {
    throw InputError(path, 0, 0, "",
                     "larger than " + std::to_string(kMaxYamlFileBytes / (1 << 20)) +
                         " MiB; a scenario file is a few kB");
  }
  try {
    std::vector<YAML::Node> docs = YAML::LoadAll(text);
    if (docs.size() > 1) {
      const YAML::Mark m = docs[1].Mark();
      throw InputError(path, m.line + 1, m.column + 1, "",
                       "a second YAML document ('---'): a scenario file holds one");
    }
    if (docs.empty() || docs[0].IsNull()) throw InputError(path, 1, 1, "", "file is empty");
    CheckYamlShape(docs[0], path);
    return docs[0];
  } catch (const YAML::ParserException& e) {
    throw InputError(path, e.mark.line + 1, e.mark.column + 1, "", "invalid YAML: " + e.msg);
  }
}

void CheckYamlShape(const YAML::Node& root, const std::string& file) {
  ShapeCheck(file).Walk(root, "", 0);
}

std::string ControlCharacterProblem(std::string_view text) {
  for (size_t i = 0; i < text.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 || c == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof(hex), "0x%02x", c);
      return std::string("must not contain control characters (") + hex + " at " +
             std::to_string(i) + ")";
    }
  }
  return "";
}

YamlMap::YamlMap(const YAML::Node& node, std::string file, std::string path)
    : node_(node), file_(std::move(file)), path_(std::move(path)), mark_(node.Mark()) {
  if (node_.IsDefined() && !node_.IsNull() && !node_.IsMap()) {
    throw InputError(file_, mark_.line + 1, mark_.column + 1, path_,
                     "expected a map of keys, got " + Shape(node_));
  }
  // yaml-cpp keeps the first of two equal keys silently; a repeated key is a mistake.
  std::set<std::string, std::less<>> seen;
  if (node_.IsMap()) {
    for (const auto& kv : node_) {
      const std::string k = kv.first.Scalar();
      if (!seen.insert(k).second) {
        const YAML::Mark m = kv.first.Mark();
        throw InputError(file_, m.line + 1, m.column + 1, KeyPath(k), "key appears twice");
      }
    }
  }
}

std::string YamlMap::KeyPath(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

InputError YamlMap::ErrorAt(const YAML::Node& node, std::string_view key,
                            const std::string& message) const {
  YAML::Mark m = node.IsDefined() ? node.Mark() : mark_;
  if (m.line < 0) m = mark_;
  return InputError(file_, m.line + 1, m.column + 1, KeyPath(key), message);
}

InputError YamlMap::Error(std::string_view key, const std::string& message) const {
  YAML::Node v;
  if (node_.IsMap()) {
    for (const auto& kv : node_) {
      if (kv.first.Scalar() == key) v = kv.second;
    }
  }
  return ErrorAt(v, key, message);
}

bool YamlMap::Has(std::string_view key) const {
  if (!node_.IsMap()) return false;
  for (const auto& kv : node_) {
    if (kv.first.Scalar() == key) return true;
  }
  return false;
}

YAML::Node YamlMap::Get(std::string_view key) {
  used_.insert(std::string(key));
  if (!node_.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
  for (const auto& kv : node_) {
    if (kv.first.Scalar() == key) return kv.second;
  }
  return YAML::Node(YAML::NodeType::Undefined);
}

double YamlMap::ToDouble(const YAML::Node& value, std::string_view key) const {
  if (!value.IsScalar()) throw ErrorAt(value, key, "expected a number, got " + Shape(value));
  double v;
  try {
    v = value.as<double>();
  } catch (const YAML::Exception&) {
    throw ErrorAt(value, key, "expected a number, got " + Shape(value));
  }
  if (!std::isfinite(v)) throw ErrorAt(value, key, "must be finite, got " + value.Scalar());
  return v;
}

double YamlMap::Double(std::string_view key, double default_value, Range range) {
  YAML::Node v = Get(key);
  if (!v.IsDefined() || v.IsNull()) return default_value;
  const double x = ToDouble(v, key);
  if (!range.Contains(x)) throw ErrorAt(v, key, range.Describe() + ", got " + v.Scalar());
  return x;
}

double YamlMap::RequiredDouble(std::string_view key, Range range) {
  if (!Has(key)) throw Error(key, "is required");
  // "key:" with nothing after it is null, which Double() reads as its default: not a value.
  if (const YAML::Node v = Get(key); v.IsNull()) throw ErrorAt(v, key, "is required, got nothing");
  return Double(key, 0.0, range);
}

int YamlMap::Int(std::string_view key, int default_value, int lo, int hi) {
  YAML::Node v = Get(key);
  if (!v.IsDefined() || v.IsNull()) return default_value;
  if (!v.IsScalar()) throw ErrorAt(v, key, "expected a whole number, got " + Shape(v));
  long long x;
  try {
    x = v.as<long long>();
  } catch (const YAML::Exception&) {
    throw ErrorAt(v, key, "expected a whole number, got " + Shape(v));
  }
  if (x < lo || x > hi) {
    throw ErrorAt(v, key,
                  "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                      v.Scalar());
  }
  return static_cast<int>(x);
}

bool YamlMap::Bool(std::string_view key, bool default_value) {
  YAML::Node v = Get(key);
  if (!v.IsDefined() || v.IsNull()) return default_value;
  const std::string s = v.IsScalar() ? v.Scalar() : "";
  if (s == "true") return true;
  if (s == "false") return false;
  throw ErrorAt(v, key, "expected true or false, got " + Shape(v));
}

std::string YamlMap::String(std::string_view key, const std::string& default_value) {
  YAML::Node v = Get(key);
  if (!v.IsDefined() || v.IsNull()) return default_value;
  if (!v.IsScalar()) throw ErrorAt(v, key, "expected text, got " + Shape(v));
  if (const std::string problem = ControlCharacterProblem(v.Scalar()); !problem.empty()) {
    throw ErrorAt(v, key, problem);
  }
  return v.Scalar();
}

std::string YamlMap::RequiredString(std::string_view key) {
  if (!Has(key)) throw Error(key, "is required");
  std::string s = String(key, "");
  if (s.empty()) throw Error(key, "must not be empty");
  return s;
}

std::string YamlMap::Choice(std::string_view key, const std::string& default_value,
                            const std::vector<std::string>& allowed) {
  YAML::Node v = Get(key);
  const std::string s = String(key, default_value);
  for (const auto& a : allowed) {
    if (a == s) return s;
  }
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
  throw ErrorAt(v, key, "must be one of " + list + ", got '" + s + "'");
}

std::vector<double> YamlMap::Doubles(std::string_view key,
                                     const std::vector<double>& default_value, size_t size,
                                     Range range) {
  YAML::Node v = Get(key);
  if (!v.IsDefined() || v.IsNull()) return default_value;
  if (!v.IsSequence() || v.size() == 0) {
    throw ErrorAt(v, key, "expected a list of numbers, got " + Shape(v));
  }
  if (size != 0 && v.size() != size) {
    throw ErrorAt(v, key, "expected " + std::to_string(size) + " numbers, got " +
                              std::to_string(v.size()));
  }
  std::vector<double> out;
  for (const auto& item : v) {
    const double x = ToDouble(item, key);
    if (!range.Contains(x)) throw ErrorAt(item, key, range.Describe() + ", got " + item.Scalar());
    out.push_back(x);
  }
  return out;
}

std::vector<std::vector<double>> YamlMap::Matrix(std::string_view key, size_t rows, size_t cols,
                                                 Range range) {
  YAML::Node v = Get(key);
  if (!v.IsSequence() || v.size() != rows) {
    throw ErrorAt(v, key,
                  "expected a list of " + std::to_string(rows) + " rows, got " + Shape(v));
  }
  std::vector<std::vector<double>> out;
  for (const auto& row : v) {
    if (!row.IsSequence() || row.size() != cols) {
      throw ErrorAt(row, key, "each row must hold " + std::to_string(cols) + " numbers");
    }
    std::vector<double> r;
    for (const auto& item : row) {
      const double x = ToDouble(item, key);
      if (!range.Contains(x)) {
        throw ErrorAt(item, key, range.Describe() + ", got " + item.Scalar());
      }
      r.push_back(x);
    }
    out.push_back(std::move(r));
  }
  return out;
}

YamlMap YamlMap::Map(std::string_view key) {
  YAML::Node v = Get(key);
  if (!v.IsDefined()) return YamlMap(YAML::Node(YAML::NodeType::Null), file_, KeyPath(key));
  return YamlMap(v, file_, KeyPath(key));
}

YAML::Node YamlMap::Raw(std::string_view key) { return Get(key); }

void YamlMap::CheckNoUnknownKeys() const {
  if (!node_.IsMap()) return;
  for (const auto& kv : node_) {
    const std::string k = kv.first.Scalar();
    if (used_.count(k) == 0) {
      const YAML::Mark m = kv.first.Mark();
      std::string known;
      for (const auto& u : used_) known += (known.empty() ? "" : ", ") + u;
      throw InputError(file_, m.line + 1, m.column + 1, KeyPath(k),
                       "unknown key (known here: " + known + ")");
    }
  }
}

}  // namespace climbsim::sim
