// DATA.csv of climbsim fit-adhesion: one measured pull-off a row, the angle convention in the
// column's name. Every error names the file, the line, the column and the column's name.
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include "common/common.h"
#include "experiments/fit_adhesion.h"

namespace climbsim::optimise {
namespace {

struct Column {
  const char* name;
  double lo, hi;  // allowed values (closed)
  const char* meaning;
};

// The columns a file may have; angle_from_normal_deg and force_n are required.
constexpr Column kColumns[] = {
    {"angle_from_normal_deg", 0, 180, "pull angle from the pad normal: 0 pulls straight off, 90 "
                                      "shears, over 90 pushes"},
    {"force_n", 0, 1e6, "measured pull-off force"},
    {"azimuth_deg", -360, 360, "azimuth of the pull's in-plane part, from pad +x towards +y"},
    {"pad_width_m", 1e-4, 1, "pad width"},
    {"pad_length_m", 1e-4, 1, "pad length"},
    {"lever_arm_m", 0, 1, "height of the pull point above the pad face"},
    {"preload_n", 0, 1e6, "preload before the pull"},
    {"repeat", 0, 1e6, "repeat index of the same condition"},
};

// A field with its column (1-based character position) on its line.
struct Field {
  std::string text;
  int column = 1;
};

std::vector<Field> Split(const std::string& line) {
  std::vector<Field> fields;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    const size_t end = comma == std::string::npos ? line.size() : comma;
    size_t a = start, b = end;
    while (a < b && std::isspace(static_cast<unsigned char>(line[a]))) ++a;
    while (b > a && std::isspace(static_cast<unsigned char>(line[b - 1]))) --b;
    fields.push_back(Field{line.substr(a, b - a), static_cast<int>(a) + 1});
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return fields;
}

bool Blank(const std::string& line) {
  for (char c : line) {
    if (c == '#') return true;
    if (!std::isspace(static_cast<unsigned char>(c))) return false;
  }
  return true;
}

// The header's columns: index of each known name. Refuses a bare or unknown angle.
std::map<std::string, int> ReadHeader(const std::string& file, int line_no,
                                      const std::vector<Field>& header) {
  std::map<std::string, int> index;
  for (size_t i = 0; i < header.size(); ++i) {
    const std::string& name = header[i].text;
    const auto fail = [&](const std::string& message) {
      throw InputError(file, line_no, header[i].column, name, message);
    };
    bool known = false;
    for (const Column& c : kColumns) known = known || name == c.name;
    if (!known && name.rfind("angle", 0) == 0) {
      fail("name the angle's convention: angle_from_normal_deg (0 pulls straight off the "
           "surface, 90 shears along it)");
    }
    if (!known) {
      std::string names;
      for (const Column& c : kColumns) names += std::string(names.empty() ? "" : ", ") + c.name;
      fail("unknown column; the columns are " + names);
    }
    if (index.count(name)) fail("column given twice");
    index[name] = static_cast<int>(i);
  }
  for (const char* required : {"angle_from_normal_deg", "force_n"}) {
    if (!index.count(required)) {
      throw InputError(file, line_no, 1, required, "the header must have this column");
    }
  }
  return index;
}

double Number(const std::string& file, int line_no, const Field& f, const Column& c) {
  const auto fail = [&](const std::string& m) { throw InputError(file, line_no, f.column, c.name, m); };
  if (f.text.empty()) fail("empty cell");
  char* end = nullptr;
  const double v = std::strtod(f.text.c_str(), &end);
  if (end != f.text.c_str() + f.text.size() || !std::isfinite(v)) {
    fail("not a number: '" + f.text + "'");
  }
  if (v < c.lo || v > c.hi) {
    fail(std::string("must be in [") + ShortNumber(c.lo) + ", " + ShortNumber(c.hi) + "] (" +
         c.meaning + "), got " + f.text);
  }
  if (std::string(c.name) == "repeat" && v != std::floor(v)) fail("must be a whole number");
  return v;
}

PulloffMeasurement ReadRow(const std::string& file, int line_no, const std::vector<Field>& f,
                           const std::map<std::string, int>& index, size_t columns,
                           double width_m, double length_m) {
  if (f.size() != columns) {
    throw InputError(file, line_no, f.back().column, "",
                     "has " + std::to_string(f.size()) + " cells, the header " +
                         std::to_string(columns));
  }
  std::map<std::string, double> v;
  for (const Column& c : kColumns) {
    const auto it = index.find(c.name);
    if (it != index.end()) v[c.name] = Number(file, line_no, f[it->second], c);
  }
  const auto get = [&](const char* name, double fallback) {
    const auto it = v.find(name);
    return it == v.end() ? fallback : it->second;
  };
  PulloffMeasurement m;
  m.angle_from_normal_deg = v["angle_from_normal_deg"];
  m.force_n = v["force_n"];
  m.azimuth_deg = get("azimuth_deg", 0.0);
  m.width_m = get("pad_width_m", width_m);
  m.length_m = get("pad_length_m", length_m > 0 ? length_m : m.width_m);
  m.arm_m = get("lever_arm_m", 0.0);
  m.preload_n = get("preload_n", 0.0);
  m.repeat = static_cast<int>(get("repeat", 0.0));
  m.line = line_no;
  if (!(m.width_m > 0.0)) {
    throw InputError(file, line_no, 1, "pad_width_m",
                     "no pad size: add the columns pad_width_m and pad_length_m, or give "
                     "--width-m (and --length-m)");
  }
  return m;
}

}  // namespace

PulloffData ReadPulloffCsv(const std::string& path, double width_m, double length_m) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, 0, "", "cannot read the file");
  PulloffData data;
  data.file = path;
  std::map<std::string, int> index;
  size_t columns = 0;
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (Blank(line)) continue;
    const std::vector<Field> fields = Split(line);
    if (columns == 0) {
      index = ReadHeader(path, line_no, fields);
      columns = fields.size();
      data.has_azimuth = index.count("azimuth_deg") > 0;
      data.has_repeat = index.count("repeat") > 0;
      continue;
    }
    data.rows.push_back(ReadRow(path, line_no, fields, index, columns, width_m, length_m));
  }
  if (columns == 0) throw InputError(path, 1, 1, "", "no header: the file is empty");
  if (data.rows.empty()) throw InputError(path, 0, 0, "", "no measurements after the header");
  return data;
}

}  // namespace climbsim::optimise
