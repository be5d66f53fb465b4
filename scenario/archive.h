// One description of every scenario key, three uses. Each parameter struct has
//   template <class Archive> void Serialize(Archive* a) { a->Visit(Field{...}, &member); }
// (the pattern of Drake's YAML archives). YamlReadArchive fills the struct from a file with
// full validation; YamlWriteArchive emits the resolved scenario; DocArchive lists every
// key with its unit, default and meaning for docs/scenario.md. A struct may also define
//   void Validate(const Checker& c) const
// for rules that span several keys; the reader calls it after the struct's keys are read.
#ifndef CLIMBSIM_SCENARIO_ARCHIVE_H_
#define CLIMBSIM_SCENARIO_ARCHIVE_H_

#include <yaml-cpp/yaml.h>

#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "scenario/robot_key.h"
#include "scenario/yaml_reader.h"

namespace climbsim::sim {

// Where each key was read (dotted path → 1-based line and column), so that checks which
// need the compiled model (a gait that does not fit the leg count, a pad body that does not
// exist) can still point at the file's line.
struct SourcePlace {
  int line = 0;
  int column = 0;
};
using SourceMap = std::map<std::string, SourcePlace, std::less<>>;

// The Checker of a YAML map: raises an InputError at a key of the struct being read.
class YamlChecker : public Checker {
 public:
  explicit YamlChecker(const YamlMap* map) : map_(map) {}
  [[noreturn]] void Fail(std::string_view key, const std::string& message) const override {
    throw map_->Error(key, message);
  }
  bool Has(std::string_view key) const override { return map_->Has(key); }

 private:
  const YamlMap* map_;
};

class YamlWriteArchive;

// A parameter struct: it describes its keys to any archive.
template <class T>
concept HasSerialize = requires(T t, YamlWriteArchive* a) { t.Serialize(a); };

class YamlReadArchive {
 public:
  YamlReadArchive(YamlMap map, SourceMap* places) : map_(std::move(map)), places_(places) {}

  template <class T>
  void Read(T* value) {
    value->Serialize(this);
    if constexpr (requires(const T& t, const Checker& c) { t.Validate(c); }) {
      value->Validate(YamlChecker(&map_));
    }
    map_.CheckNoUnknownKeys();
  }

  void Visit(const Field& f, double* v) {
    Place(f);
    *v = f.required ? map_.RequiredDouble(f.key, f.range) : map_.Double(f.key, *v, f.range);
  }
  void Visit(const Field& f, std::optional<double>* v) {
    Place(f);
    // Absent or null ("key:" alone, as for every other key): the default, not 0.
    if (const YAML::Node n = map_.Raw(f.key); n.IsDefined() && !n.IsNull()) {
      *v = map_.Double(f.key, 0.0, f.range);
    }
  }
  void Visit(const Field& f, std::optional<int>* v) {
    Place(f);
    if (const YAML::Node n = map_.Raw(f.key); n.IsDefined() && !n.IsNull()) {
      int value = 0;
      Visit(f, &value);
      *v = value;
    }
  }
  void Choice(const Field& f, std::optional<std::string>* v,
              const std::vector<std::string>& allowed) {
    Place(f);
    if (const YAML::Node n = map_.Raw(f.key); n.IsDefined() && !n.IsNull()) {
      *v = map_.Choice(f.key, allowed.front(), allowed);
    }
  }
  void Visit(const Field& f, int* v) {
    Place(f);
    if (f.required && !map_.Has(f.key)) throw map_.Error(f.key, "is required");
    // The whole int range is allowed (seed: up to 2147483647, as documented).
    *v = map_.Int(f.key, *v, static_cast<int>(std::max(f.range.lo, -2147483648.0)),
                  static_cast<int>(std::min(f.range.hi, 2147483647.0)));
  }
  void Visit(const Field& f, bool* v) {
    Place(f);
    *v = map_.Bool(f.key, *v);
  }
  void Visit(const Field& f, std::string* v) {
    Place(f);
    *v = f.required ? map_.RequiredString(f.key) : map_.String(f.key, *v);
  }
  void Choice(const Field& f, std::string* v, const std::vector<std::string>& allowed) {
    Place(f);
    if (f.required && !map_.Has(f.key)) throw map_.Error(f.key, "is required");
    *v = map_.Choice(f.key, *v, allowed);
  }
  // A list of numbers; size 0 accepts any length (and absence keeps the default).
  void Visit(const Field& f, std::vector<double>* v, size_t size) {
    Place(f);
    if (f.required && (!map_.Has(f.key) || map_.Raw(f.key).IsNull())) {
      throw map_.Error(f.key, "is required");
    }
    *v = map_.Doubles(f.key, *v, size, f.range);
  }
  void Visit(const Field& f, std::vector<std::string>* v) {
    Place(f);
    YAML::Node n = map_.Raw(f.key);
    if (!n.IsDefined() || n.IsNull()) return;
    if (n.IsScalar()) {
      if (const std::string problem = ControlCharacterProblem(n.Scalar()); !problem.empty()) {
        throw map_.ErrorAt(n, f.key, problem);
      }
      *v = {n.Scalar()};
      return;
    }
    if (!n.IsSequence()) throw map_.ErrorAt(n, f.key, "expected a list of names");
    v->clear();
    for (const auto& item : n) {
      if (!item.IsScalar()) throw map_.ErrorAt(item, f.key, "expected a name");
      if (const std::string problem = ControlCharacterProblem(item.Scalar()); !problem.empty()) {
        throw map_.ErrorAt(item, f.key, problem);
      }
      v->push_back(item.Scalar());
    }
  }
  // A square or rectangular matrix given as a list of rows.
  void Visit(const Field& f, std::vector<std::vector<double>>* v) {
    Place(f);
    YAML::Node n = map_.Raw(f.key);
    if (!n.IsDefined() || n.IsNull()) return;
    const size_t rows = n.IsSequence() ? n.size() : 0;
    const size_t cols = rows > 0 && n[0].IsSequence() ? n[0].size() : 0;
    if (rows == 0 || cols == 0) throw map_.ErrorAt(n, f.key, "expected a list of rows of numbers");
    *v = map_.Matrix(f.key, rows, cols, f.range);
  }
  template <HasSerialize T>
  void Visit(const Field& f, T* nested) {
    Place(f);
    if (f.required && !map_.Has(f.key)) throw map_.Error(f.key, "is required");
    // A struct may accept a bare scalar as shorthand for one of its keys ("scene: wall").
    if constexpr (requires { T::kShorthandKey; }) {
      YAML::Node n = map_.Raw(f.key);
      if (n.IsDefined() && n.IsScalar()) {
        YAML::Node expanded(YAML::NodeType::Map);
        expanded[std::string(T::kShorthandKey)] = n;
        YamlReadArchive sub(YamlMap(expanded, map_.file(), map_.KeyPath(f.key)), places_);
        sub.Read(nested);
        return;
      }
    }
    YamlReadArchive sub(map_.Map(f.key), places_);
    sub.Read(nested);
  }
  // Absent keys keep the value they have (a scenario's blocks start absent: the effect is not
  // constructed; a robot design's parts start as its preset has them). A given block is read
  // over that value, or over the block's defaults when there was none.
  template <HasSerialize T>
  void Visit(const Field& f, std::optional<T>* nested) {
    Place(f);
    if (!map_.Has(f.key)) {
      map_.Raw(f.key);  // known key, absent
      return;
    }
    if (!nested->has_value()) nested->emplace();
    YamlReadArchive sub(map_.Map(f.key), places_);
    sub.Read(&**nested);
  }
  template <HasSerialize T>
  void Visit(const Field& f, std::vector<T>* list) {
    Place(f);
    YAML::Node n = map_.Raw(f.key);
    if (!n.IsDefined() || n.IsNull()) return;
    if (!n.IsSequence()) throw map_.ErrorAt(n, f.key, "expected a list");
    list->clear();
    for (size_t i = 0; i < n.size(); ++i) {
      T item;
      YamlReadArchive sub(YamlMap(n[i], map_.file(), map_.KeyPath(f.key) + "[" +
                                                         std::to_string(i) + "]"),
                          places_);
      sub.Read(&item);
      list->push_back(std::move(item));
    }
  }

  void Visit(const Field& f, RobotKey* robot);  // robot_key.cc

  const YamlMap& map() const { return map_; }

 private:
  void Place(const Field& f) {
    if (places_ == nullptr) return;
    YAML::Node n;
    if (map_.node().IsMap()) {
      for (const auto& kv : map_.node()) {
        if (kv.first.Scalar() == f.key) n = kv.second;
      }
    }
    const YAML::Mark m = n.IsDefined() ? n.Mark() : map_.node().Mark();
    (*places_)[map_.KeyPath(f.key)] = {m.line + 1, m.column + 1};
  }

  YamlMap map_;
  SourceMap* places_;
};

// Shortest text that reads back to the same double (std::to_chars), so a resolved scenario
// replays bit for bit without printing 0.1 as 0.10000000000000001.
std::string ExactNumber(double v);

class YamlWriteArchive {
 public:
  template <class T>
  static YAML::Node Write(const T& value) {
    YamlWriteArchive a;
    const_cast<T&>(value).Serialize(&a);
    return a.node_;
  }

  void Visit(const Field& f, double* v) { node_[std::string(f.key)] = ExactNumber(*v); }
  void Visit(const Field& f, std::optional<double>* v) {
    if (v->has_value()) node_[std::string(f.key)] = ExactNumber(**v);
  }
  void Visit(const Field& f, int* v) { node_[std::string(f.key)] = *v; }
  void Visit(const Field& f, std::optional<int>* v) {
    if (v->has_value()) node_[std::string(f.key)] = **v;
  }
  void Choice(const Field& f, std::optional<std::string>* v, const std::vector<std::string>&) {
    if (v->has_value()) node_[std::string(f.key)] = **v;
  }
  void Visit(const Field& f, bool* v) { node_[std::string(f.key)] = *v; }
  void Visit(const Field& f, std::string* v) { node_[std::string(f.key)] = *v; }
  void Choice(const Field& f, std::string* v, const std::vector<std::string>&) {
    node_[std::string(f.key)] = *v;
  }
  void Visit(const Field& f, std::vector<double>* v, size_t) {
    if (v->empty()) return;
    YAML::Node list(YAML::NodeType::Sequence);
    list.SetStyle(YAML::EmitterStyle::Flow);
    for (double x : *v) list.push_back(ExactNumber(x));
    node_[std::string(f.key)] = list;
  }
  void Visit(const Field& f, std::vector<std::string>* v) {
    if (v->empty()) return;
    YAML::Node list(YAML::NodeType::Sequence);
    list.SetStyle(YAML::EmitterStyle::Flow);
    for (const auto& x : *v) list.push_back(x);
    node_[std::string(f.key)] = list;
  }
  void Visit(const Field& f, std::vector<std::vector<double>>* v) {
    if (v->empty()) return;
    YAML::Node rows(YAML::NodeType::Sequence);
    for (const auto& r : *v) {
      YAML::Node row(YAML::NodeType::Sequence);
      row.SetStyle(YAML::EmitterStyle::Flow);
      for (double x : r) row.push_back(ExactNumber(x));
      rows.push_back(row);
    }
    node_[std::string(f.key)] = rows;
  }
  template <HasSerialize T>
  void Visit(const Field& f, T* nested) {
    node_[std::string(f.key)] = Write(*nested);
  }
  template <HasSerialize T>
  void Visit(const Field& f, std::optional<T>* nested) {
    if (nested->has_value()) node_[std::string(f.key)] = Write(**nested);
  }
  template <HasSerialize T>
  void Visit(const Field& f, std::vector<T>* list) {
    if (list->empty()) return;
    YAML::Node seq(YAML::NodeType::Sequence);
    for (const auto& item : *list) seq.push_back(Write(item));
    node_[std::string(f.key)] = seq;
  }
  void Visit(const Field& f, RobotKey* robot);  // robot_key.cc

 private:
  YAML::Node node_{YAML::NodeType::Map};
};

// Lists keys as rows "dotted.key | unit | default | allowed | meaning" for the docs.
struct DocArchive {
  struct Row {
    std::string key, unit, default_value, allowed, doc;
  };
  std::vector<Row> rows;
  std::string prefix;

  template <class T>
  static std::vector<Row> List(std::string prefix = "") {
    DocArchive a;
    a.prefix = std::move(prefix);
    T value{};
    value.Serialize(&a);
    return a.rows;
  }

  void Add(const Field& f, const std::string& def, std::string allowed = "") {
    if (allowed.empty() && (f.range.lo > -1e299 || f.range.hi < 1e299)) {
      allowed = f.range.Describe().substr(std::string("must be ").size());
    }
    if (f.required) allowed = "required" + (allowed.empty() ? "" : "; " + allowed);
    rows.push_back({prefix + std::string(f.key), std::string(f.unit), def, allowed,
                    std::string(f.doc)});
  }
  static std::string Num(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
  }
  void Visit(const Field& f, double* v) { Add(f, f.required ? "(none)" : Num(*v)); }
  void Visit(const Field& f, std::optional<double>*) { Add(f, "(see meaning)"); }
  void Visit(const Field& f, int* v) { Add(f, std::to_string(*v)); }
  void Visit(const Field& f, std::optional<int>*) { Add(f, "(see meaning)"); }
  void Choice(const Field& f, std::optional<std::string>*,
              const std::vector<std::string>& allowed) {
    std::string a;
    for (const auto& x : allowed) a += (a.empty() ? "" : ", ") + x;
    Add(f, "(see meaning)", a);
  }
  void Visit(const Field& f, bool* v) { Add(f, *v ? "true" : "false"); }
  void Visit(const Field& f, std::string* v) {
    Add(f, v->empty() || f.required ? "(none)" : *v);
  }
  void Choice(const Field& f, std::string* v, const std::vector<std::string>& allowed) {
    std::string a;
    for (const auto& x : allowed) a += (a.empty() ? "" : ", ") + x;
    Add(f, *v, a);
  }
  void Visit(const Field& f, std::vector<double>* v, size_t) {
    std::string s = "[";
    for (size_t i = 0; i < v->size(); ++i) s += (i ? ", " : "") + Num((*v)[i]);
    Add(f, v->empty() ? "(none)" : s + "]");
  }
  void Visit(const Field& f, std::vector<std::string>* v) {
    std::string s;
    for (const auto& x : *v) s += (s.empty() ? "" : ", ") + x;
    Add(f, s.empty() ? "(none)" : "[" + s + "]");
  }
  void Visit(const Field& f, std::vector<std::vector<double>>*) { Add(f, "(none)"); }
  template <HasSerialize T>
  void Visit(const Field& f, T*) {
    Add(f, "(map)");
    auto sub = List<T>(prefix + std::string(f.key) + ".");
    rows.insert(rows.end(), sub.begin(), sub.end());
  }
  template <HasSerialize T>
  void Visit(const Field& f, std::optional<T>*) {
    Add(f, "(absent: off)");
    auto sub = List<T>(prefix + std::string(f.key) + ".");
    rows.insert(rows.end(), sub.begin(), sub.end());
  }
  template <HasSerialize T>
  void Visit(const Field& f, std::vector<T>*) {
    Add(f, "(empty list)");
    auto sub = List<T>(prefix + std::string(f.key) + "[].");
    rows.insert(rows.end(), sub.begin(), sub.end());
  }
  void Visit(const Field& f, RobotKey* robot);  // robot_key.cc
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SCENARIO_ARCHIVE_H_
