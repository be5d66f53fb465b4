// climbsim sweep's design-question options: the stalled and fall columns against each run's
// own summary.json (--keep-runs), worst and mean over --seeds, the same table for any thread
// count; --find against a 1 % grid of the same key; what --find refuses (exit code 2).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "experiments/experiments.h"
#include "tests/common/test_util.h"

namespace {

using climbsim::testing::CliResult;
using climbsim::testing::Has;
using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsimArgs;
using climbsim::testing::Source;
using climbsim::testing::SplitCsv;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

// examples/gecko_wall.yaml with a shorter run (and other lines replaced as given).
std::string GeckoWall(const std::string& name, const std::string& duration_s,
                      const std::string& support_bond_fraction = "0.85") {
  std::string text = ReadFile(Source("examples/gecko_wall.yaml"));
  text = std::regex_replace(text, std::regex("^duration_s:.*$", std::regex::multiline),
                            "duration_s: " + duration_s);
  text = std::regex_replace(text, std::regex("support_bond_fraction: 0\\.85"),
                            "support_bond_fraction: " + support_bond_fraction);
  return WriteFile("sweep_test/" + name + ".yaml", text);
}

std::vector<std::vector<std::string>> Rows(const std::string& csv) {
  std::vector<std::vector<std::string>> rows;
  size_t at = 0;
  while (at < csv.size()) {
    const size_t end = csv.find('\n', at);
    rows.push_back(SplitCsv(csv.substr(at, end - at)));
    at = end == std::string::npos ? csv.size() : end + 1;
  }
  return rows;
}

nlohmann::json Summary(const std::string& dir) {
  return nlohmann::json::parse(ReadFile(dir + "/summary.json"));
}

// A gait that waits for every bond in full stalls (cpg.wait_for_support) a second into the
// run; at the example's 0.85 it climbs. The columns are the runs' own summaries.
TEST(Sweep, StalledColumnIsTheRunsOwnAndAStallIsNotProgress) {
  const std::string scenario = GeckoWall("stall", "5");
  std::string first_csv;
  for (const char* threads : {"1", "2"}) {
    const std::string out = TempDir() + "/sweep_stall_" + threads;
    const CliResult r = RunClimbsimArgs({"sweep", scenario, "--key", "cpg.support_bond_fraction",
                                         "--from", "0.85", "--to", "1", "--step", "0.15",
                                         "--seeds", "2", "--keep-runs", "--threads", threads,
                                         "--out", out});
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string csv = ReadFile(out + "/sweep.csv");
    if (first_csv.empty()) first_csv = csv;
    EXPECT_EQ(csv, first_csv) << "threads " << threads;
    const auto rows = Rows(csv);
    ASSERT_EQ(rows.size(), 3u) << csv;
    EXPECT_EQ(rows[0][6], "stall_stalled");
    for (size_t i = 1; i <= 2; ++i) {
      int stalled = 0;
      double first_stall = -1, sum_speed = 0, worst_speed = 1e9;
      for (int k = 0; k < 2; ++k) {
        const nlohmann::json s = Summary(out + "/runs/stall/v00" + std::to_string(i - 1) +
                                         "_seed" + std::to_string(k));
        sum_speed += s["mean_speed_mps"].get<double>();
        worst_speed = std::min(worst_speed, s["mean_speed_mps"].get<double>());
        if (!s["stalled"].get<bool>()) continue;
        ++stalled;
        const double t = s["stall_time_s"].get<double>();
        first_stall = first_stall < 0 ? t : std::min(first_stall, t);
      }
      EXPECT_EQ(rows[i][6], std::to_string(stalled)) << csv;
      EXPECT_NEAR(std::stod(rows[i][3]), sum_speed / 2, 1e-12);
      if (stalled > 0) {
        EXPECT_EQ(std::stod(rows[i][7]), first_stall);
        EXPECT_EQ(rows[i][2], "0");  // worst speed: a stall is no progress
      } else {
        EXPECT_EQ(rows[i][7], "");
        EXPECT_NEAR(std::stod(rows[i][2]), worst_speed, 1e-12);
      }
    }
    EXPECT_EQ(rows[1][6], "0") << "the example's 0.85 climbs";
    EXPECT_EQ(rows[2][6], "2") << "every seed stalls waiting for a full bond";
    // The table shows no speed for the stalled point, and its stall time.
    EXPECT_TRUE(std::regex_search(r.out, std::regex("\\n +1 +- +[0-9.]+ +- +[0-9.]+ \\(2/2\\)")))
        << r.out;
  }
}

// The least adhesive strength at which the gecko does not fall in 1.5 s: a 1 % grid of the
// key against the bisection to 1 %.
TEST(SweepFind, FindsTheGridsEdgeWithinOnePercentInFewerRuns) {
  const std::string scenario = GeckoWall("edge", "1.5");
  const std::string grid_out = TempDir() + "/sweep_grid";
  const CliResult g = RunClimbsimArgs({"sweep", scenario, "--key", "adhesion.sigma_t_pa",
                                       "--from", "5600", "--to", "6800", "--step", "60",
                                       "--threads", "2", "--out", grid_out});
  ASSERT_EQ(g.code, 0) << g.err;
  const auto rows = Rows(ReadFile(grid_out + "/sweep.csv"));
  const int grid_runs = static_cast<int>(rows.size()) - 1;
  // The grid's edges: the holding side of each pair of neighbours whose outcomes differ (in
  // 1.5 s the gecko holds at 6140-6200 Pa, falls at 6260-6320 and holds from 6380: not
  // monotone, so the bisection finds one of several edges).
  std::vector<double> grid_edges;
  for (size_t i = 2; i < rows.size(); ++i) {
    if (rows[i][4] != rows[i - 1][4]) {
      grid_edges.push_back(std::stod(rows[i][4] == "0" ? rows[i][0] : rows[i - 1][0]));
    }
  }
  ASSERT_FALSE(grid_edges.empty());

  const std::string find_out = TempDir() + "/sweep_find";
  const CliResult f = RunClimbsimArgs({"sweep", scenario, "--find", "adhesion.sigma_t_pa",
                                       "--low", "5600", "--high", "6800", "--condition",
                                       "fell==0", "--tolerance", "0.01", "--threads", "2",
                                       "--out", find_out});
  ASSERT_EQ(f.code, 0) << f.err;
  const auto probes = Rows(ReadFile(find_out + "/find.csv"));
  const int find_runs = static_cast<int>(probes.size()) - 1;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(f.out, m, std::regex("holds at adhesion.sigma_t_pa = ([0-9.]+), "
                                                     "fails at ([0-9.]+)")))
      << f.out;
  const double holds = std::stod(m[1]), fails = std::stod(m[2]);
  EXPECT_LT(fails, holds);
  EXPECT_LE(holds - fails, 0.01 * holds);
  const double nearest = *std::min_element(grid_edges.begin(), grid_edges.end(),
                                            [&](double a, double b) {
                                              return std::abs(a - holds) < std::abs(b - holds);
                                            });
  EXPECT_NEAR(holds, nearest, 0.01 * nearest) << f.out;
  EXPECT_LT(find_runs, grid_runs);
}

TEST(SweepFind, RefusesAnIntervalWithoutAnEdge) {
  const std::string scenario = GeckoWall("no_edge", "0.3");
  const std::string out = TempDir() + "/sweep_no_edge";
  const CliResult r = RunClimbsimArgs({"sweep", scenario, "--find", "adhesion.sigma_t_pa",
                                       "--low", "7000", "--high", "8000", "--condition",
                                       "fell==0", "--out", out});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(Has(r.err, "holds on every seed at both adhesion.sigma_t_pa = 7000 and 8000"))
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

// The condition is read by a fixed grammar: anything else is bad input naming --condition,
// before any run.
TEST(SweepFind, ConditionGrammar) {
  using climbsim::optimise::Meets;
  using climbsim::optimise::ParseCondition;
  const auto c = ParseCondition("distance_m>=0.1 and fell == 0");
  ASSERT_EQ(c.terms.size(), 2u);
  EXPECT_EQ(c.terms[0].field, "distance_m");
  EXPECT_EQ(c.terms[0].op, ">=");
  EXPECT_EQ(c.terms[1].op, "==");
  std::string why;
  EXPECT_TRUE(Meets(c, {{"distance_m", 0.1}, {"fell", false}}, &why));
  EXPECT_FALSE(Meets(c, {{"distance_m", 0.0999}, {"fell", false}}, &why));
  EXPECT_EQ(why, "distance_m = 0.0999");
  EXPECT_FALSE(Meets(c, {{"distance_m", 0.2}, {"fell", true}}, &why));
  EXPECT_EQ(why, "fell = 1");
  EXPECT_THROW(Meets(c, {{"fell", false}}, &why), climbsim::InputError);
  for (const char* bad : {"", "distance_m", "distance_m => 1", "distance_m >= x",
                          "distance_m >= 1; rm -rf /", "system('x') > 0", "1x > 0",
                          "distance_m >= nan", "distance_m >= 1 or fell == 0"}) {
    EXPECT_THROW(ParseCondition(bad), climbsim::InputError) << bad;
  }
  const std::string out = TempDir() + "/sweep_bad_condition";
  const CliResult r = RunClimbsimArgs({"sweep", GeckoWall("bad", "0.3"), "--find",
                                       "adhesion.sigma_t_pa", "--low", "1", "--high", "2",
                                       "--condition", "distance_m >= $(touch x)", "--out", out});
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "--condition")) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
