// Reading and checking the files of a run directory.
#include <mujoco/mujoco.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "inspect/inspect.h"
#include "common/common.h"
#include "sim/world.h"

namespace climbsim::inspect {
namespace {

namespace fs = std::filesystem;

std::string ReadWholeFile(const std::string& path, const std::string& what) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    throw InputError(path, 0, 0, "", "missing file (" + what + ")");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, 0, "", "cannot be read");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// One line of a CSV file: its cells and where each starts (1-based character column).
struct CsvLine {
  int number = 0;
  std::vector<std::string_view> cells;
  std::vector<int> starts;
};

// A CSV file split into lines. Checks what every reader needs: the file is not empty, it
// ends with a newline (otherwise the last row was cut off), every row has as many cells as
// the header.
class CsvFile {
 public:
  CsvFile(std::string path, std::string what) : path_(std::move(path)) {
    text_ = ReadWholeFile(path_, what);
    if (text_.empty()) throw InputError(path_, 0, 0, "", "empty file (expected a header line)");
    size_t begin = 0;
    int number = 0;
    while (begin < text_.size()) {
      size_t end = text_.find('\n', begin);
      const bool has_newline = end != std::string::npos;
      if (!has_newline) end = text_.size();
      ++number;
      std::string_view line(text_.data() + begin, end - begin);
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      CsvLine l;
      l.number = number;
      size_t at = 0;
      while (true) {
        const size_t comma = line.find(',', at);
        l.starts.push_back(static_cast<int>(at) + 1);
        l.cells.push_back(
            line.substr(at, comma == std::string_view::npos ? line.npos : comma - at));
        if (comma == std::string_view::npos) break;
        at = comma + 1;
      }
      if (!has_newline) {
        const size_t expected = lines_.empty() ? l.cells.size() : lines_[0].cells.size();
        throw InputError(path_, number, 0, "",
                         "truncated row: the file ends inside it, without a newline (" +
                             std::to_string(l.cells.size()) + " of " + std::to_string(expected) +
                             " columns present; was the writer stopped?)");
      }
      lines_.push_back(std::move(l));
      begin = end + 1;
    }
    const size_t width = lines_[0].cells.size();
    for (size_t i = 1; i < lines_.size(); ++i) {
      if (lines_[i].cells.size() != width) {
        const bool blank = lines_[i].cells.size() == 1 && lines_[i].cells[0].empty();
        throw InputError(
            path_, lines_[i].number, 0, "",
            "wrong column count: expected " + std::to_string(width) +
                " columns as in the header, got " +
                (blank ? std::string("an empty line") : std::to_string(lines_[i].cells.size())));
      }
    }
  }

  const std::string& path() const { return path_; }
  const std::vector<CsvLine>& lines() const { return lines_; }
  std::string header() const {
    const CsvLine& h = lines_[0];
    std::string s;
    for (size_t i = 0; i < h.cells.size(); ++i) s.append(i ? "," : "").append(h.cells[i]);
    return s;
  }

  // The number in a cell; InputError at line:column with the column's name otherwise.
  double Number(const CsvLine& l, size_t c) const {
    const std::string_view cell = l.cells[c];
    double v = 0.0;
    const auto r = std::from_chars(cell.data(), cell.data() + cell.size(), v);
    if (cell.empty() || r.ec != std::errc() || r.ptr != cell.data() + cell.size()) {
      throw InputError(path_, l.number, l.starts[c], std::string(lines_[0].cells[c]),
                       "expected a number, got '" + std::string(cell) + "'");
    }
    // climbsim writes finite numbers only: nan or inf is damage (or an edit), not data.
    if (!std::isfinite(v)) {
      throw InputError(path_, l.number, l.starts[c], std::string(lines_[0].cells[c]),
                       "expected a finite number, got '" + std::string(cell) + "'");
    }
    return v;
  }

 private:
  std::string path_;
  std::string text_;
  std::vector<CsvLine> lines_;
};

// Rows must not go back in time (the writers append in step order).
void CheckTimeOrder(const std::string& path, int line, double previous, double now) {
  if (now < previous) {
    std::ostringstream m;
    m << "time goes backwards: " << now << " s after " << previous << " s on the line before";
    throw InputError(path, line, 1, "time_s", m.str());
  }
}


}  // namespace

double EventRow::shear_n() const { return std::hypot(fx_n, fy_n); }

std::string EventRow::cause_name() const {
  if (cause.empty()) return "unknown";
  return cause.substr(0, cause.find('='));
}

int NumericTable::Column(std::string_view name) const {
  for (size_t i = 0; i < columns.size(); ++i) {
    if (columns[i] == name) return static_cast<int>(i);
  }
  return -1;
}

std::vector<EventRow> ReadEvents(const std::string& path) {
  const CsvFile f(path, "the pad events of a run, written by climbsim simulate");
  if (f.header() != kEventsHeader) {
    throw InputError(
        path, 1, 0, "",
        "wrong header: expected '" + std::string(kEventsHeader) + "', got '" + f.header() + "'");
  }
  std::vector<EventRow> rows;
  rows.reserve(f.lines().size() - 1);
  double previous = -std::numeric_limits<double>::infinity();
  for (size_t i = 1; i < f.lines().size(); ++i) {
    const CsvLine& l = f.lines()[i];
    EventRow e;
    e.line = l.number;
    e.time_s = f.Number(l, 0);
    CheckTimeOrder(path, l.number, previous, e.time_s);
    previous = e.time_s;
    e.pad = l.cells[1];
    e.event = l.cells[2];
    e.cause = l.cells[3];
    e.surface = l.cells[4];
    if (e.pad.empty()) throw InputError(path, l.number, l.starts[1], "pad", "is empty");
    if (e.event.empty()) throw InputError(path, l.number, l.starts[2], "event", "is empty");
    e.bonded_fraction = f.Number(l, 5);
    e.fn_n = f.Number(l, 6);
    e.fx_n = f.Number(l, 7);
    e.fy_n = f.Number(l, 8);
    e.mx_nm = f.Number(l, 9);
    e.my_nm = f.Number(l, 10);
    rows.push_back(std::move(e));
  }
  return rows;
}

NumericTable ReadTrajectory(const std::string& path) {
  const CsvFile f(path, "the recorded state of a run, written by climbsim simulate");
  NumericTable t;
  t.path = path;
  for (std::string_view c : f.lines()[0].cells) t.columns.emplace_back(c);
  std::vector<std::string> leading;
  {
    std::string_view s = kTrajectoryLeadingColumns;
    for (size_t at = 0; at <= s.size();) {
      const size_t comma = std::min(s.find(',', at), s.size());
      leading.emplace_back(s.substr(at, comma - at));
      at = comma + 1;
    }
  }
  for (size_t i = 0; i < leading.size(); ++i) {
    if (i >= t.columns.size() || t.columns[i] != leading[i]) {
      throw InputError(path, 1, 0, "",
                       "wrong header: column " + std::to_string(i + 1) + " must be '" + leading[i] +
                           "', got '" +
                           (i < t.columns.size() ? t.columns[i] : std::string("(none)")) +
                           "' (the header starts " + std::string(kTrajectoryLeadingColumns) + ")");
    }
  }
  t.values.reserve((f.lines().size() - 1) * t.columns.size());
  double previous = -std::numeric_limits<double>::infinity();
  for (size_t i = 1; i < f.lines().size(); ++i) {
    const CsvLine& l = f.lines()[i];
    for (size_t c = 0; c < l.cells.size(); ++c) t.values.push_back(f.Number(l, c));
    const double time = t.values[t.values.size() - t.columns.size()];
    CheckTimeOrder(path, l.number, previous, time);
    previous = time;
  }
  if (t.rows() == 0) throw InputError(path, 1, 0, "", "no rows after the header");
  return t;
}

TextTable ReadTextCsv(const std::string& path) {
  const CsvFile f(path, "a table written by climbsim");
  TextTable t;
  t.path = path;
  for (std::string_view c : f.lines()[0].cells) {
    if (c.empty()) throw InputError(path, 1, 0, "", "wrong header: an empty column name");
    t.columns.emplace_back(c);
  }
  for (size_t i = 1; i < f.lines().size(); ++i) {
    std::vector<std::string> row;
    for (std::string_view c : f.lines()[i].cells) row.emplace_back(c);
    t.rows.push_back(std::move(row));
  }
  return t;
}

RunKind DetectRunKind(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    throw InputError(
        dir, 0, 0, "",
        fs::exists(dir, ec) ? "not a folder (expected a run directory)" : "no such folder");
  }
  if (fs::exists(fs::path(dir) / "events.csv", ec)) return RunKind::kSimulation;
  if (fs::exists(fs::path(dir) / "best.yaml", ec)) return RunKind::kOptimise;
  if (fs::exists(fs::path(dir) / "pulloff.csv", ec)) return RunKind::kPulloff;
  return RunKind::kSimulation;
}

const char* RunKindName(RunKind kind) {
  switch (kind) {
    case RunKind::kSimulation:
      return "simulation";
    case RunKind::kOptimise:
      return "optimise";
    case RunKind::kPulloff:
      return "pulloff";
  }
  return "";
}

int Run::LegIndex(std::string_view name) const {
  for (size_t i = 0; i < legs.size(); ++i) {
    if (legs[i] == name || pads[i] == name) return static_cast<int>(i);
  }
  return -1;
}

nlohmann::json ReadSummary(const std::string& path) {
  nlohmann::json summary;
  const std::string summary_text =
      ReadWholeFile(path, "written last by climbsim simulate: without it the run did not finish");
  const auto line_of = [&](size_t byte) {
    byte = std::min(byte, summary_text.size());
    return 1 +
           static_cast<int>(std::count(summary_text.begin(), summary_text.begin() + byte, '\n'));
  };
  try {
    summary = nlohmann::json::parse(summary_text);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(path, line_of(e.byte), 0, "", std::string("not valid JSON: ") + e.what());
  } catch (const nlohmann::json::exception& e) {
    // A number out of range ("number overflow parsing '1e400'"): the line of that number.
    const std::string what = e.what();
    const size_t q = what.find("parsing '");
    int line = 0;
    if (q != std::string::npos) {
      const size_t end = what.find('\'', q + 9);
      const std::string token = what.substr(q + 9, end == std::string::npos ? end : end - q - 9);
      const size_t at = token.empty() ? std::string::npos : summary_text.find(token);
      if (at != std::string::npos) line = line_of(at);
    }
    throw InputError(path, line, 0, "", "not valid climbsim JSON: " + what);
  }
  const size_t key = summary_text.find("\"duration_s\"");
  const int key_line = key == std::string::npos ? 0 : line_of(key);
  if (!summary.is_object() || !summary.contains("duration_s") ||
      !summary["duration_s"].is_number()) {
    throw InputError(path, key_line, 0, "duration_s", "missing or not a number");
  }
  // A run's simulated time: the window of every report is clipped to [0, duration_s].
  if (!(summary["duration_s"].get<double>() >= 0.0)) {
    throw InputError(path, key_line, 0, "duration_s",
                     "must be >= 0, got " + summary["duration_s"].dump());
  }
  return summary;
}

Run LoadRun(const std::string& dir_in) {
  std::string dir = dir_in;
  while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
  DetectRunKind(dir);  // the folder exists
  Run run;
  run.dir = dir;

  // summary.json: written last, so its absence means the run did not finish.
  run.summary = ReadSummary(dir + "/summary.json");
  run.duration_s = run.summary["duration_s"].get<double>();

  // model.xml: the legs (robot contract) and the scene's travel direction.
  const std::string model_path = dir + "/model.xml";
  // Compiled from its text: its meshes/ (if any) named by their place, as found now.
  run.model_xml =
      sim::WithRunMeshes(ReadWholeFile(model_path, "the composed model of the run"), dir);
  std::string error;
  mjModel* m = common::CompileMjcfString(run.model_xml, &error);
  if (m == nullptr) throw InputError(model_path, 0, 0, "", "MuJoCo cannot load it: " + error);
  const int legs_id = mj_name2id(m, mjOBJ_TEXT, "climbsim_legs");
  if (legs_id >= 0) {
    std::istringstream in(std::string(m->text_data + m->text_adr[legs_id]));
    for (std::string n; in >> n;) {
      run.legs.push_back(n);
      run.pads.push_back(n + "_pad");
    }
  }
  double v[3];
  if (sim::CustomNumeric(m, "climbsim_travel", 3, v)) {
    const Eigen::Vector3d t(v[0], v[1], v[2]);
    if (t.norm() > 0) run.travel = t.normalized();
  }
  mj_deleteModel(m);
  if (run.legs.empty()) {
    throw InputError(model_path, 0, 0, "",
                     "the robot has no custom text 'climbsim_legs' (mjcf/README.md, contract)");
  }

  // events.csv, every pad one of the robot's.
  const std::string events_path = dir + "/events.csv";
  run.events = ReadEvents(events_path);
  for (const EventRow& e : run.events) {
    if (run.LegIndex(e.pad) < 0) {
      std::string known;
      for (const auto& p : run.pads) known += (known.empty() ? "" : ", ") + p;
      throw InputError(events_path, e.line, 0, "pad",
                       "'" + e.pad + "' is not a pad of the robot (" + known + ")");
    }
  }

  // trajectory.csv: optional (outputs.trajectory_rate_hz: 0 records none).
  const std::string trajectory_path = dir + "/trajectory.csv";
  std::error_code ec;
  if (fs::exists(trajectory_path, ec)) run.trajectory = ReadTrajectory(trajectory_path);
  return run;
}

}  // namespace climbsim::inspect
