// ns per OscillatorNetwork::Step at dt = 1 ms (a typical physics or control step), for the
// phase and Hopf networks, 4 legs (lateral-sequence walk) and 6 legs (wave gait), each
// stepper. "fb" variants pass Tegotae-like feedback that changes every step, as the simulator
// does: Dopri5 then re-evaluates its first derivative each Step (no FSAL reuse).
// Counter rhs_per_step: right-hand-side evaluations per Step, the cost driver.
#include <benchmark/benchmark.h>

#include <memory>
#include <string>
#include <vector>

#include "cpg/cpg.h"
#include "tests/cpg/test_util.h"

namespace climbsim::cpg {
namespace {

// Args: hopf (0/1), legs (4/6), stepper (0 Euler, 1 RK4, 2 Dopri5), changing feedback (0/1).
void BM_Step(benchmark::State& state) {
  const bool hopf = state.range(0) != 0;
  const int legs = static_cast<int>(state.range(1));
  const auto stepper = static_cast<Stepper>(state.range(2));
  const bool feedback_on = state.range(3) != 0;
  std::unique_ptr<OscillatorNetwork> network = testing::MakeGaitNetwork(hopf, legs, stepper);
  std::vector<double> feedback(legs, 0.0);
  // Settle first, so that Dopri5's step size is the steady one.
  for (int k = 0; k < 2000; ++k) network->Step(1e-3, {});
  const IntegrationStats before = network->stats();
  for (auto _ : state) {
    if (feedback_on) {
      for (int i = 0; i < legs; ++i) {
        feedback[i] = TegotaeFeedback(6.0, 0.5, network->phase_rad()[i]);
      }
      network->Step(1e-3, feedback);
    } else {
      network->Step(1e-3, {});
    }
    benchmark::DoNotOptimize(network->phase_rad().data());
  }
  const IntegrationStats after = network->stats();
  state.counters["rhs_per_step"] =
      static_cast<double>(after.rhs_evaluations - before.rhs_evaluations) /
      static_cast<double>(after.steps - before.steps);
  static const char* kStepper[] = {"euler", "rk4", "dopri5"};
  state.SetLabel(std::string(hopf ? "hopf" : "phase") + "/" + std::to_string(legs) + "legs/" +
                 kStepper[state.range(2)] + (feedback_on ? "/fb" : ""));
}

BENCHMARK(BM_Step)->ArgsProduct({{0, 1}, {4, 6}, {0, 1, 2}, {0, 1}});

}  // namespace
}  // namespace climbsim::cpg

BENCHMARK_MAIN();
