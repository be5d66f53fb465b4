// The optimiser's pieces: dotted keys, validation of the optimise block, the cost formula,
// failed rollouts, thread-count independence and bit-exact replay of best.yaml.
#include "experiments/experiments.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "tests/common/test_util.h"

namespace climbsim::optimise {
namespace {

using climbsim::testing::ReadFile;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

// A 1 s trot on the floor: rollouts take ~0.1 s, so a dozen evaluations fit in a test.
const std::string kFloor =
    "robot: gecko\nscene: floor\nduration_s: 1\n"
    "cpg:\n  gait: trot\n  frequency_hz: 1.0\n  stride_rad: [0.35, 0.0, 0.0]\n"
    "  lift_rad: [0.0, 0.4, 0.3]\n"
    "outputs:\n  trajectory_rate_hz: 0\n";
const std::string kBlock =
    "optimise:\n  parameters:\n"
    "    - {key: cpg.frequency_hz, start: 1.0, min: 0.5, max: 2.5}\n"
    "    - {key: \"cpg.stride_rad[0]\", start: 0.35, min: 0.1, max: 0.45}\n";

std::string ErrorOf(const std::string& name, const std::string& text) {
  try {
    Problem p(WriteFile(name, text));
  } catch (const InputError& e) {
    const std::string msg = e.what(), prefix = TempDir() + "/";
    return msg.rfind(prefix, 0) == 0 ? msg.substr(prefix.size()) : msg;
  }
  return "";
}

TEST(OptimiseDottedKey, SetsAndGetsMapsListsAndMatrices) {
  YAML::Node root = YAML::Load("a:\n  b: 1\n  list: [1, 2, 3]\n  m: [[0, 1], [2, 3]]\n");
  SetDottedKey(root, "a.b", 0.1);
  SetDottedKey(root, "a.list[2]", -4.5);
  SetDottedKey(root, "a.m[1][0]", 7);
  SetDottedKey(root, "a.new.deep", 2.5);  // missing maps are made
  EXPECT_EQ(GetDottedKey(root, "a.b"), 0.1);  // exact: shortest round-trip text
  EXPECT_EQ(GetDottedKey(root, "a.list[2]"), -4.5);
  EXPECT_EQ(GetDottedKey(root, "a.m[1][0]"), 7.0);
  EXPECT_EQ(GetDottedKey(root, "a.new.deep"), 2.5);
  EXPECT_EQ(GetDottedKey(root, "a.list[0]"), 1.0);  // neighbours untouched
}

TEST(OptimiseDottedKey, RejectsWhatTheFileDoesNotHold) {
  YAML::Node root = YAML::Load("a:\n  list: [1, 2]\n");
  EXPECT_THROW(SetDottedKey(root, "a.list[5]", 1), std::invalid_argument);
  EXPECT_THROW(SetDottedKey(root, "a.missing[0]", 1), std::invalid_argument);
  EXPECT_THROW(SetDottedKey(root, "a.list", 1), std::invalid_argument);  // a list, not a number
  EXPECT_THROW(SetDottedKey(root, "a..b", 1), std::invalid_argument);
  EXPECT_THROW(SetDottedKey(root, "a.list[x]", 1), std::invalid_argument);
}

TEST(OptimiseProblem, BlockErrorsNameTheirPlace) {
  EXPECT_EQ(ErrorOf("noblock.yaml", kFloor),
            "noblock.yaml: optimise: the scenario has no optimise block");
  EXPECT_EQ(
      ErrorOf("bounds.yaml", kFloor + "optimise:\n  parameters:\n"
                                      "    - {key: cpg.frequency_hz, start: 1, min: 2, max: 1}\n"),
      "bounds.yaml:13:54: optimise.parameters[0].max: must be greater than min");
  EXPECT_EQ(
      ErrorOf("start.yaml", kFloor + "optimise:\n  parameters:\n"
                                     "    - {key: cpg.frequency_hz, start: 9, min: 0.5, max: 2}\n"),
      "start.yaml:13:38: optimise.parameters[0].start: must lie in [min, max]");
  EXPECT_EQ(ErrorOf("nokey.yaml",
                    kFloor + "optimise:\n  parameters:\n"
                             "    - {key: \"cpg.lift_rad[7]\", start: 0.1, min: 0, max: 1}\n"),
            "nokey.yaml:13:13: optimise.parameters[0].key: cpg.lift_rad[7] is not in the file");
  // A bound outside what the key accepts is caught before any rollout.
  EXPECT_EQ(
      ErrorOf("range.yaml", kFloor + "optimise:\n  parameters:\n"
                                     "    - {key: cpg.frequency_hz, start: 1, min: -1, max: 2}\n"),
      "range.yaml:13:13: optimise.parameters[0].key: cpg.frequency_hz = -1 does not give a "
      "valid scenario: cpg.frequency_hz must be in (0, 20], got -1");
}

TEST(OptimiseCost, FollowsTheDocumentedFormula) {
  const std::string path =
      WriteFile("cost.yaml", kFloor + kBlock + "  objective:\n    energy_weight_mps: 0.01\n");
  Problem p(path);
  const sim::Scenario s = p.ScenarioFor(p.start(), 0);
  EXPECT_TRUE(s.fall.stop);  // a fall ends a rollout
  auto model = sim::CompileScenario(s);
  sim::Simulation run(s, *model);
  run.Run();
  const Cost c = RolloutCost(run, p.params().objective);
  const nlohmann::json summary = run.Summary();
  // J = −v + 0 (no fall) + 0 (no adhesion) + 0.01·CoT, v = distance / duration.
  const double v = run.result().distance_m / 1.0;
  EXPECT_DOUBLE_EQ(c.speed_mps, v);
  EXPECT_DOUBLE_EQ(c.energy_penalty, 0.01 * summary["cost_of_transport"].get<double>());
  EXPECT_DOUBLE_EQ(c.total, -v + c.energy_penalty);
  EXPECT_GT(v, 0.02);  // the trot moves forward
}

TEST(OptimiseProblem, PerturbedRunsDependOnlyOnSeedAndRun) {
  Problem p(WriteFile("perturb.yaml", kFloor + kBlock + "  objective:\n    runs: 3\n"));
  const auto x = p.start();
  const sim::Scenario nominal = p.ScenarioFor(x, 0);
  const sim::Scenario a = p.ScenarioFor(x, 1), b = p.ScenarioFor(x, 1), c = p.ScenarioFor(x, 2);
  EXPECT_EQ(nominal.initial.offset_m[0], 0.0);
  EXPECT_NE(a.initial.offset_m[0], 0.0);
  EXPECT_EQ(a.initial.offset_m, b.initial.offset_m);  // same seed and run: same draw
  EXPECT_NE(a.initial.offset_m, c.initial.offset_m);
  std::vector<double> other = {2.0, 0.2};
  EXPECT_EQ(p.ScenarioFor(other, 1).initial.offset_m, a.initial.offset_m);  // common numbers
}

TEST(Optimise, ThreadCountDoesNotChangeTheResultAndBestReplaysBitForBit) {
  const std::string path =
      WriteFile("threads.yaml", kFloor + kBlock + "  max_evaluations: 8\n  starts: 2\n");
  Options one, two;
  one.out_dir = TempDir() + "/threads1";
  one.threads = 1;
  two.out_dir = TempDir() + "/threads2";
  two.threads = 2;
  const Result r1 = Optimise(path, one), r2 = Optimise(path, two);
  ASSERT_EQ(r1.history.size(), 8u);
  ASSERT_EQ(r2.history.size(), 8u);
  for (size_t i = 0; i < r1.history.size(); ++i) {
    EXPECT_EQ(r1.history[i].x, r2.history[i].x) << i;
    EXPECT_EQ(r1.history[i].objective, r2.history[i].objective) << i;
  }
  EXPECT_EQ(ReadFile(one.out_dir + "/best.yaml"), ReadFile(two.out_dir + "/best.yaml"));
  EXPECT_LE(r1.best.objective, r1.start_objective);

  // best.yaml, simulated as a plain scenario, gives the best evaluation's cost exactly.
  const sim::Scenario best = sim::LoadScenario(one.out_dir + "/best.yaml");
  auto model = sim::CompileScenario(best);
  sim::Simulation replay(best, *model);
  replay.Run();
  EXPECT_EQ(NominalCost(replay).total, r1.best.nominal.total);
  EXPECT_EQ(r1.best.objective, r1.best.nominal.total);  // one run per evaluation
}

// A rollout that goes numerically bad costs kFailedCost, is logged, and the optimisation
// goes on (an exception through NLopt would end it).
TEST(Optimise, FailedRolloutsScoreLargeAndAreLogged) {
  WriteFile("models/fragile.xml", climbsim::testing::kUnstableRobotMjcf);
  const std::string path = WriteFile("fragile.yaml",
                                     "robot: models/fragile.xml\nscene: floor\nduration_s: 0.5\n"
                                     "physics:\n  integrator: euler\n  timestep_s: 0.005\n"
                                     "optimise:\n  parameters:\n    - {key: physics.timestep_s, "
                                     "start: 0.005, min: 0.004, max: 0.006}\n"
                                     "  max_evaluations: 3\n  starts: 1\n");
  Options o;
  o.out_dir = TempDir() + "/fragile";
  const Result r = Optimise(path, o);
  ASSERT_EQ(r.history.size(), 3u);
  for (const Evaluation& e : r.history) {
    EXPECT_EQ(e.objective, kFailedCost);
    EXPECT_EQ(e.failed_runs, 1);
  }
  const std::string log = ReadFile(o.out_dir + "/failures.log");
  EXPECT_NE(log.find("start 0 evaluation 0 run 0: step "), std::string::npos) << log;
  EXPECT_NE(log.find("mjWARN_BAD"), std::string::npos) << log;
}

// The case on a short budget: from the hand-tuned gecko_wall.yaml, eight evaluations
// of the default algorithm already find a faster climb, and best.yaml, simulated as a plain
// scenario, reports the best evaluation's cost bit for bit. (The full 400-evaluation run,
// 1.80x faster, is in docs/optimise.md.)
TEST(Optimise, GeckoWallShortBudgetClimbsFasterAndBestReplays) {
  Options o;
  o.out_dir = TempDir() + "/gecko_wall_opt";
  o.max_evaluations = 8;
  o.threads = 2;
  const Result r = Optimise(climbsim::testing::Source("examples/gecko_wall.yaml"), o);
  ASSERT_EQ(r.history.size(), 8u);
  EXPECT_GT(r.best.nominal.speed_mps, r.history.front().nominal.speed_mps);
  EXPECT_EQ(r.best.nominal.fall_penalty, 0.0);
  const sim::Scenario best = sim::LoadScenario(o.out_dir + "/best.yaml");
  auto model = sim::CompileScenario(best);
  sim::Simulation replay(best, *model);
  replay.Run();
  EXPECT_EQ(NominalCost(replay).total, r.best.objective);
}

// ---- Early stopping -------------------------------------------------------------------

// The gecko on the wall without adhesion: it falls within a fraction of a second.
const std::string kFallingWall =
    "robot: gecko\nscene: wall\nduration_s: 3\n"
    "cpg:\n  gait: lateral_sequence\n  frequency_hz: 0.6\n"
    "outputs:\n  trajectory_rate_hz: 0\n"
    "optimise:\n  parameters:\n    - {key: cpg.frequency_hz, start: 0.6, min: 0.3, max: 1.0}\n";

Cost FullRunCost(const Problem& p, const sim::Scenario& s) {
  auto model = sim::CompileScenario(s);
  sim::Simulation full(s, *model);
  full.Run();
  return RolloutCost(full, p.params().objective);
}

TEST(OptimiseEarlyStop, FallingGaitStopsAtTheFallWithTheFullRunsScore) {
  const Problem p(WriteFile("falling.yaml", kFallingWall));
  const sim::Scenario s = p.ScenarioFor(p.start(), 0);
  const Cost full = FullRunCost(p, s);
  auto model = sim::CompileScenario(s);
  for (double bound : {std::numeric_limits<double>::infinity(), 1.0}) {
    sim::Simulation early(s, *model);
    const Cost c = RunRollout(early, p.params().objective, bound);
    ASSERT_TRUE(early.result().fell);
    EXPECT_EQ(c.early_stop, "");     // decided by the fall, not by a bound or a stall
    EXPECT_EQ(c.total, full.total);  // bit for bit
    EXPECT_EQ(c.speed_mps, full.speed_mps);
    EXPECT_EQ(c.fall_penalty, p.params().objective.fall_penalty_mps);
    EXPECT_LT(c.stop_time_s, 0.5 * s.duration_s);
    EXPECT_NEAR(c.stop_time_s, early.result().fall_time_s, 1e-9);
  }
}

TEST(OptimiseEarlyStop, ARolloutThatRunsToTheEndScoresExactlyAsRolloutCost) {
  const Problem p(WriteFile("to_end.yaml", kFloor + kBlock));
  const sim::Scenario s = p.ScenarioFor(p.start(), 0);
  const Cost full = FullRunCost(p, s);
  auto model = sim::CompileScenario(s);
  sim::Simulation early(s, *model);
  const Cost c = RunRollout(early, p.params().objective, std::numeric_limits<double>::infinity());
  EXPECT_EQ(c.early_stop, "");
  EXPECT_EQ(c.total, full.total);
  EXPECT_NEAR(c.stop_time_s, s.duration_s, 1e-9);
}

TEST(OptimiseEarlyStop, AStalledGaitStopsAfterTheWindowAndKeepsItsDistance) {
  const std::string text =
      "robot: gecko\nscene: floor\nduration_s: 3\n"
      "cpg:\n  gait: trot\n  frequency_hz: 1.0\n  stride_rad: [0.0, 0.0, 0.0]\n"
      "  lift_rad: [0.0, 0.0, 0.0]\n"
      "outputs:\n  trajectory_rate_hz: 0\n" +
      kBlock + "  objective: {stall_window_s: 1.0, stall_distance_m: 0.005}\n";
  const Problem p(WriteFile("stalled.yaml", text));
  const sim::Scenario s = p.ScenarioFor(p.start(), 0);
  auto model = sim::CompileScenario(s);
  sim::Simulation early(s, *model);
  const Cost c = RunRollout(early, p.params().objective, std::numeric_limits<double>::infinity());
  EXPECT_EQ(c.early_stop, "stalled");
  EXPECT_GE(c.stop_time_s, 1.0);
  EXPECT_LE(c.stop_time_s, 1.1);  // the first check after a full window
  EXPECT_LT(std::abs(c.speed_mps), 0.005 / 1.0);
  EXPECT_EQ(c.total, -c.speed_mps + c.overload_penalty);  // as if it stayed put
}

// The bound rule stops a rollout that cannot beat the bound even at max_speed_mps; its
// score is a lower bound of the full run's, above the bound.
TEST(OptimiseEarlyStop, ABoundedRolloutScoresALowerBoundAboveTheBound) {
  const Problem p(
      WriteFile("bounded.yaml", kFloor + kBlock + "  objective: {max_speed_mps: 0.2}\n"));
  const sim::Scenario s = p.ScenarioFor(p.start(), 0);
  const Cost full = FullRunCost(p, s);
  const double bound = -0.15;
  ASSERT_GT(full.total, bound);  // the gait is slower than 0.15 m/s
  auto model = sim::CompileScenario(s);
  sim::Simulation early(s, *model);
  const Cost c = RunRollout(early, p.params().objective, bound);
  EXPECT_EQ(c.early_stop, "bound");
  EXPECT_GT(c.total, bound);
  EXPECT_LE(c.total, full.total);
  EXPECT_LT(c.stop_time_s, s.duration_s);
}

// A rollout run before its bound is known records a BoundTrace; cut to a bound afterwards
// (BoundedCost), it scores exactly what the bounded rollout scores, for bounds that stop it
// early, late or not at all.
TEST(OptimiseEarlyStop, ATracedRolloutCutToTheBoundScoresAsTheBoundedOne) {
  const Problem p(
      WriteFile("traced.yaml", kFloor + kBlock + "  objective: {max_speed_mps: 0.2}\n"));
  const sim::Scenario s = p.ScenarioFor(p.start(), 0);
  auto model = sim::CompileScenario(s);
  sim::Simulation traced_run(s, *model);
  BoundTrace trace;
  const Cost traced = RunRollout(traced_run, p.params().objective,
                                 std::numeric_limits<double>::infinity(), &trace);
  ASSERT_GT(trace.lower_j.size(), 10u);  // a check every 50 ms of the 1 s run
  EXPECT_EQ(traced.early_stop, "");
  int stopped = 0;
  for (double bound : {-0.19, -0.15, -0.1, traced.total - 1e-3, traced.total + 1.0,
                       std::numeric_limits<double>::infinity()}) {
    sim::Simulation bounded_run(s, *model);
    const Cost bounded = RunRollout(bounded_run, p.params().objective, bound);
    const Cost cut = BoundedCost(traced, trace, bound);
    EXPECT_EQ(cut.total, bounded.total) << bound;  // bit for bit
    EXPECT_EQ(cut.early_stop, bounded.early_stop) << bound;
    EXPECT_EQ(cut.stop_time_s, bounded.stop_time_s) << bound;
    EXPECT_EQ(cut.speed_mps, bounded.speed_mps) << bound;
    EXPECT_EQ(cut.overload_penalty, bounded.overload_penalty) << bound;
    EXPECT_EQ(cut.wall_time_s, traced.wall_time_s);  // the time the traced run took
    stopped += bounded.early_stop == "bound";
  }
  EXPECT_GE(stopped, 2);  // the cases include early stops
}

// ---- CMA-ES ------------------------------------------------------------------------------

TEST(OptimiseCmaes, GenerationsRunInParallelWithTheSameResultForAnyThreadCount) {
  const std::string path =
      WriteFile("cmaes.yaml", kFloor + kBlock +
                                  "  algorithm: cmaes\n  population: 5\n  max_evaluations: 11\n"
                                  "  starts: 1\n");
  Options one, two;
  one.out_dir = TempDir() + "/cmaes1";
  one.threads = 1;
  two.out_dir = TempDir() + "/cmaes2";
  two.threads = 2;
  const Result r1 = Optimise(path, one), r2 = Optimise(path, two);
  ASSERT_EQ(r1.history.size(), 11u);  // the start, then two generations of 5
  ASSERT_EQ(r2.history.size(), 11u);
  for (size_t i = 0; i < r1.history.size(); ++i) {
    EXPECT_EQ(r1.history[i].x, r2.history[i].x) << i;
    EXPECT_EQ(r1.history[i].objective, r2.history[i].objective) << i;
    EXPECT_GE(r1.history[i].x[0], 0.5);
    EXPECT_LE(r1.history[i].x[0], 2.5);
  }
  // The candidates of a generation differ (sampled, not copies of the start).
  EXPECT_NE(r1.history[1].x, r1.history[2].x);
  EXPECT_EQ(ReadFile(one.out_dir + "/best.yaml"), ReadFile(two.out_dir + "/best.yaml"));
  EXPECT_LE(r1.best.objective, r1.start_objective);
}

// A batch's rollouts are queued longest predicted first (the mean wall time of the same run
// in the start's previous batch); the order changes no result: the same history and
// best.yaml for 1 and 2 threads. The records the schedule simulation reads add up.
// (The first generation beside the start point changes nothing: a traced rollout cut to the
// bound scores as the bounded one, and CmaesStart throws if the points sampled with the
// start's real cost differ from those evaluated.)
TEST(OptimiseCmaes, RolloutsQueueLongestPredictedFirstWithTheSameResult) {
  const std::string path = WriteFile(
      "lpt.yaml", kFloor + kBlock +
                      "  algorithm: cmaes\n  population: 5\n  max_evaluations: 11\n  starts: 1\n"
                      "  objective: {runs: 3}\n");
  Options one, two;
  one.out_dir = TempDir() + "/lpt1";
  one.threads = 1;
  two.out_dir = TempDir() + "/lpt2";
  two.threads = 2;
  const Result r1 = Optimise(path, one), r2 = Optimise(path, two);
  ASSERT_EQ(r1.history.size(), 11u);  // the start, then two generations of 5
  ASSERT_EQ(r2.history.size(), 11u);
  for (size_t i = 0; i < r1.history.size(); ++i) {
    EXPECT_EQ(r1.history[i].x, r2.history[i].x) << i;
    EXPECT_EQ(r1.history[i].objective, r2.history[i].objective) << i;
  }
  EXPECT_EQ(ReadFile(one.out_dir + "/best.yaml"), ReadFile(two.out_dir + "/best.yaml"));

  for (const Result* r : {&r1, &r2}) {
    // The start point and the first generation in one batch (the first generation traced
    // until the start point's cost sets the bound), then the second generation.
    ASSERT_EQ(r->batches.size(), 2u);
    ASSERT_EQ(r->batches[0].wall_s.size(), 18u);
    std::vector<int> in_order(18);
    std::iota(in_order.begin(), in_order.end(), 0);
    EXPECT_EQ(r->batches[0].order, in_order);  // nothing to predict from
    double recorded_s = 0.0;
    for (size_t n = 0; n < r->batches.size(); ++n) {
      const BatchRecord& b = r->batches[n];
      EXPECT_EQ(b.number, static_cast<int>(n));
      std::vector<int> sorted = b.order;
      std::sort(sorted.begin(), sorted.end());
      std::vector<int> all(b.wall_s.size());
      std::iota(all.begin(), all.end(), 0);
      EXPECT_EQ(sorted, all) << "every slot queued once";
      for (double w : b.wall_s) {
        EXPECT_GT(w, 0.0);
        recorded_s += w;
      }
      if (n == 0) continue;
      EXPECT_NE(b.order, all) << "queued by run, not candidate by candidate";
      // The prediction: the previous batch's mean per run; queued in non-increasing order.
      const BatchRecord& prev = r->batches[n - 1];
      std::vector<double> mean_s(3, 0.0);
      for (size_t slot = 0; slot < prev.wall_s.size(); ++slot) {
        mean_s[slot % 3] += prev.wall_s[slot] / (prev.wall_s.size() / 3);
      }
      for (size_t i = 1; i < b.order.size(); ++i) {
        EXPECT_GE(mean_s[b.order[i - 1] % 3], mean_s[b.order[i] % 3] * (1 - 1e-12)) << n << i;
      }
    }
    double busy_s = 0.0;
    for (double w : r->worker_busy_s) busy_s += w;
    EXPECT_NEAR(busy_s, recorded_s, 1e-9 * recorded_s);
    for (double w : r->worker_busy_s) EXPECT_LE(w, r->serve_wall_s);
  }
  EXPECT_EQ(r1.worker_busy_s.size(), 1u);
  EXPECT_EQ(r2.worker_busy_s.size(), 2u);
}

}  // namespace
}  // namespace climbsim::optimise
