// `climbsim inspect --json` against the per-leg table recomputed here from events.csv by a
// parser and a state machine of its own (std::getline, std::stod; nothing of inspect/), on
// real runs of the gecko and the spider climbing a wall with adhesion and reflexes.
// Doubles must be equal, not near: both sides parse with correctly rounded conversions and
// add the same numbers in the same (time) order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <vector>

#include "scenario/scenario.h"
#include "tests/inspect/inspect_test_util.h"

namespace {

using climbsim::testing::CopyRun;
using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsim;
using climbsim::testing::SharedRun;
using climbsim::testing::Source;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;
using nlohmann::json;

struct Ev {
  double t;
  std::string pad, event, cause;
  double bonded, fn, fx, fy;
};

std::vector<Ev> ParseEvents(const std::string& path) {
  std::istringstream in(ReadFile(path));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "time_s,pad,event,cause,surface,bonded_fraction,fn_n,fx_n,fy_n,mx_nm,my_nm");
  std::vector<Ev> out;
  while (std::getline(in, line)) {
    std::vector<std::string> c;
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) c.push_back(cell);
    if (c.size() == 10) c.push_back("");  // getline drops an empty last cell
    EXPECT_EQ(c.size(), 11u) << line;
    out.push_back({std::stod(c[0]), c[1], c[2], c[3], std::stod(c[5]), std::stod(c[6]),
                   std::stod(c[7]), std::stod(c[8])});
  }
  return out;
}

struct Interval {
  double start, end;
  bool closed;
  std::string cause;
  std::vector<const Ev*> rows;  // attach row .. detach row
};

// The table of one pad, from the definitions in docs/inspect.md.
json Recompute(const std::vector<Ev>& all, const std::string& pad, double a, double b,
               double duration) {
  std::vector<const Ev*> ev;
  for (const Ev& e : all) {
    if (e.pad == pad) ev.push_back(&e);
  }
  std::map<std::string, int> counts, rejected_by, detached_by, reflexes;
  for (const Ev* e : ev) {
    if (e->t < a || e->t > b) continue;
    ++counts[e->event];
    if (e->event == "attach_rejected") {
      ++rejected_by[e->cause.substr(0, e->cause.find('='))];
    } else if (e->event == "detach") {
      ++detached_by[e->cause];
    } else if (e->event != "touchdown" && e->event != "attach" && e->event != "bonds_lost") {
      ++reflexes[e->event];
    }
  }
  // A touchdown in the window is answered by the pad's next attach or attach_rejected; the
  // next touchdown first means it left inside the attach window; nothing means the run ended.
  int unanswered = 0;
  std::map<std::string, int> unanswered_by;
  for (size_t i = 0; i < ev.size(); ++i) {
    if (ev[i]->event != "touchdown" || ev[i]->t < a || ev[i]->t > b) continue;
    std::string next;
    for (size_t j = i + 1; j < ev.size() && next.empty(); ++j) {
      const std::string& k = ev[j]->event;
      if (k == "touchdown" || k == "attach" || k == "attach_rejected") next = k;
    }
    if (next == "attach" || next == "attach_rejected") continue;
    ++unanswered;
    ++unanswered_by[next.empty() ? "run_ended_during_touch" : "left_within_attach_window"];
  }
  std::vector<Interval> intervals;
  std::optional<Interval> open;
  for (const Ev* e : ev) {
    if (!open && e->event == "attach") open = Interval{e->t, 0, false, "", {}};
    if (open) open->rows.push_back(e);
    if (open && e->event == "detach") {
      open->end = e->t;
      open->closed = true;
      open->cause = e->cause;
      intervals.push_back(*open);
      open.reset();
    }
  }
  if (open) {
    open->end = duration;
    intervals.push_back(*open);
  }
  json stances = json::array();
  double attached = 0, complete_sum = 0;
  int complete = 0;
  std::optional<double> shortest, peak_n, peak_s, lowest;
  for (const Interval& i : intervals) {
    for (const Ev* e : i.rows) {
      if (e->t < a || e->t > b) continue;
      peak_n = std::max(peak_n.value_or(-INFINITY), e->fn);
      peak_s = std::max(peak_s.value_or(-INFINITY), std::hypot(e->fx, e->fy));
      if (!i.closed || e->t < i.end) lowest = std::min(lowest.value_or(INFINITY), e->bonded);
    }
    if (i.end < a || i.start > b) continue;
    const double s = std::max(i.start, a), t = std::min(i.end, b);
    const bool open_start = i.start < a, open_end = !i.closed || i.end > b;
    stances.push_back({{"start_s", s},
                       {"end_s", t},
                       {"open_start", open_start},
                       {"open_end", open_end},
                       {"end_cause", open_end ? "" : i.cause}});
    attached += t - s;
    if (!open_start && !open_end) {
      ++complete;
      complete_sum += t - s;
      shortest = std::min(shortest.value_or(INFINITY), t - s);
    }
  }
  auto opt = [](const std::optional<double>& v) { return v ? json(*v) : json(nullptr); };
  return {{"pad", pad},
          {"touchdowns", counts["touchdown"]},
          {"attachments", counts["attach"]},
          {"rejected", counts["attach_rejected"]},
          {"rejected_by", rejected_by},
          {"unanswered_touchdowns", unanswered},
          {"unanswered_by", unanswered_by},
          {"detaches", counts["detach"]},
          {"detached_by", detached_by},
          {"bonds_lost_steps", counts["bonds_lost"]},
          {"stances", stances},
          {"complete_stances", complete},
          {"mean_stance_s", complete ? json(complete_sum / complete) : json(nullptr)},
          {"shortest_stance_s", opt(shortest)},
          {"attached_s", attached},
          {"duty_factor", attached / (b - a)},
          {"peak_normal_n", opt(peak_n)},
          {"peak_shear_n", opt(peak_s)},
          {"lowest_bonded_fraction", opt(lowest)},
          {"reflexes", reflexes}};
}

// The largest `<pad>_utilisation` of trajectory.csv over rows with a <= t <= b (null when
// the column is absent), read independently of inspect.
json PeakUtilisation(const std::string& dir, const std::string& pad, double a, double b) {
  std::istringstream in(ReadFile(dir + "/trajectory.csv"));
  std::string line;
  std::getline(in, line);
  int column = -1;
  {
    std::istringstream h(line);
    std::string name;
    for (int c = 0; std::getline(h, name, ','); ++c) {
      if (name == pad + "_utilisation") column = c;
    }
  }
  if (column < 0) return nullptr;
  std::optional<double> peak;
  while (std::getline(in, line)) {
    std::istringstream f(line);
    std::string cell;
    double t = 0, u = 0;
    for (int c = 0; std::getline(f, cell, ','); ++c) {
      if (c == 0) t = std::stod(cell);
      if (c == column) u = std::stod(cell);
    }
    if (t >= a && t <= b) peak = std::max(peak.value_or(-INFINITY), u);
  }
  return peak ? json(*peak) : json(nullptr);
}

// The utilisation split into stance (attached, not peeling) and peel rows of trajectory.csv
// with a <= t <= b: spans [start, end) from attach to detach and from peel to peel_end or
// detach; the stance's 99th percentile by nearest rank. Nulls without stance or peel rows.
json UtilisationSplit(const std::string& dir, const std::vector<Ev>& events, const std::string& pad,
                      double a, double b, double duration) {
  using Spans = std::vector<std::pair<double, double>>;
  Spans stances, peels;
  bool attached = false, peeling = false;
  for (const Ev& e : events) {
    if (e.pad != pad) continue;
    if (e.event == "attach" && !attached) stances.push_back({e.t, duration}), attached = true;
    if (e.event == "peel" && !peeling) peels.push_back({e.t, duration}), peeling = true;
    if (e.event == "detach" && attached) stances.back().second = e.t, attached = false;
    if ((e.event == "detach" || e.event == "peel_end") && peeling) {
      peels.back().second = e.t;
      peeling = false;
    }
  }
  auto inside = [](const Spans& spans, double t) {
    return std::any_of(spans.begin(), spans.end(),
                       [t](const auto& s) { return t >= s.first && t < s.second; });
  };
  std::istringstream in(ReadFile(dir + "/trajectory.csv"));
  std::string line;
  std::getline(in, line);
  int column = -1;
  {
    std::istringstream h(line);
    std::string name;
    for (int c = 0; std::getline(h, name, ','); ++c) {
      if (name == pad + "_utilisation") column = c;
    }
  }
  std::vector<double> stance;
  std::optional<double> peel;
  while (column >= 0 && std::getline(in, line)) {
    std::istringstream f(line);
    std::string cell;
    double t = 0, u = 0;
    for (int c = 0; std::getline(f, cell, ','); ++c) {
      if (c == 0) t = std::stod(cell);
      if (c == column) u = std::stod(cell);
    }
    if (t < a || t > b || !inside(stances, t)) continue;
    if (inside(peels, t)) {
      peel = std::max(peel.value_or(-INFINITY), u);
    } else {
      stance.push_back(u);
    }
  }
  std::sort(stance.begin(), stance.end());
  const size_t n = stance.size();
  return {{"utilisation_stance_peak", n ? json(stance.back()) : json(nullptr)},
          {"utilisation_stance_p99",
           n ? json(stance[static_cast<size_t>(std::ceil(0.99 * n)) - 1]) : json(nullptr)},
          {"utilisation_peel_peak", peel ? json(*peel) : json(nullptr)}};
}

// Runs inspect --json on `dir` and compares every leg with the recomputed table.
void ExpectTableMatches(const std::string& dir, const std::string& window_args, double from,
                        double to) {
  const auto r = RunClimbsim("inspect " + dir + " --json " + window_args);
  ASSERT_EQ(r.code, 0) << r.err;
  const json got = json::parse(r.out);
  const json summary = json::parse(ReadFile(dir + "/summary.json"));
  const double duration = summary["duration_s"];
  const double a = std::max(from, 0.0), b = std::min(to, duration);
  EXPECT_EQ(got["window"]["from_s"], a);
  EXPECT_EQ(got["window"]["to_s"], b);
  const std::vector<Ev> events = ParseEvents(dir + "/events.csv");
  ASSERT_FALSE(got["legs"].empty());
  int attachments = 0;
  for (const json& leg : got["legs"]) {
    json want = Recompute(events, leg["pad"], a, b, duration);
    want["peak_utilisation"] = PeakUtilisation(dir, leg["pad"], a, b);
    want.update(UtilisationSplit(dir, events, leg["pad"], a, b, duration));
    json have = leg;
    have.erase("leg");
    EXPECT_EQ(have, want) << "leg " << leg["leg"] << "\n got: " << have.dump()
                          << "\nwant: " << want.dump();
    attachments += leg["attachments"].get<int>();
  }
  EXPECT_GT(attachments, 0) << "a run with adhesion events is needed";
}

std::string GeckoWall() { return SharedRun("gecko_wall", Source("examples/gecko_wall.yaml")); }
std::string SpiderWall() { return SharedRun("spider_wall", Source("examples/spider_wall.yaml")); }

TEST(InspectTable, GeckoWallMatchesAnIndependentRecount) {
  ExpectTableMatches(GeckoWall(), "", 0, INFINITY);
}

TEST(InspectTable, SpiderWallMatchesAnIndependentRecount) {
  ExpectTableMatches(SpiderWall(), "", 0, INFINITY);
}

TEST(InspectTable, WindowClipsStancesAndCountsTheSameWay) {
  ExpectTableMatches(GeckoWall(), "--from 3.3 --to 11.7", 3.3, 11.7);
  ExpectTableMatches(SpiderWall(), "--from 7.25 --to 50", 7.25, 50);
}

// A third source: the adhesion effect's own per-pad counts in summary.json.
TEST(InspectTable, CountsAgreeWithTheRunSummary) {
  for (const std::string& dir : {GeckoWall(), SpiderWall()}) {
    const auto r = RunClimbsim("inspect " + dir + " --json");
    ASSERT_EQ(r.code, 0) << r.err;
    const json got = json::parse(r.out);
    const json pads = json::parse(ReadFile(dir + "/summary.json"))["adhesion"]["pads"];
    for (const json& leg : got["legs"]) {
      const json& p = pads[leg["pad"].get<std::string>()];
      EXPECT_EQ(leg["touchdowns"], p["touchdown"]) << dir << " " << leg["pad"];
      EXPECT_EQ(leg["attachments"], p["attach"]);
      EXPECT_EQ(leg["rejected"], p["attach_rejected"]);
      EXPECT_EQ(leg["bonds_lost_steps"], p["bonds_lost_steps"]);
      // trajectory.csv samples the utilisation that the summary's peak sees every step.
      EXPECT_GT(leg["peak_utilisation"].get<double>(), 0.0);
      EXPECT_LE(leg["peak_utilisation"].get<double>(), p["peak_utilisation"].get<double>());
      for (const char* cause : {"peel", "overload", "released", "contact_lost"}) {
        EXPECT_EQ(leg["detached_by"].value(cause, 0), p["detach_" + std::string(cause)]) << cause;
      }
      const json& last = leg["stances"].back();
      EXPECT_EQ(last["open_end"], p["attached_at_end"]);
    }
  }
}

// The margin a designer reads: the peel takes every pad to a bond breaking (utilisation 1) on
// purpose; in stance the gecko keeps a margin. summary.json over every step, inspect over the
// trajectory's rows, apart, each within [0, 1].
TEST(InspectTable, StanceUtilisationIsApartFromThePeelsAndBelowIt) {
  const std::string dir = GeckoWall();
  const auto r = RunClimbsim("inspect " + dir + " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const json pads = json::parse(ReadFile(dir + "/summary.json"))["adhesion"]["pads"];
  for (const json& leg : json::parse(r.out)["legs"]) {
    SCOPED_TRACE(leg["pad"].get<std::string>());
    const json& p = pads[leg["pad"].get<std::string>()];
    const double stance = p["utilisation_stance_peak"], p99 = p["utilisation_stance_p99"];
    const double peel = p["utilisation_peel_peak"];
    EXPECT_GT(stance, 0.0);
    EXPECT_LT(stance, peel);
    EXPECT_LE(p99, stance);
    EXPECT_LE(peel, 1.0 + 1e-9);
    EXPECT_EQ(std::max(stance, peel), p["peak_utilisation"].get<double>());
    // trajectory.csv's rows are some of the steps: never above the summary's peaks.
    EXPECT_LE(leg["utilisation_stance_peak"].get<double>(), stance);
    EXPECT_LE(leg["utilisation_peel_peak"].get<double>(), peel);
    EXPECT_LT(leg["utilisation_stance_peak"].get<double>(),
              leg["utilisation_peel_peak"].get<double>());
  }
  // The table says which is which.
  const auto text = RunClimbsim("inspect " + dir);
  EXPECT_NE(text.out.find("utilisation stance peak"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("utilisation peel peak"), std::string::npos) << text.out;
}

// The summary's 99th percentile comes from a histogram of 0.001 bins filled every step; with a
// trajectory row every step (1 kHz, the scenes' 1 ms step), inspect's exact nearest rank over
// the same steps must agree to a bin (the two tell stance from peel by different means, the
// controller's flag against the peel events: a few steps at the boundaries may differ).
TEST(InspectTable, SummaryPercentileAgreesWithAnExactOneOverEveryStep) {
  climbsim::sim::Scenario s = climbsim::sim::LoadScenario(Source("examples/gecko_wall.yaml"));
  s.duration_s = 6.0;
  s.outputs.trajectory_rate_hz = 1000.0;
  const std::string yaml = TempDir() + "/every_step.yaml";
  WriteFile(yaml, climbsim::sim::ScenarioToYamlText(s));
  const std::string dir = TempDir() + "/every_step_run";
  ASSERT_EQ(RunClimbsim("simulate " + yaml + " --out " + dir + " --force --quiet").code, 0);
  const auto r = RunClimbsim("inspect " + dir + " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const json pads = json::parse(ReadFile(dir + "/summary.json"))["adhesion"]["pads"];
  for (const json& leg : json::parse(r.out)["legs"]) {
    SCOPED_TRACE(leg["pad"].get<std::string>());
    const json& p = pads[leg["pad"].get<std::string>()];
    EXPECT_NEAR(leg["utilisation_stance_p99"].get<double>(),
                p["utilisation_stance_p99"].get<double>(), 0.002);
    EXPECT_NEAR(leg["utilisation_stance_peak"].get<double>(),
                p["utilisation_stance_peak"].get<double>(), 0.01);
    EXPECT_NEAR(leg["utilisation_peel_peak"].get<double>(),
                p["utilisation_peel_peak"].get<double>(), 0.01);
  }
}

TEST(InspectLeg, ListsThatPadsEventsInTimeOrderWithTheirLoads) {
  const std::string dir = GeckoWall();
  const auto r = RunClimbsim("inspect " + dir + " --json --leg RF --from 2 --to 6");
  ASSERT_EQ(r.code, 0) << r.err;
  const json got = json::parse(r.out);
  EXPECT_EQ(got["leg"], "RF");
  EXPECT_EQ(got["pad"], "RF_pad");
  std::vector<Ev> want;
  for (const Ev& e : ParseEvents(dir + "/events.csv")) {
    if (e.pad == "RF_pad" && e.t >= 2 && e.t <= 6) want.push_back(e);
  }
  ASSERT_EQ(got["events"].size(), want.size());
  ASSERT_FALSE(want.empty());
  for (size_t i = 0; i < want.size(); ++i) {
    const json& e = got["events"][i];
    EXPECT_EQ(e["time_s"], want[i].t);
    EXPECT_EQ(e["event"], want[i].event);
    EXPECT_EQ(e["cause"], want[i].cause);
    EXPECT_EQ(e["fn_n"], want[i].fn);
    EXPECT_EQ(e["shear_n"], std::hypot(want[i].fx, want[i].fy));
  }
  // The text form: one line per event under a header.
  const auto text = RunClimbsim("inspect " + dir + " --leg RF_pad --from 2 --to 6");
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_EQ(std::count(text.out.begin(), text.out.end(), '\n'), 3 + static_cast<long>(want.size()));
}

TEST(InspectTable, TextShowsEveryLegAndTheDefinitions) {
  const auto r = RunClimbsim("inspect " + SpiderWall());
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* leg : {"L1", "L2", "L3", "R1", "R2", "R3"}) {
    EXPECT_NE(r.out.find(leg), std::string::npos) << leg;
  }
  for (const char* row : {"attachments", "rejected attaches", "detaches", "stance mean (s)",
                          "stance shortest (s)", "duty factor", "peak normal load (N)",
                          "peak shear load (N)", "lowest bonded fraction", "reflexes fired"}) {
    EXPECT_NE(r.out.find(row), std::string::npos) << row;
  }
}

TEST(InspectPulloff, ShowsPulloffCsvAsATableAndAsJson) {
  const std::string dir = TempDir() + "/pulloff";
  ASSERT_EQ(RunClimbsim("pulloff --out " + dir + " --model bonds --step-deg 45 --quiet").code, 0);
  const auto text = RunClimbsim("inspect " + dir);
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("angle_deg"), std::string::npos);
  const auto r = RunClimbsim("inspect " + dir + " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const json got = json::parse(r.out);
  EXPECT_EQ(got["kind"], "pulloff");
  std::istringstream in(ReadFile(dir + "/pulloff.csv"));
  std::string header, line;
  std::getline(in, header);
  int rows = 0;
  while (std::getline(in, line)) ++rows;
  EXPECT_EQ(got["rows"].size(), static_cast<size_t>(rows));
  EXPECT_EQ(got["columns"][0], "angle_deg");
  EXPECT_EQ(got["rows"][1][0], 45.0);
  // --leg has no meaning there.
  EXPECT_EQ(RunClimbsim("inspect " + dir + " --leg LF").code, 2);
}

// An optimise folder: best.yaml is simulated into best_run the first time, reused after.
TEST(InspectOptimise, ReplaysBestYamlOnceThenInspectsIt) {
  const std::string dir = TempDir() + "/optimise_results";
  std::string best = ReadFile(Source("examples/gecko_wall.yaml"));
  best.replace(best.find("duration_s: 20"), 14, "duration_s: 3");
  WriteFile(dir + "/best.yaml", best);
  WriteFile(dir + "/summary.json", "{\"best_cost\": -0.01}\n");  // as optimise leaves it
  const auto first = RunClimbsim("inspect " + dir + " --json");
  ASSERT_EQ(first.code, 0) << first.err;
  EXPECT_NE(first.err.find("just replayed"), std::string::npos) << first.err;
  const json got = json::parse(first.out);
  EXPECT_EQ(got["kind"], "optimise");
  EXPECT_EQ(got["run"], dir + "/best_run");
  EXPECT_EQ(got["duration_s"], 3.0);
  EXPECT_GT(got["legs"][0]["attachments"].get<int>(), 0);
  const auto when = std::filesystem::last_write_time(dir + "/best_run/summary.json");
  const auto second = RunClimbsim("inspect " + dir + " --json");
  ASSERT_EQ(second.code, 0) << second.err;
  EXPECT_EQ(second.err.find("just replayed"), std::string::npos);
  EXPECT_EQ(std::filesystem::last_write_time(dir + "/best_run/summary.json"), when);
  EXPECT_EQ(json::parse(second.out)["legs"], got["legs"]);
}

// STYLE.md 10: each verb's --help ends with an example that runs.
TEST(InspectCli, HelpEndsWithExamplesThatRun) {
  for (const std::string verb : {"inspect", "render"}) {
    const auto r = RunClimbsim(verb + " --help");
    EXPECT_EQ(r.code, 0) << verb;
    const size_t at = r.out.rfind("Example:\n  climbsim " + verb + " runs/gecko_wall");
    ASSERT_NE(at, std::string::npos) << r.out;
    // Nothing but example lines after it.
    std::istringstream rest(r.out.substr(at + 9));
    for (std::string line; std::getline(rest, line);) {
      EXPECT_TRUE(line.empty() || line.rfind("  climbsim " + verb + " ", 0) == 0) << line;
    }
  }
  // The example's run directory comes from the example scenario the README simulates.
  EXPECT_TRUE(std::filesystem::exists(Source("examples/gecko_wall.yaml")));
}

}  // namespace
