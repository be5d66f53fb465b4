// ns per BondGrid::Update of one pad, for square grids 4² to 64² (0.02 m × 0.02 m,
// σ_T = 10 kPa, μ = 0.5):
//   Holding:  a loaded pad that holds (every step of a stance): a 45° pull with a lever and
//             a side shear at 60 % of its pull-off; one round, nothing breaks. Most rows
//             are cleared by their bound, without a scan.
//   HoldingNear: the same at 95 % of pull-off (capped at 99 % of the first break): the
//             bound still clears every row, as the peaks of σ and τ share a column.
//   HoldingScan: the bound's worst case: σ from M_y peaks at the ±x edges, τ_y from F_y in
//             the centre columns, each at 0.8 σ_T; utilisation 0.8 but the bound 1.13, so
//             every row is scanned bond by bond.
//   Cascade:  BondAll + Update at 1.02× the pull-off of a 90° pull with a lever: the crack
//             runs from the trailing edge through the whole pad (counter: rounds).
//   BondAll:  the re-bonding alone, to subtract from Cascade.
//   Evaluate: the stress field and summary without the rupture bookkeeping.
//   PullOff:  the whole quasi-static search (about 25 cascades), for the CLI's pulloff verb.
//   PeakUtilisation/holding: the reflexes' signal after a Holding update (rows by their
//             bound); holding_hinted: with the last call's peak bond as hint (the adhesion
//             effect's call); scan, scan_hinted: the same after the HoldingScan load (the
//             loose row bound).
//   FrictionalHolding: FrictionalUpdate of a pad that holds (a gripping pull at 60 % of the
//             shear limit, with a lever): the bond of largest σ decides, no scan.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "adhesion/bond_grid.h"
#include "adhesion/frictional_law.h"
#include "adhesion/pulloff.h"

namespace climbsim::adhesion {
namespace {

PadParams Pad(int n) {
  PadParams p;
  p.width_m = 0.02;
  p.length_m = 0.02;
  p.grid_x = n;
  p.grid_y = n;
  p.mu = 0.5;
  return p;
}

const PullSetup kHoldingPull{.angle_rad = std::numbers::pi / 4, .azimuth_rad = 0.3, .arm_m = 0.005};
const PullSetup kPeelPull{.angle_rad = std::numbers::pi / 2, .arm_m = 0.01};

void Holding(benchmark::State& state, double fraction) {
  const PadParams pad = Pad(static_cast<int>(state.range(0)));
  const PulloffResult pull_off = PullOff(pad, kHoldingPull);
  // Never above the first break: the pad must hold.
  BondGrid probe(pad);
  probe.BondAll();
  const double first_break =
      pull_off.force_n / probe.Evaluate(PullLoad(pull_off.force_n, kHoldingPull)).peak_utilisation;
  const PadLoad load =
      PullLoad(std::min(fraction * pull_off.force_n, 0.99 * first_break), kHoldingPull);
  BondGrid grid(pad);
  grid.BondAll();
  for (auto _ : state) {
    BondGrid::UpdateResult r = grid.Update(load);
    benchmark::DoNotOptimize(r);
  }
  if (grid.bonded_count() != grid.size()) state.SkipWithError("the holding case broke bonds");
  state.counters["bonds"] = grid.size();
  state.counters["utilisation"] = grid.Summary().peak_utilisation;
}

// The row bound's worst case (HoldingScan): σ from M_y at the ±x edges, τ_y in the centre.
PadLoad ScanLoad(const PadParams& pad) {
  const double b = pad.width_m, area = pad.width_m * pad.length_m;
  const double i_y = pad.length_m * b * b * b / 12.0;
  return PadLoad{.fy_n = 0.8 * pad.sigma_t_pa * area / (1.5 * std::sqrt(3.0)),
                 .my_nm = 0.8 * pad.sigma_t_pa * i_y / (b / 2)};
}

void BM_UpdateHoldingScan(benchmark::State& state) {
  const PadParams pad = Pad(static_cast<int>(state.range(0)));
  const PadLoad load = ScanLoad(pad);
  BondGrid grid(pad);
  grid.BondAll();
  for (auto _ : state) {
    BondGrid::UpdateResult r = grid.Update(load);
    benchmark::DoNotOptimize(r);
  }
  if (grid.bonded_count() != grid.size()) state.SkipWithError("the holding case broke bonds");
  state.counters["bonds"] = grid.size();
  state.counters["utilisation"] = grid.Summary().peak_utilisation;
}

void BM_UpdateHolding(benchmark::State& state) { Holding(state, 0.6); }
void BM_UpdateHoldingNear(benchmark::State& state) { Holding(state, 0.95); }

void BM_UpdateCascade(benchmark::State& state) {
  const PadParams pad = Pad(static_cast<int>(state.range(0)));
  const double pull_off = PullOff(pad, kPeelPull).force_n;
  const PadLoad load = PullLoad(1.02 * pull_off, kPeelPull);
  BondGrid grid(pad);
  int rounds = 0;
  for (auto _ : state) {
    grid.BondAll();
    BondGrid::UpdateResult r = grid.Update(load);
    rounds = r.rounds;
    benchmark::DoNotOptimize(r);
  }
  if (!grid.detached()) state.SkipWithError("the cascade case did not detach");
  state.counters["bonds"] = grid.size();
  state.counters["rounds"] = rounds;
}

void BM_BondAll(benchmark::State& state) {
  BondGrid grid(Pad(static_cast<int>(state.range(0))));
  for (auto _ : state) {
    grid.BondAll();
    benchmark::ClobberMemory();
  }
}

void BM_Evaluate(benchmark::State& state) {
  const PadParams pad = Pad(static_cast<int>(state.range(0)));
  const PadLoad load = PullLoad(0.6 * PullOff(pad, kHoldingPull).force_n, kHoldingPull);
  BondGrid grid(pad);
  grid.BondAll();
  for (auto _ : state) {
    StressSummary s = grid.Evaluate(load);
    benchmark::DoNotOptimize(s);
  }
}

// PeakUtilisation after an update under `load`; `hinted`: with the last call's peak bond as
// the hint, as the adhesion effect calls it each step.
void Peak(benchmark::State& state, const PadParams& pad, const PadLoad& load, bool hinted) {
  BondGrid grid(pad);
  grid.BondAll();
  grid.Update(load);
  int bond = -1;
  grid.PeakUtilisation(&bond);
  for (auto _ : state) {
    const int hint = hinted ? bond : -1;
    const double u = grid.PeakUtilisation(&bond, hint);
    benchmark::DoNotOptimize(u);
  }
  if (grid.bonded_count() != grid.size()) state.SkipWithError("the load broke bonds");
  state.counters["utilisation"] = grid.PeakUtilisation();
}

PadLoad HoldingLoad(const PadParams& pad) {
  return PullLoad(0.6 * PullOff(pad, kHoldingPull).force_n, kHoldingPull);
}

// `load_of`: HoldingLoad (rows by their bound) or ScanLoad (every row read).
void BM_PeakUtilisation(benchmark::State& state, PadLoad (*load_of)(const PadParams&),
                        bool hinted) {
  const PadParams pad = Pad(static_cast<int>(state.range(0)));
  Peak(state, pad, load_of(pad), hinted);
}

void BM_FrictionalHolding(benchmark::State& state) {
  const PadParams pad = Pad(static_cast<int>(state.range(0)));
  FrictionalParams f;
  f.shear_limit_pa = pad.sigma_t_pa;
  const FrictionalLaw law(f);
  const double shear_n = 0.6 * f.shear_limit_pa * pad.width_m * pad.length_m;
  const PadLoad load{.fn_n = 0.3 * shear_n, .fx_n = -shear_n, .fy_n = 0.1 * shear_n,
                     .mx_nm = 1e-4 * shear_n, .my_nm = 2e-4 * shear_n};
  BondGrid grid(pad);
  grid.BondAll();
  double u = 0.0;
  for (auto _ : state) {
    BondGrid::UpdateResult r = FrictionalUpdate(&grid, law, load, &u);
    benchmark::DoNotOptimize(r);
  }
  if (grid.bonded_count() != grid.size()) state.SkipWithError("the holding case broke bonds");
  state.counters["utilisation"] = u;
}

void BM_PullOff(benchmark::State& state) {
  const PadParams pad = Pad(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    PulloffResult r = PullOff(pad, kPeelPull);
    benchmark::DoNotOptimize(r);
  }
}

BENCHMARK(BM_UpdateHolding)->RangeMultiplier(2)->Range(4, 64);
BENCHMARK(BM_UpdateHoldingNear)->RangeMultiplier(2)->Range(4, 64);
BENCHMARK(BM_UpdateHoldingScan)->RangeMultiplier(2)->Range(4, 64);
BENCHMARK(BM_UpdateCascade)->RangeMultiplier(2)->Range(4, 64);
BENCHMARK(BM_BondAll)->RangeMultiplier(2)->Range(4, 64);
BENCHMARK(BM_Evaluate)->RangeMultiplier(2)->Range(4, 64);
BENCHMARK_CAPTURE(BM_PeakUtilisation, holding, HoldingLoad, false)
    ->RangeMultiplier(2)
    ->Range(4, 64);
BENCHMARK_CAPTURE(BM_PeakUtilisation, holding_hinted, HoldingLoad, true)
    ->RangeMultiplier(2)
    ->Range(4, 64);
BENCHMARK_CAPTURE(BM_PeakUtilisation, scan, ScanLoad, false)
    ->RangeMultiplier(2)
    ->Range(4, 64);
BENCHMARK_CAPTURE(BM_PeakUtilisation, scan_hinted, ScanLoad, true)
    ->RangeMultiplier(2)
    ->Range(4, 64);
BENCHMARK(BM_FrictionalHolding)->RangeMultiplier(2)->Range(4, 64);
BENCHMARK(BM_PullOff)->Arg(16)->Arg(32)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace climbsim::adhesion

BENCHMARK_MAIN();
