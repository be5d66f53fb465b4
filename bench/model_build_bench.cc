// What a robot key in sweep or optimise costs: each evaluation of a new design generates its
// robot (robot/design.h), composes and compiles the model (sim::CompiledModel::Build), where
// an evaluation of effect keys reuses one compiled model. Measured against one 20 s rollout
// of examples/gecko_wall.yaml in the same process; counter build_per_rollout is the ratio
// (docs/climbing.md, "Designing the body", quotes it; the target is at most 0.05).
#include <benchmark/benchmark.h>

#include <chrono>
#include <string>

#include "sim/sim.h"

namespace climbsim::sim {
namespace {

// examples/gecko_wall.yaml with duration_s 20, its robot a design: the gecko with a femur
// 20 % longer (docs/climbing.md's example).
Scenario WallDesign() {
  YAML::Node root = LoadYamlFile(std::string(CLIMBSIM_SOURCE_DIR) + "/examples/gecko_wall.yaml");
  root["duration_s"] = 20;
  RobotDesign design = PresetDesign("gecko");
  design.legs.femur_m *= 1.2;
  root["robot"] = YamlWriteArchive::Write(design);
  return ParseScenario(root, std::string(CLIMBSIM_SOURCE_DIR) + "/examples/gecko_wall.yaml");
}

double Seconds(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

void BM_BuildVersusRollout(benchmark::State& state) {
  const Scenario s = WallDesign();
  const MjcfAdditions additions = EffectAdditions(s);
  const auto t0 = std::chrono::steady_clock::now();
  {
    const auto model = CompiledModel::Build(s, additions);
    Simulation run(s, *model);
    benchmark::DoNotOptimize(run.Run().distance_m);
  }
  const double rollout_s = Seconds(std::chrono::steady_clock::now() - t0);
  double build_s = 0;
  int builds = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    const auto model = CompiledModel::Build(s, additions);  // generates the robot, compiles
    benchmark::DoNotOptimize(model->model());
    build_s += Seconds(std::chrono::steady_clock::now() - start);
    ++builds;
  }
  state.counters["rollout_s"] = rollout_s;
  state.counters["build_s"] = build_s / builds;
  state.counters["build_per_rollout"] = build_s / builds / rollout_s;
}

BENCHMARK(BM_BuildVersusRollout)->Unit(benchmark::kMillisecond)->Iterations(20);

// The generator alone (the model cache's key for a preset or a design is the composed text,
// so each rollout of sweep or optimise pays this much even when its model is cached).
void BM_GenerateOnly(benchmark::State& state) {
  const Scenario s = WallDesign();
  for (auto _ : state) benchmark::DoNotOptimize(RobotMjcf(s).size());
}

BENCHMARK(BM_GenerateOnly)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace climbsim::sim

BENCHMARK_MAIN();
