// The objective's robustness term (optimise.objective.robustness): J adds each case's penalty
// exactly when one of its runs does not survive by the bench's rule; the same best.yaml and
// history for 1 or 2 threads and (with MPI) 1 or 2 ranks; a killed run resumes to the same
// end (cli_test.cc); bad cases are refused at their key before any rollout.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "experiments/experiments.h"
#include "tests/common/test_util.h"

namespace {

using climbsim::testing::CliResult;
using climbsim::testing::Has;
using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsimArgs;
using climbsim::testing::SplitCsv;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

// A trot on the floor, 1 s runs; `robustness` is the objective's robustness list.
std::string Scenario(const std::string& robustness, const std::string& extra = "") {
  return "robot: gecko\nscene: floor\nduration_s: 1\n"
         "cpg:\n  gait: trot\n  frequency_hz: 1.0\n  stride_rad: [0.35, 0.0, 0.0]\n"
         "  lift_rad: [0.0, 0.4, 0.3]\n"
         "outputs:\n  trajectory_rate_hz: 0\n"
         "optimise:\n  parameters:\n"
         "    - {key: cpg.frequency_hz, start: 1.0, min: 0.5, max: 2.5}\n"
         "    - {key: \"cpg.stride_rad[0]\", start: 0.35, min: 0.1, max: 0.45}\n" +
         extra + "  objective:\n    robustness:\n" + robustness;
}

const char* kCases =
    "      - {family: push_off, magnitude: 0.05, seeds: 2, phases: 2, penalty_mps: 0.1}\n"
    "      - {family: push_side, magnitude: 2, seeds: 1, phases: 2, penalty_mps: 0.25}\n"
    "      - {family: payload, magnitude: 0.001, seeds: 2, first_seed: 5, penalty_mps: 0.5}\n";

std::vector<std::vector<std::string>> Rows(const std::string& csv) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(csv);
  for (std::string line; std::getline(in, line);) rows.push_back(SplitCsv(line));
  return rows;
}

size_t Column(const std::vector<std::string>& header, const std::string& name) {
  for (size_t i = 0; i < header.size(); ++i) {
    if (header[i] == name) return i;
  }
  ADD_FAILURE() << "no column " << name;
  return 0;
}

// Everything but the wall_time_s column, which no two runs share.
std::string WithoutWallTime(const std::string& csv) {
  std::string out;
  for (const auto& row : Rows(csv)) {
    for (size_t i = 0; i + 1 < row.size(); ++i) out += row[i] + ",";
    out += "\n";
  }
  return out;
}

CliResult Optimise(const std::string& scenario, const std::string& out,
                   const std::vector<std::string>& more = {}) {
  std::vector<std::string> args = {"optimise", scenario, "--out", out, "--quiet"};
  args.insert(args.end(), more.begin(), more.end());
  return RunClimbsimArgs(args);
}

// One evaluation (the start) with and without the term: J differs by exactly the penalties
// of the cases its history says failed; a 2 N s push across the floor (10 ms) throws it,
// a gram of payload does not matter.
TEST(OptimiseRobustnessTerm, AddsEachFailedCasesPenaltyExactly) {
  const std::string with = WriteFile("robust_term/with.yaml",
                                     Scenario(kCases, "  max_evaluations: 1\n  starts: 1\n"));
  std::string plain_text = Scenario("", "  max_evaluations: 1\n  starts: 1\n");
  plain_text = plain_text.substr(0, plain_text.find("  objective:"));
  const std::string plain = WriteFile("robust_term/plain.yaml", plain_text);
  ASSERT_EQ(Optimise(with, TempDir() + "/robust_with").code, 0);
  ASSERT_EQ(Optimise(plain, TempDir() + "/robust_plain").code, 0);
  const auto w = Rows(ReadFile(TempDir() + "/robust_with/history.csv"));
  const auto p = Rows(ReadFile(TempDir() + "/robust_plain/history.csv"));
  ASSERT_EQ(w.size(), 2u);
  ASSERT_EQ(p.size(), 2u);
  const int failed = std::stoi(w[1][Column(w[0], "robustness_cases_failed")]);
  const double penalty = std::stod(w[1][Column(w[0], "robustness_penalty_mps")]);
  EXPECT_EQ(failed, 1) << "the side push fails, the rest survive";
  EXPECT_EQ(penalty, 0.25);
  EXPECT_EQ(std::stod(w[1][Column(w[0], "objective")]),
            std::stod(p[1][Column(p[0], "objective")]) + 0.25);
  EXPECT_EQ(p[0].size() + 2, w[0].size()) << "the plain history keeps its columns";
}

// (Kill and resume, and 2 MPI ranks: tests/optimise/cli_test.cc, OptimiseCli.Robustness*.)
TEST(OptimiseRobustnessTerm, SameBestForOneOrTwoThreads) {
  const std::string scenario = WriteFile(
      "robust_term/threads.yaml",
      Scenario(kCases, "  algorithm: cmaes\n  population: 5\n  max_evaluations: 6\n"
                       "  starts: 1\n"));
  const std::string one = TempDir() + "/robust_threads_1", two = TempDir() + "/robust_threads_2";
  ASSERT_EQ(Optimise(scenario, one, {"--threads", "1"}).code, 0);
  ASSERT_EQ(Optimise(scenario, two, {"--threads", "2"}).code, 0);
  EXPECT_EQ(ReadFile(two + "/best.yaml"), ReadFile(one + "/best.yaml"));
  EXPECT_EQ(WithoutWallTime(ReadFile(two + "/history.csv")),
            WithoutWallTime(ReadFile(one + "/history.csv")));
  EXPECT_EQ(Rows(ReadFile(one + "/history.csv")).size(), 7u);
  EXPECT_TRUE(Has(ReadFile(one + "/best.yaml"), "family: push_side"));
}

TEST(OptimiseRobustnessTerm, BadCasesAreRefusedAtTheirKey) {
  struct Case {
    std::string robustness, where, what;
  };
  const std::vector<Case> cases = {
      {"      - {family: push_up, magnitude: 0.1}\n", "optimise.objective.robustness[0].family",
       "unknown family 'push_up'"},
      {"      - {family: payload, magnitude: 0.1}\n      - {family: weak_patch, magnitude: 0.5}\n",
       "optimise.objective.robustness[1].family", "it has no adhesion"},
      {"      - {family: push_off, magnitude: 0.1, push_time_s: 0.5}\n",
       "optimise.objective.robustness[0].push_time_s", "at most a third of the 1 s run"},
      {"      - {family: push_off, magnitude: 0}\n", "optimise.objective.robustness[0].magnitude",
       ""},
      {"      - {family: push_off}\n", "optimise.objective.robustness[0].magnitude", ""},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const std::string scenario =
        WriteFile("robust_term/bad" + std::to_string(i) + ".yaml", Scenario(cases[i].robustness));
    const std::string out = TempDir() + "/robust_bad" + std::to_string(i);
    const CliResult r = Optimise(scenario, out);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_TRUE(Has(r.err, cases[i].where)) << r.err;
    EXPECT_TRUE(Has(r.err, cases[i].what)) << r.err;
    EXPECT_FALSE(std::filesystem::exists(out + "/history.csv"));
  }
}

}  // namespace
