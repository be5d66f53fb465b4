// ns per LegReflex::Update (one leg, one control period, every reflex on), and per law.
// The sensing cycles through a precomputed 400-period gait script so that every branch of
// the state machine is taken, as in a simulation; building the script is not timed.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "reflex/reflex.h"

namespace climbsim::reflex {
namespace {

constexpr double kDt = 0.002;

std::vector<LegSensing> GaitScript() {
  std::vector<LegSensing> script;
  for (int k = 0; k < 400; ++k) {
    const int phase = k % 200;
    const bool failed_step = k >= 200;  // the second step misses: search
    LegSensing s;
    s.stance = phase < 120;
    s.phase_progress = s.stance ? phase / 120.0 : (phase - 120) / 80.0;
    s.touching = failed_step ? (phase > 60 && phase < 124) : (phase > 2 && phase < 124);
    s.attached = s.touching && phase > 10;
    s.bonded_fraction = s.attached ? std::min(1.0, (phase - 10) / 40.0) : 0.0;
    s.normal_load_n = s.attached && phase < 90 ? 0.4 : 0.0;
    s.preload_n = s.touching ? 0.3 : 0.0;
    s.bonds_lost = phase == 50 || phase == 125;
    s.partner_attached = true;
    s.stretch_rad = Eigen::Vector3d(0.1, -0.2, 0.3) * std::sin(0.05 * k);
    s.stretch_velocity_rad_per_s = Eigen::Vector3d(1.0, -2.0, 3.0) * std::cos(0.05 * k);
    script.push_back(s);
  }
  return script;
}

void BM_LegReflexUpdate(benchmark::State& state) {
  const std::vector<LegSensing> script = GaitScript();
  LegReflex leg(LegReflexParams{}, kDt);
  size_t k = 0;
  for (auto _ : state) {
    LegReflexOutput out = leg.Update(script[k]);
    benchmark::DoNotOptimize(out);
    k = k + 1 == script.size() ? 0 : k + 1;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_LegReflexUpdate);

// Six legs, as the spider: the per-period cost of the reflex layer.
void BM_SixLegReflexUpdate(benchmark::State& state) {
  const std::vector<LegSensing> script = GaitScript();
  std::vector<LegReflex> legs(6, LegReflex(LegReflexParams{}, kDt));
  size_t k = 0;
  for (auto _ : state) {
    for (size_t leg = 0; leg < legs.size(); ++leg) {
      LegReflexOutput out = legs[leg].Update(script[(k + 67 * leg) % script.size()]);
      benchmark::DoNotOptimize(out);
    }
    k = k + 1 == script.size() ? 0 : k + 1;
  }
  state.SetItemsProcessed(state.iterations() * 6);
}
BENCHMARK(BM_SixLegReflexUpdate);

void BM_SpindleUpdate(benchmark::State& state) {
  SpindleReflex spindle(SpindleParams{}, kDt);
  double q = 0.0;
  for (auto _ : state) {
    q = q > 0.5 ? -0.5 : q + 0.01;
    benchmark::DoNotOptimize(spindle.Update(q, 10.0 * q));
  }
}
BENCHMARK(BM_SpindleUpdate);

void BM_GtoUpdate(benchmark::State& state) {
  GtoReflex gto(GtoParams{}, kDt);
  double f = 0.0;
  for (auto _ : state) {
    f = f > 1.0 ? 0.0 : f + 0.01;
    benchmark::DoNotOptimize(gto.Update(f));
  }
}
BENCHMARK(BM_GtoUpdate);

}  // namespace
}  // namespace climbsim::reflex

BENCHMARK_MAIN();
