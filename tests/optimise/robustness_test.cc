// `climbsim bench robustness`: the example of its --help runs; robustness.csv has its columns;
// each reported magnitude is the edge the bisection claims (re-run: the survived magnitude
// survives, the failing one, within 10 % above it, fails, and so does its failing/ file); the report does not depend on the
// thread count; an --out that holds anything is refused before anything runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "experiments/experiments.h"
#include "tests/common/test_util.h"

namespace climbsim::optimise {
namespace {

using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsim;
using climbsim::testing::Source;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

std::vector<std::vector<std::string>> ReadCsv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::string cur;
    bool quoted = false;
    for (char c : line) {
      if (c == '"') {
        quoted = !quoted;
      } else if (c == ',' && !quoted) {
        cells.push_back(cur);
        cur.clear();
      } else {
        cur += c;
      }
    }
    cells.push_back(cur);
    rows.push_back(cells);
  }
  return rows;
}

TEST(Robustness, HelpExampleRunsAndEachMagnitudeIsTheBisectionsEdge) {
  const auto help = RunClimbsim("bench robustness --help");
  ASSERT_EQ(help.code, 0);
  const size_t at = help.out.rfind("Example:\n  climbsim ");
  ASSERT_NE(at, std::string::npos) << help.out;
  std::string args = help.out.substr(at + std::string("Example:\n  climbsim ").size());
  args = args.substr(0, args.find('\n'));
  // As a user in the source tree would run it, the output in a fresh folder.
  const std::string out = TempDir() + "/robustness_example";
  args.replace(args.find("examples/"), 9, Source("examples/"));
  args.replace(args.find("runs/robustness_quick"), 21, out);
  const auto r = RunClimbsim(args);
  ASSERT_EQ(r.code, 0) << args << "\n" << r.err;
  EXPECT_NE(r.out.find("push_down"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("robustness"), std::string::npos);  // the progress bar

  const auto rows = ReadCsv(ReadFile(out + "/robustness.csv"));
  ASSERT_EQ(rows.size(), 5u);  // header, two families x two modes
  EXPECT_EQ(rows[0], (std::vector<std::string>{"family", "unit", "mode", "survived", "failed", "lo",
                                               "hi", "evaluations", "runs", "failing_case",
                                               "failing_how", "same_as_reflexes"}));
  EXPECT_EQ(rows[1][0], "push_down");
  EXPECT_EQ(rows[1][2], "reflexes");
  EXPECT_EQ(rows[2][2], "spindle_gto_off");
  EXPECT_EQ(rows[3][0], "pad_failure");

  // Re-run the edges of each search with the library, on the same cases.
  const sim::Scenario base = sim::LoadScenario(Source("examples/gecko_wall.yaml"));
  RobustnessOptions o;
  o.duration_s = 3;
  o.seeds = 1;
  o.phases = 1;
  for (size_t i = 1; i < rows.size(); ++i) {
    const std::string& family = rows[i][0];
    const int mode = rows[i][2] == "reflexes" ? 0 : 1;
    const double survived = std::stod(rows[i][3]);
    const double lo = std::stod(rows[i][5]), hi = std::stod(rows[i][6]);
    ASSERT_NE(rows[i][4], "inf") << "the example's families fail inside their range";
    const double failed = std::stod(rows[i][4]);
    ASSERT_GE(survived, lo) << family;
    EXPECT_LE(failed, hi);
    EXPECT_GT(failed, survived);
    EXPECT_LE(failed, survived * 1.1 * (1 + 1e-12)) << family;  // bisection to 10 %
    if (mode == 1 && rows[i][11] == "1") continue;              // one search serves both modes
    sim::Simulation calm(RobustnessCase(base, o, "", 0, mode, 0, 0),
                         *sim::CompileScenario(RobustnessCase(base, o, "", 0, mode, 0, 0)));
    const double baseline = calm.Run().distance_m;
    ASSERT_GT(baseline, 0);
    std::string how;
    EXPECT_TRUE(
        RobustnessSurvives(RobustnessCase(base, o, family, survived, mode, 0, 0), baseline, &how))
        << family << " at " << survived << ": " << how;
    EXPECT_FALSE(
        RobustnessSurvives(RobustnessCase(base, o, family, failed, mode, 0, 0), baseline, &how))
        << family << " at " << failed;
    EXPECT_EQ(how, rows[i][10]) << family;  // the same failure as reported
    // The failing case as a file replays to the same failure.
    const std::string file =
        out + "/failing/" + family + (mode == 0 ? "" : "_spindle_gto_off") + ".yaml";
    ASSERT_TRUE(std::filesystem::exists(file)) << file;
    EXPECT_FALSE(RobustnessSurvives(sim::LoadScenario(file), baseline, &how)) << file;
    EXPECT_EQ(how, rows[i][10]) << file;
  }
}

TEST(Robustness, PushesPointOffDownAndAcrossTheWall) {
  const sim::Scenario base = sim::LoadScenario(Source("examples/gecko_wall.yaml"));
  RobustnessOptions o;
  o.duration_s = 6;
  o.phases = 4;
  const double f = base.cpg->frequency_hz;
  struct {
    const char* family;
    std::vector<double> dir;
  } cases[] = {{"push_off", {0, 0, 1}}, {"push_down", {-1, 0, 0}}, {"push_side", {0, -1, 0}}};
  for (const auto& c : cases) {
    const sim::Scenario s = RobustnessCase(base, o, c.family, 0.2, 0, 0, 3);
    ASSERT_EQ(s.perturbations.size(), 1u);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(s.perturbations[0].impulse_ns[k], 0.2 * c.dir[k], 1e-15);
    EXPECT_DOUBLE_EQ(s.perturbations[0].duration_s, 0.01);
    EXPECT_DOUBLE_EQ(s.perturbations[0].time_s, 2.0 + 3 / (4 * f));  // a third of 6 s, phase 3/4
    EXPECT_TRUE(s.fall.stop);
  }
  // Spindle and GTO off in mode 1, nothing else changed.
  sim::Scenario on = base, off = RobustnessCase(base, o, "", 0, 1, 0, 0);
  EXPECT_FALSE(off.reflex->spindle.enabled);
  EXPECT_FALSE(off.reflex->gto.enabled);
  EXPECT_EQ(off.reflex->peel.enabled, on.reflex->peel.enabled);
  // Seeds ≥ 1 move the start a little; seed 0 is the scenario's.
  const sim::Scenario s0 = RobustnessCase(base, o, "", 0, 0, 0, 0);
  const sim::Scenario s1 = RobustnessCase(base, o, "", 0, 0, 1, 0);
  EXPECT_EQ(s0.initial.offset_m, base.initial.offset_m);
  EXPECT_NE(s1.initial.offset_m, base.initial.offset_m);
  EXPECT_LE(std::abs(s1.initial.offset_m[0]), 0.005);
  EXPECT_LE(std::abs(s1.initial.yaw_deg), 5.0);
  EXPECT_EQ(s1.seed, base.seed + 1);
}

// A step's cases run side by side (experiments/case_pool.h): the table, robustness.csv and
// each row's runs are those of the cases run one by one, and the records that the schedule
// simulation reads agree with the rows.
TEST(Robustness, SameReportWhateverTheThreads) {
  RobustnessOptions o;
  o.duration_s = 2.0;
  o.seeds = 2;
  o.families = {"payload"};
  o.phases = 1;
  o.threads = 1;
  const RobustnessReport one = BenchRobustness(Source("examples/gecko_wall.yaml"), o);
  o.threads = 2;
  const RobustnessReport two = BenchRobustness(Source("examples/gecko_wall.yaml"), o);
  ASSERT_EQ(one.rows.size(), 2u);
  ASSERT_EQ(one.rows.size(), two.rows.size());
  for (size_t i = 0; i < one.rows.size(); ++i) {
    EXPECT_EQ(one.rows[i].survived, two.rows[i].survived) << one.rows[i].family;
    EXPECT_EQ(one.rows[i].failed, two.rows[i].failed);
    EXPECT_EQ(one.rows[i].failing_how, two.rows[i].failing_how);
    EXPECT_EQ(one.rows[i].runs, two.rows[i].runs);
    EXPECT_EQ(one.rows[i].evaluations, two.rows[i].evaluations);
    EXPECT_EQ(one.rows[i].failing_case, two.rows[i].failing_case);
  }
  EXPECT_EQ(one.baseline_m, two.baseline_m);
  EXPECT_EQ(RobustnessTable(one), RobustnessTable(two));
  const std::string dir_one = TempDir() + "/robust_threads1";
  const std::string dir_two = TempDir() + "/robust_threads2";
  WriteRobustness(dir_one, one);
  WriteRobustness(dir_two, two);
  EXPECT_EQ(ReadFile(dir_one + "/robustness.csv"), ReadFile(dir_two + "/robustness.csv"));

  for (const RobustnessReport* r : {&one, &two}) {
    ASSERT_EQ(r->searches.size(), 2u);  // payload in two modes
    EXPECT_EQ(r->baselines.wall_s.size(), 4u);  // two modes x two seeds
    for (size_t s = 0; s < r->searches.size(); ++s) {
      const RobustnessRow& row = r->rows[s];
      ASSERT_EQ(static_cast<int>(r->searches[s].size()), row.evaluations);
      int runs = 0;
      for (const RobustnessStepRecord& step : r->searches[s]) {
        ASSERT_EQ(step.wall_s.size(), 2u);  // two seeds, one phase
        // The in-order verdict: the cases up to the first failure ran, and count as runs.
        size_t first = 0;
        while (first < step.failed.size() && !step.failed[first]) ++first;
        for (size_t i = 0; i < std::min(first + 1, step.ran.size()); ++i) EXPECT_TRUE(step.ran[i]);
        runs += static_cast<int>(std::min(first + 1, step.ran.size()));
      }
      EXPECT_EQ(runs, row.runs) << row.mode;
    }
    double busy_s = 0.0;
    for (double b : r->worker_busy_s) busy_s += b;
    EXPECT_GT(busy_s, 0.0);
    EXPECT_LE(busy_s, r->wall_s * r->worker_busy_s.size());
  }
  EXPECT_EQ(one.worker_busy_s.size(), 1u);
  EXPECT_EQ(two.worker_busy_s.size(), 2u);
}

TEST(Robustness, RefusesAnOutFolderThatHoldsSomething) {
  const std::string out = TempDir() + "/robustness_full";
  WriteFile(out + "/mine.txt", "a user's file");
  const auto r = RunClimbsim("bench robustness " + Source("examples/gecko_wall.yaml") +
                             " --duration 1 --out " + out);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--out"), std::string::npos) << r.err;
  EXPECT_EQ(ReadFile(out + "/mine.txt"), "a user's file");
  EXPECT_FALSE(std::filesystem::exists(out + "/robustness.csv"));
  // An unknown family is bad input too.
  const auto f = RunClimbsim("bench robustness " + Source("examples/gecko_wall.yaml") +
                             " --families wind --out " + TempDir() + "/robustness_wind");
  EXPECT_EQ(f.code, 2);
  EXPECT_NE(f.err.find("unknown family 'wind'"), std::string::npos) << f.err;
}

}  // namespace
}  // namespace climbsim::optimise
