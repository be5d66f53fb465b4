// Sweep and optimise over the body: robot.* keys on a scenario whose robot is a preset name
// (the name becomes {preset: name, ...}); a model is generated and compiled per design.
#include <gtest/gtest.h>

#include <set>

#include "experiments/experiments.h"
#include "tests/common/test_util.h"

namespace climbsim::optimise {
namespace {

using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

// A 2 s trot on the floor: the feet reach as far as the femur lets them.
const std::string kFloor =
    "robot: gecko\nscene: floor\nduration_s: 2\n"
    "cpg:\n  gait: trot\n  frequency_hz: 1.0\n  stride_rad: [0.35, 0.0, 0.0]\n"
    "  lift_rad: [0.0, 0.4, 0.3]\n"
    "outputs:\n  trajectory_rate_hz: 0\n";

// The femur_m the tree gives, its model: the knee's place and the pad's reach change with it.
std::string ModelText(const std::string& file, double femur_m) {
  YAML::Node tree = sim::LoadYamlFile(file);
  SetDottedKey(tree, "robot.legs.femur_m", femur_m);
  return sim::RobotMjcf(sim::ParseScenario(tree, file));
}

TEST(RobotKeys, SweepingTheFemurGivesFiveBodiesAndFiveOutcomes) {
  const std::string file = WriteFile("robot_sweep.yaml", kFloor);
  SweepOptions o;
  o.key = "robot.legs.femur_m";
  o.from = 0.05;
  o.to = 0.07;
  o.step = 0.005;
  o.threads = 2;
  const std::vector<SweepRow> rows = Sweep({file}, o);
  ASSERT_EQ(rows.size(), 5u);
  std::set<std::string> models;
  std::set<double> distances;
  for (const SweepRow& r : rows) {
    models.insert(ModelText(file, r.value));
    ASSERT_TRUE(r.results[0].stable) << r.value;
    distances.insert(r.results[0].distance_m);
  }
  EXPECT_EQ(models.size(), 5u);
  EXPECT_EQ(distances.size(), 5u);
}

TEST(RobotKeys, OptimisesTheFemurWithTheFrequency) {
  const std::string file = WriteFile(
      "robot_opt.yaml",
      kFloor +
          "optimise:\n  parameters:\n"
          "    - {key: robot.legs.femur_m, start: 0.06, min: 0.045, max: 0.075}\n"
          "    - {key: cpg.frequency_hz, start: 1.0, min: 0.5, max: 1.5}\n"
          "  max_evaluations: 5\n  starts: 1\n");
  Options o;
  o.out_dir = TempDir() + "/robot_opt";
  o.threads = 2;
  const Result r = Optimise(file, o);
  ASSERT_EQ(r.history.size(), 5u);
  std::set<double> femurs;
  for (const Evaluation& e : r.history) {
    EXPECT_EQ(e.failed_runs, 0);
    femurs.insert(e.x[0]);
  }
  EXPECT_GT(femurs.size(), 1u) << "the femur was varied";
  EXPECT_LE(r.best.objective, r.history.front().objective);
  // best.yaml holds the best femur as a design over the preset, and reruns its cost.
  const sim::Scenario best = sim::LoadScenario(o.out_dir + "/best.yaml");
  ASSERT_TRUE(best.robot_design.has_value());
  EXPECT_EQ(best.robot_design->legs.femur_m, r.best.x[0]);
  EXPECT_EQ(best.robot_design->preset, "gecko");
  const auto model = sim::CompileScenario(best);
  sim::Simulation replay(best, *model);
  replay.Run();
  EXPECT_EQ(NominalCost(replay).total, r.best.nominal.total);
}

}  // namespace
}  // namespace climbsim::optimise
