// The per-leg table, the events of one leg, and pulloff.csv, as text and as JSON.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <set>

#include "inspect/inspect.h"
#include "common/common.h"

namespace climbsim::inspect {
namespace {

constexpr const char* kCli = "climbsim inspect";

std::string Num(double v, const char* format = "%.3f") {
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  return buf;
}

// The window clipped to the run; InputError when nothing is left.
std::pair<double, double> Clip(const Run& run, const Window& w) {
  if (!(w.from_s < w.to_s)) {
    throw InputError(
        kCli, 0, 0, "--from",
        "must be below --to, got " + Num(w.from_s, "%g") + " and " + Num(w.to_s, "%g"));
  }
  const double a = std::max(w.from_s, 0.0), b = std::min(w.to_s, run.duration_s);
  if (!(a < b)) {
    throw InputError(kCli, 0, 0, w.from_s > 0 ? "--from" : "--to",
                     "the window " + Num(w.from_s, "%g") + " .. " + Num(w.to_s, "%g") +
                         " s holds none of the run (0 .. " + Num(run.duration_s, "%g") + " s)");
  }
  return {a, b};
}

int LegOrThrow(const Run& run, std::string_view leg) {
  const int i = run.LegIndex(leg);
  if (i < 0) {
    std::string known;
    for (const auto& l : run.legs) known += (known.empty() ? "" : ", ") + l;
    throw InputError(kCli, 0, 0, "--leg",
                     "'" + std::string(leg) + "' is not a leg of the robot (" + known + ")");
  }
  return i;
}

nlohmann::json Optional(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

void Max(std::optional<double>* v, double x) {
  if (!*v || x > **v) *v = x;
}
void Min(std::optional<double>* v, double x) {
  if (!*v || x < **v) *v = x;
}

std::string SummaryText(const Run& run, const char* key) {
  const auto it = run.summary.find(key);
  return it != run.summary.end() && it->is_string() ? it->get<std::string>() : "?";
}

nlohmann::json WindowJson(double a, double b) {
  return {{"from_s", a}, {"to_s", b}, {"observed_s", b - a}};
}

// A stance over the whole run (attach .. detach, or .. the run's end when still open),
// before it is clipped to the window.
struct RawStance {
  double start, end;
  bool closed;
  std::string cause;
};

// One pad's events followed in order over the whole run, the window [a, b] counted.
struct LegScan {
  double a = 0.0, b = 0.0;
  LegReport* r = nullptr;
  std::vector<RawStance> raw;
  std::vector<const EventRow*> rows;  // the open stance's rows, kept for its loads
  bool attached = false;
  double start = 0.0;
  // A touchdown in the window still waiting to attach or be rejected.
  bool pending_touchdown = false;
};

// Loads while attached: every row of the stance in the window; bonded fraction: those
// before the detach's own step.
void TakeLoads(const LegScan& s, double detach_time) {
  for (const EventRow* e : s.rows) {
    if (e->time_s < s.a || e->time_s > s.b) continue;
    Max(&s.r->peak_normal_n, e->fn_n);
    Max(&s.r->peak_shear_n, e->shear_n());
    if (e->time_s < detach_time) Min(&s.r->lowest_bonded_fraction, e->bonded_fraction);
  }
}

// A touchdown in the window that neither attached nor was rejected, and why: the pad
// touched again (it left the surface inside the attach window, before its contacts and
// preload met the attach conditions), or the run ended during the touch.
void Unanswered(LegScan* s, const char* why) {
  ++s->r->unanswered_touchdowns;
  ++s->r->unanswered_by[why];
  s->pending_touchdown = false;
}

// Counts an event inside the window by its kind (and cause).
void CountInWindow(const EventRow& e, LegScan* s) {
  LegReport& r = *s->r;
  if (e.event == "touchdown") {
    ++r.touchdowns;
    s->pending_touchdown = true;
  } else if (e.event == "attach") {
    ++r.attachments;
  } else if (e.event == "attach_rejected") {
    ++r.rejected;
    ++r.rejected_by[e.cause_name()];
  } else if (e.event == "detach") {
    ++r.detaches;
    ++r.detached_by[e.cause.empty() ? "unknown" : e.cause];
  } else if (e.event == "bonds_lost") {
    ++r.bonds_lost_steps;
  } else {
    ++r.reflexes[e.event];
  }
}

// Opens a stance at the first attach, keeps its rows, closes it (and takes its loads) at
// the detach; stances are followed over the whole run so the window can clip them.
void FollowStance(const EventRow& e, LegScan* s) {
  if (e.event == "attach" && !s->attached) {
    s->attached = true;
    s->start = e.time_s;
    s->rows.clear();
  }
  if (s->attached) s->rows.push_back(&e);
  if (e.event == "detach" && s->attached) {
    s->raw.push_back({s->start, e.time_s, true, e.cause});
    TakeLoads(*s, e.time_s);
    s->attached = false;
  }
}

// The leg's counts and loads in the window, and its stances over the whole run.
std::vector<RawStance> ScanLegEvents(const Run& run, double a, double b, LegReport* r) {
  LegScan s;
  s.a = a;
  s.b = b;
  s.r = r;
  for (const EventRow& e : run.events) {
    if (e.pad != r->pad) continue;
    if (e.event == "touchdown" && s.pending_touchdown) Unanswered(&s, "left_within_attach_window");
    if (e.event == "attach" || e.event == "attach_rejected") s.pending_touchdown = false;
    if (e.time_s >= a && e.time_s <= b) CountInWindow(e, &s);
    FollowStance(e, &s);
  }
  if (s.pending_touchdown) Unanswered(&s, "run_ended_during_touch");
  if (s.attached) {
    s.raw.push_back({s.start, run.duration_s, false, ""});
    TakeLoads(s, std::numeric_limits<double>::infinity());
  }
  return std::move(s.raw);
}

// The stances clipped to the window [a, b]: attached time, complete stances' mean and
// shortest, duty factor.
void ClipStances(const std::vector<RawStance>& raw, double a, double b, double observed_s,
                 LegReport* r) {
  double sum_complete = 0.0;
  for (const RawStance& s : raw) {
    if (s.end < a || s.start > b) continue;
    Stance c;
    c.start_s = std::max(s.start, a);
    c.end_s = std::min(s.end, b);
    c.open_start = s.start < a;
    c.open_end = !s.closed || s.end > b;
    c.end_cause = c.open_end ? "" : s.cause;
    r->attached_s += c.length_s();
    if (!c.open_start && !c.open_end) {
      ++r->complete_stances;
      sum_complete += c.length_s();
      Min(&r->shortest_stance_s, c.length_s());
    }
    r->stances.push_back(c);
  }
  if (r->complete_stances > 0) r->mean_stance_s = sum_complete / r->complete_stances;
  r->duty_factor = r->attached_s / observed_s;
}

// The pad's peels: from each `peel` event to its next `peel_end` or `detach`, over the run.
std::vector<std::pair<double, double>> PeelIntervals(const Run& run, const std::string& pad,
                                                     double end_s) {
  std::vector<std::pair<double, double>> peels;
  bool open = false;
  for (const EventRow& e : run.events) {
    if (e.pad != pad) continue;
    if (e.event == "peel" && !open) {
      peels.push_back({e.time_s, end_s});
      open = true;
    } else if (open && (e.event == "peel_end" || e.event == "detach")) {
      peels.back().second = e.time_s;
      open = false;
    }
  }
  return peels;
}

bool Inside(const std::vector<std::pair<double, double>>& spans, double t) {
  for (const auto& [start, end] : spans) {
    if (t >= start && t < end) return true;
  }
  return false;
}

// Peak utilisation from trajectory.csv, when the run has the column, and its split into
// stance rows (attached, not peeling) and peel rows (attached, peeling).
void TakePeakUtilisation(const Run& run, const std::vector<RawStance>& raw, double a, double b,
                         LegReport* r) {
  const int u = run.trajectory ? run.trajectory->Column(r->pad + "_utilisation") : -1;
  if (u < 0) return;
  const auto& t = *run.trajectory;
  std::vector<std::pair<double, double>> stances;
  for (const RawStance& s : raw) stances.push_back({s.start, s.end});
  const auto peels = PeelIntervals(run, r->pad, run.duration_s);
  std::vector<double> stance_values;
  for (size_t row = 0; row < t.rows(); ++row) {
    const double time = t.at(row, 0), value = t.at(row, u);
    if (time < a || time > b) continue;
    Max(&r->peak_utilisation, value);
    if (!Inside(stances, time)) continue;
    if (Inside(peels, time)) {
      Max(&r->utilisation_peel_peak, value);
    } else {
      stance_values.push_back(value);
    }
  }
  if (stance_values.empty()) return;
  std::sort(stance_values.begin(), stance_values.end());
  r->utilisation_stance_peak = stance_values.back();
  // Nearest rank: the ceil(0.99 n)-th smallest.
  const size_t rank = (99 * stance_values.size() + 99) / 100;
  r->utilisation_stance_p99 = stance_values[rank - 1];
}

// The text report's table: a label column, then one right-aligned column per leg.
class LegTable {
 public:
  LegTable(const Report& report, std::string* out) : report_(report), out_(out) {
    for (const LegReport& r : report.legs) width_ = std::max(width_, r.leg.size() + 2);
  }

  // One row; value_of(leg) gives a leg's cell.
  template <typename ValueOf>
  void Row(const std::string& label, ValueOf value_of) {
    char buf[256];
    std::snprintf(buf, sizeof(buf), "%-*s", kLabel, label.c_str());
    *out_ += buf;
    for (const LegReport& r : report_.legs) {
      std::snprintf(buf, sizeof(buf), "%*s", static_cast<int>(width_), value_of(r).c_str());
      *out_ += buf;
    }
    *out_ += "\n";
  }

  // A total, then one indented row per key (a cause) any leg counted, 0 where a leg has none.
  template <typename Total, typename MapOf>
  void CountRows(const std::string& label, Total total, MapOf map_of) {
    Row(label, [&](const LegReport& r) { return std::to_string(total(r)); });
    std::set<std::string> keys;
    for (const LegReport& r : report_.legs) {
      for (const auto& [k, n] : map_of(r)) keys.insert(k);
    }
    for (const std::string& k : keys) {
      Row("  " + k, [&](const LegReport& r) {
        const auto& m = map_of(r);
        const auto it = m.find(k);
        return std::to_string(it == m.end() ? 0 : it->second);
      });
    }
  }

 private:
  static constexpr int kLabel = 28;
  const Report& report_;
  std::string* out_;
  size_t width_ = 8;
};

std::string OrDash(const std::optional<double>& v, const char* format) {
  return v ? Num(*v, format) : std::string("-");
}

// The leg names, then what the pad's events were: touchdowns, attaches, detaches.
void EventRows(LegTable* t) {
  using Counts = const std::map<std::string, int>&;
  t->Row("leg", [](const LegReport& r) { return r.leg; });
  t->Row("touchdowns", [](const LegReport& r) { return std::to_string(r.touchdowns); });
  t->Row("attachments", [](const LegReport& r) { return std::to_string(r.attachments); });
  t->CountRows(
      "rejected attaches", [](const LegReport& r) { return r.rejected; },
      [](const LegReport& r) -> Counts { return r.rejected_by; });
  t->CountRows(
      "touchdowns unanswered", [](const LegReport& r) { return r.unanswered_touchdowns; },
      [](const LegReport& r) -> Counts { return r.unanswered_by; });
  t->CountRows(
      "detaches", [](const LegReport& r) { return r.detaches; },
      [](const LegReport& r) -> Counts { return r.detached_by; });
  t->Row("bonds-lost steps", [](const LegReport& r) { return std::to_string(r.bonds_lost_steps); });
}

// How long the pads held and what they carried.
void StanceAndLoadRows(LegTable* t) {
  t->Row("stances (complete)",
         [](const LegReport& r) { return std::to_string(r.complete_stances); });
  t->Row("stance mean (s)", [](const LegReport& r) { return OrDash(r.mean_stance_s, "%.3f"); });
  t->Row("stance shortest (s)",
         [](const LegReport& r) { return OrDash(r.shortest_stance_s, "%.3f"); });
  t->Row("attached (s)", [](const LegReport& r) { return Num(r.attached_s); });
  t->Row("duty factor", [](const LegReport& r) { return Num(r.duty_factor); });
  t->Row("peak normal load (N)",
         [](const LegReport& r) { return OrDash(r.peak_normal_n, "%.3f"); });
  t->Row("peak shear load (N)", [](const LegReport& r) { return OrDash(r.peak_shear_n, "%.3f"); });
  t->Row("lowest bonded fraction",
         [](const LegReport& r) { return OrDash(r.lowest_bonded_fraction, "%.3f"); });
  // The margin in stance apart from the peel, which takes every pad to 1 on purpose.
  t->Row("utilisation stance peak",
         [](const LegReport& r) { return OrDash(r.utilisation_stance_peak, "%.3f"); });
  t->Row("utilisation stance p99",
         [](const LegReport& r) { return OrDash(r.utilisation_stance_p99, "%.3f"); });
  t->Row("utilisation peel peak",
         [](const LegReport& r) { return OrDash(r.utilisation_peel_peak, "%.3f"); });
}

// The reflexes any leg fired, one row each; nothing when none fired.
void ReflexRows(const Report& report, LegTable* t, std::string* out) {
  std::set<std::string> reflexes;
  for (const LegReport& r : report.legs) {
    for (const auto& [k, n] : r.reflexes) reflexes.insert(k);
  }
  if (reflexes.empty()) return;
  *out += "reflexes fired\n";
  for (const std::string& k : reflexes) {
    t->Row("  " + k, [&](const LegReport& r) {
      const auto it = r.reflexes.find(k);
      return std::to_string(it == r.reflexes.end() ? 0 : it->second);
    });
  }
}

}  // namespace

Report Analyse(const Run& run, const Window& window) {
  const auto [a, b] = Clip(run, window);
  Report report;
  report.dir = run.dir;
  report.from_s = a;
  report.to_s = b;
  report.observed_s = b - a;
  for (size_t leg = 0; leg < run.legs.size(); ++leg) {
    LegReport r;
    r.leg = run.legs[leg];
    r.pad = run.pads[leg];
    const std::vector<RawStance> raw = ScanLegEvents(run, a, b, &r);
    ClipStances(raw, a, b, report.observed_s, &r);
    TakePeakUtilisation(run, raw, a, b, &r);
    report.legs.push_back(std::move(r));
  }
  return report;
}

nlohmann::json ReportJson(const Run& run, const Report& report) {
  nlohmann::json j;
  j["kind"] = "simulation";
  j["run"] = run.dir;
  j["robot"] = SummaryText(run, "robot");
  j["scene"] = SummaryText(run, "scene");
  j["duration_s"] = run.duration_s;
  j["window"] = WindowJson(report.from_s, report.to_s);
  nlohmann::json legs = nlohmann::json::array();
  for (const LegReport& r : report.legs) {
    nlohmann::json stances = nlohmann::json::array();
    for (const Stance& s : r.stances) {
      stances.push_back({{"start_s", s.start_s},
                         {"end_s", s.end_s},
                         {"open_start", s.open_start},
                         {"open_end", s.open_end},
                         {"end_cause", s.end_cause}});
    }
    legs.push_back({{"leg", r.leg},
                    {"pad", r.pad},
                    {"touchdowns", r.touchdowns},
                    {"attachments", r.attachments},
                    {"rejected", r.rejected},
                    {"rejected_by", r.rejected_by},
                    {"unanswered_touchdowns", r.unanswered_touchdowns},
                    {"unanswered_by", r.unanswered_by},
                    {"detaches", r.detaches},
                    {"detached_by", r.detached_by},
                    {"bonds_lost_steps", r.bonds_lost_steps},
                    {"stances", stances},
                    {"complete_stances", r.complete_stances},
                    {"mean_stance_s", Optional(r.mean_stance_s)},
                    {"shortest_stance_s", Optional(r.shortest_stance_s)},
                    {"attached_s", r.attached_s},
                    {"duty_factor", r.duty_factor},
                    {"peak_normal_n", Optional(r.peak_normal_n)},
                    {"peak_shear_n", Optional(r.peak_shear_n)},
                    {"lowest_bonded_fraction", Optional(r.lowest_bonded_fraction)},
                    {"peak_utilisation", Optional(r.peak_utilisation)},
                    {"utilisation_stance_peak", Optional(r.utilisation_stance_peak)},
                    {"utilisation_stance_p99", Optional(r.utilisation_stance_p99)},
                    {"utilisation_peel_peak", Optional(r.utilisation_peel_peak)},
                    {"reflexes", r.reflexes}});
  }
  j["legs"] = legs;
  return j;
}

std::string ReportText(const Run& run, const Report& report) {
  std::string out;
  char buf[256];
  std::snprintf(buf, sizeof(buf), "%s: %s (%s on %s), %.3f .. %.3f s (%.3f s observed)\n\n", kCli,
                run.dir.c_str(), SummaryText(run, "robot").c_str(),
                SummaryText(run, "scene").c_str(), report.from_s, report.to_s, report.observed_s);
  out += buf;
  LegTable table(report, &out);
  EventRows(&table);
  StanceAndLoadRows(&table);
  ReflexRows(report, &table, &out);
  out +=
      "\nstance = attach .. detach; mean and shortest over stances whole inside the window;\n"
      "duty factor = attached time / observed time; loads (pad frame, normal + pulls off) are\n"
      "those at the pad's events while attached, its detach included; lowest bonded fraction\n"
      "is before the step the pad let go; touchdowns unanswered = neither attached nor\n"
      "rejected: left_within_attach_window (the pad left the surface before its contacts and\n"
      "preload met the attach conditions), run_ended_during_touch. - : none.\n";
  return out;
}

std::vector<EventRow> LegEvents(const Run& run, std::string_view leg, const Window& window) {
  const int i = LegOrThrow(run, leg);
  const auto [a, b] = Clip(run, window);
  std::vector<EventRow> rows;
  for (const EventRow& e : run.events) {
    if (e.pad == run.pads[i] && e.time_s >= a && e.time_s <= b) rows.push_back(e);
  }
  return rows;
}

nlohmann::json LegEventsJson(const Run& run, std::string_view leg, const Window& window) {
  const int i = LegOrThrow(run, leg);
  const auto [a, b] = Clip(run, window);
  nlohmann::json events = nlohmann::json::array();
  for (const EventRow& e : LegEvents(run, leg, window)) {
    events.push_back({{"time_s", e.time_s},
                      {"event", e.event},
                      {"cause", e.cause},
                      {"surface", e.surface},
                      {"bonded_fraction", e.bonded_fraction},
                      {"fn_n", e.fn_n},
                      {"fx_n", e.fx_n},
                      {"fy_n", e.fy_n},
                      {"shear_n", e.shear_n()},
                      {"mx_nm", e.mx_nm},
                      {"my_nm", e.my_nm},
                      {"line", e.line}});
  }
  return {{"kind", "simulation"},       {"run", run.dir},
          {"leg", run.legs[i]},         {"pad", run.pads[i]},
          {"window", WindowJson(a, b)}, {"events", events}};
}

std::string LegEventsText(const Run& run, std::string_view leg, const Window& window) {
  const int i = LegOrThrow(run, leg);
  const auto [a, b] = Clip(run, window);
  const std::vector<EventRow> rows = LegEvents(run, leg, window);
  std::string out;
  char buf[512];
  std::snprintf(buf, sizeof(buf), "%s: %s, leg %s (%s), %.3f .. %.3f s: %zu events\n\n", kCli,
                run.dir.c_str(), run.legs[i].c_str(), run.pads[i].c_str(), a, b, rows.size());
  out += buf;
  std::snprintf(buf, sizeof(buf), "%10s  %-16s %-28s %-10s %7s %9s %9s %9s %9s %10s %10s\n",
                "time_s", "event", "cause", "surface", "bonded", "fn_n", "shear_n", "fx_n", "fy_n",
                "mx_nm", "my_nm");
  out += buf;
  for (const EventRow& e : rows) {
    std::snprintf(buf, sizeof(buf),
                  "%10.3f  %-16s %-28s %-10s %7.3f %9.4f %9.4f %9.4f %9.4f %10.5f %10.5f\n",
                  e.time_s, e.event.c_str(), e.cause.c_str(), e.surface.c_str(), e.bonded_fraction,
                  e.fn_n, e.shear_n(), e.fx_n, e.fy_n, e.mx_nm, e.my_nm);
    out += buf;
  }
  return out;
}

std::string PulloffText(const TextTable& t) {
  std::vector<size_t> width(t.columns.size());
  for (size_t c = 0; c < t.columns.size(); ++c) {
    width[c] = t.columns[c].size();
    for (const auto& r : t.rows) width[c] = std::max(width[c], r[c].size());
  }
  std::string out = std::string(kCli) + ": " + t.path + " (climbsim pulloff), " +
                    std::to_string(t.rows.size()) + " rows\n\n";
  auto line = [&](const std::vector<std::string>& cells) {
    for (size_t c = 0; c < cells.size(); ++c) {
      const std::string cell = cells[c].empty() ? "-" : cells[c];
      out += std::string(c ? 2 : 0, ' ') +
             std::string(width[c] - std::min(width[c], cell.size()), ' ') + cell;
    }
    out += "\n";
  };
  line(t.columns);
  for (const auto& r : t.rows) line(r);
  out += "\ninf: the pad never let go; -: not computed (that model was not run).\n";
  return out;
}

nlohmann::json PulloffJson(const std::string& dir, const TextTable& t) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& r : t.rows) {
    nlohmann::json row = nlohmann::json::array();
    for (const std::string& cell : r) {
      double v = 0.0;
      const auto res = std::from_chars(cell.data(), cell.data() + cell.size(), v);
      if (cell.empty()) {
        row.push_back(nullptr);
      } else if (res.ec == std::errc() && res.ptr == cell.data() + cell.size() &&
                 std::isfinite(v)) {
        row.push_back(v);
      } else {
        row.push_back(cell);
      }
    }
    rows.push_back(row);
  }
  return {
      {"kind", "pulloff"}, {"run", dir}, {"file", t.path}, {"columns", t.columns}, {"rows", rows}};
}

}  // namespace climbsim::inspect
