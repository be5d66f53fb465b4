// BondGrid against closed forms: the stress field, its equilibrium, the sign convention of
// the moments, rupture, the cascade, degenerate bonded sets and bad parameters.
#include "adhesion/bond_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "tests/adhesion/closed_forms.h"

namespace climbsim::adhesion {
namespace {

using testing::Kappa;

PadParams Pad(double width_m, double length_m, int nx, int ny) {
  PadParams p;
  p.width_m = width_m;
  p.length_m = length_m;
  p.grid_x = nx;
  p.grid_y = ny;
  return p;
}

// Sums over the bonded points: resultant and first moments of σ, resultants of τ.
struct Resultants {
  double fn = 0, mx = 0, my = 0, fx = 0, fy = 0;
};
Resultants Integrate(const BondGrid& g) {
  Resultants r;
  const double da = g.cell_area_m2();
  for (int i = 0; i < g.size(); ++i) {
    if (!g.bonded(i)) continue;
    const BondStress s = g.stress(i);
    r.fn += s.sigma_pa * da;
    r.mx += s.sigma_pa * g.bond_y_m(i) * da;   // M_x = Σ σ y dA
    r.my -= s.sigma_pa * g.bond_x_m(i) * da;   // M_y = −Σ σ x dA
    r.fx += s.tau_x_pa * da;
    r.fy += s.tau_y_pa * da;
  }
  return r;
}

// ---------------------------------------------------------------------------------------
// Geometry and attachment state.

TEST(BondGridGeometry, CellCentresAreSymmetricAndTileThePad) {
  const BondGrid g(Pad(0.03, 0.01, 6, 4));
  EXPECT_EQ(g.size(), 24);
  EXPECT_DOUBLE_EQ(g.cell_area_m2(), 0.03 * 0.01 / 24);
  EXPECT_DOUBLE_EQ(g.bond_x_m(g.index(0, 0)), -0.0125);
  EXPECT_DOUBLE_EQ(g.bond_y_m(g.index(0, 0)), -0.00375);
  for (int i = 0; i < g.size(); ++i) {
    const int mirror = g.index(5 - g.ix_of(i), 3 - g.iy_of(i));
    EXPECT_EQ(g.bond_x_m(i), -g.bond_x_m(mirror));  // exactly
    EXPECT_EQ(g.bond_y_m(i), -g.bond_y_m(mirror));
  }
  EXPECT_EQ(g.bonded_count(), 0);  // a new grid is unattached
}

TEST(BondGridAttach, FractionBondsTheCentreFirstAndGrowSkipsBrokenBonds) {
  BondGrid g(Pad(0.02, 0.02, 8, 8));
  // A quarter of 8x8 centre-out is the central 4x4 block: squared normalised distances
  // (in units of 1/64) 2 (4 bonds), 10 (8 bonds), 18 (4 bonds).
  g.BondFraction(0.25);
  EXPECT_EQ(g.bonded_count(), 16);
  for (int i = 0; i < g.size(); ++i) {
    const bool central = g.ix_of(i) >= 2 && g.ix_of(i) <= 5 && g.iy_of(i) >= 2 && g.iy_of(i) <= 5;
    EXPECT_EQ(g.bonded(i), central) << i;
  }
  EXPECT_DOUBLE_EQ(g.bonded_fraction(), 0.25);
  EXPECT_DOUBLE_EQ(g.bonded_area_m2(), 0.25 * 0.02 * 0.02);

  // Break the whole (central) set with a straight pull, then grow: broken bonds stay broken.
  PadLoad pull;
  pull.fn_n = 2.0 * g.params().sigma_t_pa * g.bonded_area_m2();
  EXPECT_EQ(g.Update(pull).broken, 16);
  EXPECT_EQ(g.Grow(1.0), 48);
  EXPECT_EQ(g.bonded_count(), 48);
  EXPECT_EQ(g.state(g.index(3, 3)), BondState::kBroken);
  // A new attachment clears the broken marks.
  g.BondFraction(1.0);
  EXPECT_EQ(g.bonded_count(), 64);
  g.Release();
  EXPECT_EQ(g.bonded_count(), 0);
  g.BondFraction(std::nan(""));
  EXPECT_EQ(g.bonded_count(), 0);
  EXPECT_THROW(g.SetBonded(64, true), std::out_of_range);
}

// ---------------------------------------------------------------------------------------
// The stress field.

TEST(PadStress, CentralPullIsExactlyUniform) {
  for (int n : {8, 16, 32}) {
    BondGrid g(Pad(0.02, 0.02, n, n));
    g.BondAll();
    PadLoad load;
    load.fn_n = 1.234;
    const StressSummary s = g.Evaluate(load);
    const double expected = 1.234 / (0.02 * 0.02);
    for (int i = 0; i < g.size(); ++i) {
      // The centroid of a mirror-symmetric set is exactly 0: no moment term at all.
      EXPECT_NEAR(g.stress(i).sigma_pa, expected, 1e-12 * expected);
      EXPECT_EQ(g.stress(i).sigma_pa, g.stress(0).sigma_pa);
    }
    EXPECT_NEAR(s.peak_utilisation, expected / g.params().sigma_t_pa, 1e-12);
  }
}

// With bonds as points, the full pad's second moments are the midpoint sums
// b·h³/12·(1 − 1/N_y²) and h·b³/12·(1 − 1/N_x²) (closed_forms.h): σ matches the beam formula
// with those exactly, and the continuous b·h³/12 form within the factor 1/(1 − 1/N²).
TEST(PadStress, FullPadMatchesBeamFormulaWithGridSecondMoments) {
  for (const auto& [b, h, nx, ny] :
       {std::tuple{0.02, 0.02, 16, 16}, std::tuple{0.06, 0.02, 24, 8},
        std::tuple{0.01, 0.03, 5, 15}, std::tuple{0.02, 0.02, 64, 64}}) {
    BondGrid g(Pad(b, h, nx, ny));
    g.BondAll();
    PadLoad load{.fn_n = 0.7, .fx_n = 0.2, .fy_n = -0.3, .mx_nm = 0.004, .my_nm = -0.003};
    g.Evaluate(load);
    const double i_x_grid = b * h * h * h / 12.0 * (1.0 - 1.0 / (ny * ny));
    const double i_y_grid = h * b * b * b / 12.0 * (1.0 - 1.0 / (nx * nx));
    const double scale = std::abs(load.fn_n) / (b * h) +
                         std::abs(load.mx_nm) * h / 2 / i_x_grid +
                         std::abs(load.my_nm) * b / 2 / i_y_grid;
    double worst_continuum = 0.0;
    for (int i = 0; i < g.size(); ++i) {
      const double x = g.bond_x_m(i), y = g.bond_y_m(i);
      const double exact =
          load.fn_n / (b * h) + load.mx_nm * y / i_x_grid - load.my_nm * x / i_y_grid;
      EXPECT_NEAR(g.stress(i).sigma_pa, exact, 1e-12 * scale);
      const double continuum = load.fn_n / (b * h) + load.mx_nm * y / (b * h * h * h / 12) -
                               load.my_nm * x / (h * b * b * b / 12);
      worst_continuum = std::max(worst_continuum, std::abs(g.stress(i).sigma_pa - continuum));
    }
    // The moment terms differ by 1/(N² − 1) of themselves at most.
    const double moment_scale = std::abs(load.mx_nm) * h / 2 / i_x_grid / (ny * ny - 1.0) +
                                std::abs(load.my_nm) * b / 2 / i_y_grid / (nx * nx - 1.0);
    EXPECT_LE(worst_continuum, moment_scale * (1 + 1e-9) + 1e-12 * scale);
    EXPECT_GT(worst_continuum, 0.5 * moment_scale);  // and the difference is really there
  }
}

TEST(PadStress, PureShearPeaksAtThreeHalvesOfMeanAsTheGridRefines) {
  double previous_error = 1.0;
  for (int n : {4, 8, 16, 32, 64, 128}) {
    BondGrid g(Pad(0.03, 0.01, n, n));
    g.BondAll();
    const double f = 2.0, area = 0.03 * 0.01;
    PadLoad load;
    load.fx_n = f;
    g.Evaluate(load);
    double peak = 0.0;
    for (int i = 0; i < g.size(); ++i) peak = std::max(peak, g.stress(i).tau_x_pa);
    // Exact on the grid: 3F/(2A)·κ(N) (closed_forms.h).
    EXPECT_NEAR(peak, 1.5 * f / area * Kappa(n), 1e-12 * f / area);
    const double error = std::abs(peak / (1.5 * f / area) - 1.0);
    EXPECT_LE(error, 1.5 / (n * n) + 1e-12);  // κ = 1 − 1.5/N² + O(1/N⁴)
    EXPECT_LT(error, previous_error);
    previous_error = error;
  }
  EXPECT_LT(previous_error, 1e-4);
}

// Shear integrates to the applied shear and σ to F_n and the applied moments, on full and
// partial sets of square and 3:1 pads: the bonded set is in equilibrium exactly (only
// rounding, 1e-12 relative).
TEST(PadStress, BondedSetIsInEquilibriumForAnyPatternAndShape) {
  std::mt19937 rng(20240521);
  for (const auto& [b, h] : {std::pair{0.02, 0.02}, std::pair{0.06, 0.02}, std::pair{0.01, 0.03}}) {
    BondGrid g(Pad(b, h, 12, 12));
    for (int pattern = 0; pattern < 6; ++pattern) {
      if (pattern == 0) {
        g.BondAll();
      } else if (pattern == 1) {
        g.BondFraction(0.3);
      } else {
        g.Release();
        std::bernoulli_distribution keep(0.2 + 0.15 * pattern);
        for (int i = 0; i < g.size(); ++i) g.SetBonded(i, keep(rng));
        g.SetBonded(0, true);
        g.SetBonded(g.size() - 1, true);  // never a single row or column
      }
      const PadLoad load{.fn_n = 1.3, .fx_n = -0.4, .fy_n = 0.9, .mx_nm = 0.011, .my_nm = -0.007};
      const StressSummary s = g.Evaluate(load);
      ASSERT_FALSE(s.load_unsupported);
      const Resultants r = Integrate(g);
      const double lever = std::max(b, h);
      EXPECT_NEAR(r.fn, load.fn_n, 1e-12 * 2);
      EXPECT_NEAR(r.fx, load.fx_n, 1e-12 * std::abs(load.fx_n)) << pattern;
      EXPECT_NEAR(r.fy, load.fy_n, 1e-12 * std::abs(load.fy_n)) << pattern;
      EXPECT_NEAR(r.mx, load.mx_nm, 1e-12 * (0.02 + 2 * lever)) << pattern;
      EXPECT_NEAR(r.my, load.my_nm, 1e-12 * (0.02 + 2 * lever)) << pattern;
    }
  }
}

// ---------------------------------------------------------------------------------------
// The sign convention of the moments (bond_grid.h): a pull F_n applied at (x0, y0) has
// M_x = y0·F_n and M_y = −x0·F_n about the centroid, and tensions the edge it is nearest.

TEST(PadSigns, PullAtPlusYTensionsThePlusYEdgeFirst) {
  BondGrid g(Pad(0.02, 0.02, 10, 10));
  g.BondAll();
  const double f = 1.0, y0 = 0.005;
  const PadLoad load{.fn_n = f, .mx_nm = y0 * f};
  const StressSummary s = g.Evaluate(load);
  for (int i = 0; i < g.size(); ++i) {
    if (g.iy_of(i) > 0) {
      EXPECT_GT(g.stress(i).sigma_pa, g.stress(i - 10).sigma_pa);
    }
  }
  // Raise it until something breaks: the first round takes exactly the +y row.
  const double scale = g.params().sigma_t_pa / s.peak_sigma_pa * (1 + 1e-9);
  g.Update(PadLoad{.fn_n = f * scale, .mx_nm = y0 * f * scale});
  ASSERT_FALSE(g.last_broken().empty());
  int first_round = 0;
  for (const BrokenBond& b : g.last_broken()) {
    if (b.round != 1) continue;
    ++first_round;
    EXPECT_EQ(g.iy_of(b.index), 9);
  }
  EXPECT_EQ(first_round, 10);
}

TEST(PadSigns, PullAtPlusXTensionsThePlusXEdgeFirst) {
  BondGrid g(Pad(0.02, 0.02, 10, 10));
  g.BondAll();
  const double f = 1.0, x0 = 0.005;
  const StressSummary s = g.Evaluate(PadLoad{.fn_n = f, .my_nm = -x0 * f});
  const double scale = g.params().sigma_t_pa / s.peak_sigma_pa * (1 + 1e-9);
  g.Update(PadLoad{.fn_n = f * scale, .my_nm = -x0 * f * scale});
  int first_round = 0;
  for (const BrokenBond& b : g.last_broken()) {
    if (b.round != 1) continue;
    ++first_round;
    EXPECT_EQ(g.ix_of(b.index), 9);
  }
  EXPECT_EQ(first_round, 10);
}

TEST(PadSigns, SurfaceWrenchIsNegatedIntoTheLoad) {
  // The surface holds a pad pulled with F at (0, y0): on the pad it exerts −F·n and, about
  // the centroid, the torque −(y0·F, 0, 0). The load is the negation of both.
  const double f = 3.0, y0 = 0.004;
  const PadLoad load = PadLoadFromSurfaceWrench(Eigen::Vector3d(0.5, -0.25, -f),
                                                Eigen::Vector3d(-y0 * f, 0.1, 7.0));
  EXPECT_EQ(load.fn_n, f);
  EXPECT_EQ(load.fx_n, -0.5);
  EXPECT_EQ(load.fy_n, 0.25);
  EXPECT_EQ(load.mx_nm, y0 * f);
  EXPECT_EQ(load.my_nm, -0.1);
}

// A central pull on a partly bonded pad loads the bonds nearest the pull line hardest
// (the moment moved to the bonded centroid): with the -x half gone, the +x half's inner
// column (nearest x = 0) carries the most.
TEST(PadSigns, CentralPullOnHalfPadLoadsTheInnerEdge) {
  BondGrid g(Pad(0.02, 0.02, 8, 8));
  g.BondAll();
  for (int i = 0; i < g.size(); ++i) {
    if (g.ix_of(i) < 4) g.SetBonded(i, false);
  }
  g.Evaluate(PadLoad{.fn_n = 1.0});
  EXPECT_GT(g.stress(g.index(4, 3)).sigma_pa, g.stress(g.index(7, 3)).sigma_pa);
  // Uniform stress of the half with the centroid at b/4 (x̄ = 0.005): the pull 0.005 m
  // from the centroid gives σ(x) = F/A_B·(1 − 0.005·(x − 0.005)·A_B/I_y).
  const double a_b = 0.01 * 0.02;
  const double i_y = 0.02 * std::pow(0.01, 3) / 12.0 * (1.0 - 1.0 / 16);  // 4 columns
  for (int ix = 4; ix < 8; ++ix) {
    const double x = g.bond_x_m(g.index(ix, 0));
    const double expected = 1.0 / a_b - 0.005 * (x - 0.005) / i_y;
    EXPECT_NEAR(g.stress(g.index(ix, 0)).sigma_pa, expected, 1e-12 * 1.0 / a_b);
  }
}

// ---------------------------------------------------------------------------------------
// Rupture.

// Uniform compression σ = −P/A with shear S along x: the centre rows break when
// sqrt(3)·τ_peak ≥ σ_T + μ·P/A, so μ raises the breaking shear by exactly μ|σ| in stress.
TEST(PadRupture, CompressionRaisesTheShearThresholdByMuSigma) {
  const int n = 16;
  const double area = 0.02 * 0.02;
  for (double mu : {0.0, 0.3, 1.0}) {
    PadParams p = Pad(0.02, 0.02, n, n);
    p.mu = mu;
    BondGrid g(p);
    g.BondAll();
    const double press = 2.0;  // N, σ = −5 kPa
    const double sigma_abs = press / area;
    const double tau_per_newton = 1.5 * Kappa(n) / area;
    const double shear_crit = (p.sigma_t_pa + mu * sigma_abs) / (std::sqrt(3.0) * tau_per_newton);
    // Utilisation is sqrt(3)τ/(σ_T + μ|σ|) exactly.
    const StressSummary at = g.Evaluate(PadLoad{.fn_n = -press, .fx_n = shear_crit});
    EXPECT_NEAR(at.peak_utilisation, 1.0, 1e-12);
    EXPECT_NEAR(at.peak_sigma_pa, -sigma_abs, 1e-12 * sigma_abs);
    EXPECT_EQ(g.Evaluate(PadLoad{.fn_n = -press, .fx_n = shear_crit * (1 - 1e-9)}).over_threshold,
              0);
    EXPECT_EQ(g.Evaluate(PadLoad{.fn_n = -press, .fx_n = shear_crit * (1 + 1e-9)}).over_threshold,
              2 * n);  // both centre rows
    // The same shear without the compression gain would be μ·|σ| over the plain threshold.
    EXPECT_NEAR(std::sqrt(3.0) * tau_per_newton * shear_crit - p.sigma_t_pa, mu * sigma_abs,
                1e-9 * p.sigma_t_pa);
  }
}

// At σ ≥ 0 the tension rule counts σ² as well: the same shear breaks sooner with a pull.
TEST(PadRupture, TensionAddsNormalStressToTheDemand) {
  BondGrid g(Pad(0.02, 0.02, 8, 8));
  g.BondAll();
  const double area = 4e-4;
  const PadLoad shear_only{.fx_n = 0.5};
  const PadLoad shear_and_pull{.fn_n = 1.0, .fx_n = 0.5};
  const double tau = 1.5 * Kappa(8) * 0.5 / area;
  EXPECT_NEAR(g.Evaluate(shear_only).peak_utilisation, std::sqrt(3.0) * tau / 1e4, 1e-12);
  EXPECT_NEAR(g.Evaluate(shear_and_pull).peak_utilisation,
              std::sqrt(std::pow(1.0 / area, 2) + 3 * tau * tau) / 1e4, 1e-12);
  // stress() and the summary agree.
  double peak_vm = 0.0;
  for (int i = 0; i < g.size(); ++i) peak_vm = std::max(peak_vm, g.stress(i).von_mises_pa);
  EXPECT_NEAR(peak_vm, g.Evaluate(shear_and_pull).peak_von_mises_pa, 1e-9);
}

// ---------------------------------------------------------------------------------------
// Progressive detachment.

// Pure shear F along x on a full pad: the centre rows (|y| = dy/2) go first at
// F₁ = σ_T·A/(sqrt(3)·1.5κ). Why the rest follows at once: in the continuum, with the bonds
// left at |y| ≥ a, the shear at the crack front is
//     τ(a) = F·(h²/4 − a²) / (b·∫_{a≤|y|≤h/2} (h²/4 − y²) dy) = (3F/2b)·(h + 2a)/((h − 2a)(h + a)),
// which grows strictly with a (numerator up, denominator down): each broken row loads the
// next more than the last, so at F₁ the crack runs to the edges, row pairs from the centre
// line outwards, and the pad detaches.
TEST(PadCascade, FirstRowsBreakingAtThresholdTakeTheWholePad) {
  const int n = 32;
  BondGrid g(Pad(0.02, 0.02, n, n));
  const double f1 = 1e4 * 4e-4 / (std::sqrt(3.0) * 1.5 * Kappa(n));

  g.BondAll();
  BondGrid::UpdateResult below = g.Update(PadLoad{.fx_n = f1 * (1 - 1e-9)});
  EXPECT_EQ(below.broken, 0);
  EXPECT_EQ(below.rounds, 0);
  EXPECT_FALSE(below.detached);
  EXPECT_TRUE(g.last_broken().empty());
  EXPECT_LT(g.Summary().peak_utilisation, 1.0);
  EXPECT_GT(g.Summary().peak_utilisation, 1.0 - 1e-8);

  g.BondAll();
  BondGrid::UpdateResult above = g.Update(PadLoad{.fx_n = f1 * (1 + 1e-9)});
  EXPECT_EQ(above.broken, n * n);
  EXPECT_TRUE(above.detached);
  EXPECT_GE(above.rounds, 2);
  EXPECT_EQ(g.bonded_count(), 0);
  EXPECT_EQ(g.Summary().over_threshold, 0);
  EXPECT_EQ(g.Summary().peak_utilisation, 0.0);  // nothing left to carry anything
  // Round 1 is both centre rows; later rounds lie strictly further out.
  const double dy = 0.02 / n;
  double previous_max = 0.0;
  for (int round = 1; round <= above.rounds; ++round) {
    double lo = 1.0, hi = 0.0;
    for (const BrokenBond& b : g.last_broken()) {
      if (b.round != round) continue;
      lo = std::min(lo, std::abs(g.bond_y_m(b.index)));
      hi = std::max(hi, std::abs(g.bond_y_m(b.index)));
    }
    if (round == 1) {
      EXPECT_DOUBLE_EQ(hi, dy / 2);
    } else {
      EXPECT_GT(lo, previous_max);
    }
    previous_max = hi;
  }
  // The log is in order of rounds.
  const auto log = g.last_broken();
  EXPECT_TRUE(std::is_sorted(log.begin(), log.end(), [](const BrokenBond& a, const BrokenBond& b) {
    return a.round < b.round;
  }));
}

TEST(PadCascade, LoadExactlyAtThresholdIsDeterministic) {
  for (int n : {8, 32}) {
    const double area = 4e-4;
    for (const PadLoad& load : {PadLoad{.fn_n = 1e4 * area},
                                PadLoad{.fx_n = 1e4 * area / (std::sqrt(3.0) * 1.5 * Kappa(n))}}) {
      BondGrid a(Pad(0.02, 0.02, n, n)), b(Pad(0.02, 0.02, n, n));
      a.BondAll();
      b.BondAll();
      const auto ra = a.Update(load);
      const auto rb = b.Update(load);
      EXPECT_EQ(ra.broken, rb.broken);
      EXPECT_EQ(ra.rounds, rb.rounds);
      EXPECT_EQ(ra.detached, rb.detached);
      ASSERT_EQ(a.last_broken().size(), b.last_broken().size());
      for (size_t k = 0; k < a.last_broken().size(); ++k) {
        EXPECT_EQ(a.last_broken()[k].index, b.last_broken()[k].index);
        EXPECT_EQ(a.last_broken()[k].round, b.last_broken()[k].round);
      }
      // And a repeat on the same grid after re-bonding.
      a.BondAll();
      EXPECT_EQ(a.Update(load).broken, ra.broken);
    }
  }
}

TEST(PadCascade, StraightPullBreaksEverythingInOneRound) {
  BondGrid g(Pad(0.02, 0.02, 16, 16));
  g.BondAll();
  const auto r = g.Update(PadLoad{.fn_n = 1e4 * 4e-4 * (1 + 1e-9)});
  EXPECT_EQ(r.broken, 256);
  EXPECT_EQ(r.rounds, 1);
  EXPECT_TRUE(r.detached);
}

// Update skips rows whose bound (max σ)₊² + max 3τ² stays below σ_T² (bond_grid.cc). The
// bound must never hide a breaking bond: round 1 of Update breaks exactly the bonds that a
// full scan (Evaluate) counts over threshold, for random patterns, loads and μ.
TEST(PadCascade, RowBoundNeverSkipsABreakingBond) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int checked_breaking = 0;
  for (int trial = 0; trial < 400; ++trial) {
    PadParams p = Pad(0.02, 0.012, 3 + trial % 13, 2 + trial % 7);
    p.mu = (trial % 3) * 0.4;
    BondGrid a(p), b(p);
    std::bernoulli_distribution keep(0.5 + 0.5 * (trial % 2));
    for (int i = 0; i < a.size(); ++i) {
      const bool on = keep(rng);
      a.SetBonded(i, on);
      b.SetBonded(i, on);
    }
    const double f = p.sigma_t_pa * 0.02 * 0.012 * (0.3 + std::abs(unit(rng)));
    const PadLoad load{.fn_n = f * unit(rng), .fx_n = f * unit(rng), .fy_n = f * unit(rng),
                       .mx_nm = 0.004 * f * unit(rng), .my_nm = 0.004 * f * unit(rng)};
    const int expected = b.Evaluate(load).over_threshold;
    a.Update(load);
    int first_round = 0;
    for (const BrokenBond& k : a.last_broken()) first_round += k.round == 1 ? 1 : 0;
    EXPECT_EQ(first_round, expected) << trial;
    checked_breaking += expected > 0 && expected < b.bonded_count() ? 1 : 0;
  }
  EXPECT_GT(checked_breaking, 50);  // partial breaks, where a skip could go wrong
}

TEST(PadCascade, DetachedBelowMinBonds) {
  PadParams p = Pad(0.02, 0.02, 8, 8);
  p.min_bonds = 10;
  BondGrid g(p);
  g.BondFraction(9.0 / 64);
  EXPECT_EQ(g.bonded_count(), 9);
  const auto r = g.Update(PadLoad{});
  EXPECT_TRUE(r.detached);
  EXPECT_EQ(r.broken, 0);
  g.BondFraction(10.0 / 64);
  EXPECT_FALSE(g.Update(PadLoad{}).detached);
}

TEST(PadCascade, EvaluateNeverBreaks) {
  BondGrid g(Pad(0.02, 0.02, 8, 8));
  g.BondAll();
  const StressSummary s = g.Evaluate(PadLoad{.fn_n = 100.0});
  EXPECT_EQ(s.over_threshold, 64);
  EXPECT_EQ(g.bonded_count(), 64);
}

TEST(PadCascade, NonFiniteLoadIsReportedAndBreaksNothing) {
  BondGrid g(Pad(0.02, 0.02, 8, 8));
  g.BondAll();
  const auto r = g.Update(PadLoad{.fn_n = std::nan(""), .fx_n = 1e6});
  EXPECT_FALSE(r.load_finite);
  EXPECT_EQ(r.broken, 0);
  EXPECT_EQ(g.bonded_count(), 64);
  EXPECT_EQ(g.stress(0).sigma_pa, 0.0);
  EXPECT_EQ(g.Evaluate(PadLoad{.my_nm = INFINITY}).over_threshold, 0);
}

// ---------------------------------------------------------------------------------------
// Degenerate bonded sets (bond_grid.h: a single row or column is a hinge line).

TEST(PadDegenerate, SingleRowHoldsForceButNotMoment) {
  // 7x7: row 3 lies on the centre line (y = 0 exactly).
  BondGrid g(Pad(0.021, 0.021, 7, 7));
  const double sigma_t = g.params().sigma_t_pa;
  const double area = 0.021 * 0.021;
  auto single_row = [&g](int iy) {
    g.Release();
    for (int ix = 0; ix < 7; ++ix) g.SetBonded(g.index(ix, iy), true);
  };
  const double f = 0.5 * sigma_t * g.cell_area_m2() * 7;  // half the row's capacity

  single_row(3);
  auto r = g.Update(PadLoad{.fn_n = f});
  EXPECT_EQ(r.broken, 0);
  EXPECT_FALSE(g.Summary().load_unsupported);
  EXPECT_NEAR(g.stress(g.index(0, 3)).sigma_pa, 0.5 * sigma_t, 1e-12 * sigma_t);
  // A moment about x below the tolerance is ignored...
  r = g.Update(PadLoad{.fn_n = f, .mx_nm = 1e-3 * kHingeMomentTolerance * sigma_t * area * 0.021});
  EXPECT_EQ(r.broken, 0);
  // ...a real one peels the hinge line in one round.
  r = g.Update(PadLoad{.fn_n = f, .mx_nm = 1e-4 * sigma_t * area * 0.021});
  EXPECT_EQ(r.broken, 7);
  EXPECT_EQ(r.rounds, 1);
  EXPECT_TRUE(r.detached);

  // A moment about y is carried along the row as by any beam.
  single_row(3);
  const StressSummary s = g.Evaluate(PadLoad{.fn_n = f, .my_nm = 1e-6});
  EXPECT_FALSE(s.load_unsupported);
  EXPECT_GT(g.stress(g.index(0, 3)).sigma_pa, g.stress(g.index(6, 3)).sigma_pa);

  // An off-centre row under a central pull has the moment y_c·F_n about itself: it peels.
  single_row(6);
  r = g.Update(PadLoad{.fn_n = f});
  EXPECT_TRUE(r.detached);
  EXPECT_EQ(r.broken, 7);
}

TEST(PadDegenerate, SingleBondAndSingleColumn) {
  BondGrid g(Pad(0.02, 0.02, 8, 8));
  const double da = g.cell_area_m2(), sigma_t = g.params().sigma_t_pa;
  g.SetBonded(g.index(2, 5), true);
  // One bond: σ = F/dA, τ = F/dA (the shear weights cancel), whatever its place.
  const StressSummary s =
      g.Evaluate(PadLoad{.fn_n = 0.1 * sigma_t * da, .fx_n = 0.2 * sigma_t * da});
  EXPECT_NEAR(g.stress(g.index(2, 5)).sigma_pa, 0.1 * sigma_t, 1e-12 * sigma_t);
  EXPECT_NEAR(g.stress(g.index(2, 5)).tau_x_pa, 0.2 * sigma_t, 1e-12 * sigma_t);
  // But its off-centre place gives the central pull a moment about it: a hinge (a point).
  EXPECT_TRUE(s.load_unsupported);
  EXPECT_EQ(s.peak_utilisation, INFINITY);
  EXPECT_EQ(g.stress(g.index(2, 5)).utilisation, INFINITY);
  EXPECT_TRUE(g.Update(PadLoad{.fn_n = 1e-3}).detached);
  // Pure shear has no moment: one bond holds it up to σ_T/sqrt(3).
  g.SetBonded(g.index(2, 5), true);
  EXPECT_EQ(g.Update(PadLoad{.fx_n = 0.99 * sigma_t * da / std::sqrt(3.0)}).broken, 0);
  EXPECT_EQ(g.Update(PadLoad{.fx_n = 1.01 * sigma_t * da / std::sqrt(3.0)}).broken, 1);
  // A column (ix = 4) under a moment about y: hinge.
  g.Release();
  for (int iy = 0; iy < 8; ++iy) g.SetBonded(g.index(4, iy), true);
  EXPECT_TRUE(g.Evaluate(PadLoad{.my_nm = 1e-3}).load_unsupported);
  EXPECT_FALSE(g.Evaluate(PadLoad{.mx_nm = 1e-3}).load_unsupported);
}

// A diagonal of bonds has I_x, I_y > 0 but I_x·I_y = I_xy²: still a hinge line, about the
// diagonal. The moment about the diagonal is unsupported; the one bending it is carried.
TEST(PadDegenerate, DiagonalLineIsAHingeAboutItself) {
  BondGrid g(Pad(0.02, 0.02, 8, 8));
  for (int k = 0; k < 8; ++k) g.SetBonded(g.index(k, k), true);
  const double m = 1e-4;
  // Direction d = (1, 1)/sqrt(2): M = m·d is about the line, M = m·(1, −1)/sqrt(2) bends it.
  EXPECT_TRUE(g.Evaluate(PadLoad{.mx_nm = m, .my_nm = m}).load_unsupported);
  const StressSummary bend = g.Evaluate(PadLoad{.mx_nm = m, .my_nm = -m});
  EXPECT_FALSE(bend.load_unsupported);
  const Resultants r = Integrate(g);
  EXPECT_NEAR(r.mx, m, 1e-12 * m);
  EXPECT_NEAR(r.my, -m, 1e-12 * m);
  // Tension at the (+x, +y) end: M_x > 0 lifts +y, M_y < 0 lifts +x.
  EXPECT_GT(g.stress(g.index(7, 7)).sigma_pa, 0.0);
  EXPECT_LT(g.stress(g.index(0, 0)).sigma_pa, 0.0);
}

// An L-shaped set has I_xy ≠ 0: a pure M_x then needs a gradient along x as well (docs/design.md's
// uncoupled formula would leave −Σσx·dA ≠ 0, a moment M_y nobody applied).
TEST(PadStress, AsymmetricSetCouplesTheMoments) {
  BondGrid g(Pad(0.02, 0.02, 8, 8));
  for (int i = 0; i < g.size(); ++i) g.SetBonded(i, g.ix_of(i) < 2 || g.iy_of(i) < 2);
  const PadLoad load{.mx_nm = 1e-3};
  g.Evaluate(load);
  const Resultants r = Integrate(g);
  EXPECT_NEAR(r.fn, 0.0, 1e-12);
  EXPECT_NEAR(r.mx, 1e-3, 1e-15);
  EXPECT_NEAR(r.my, 0.0, 1e-15);
  // σ varies along the bottom rows (a gradient in x).
  EXPECT_NE(g.stress(g.index(0, 0)).sigma_pa, g.stress(g.index(7, 0)).sigma_pa);
  // The uncoupled formula on the same set misses M_y: compute it by hand.
  double n = 0, sy = 0;
  for (int i = 0; i < g.size(); ++i) {
    if (!g.bonded(i)) continue;
    n += 1;
    sy += g.bond_y_m(i);
  }
  const double y_c = sy / n;
  double i_x = 0, my_uncoupled = 0;
  for (int i = 0; i < g.size(); ++i) {
    if (g.bonded(i)) i_x += std::pow(g.bond_y_m(i) - y_c, 2) * g.cell_area_m2();
  }
  for (int i = 0; i < g.size(); ++i) {
    if (!g.bonded(i)) continue;
    const double sigma = 1e-3 * (g.bond_y_m(i) - y_c) / i_x;
    my_uncoupled -= sigma * g.bond_x_m(i) * g.cell_area_m2();
  }
  EXPECT_GT(std::abs(my_uncoupled), 1e-4);  // over 10 % of the applied moment, spurious
}

TEST(PadDegenerate, EmptySetCarriesNothing) {
  BondGrid g(Pad(0.02, 0.02, 4, 4));
  const auto r = g.Update(PadLoad{.fn_n = 5.0, .fx_n = 1.0, .mx_nm = 1.0});
  EXPECT_EQ(r.broken, 0);
  EXPECT_TRUE(r.detached);
  EXPECT_EQ(g.Summary().peak_utilisation, 0.0);
  EXPECT_EQ(g.stress(0).von_mises_pa, 0.0);
}

TEST(PadDegenerate, OneByOneGridIsOneBond) {
  BondGrid g(Pad(0.02, 0.01, 1, 1));
  g.BondAll();
  const double area = 2e-4, sigma_t = 1e4;
  EXPECT_EQ(g.Update(PadLoad{.fn_n = 0.999 * sigma_t * area}).broken, 0);
  EXPECT_NEAR(g.stress(0).sigma_pa, 0.999 * sigma_t, 1e-9);
  EXPECT_EQ(g.Update(PadLoad{.fn_n = 1.001 * sigma_t * area}).broken, 1);
  g.BondAll();
  const StressSummary s = g.Evaluate(PadLoad{.fx_n = 1.0, .fy_n = 1.0});
  EXPECT_NEAR(s.peak_von_mises_pa, std::sqrt(6.0) / area, 1e-9);
  EXPECT_TRUE(std::isfinite(s.peak_utilisation));
  EXPECT_TRUE(g.Evaluate(PadLoad{.fn_n = 1.0, .mx_nm = 1e-3}).load_unsupported);
}

TEST(PadDegenerate, LargeGridIsFiniteAndExact) {
  BondGrid g(Pad(0.02, 0.02, 128, 128));
  g.BondAll();
  const PadLoad load{.fn_n = 0.5, .fx_n = 0.5, .fy_n = 0.25, .mx_nm = 1e-3, .my_nm = 1e-3};
  const StressSummary s = g.Evaluate(load);
  EXPECT_TRUE(std::isfinite(s.peak_von_mises_pa));
  const Resultants r = Integrate(g);
  EXPECT_NEAR(r.fn, 0.5, 1e-11);
  EXPECT_NEAR(r.mx, 1e-3, 1e-13);
  EXPECT_NEAR(r.fx, 0.5, 1e-11);
}

// ---------------------------------------------------------------------------------------
// Bad parameters.

void ExpectRejected(const PadParams& p, const std::string& fragment) {
  try {
    BondGrid g(p);
    ADD_FAILURE() << "accepted params, expected a message with '" << fragment << "'";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos)
        << "message '" << e.what() << "' lacks '" << fragment << "'";
  }
}

// Trial `trial` of the peak tests: a grid of nx × ny bonds (every other trial a random set,
// each bond kept with probability `keep_p`), μ 0, 0.5 or 1, under a random load: every fifth
// breaks bonds, every seventh presses; with `ties`, every eleventh has no fy and no my, so
// every row ties.
BondGrid RandomlyLoaded(int trial, int nx, int ny, double keep_p, bool ties, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::bernoulli_distribution keep(keep_p);
  PadParams p = Pad(0.025, 0.02, nx, ny);
  p.sigma_t_pa = 1.0e4;
  p.mu = 0.5 * (trial % 3);
  p.min_bonds = 1;
  BondGrid g(p);
  g.BondAll();
  if (trial % 2 == 1) {
    for (int i = 0; i < g.size(); ++i) g.SetBonded(i, keep(rng));
  }
  const double scale = trial % 5 == 0 ? 20.0 : 2.0;
  PadLoad load{.fn_n = scale * unit(rng), .fx_n = scale * unit(rng), .fy_n = scale * unit(rng),
               .mx_nm = 0.002 * scale * unit(rng), .my_nm = 0.002 * scale * unit(rng)};
  if (trial % 7 == 0) load.fn_n = -std::abs(load.fn_n) - 1.0;  // pressed: the μ branch
  if (ties && trial % 11 == 0) load.fy_n = load.my_nm = 0.0;
  g.Update(load);
  return g;
}

// PeakUtilisation skips rows by a bound; it must give Summary()'s number bit for bit on
// random bonded sets and loads, in tension, compression, shear and after a cascade.
TEST(PadStress, PeakUtilisationEqualsTheFullScanBitForBit) {
  std::mt19937 rng(20261123);
  int rows_only = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const BondGrid g = RandomlyLoaded(trial, 3 + trial % 14, 2 + trial % 11, 0.8, false, rng);
    const double full = g.Summary().peak_utilisation;
    int bond = -1;
    const double peak = g.PeakUtilisation(&bond);
    if (std::isinf(full)) {
      EXPECT_TRUE(std::isinf(peak)) << "trial " << trial;
    } else {
      EXPECT_EQ(peak, full) << "trial " << trial;
      // The bond it names carries that peak (the reflexes' gradient is taken there); the
      // largest σ from the field's parts is the scan's.
      if (g.bonded_count() > 0) {
        EXPECT_EQ(g.PeakSigma(), g.sigma_pa(g.PeakSigmaBond())) << "trial " << trial;
        int first = -1;  // the first bond, in index order, of the largest σ
        for (int i = 0; i < g.size() && first < 0; ++i) {
          if (g.bonded(i) && g.sigma_pa(i) == g.PeakSigma()) first = i;
        }
        EXPECT_EQ(g.PeakSigmaBond(), first) << "trial " << trial;
        ASSERT_GE(bond, 0) << "trial " << trial;
        EXPECT_NEAR(g.stress(bond).utilisation, peak, 1e-12 * (1.0 + peak)) << "trial " << trial;
      }
    }
    rows_only += g.bonded_count() > 0 && !std::isinf(full) ? 1 : 0;
  }
  EXPECT_GT(rows_only, 200);  // most trials compare finite peaks, not two infinities
}

// The hinted scan leaves out rows and column blocks below the hint's utilisation: number and
// bond must be the row scan's bit for bit whatever the hint (the true peak bond, a random
// bond, an unbonded one, none), on random sets and loads, wide and narrow grids, tension,
// compression and cascades.
TEST(PadStress, PeakUtilisationWithAHintEqualsTheRowScanBitForBit) {
  std::mt19937 rng(20261127);
  int compared = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const BondGrid g = RandomlyLoaded(trial, 1 + trial % 37, 1 + trial % 23, 0.85, true, rng);
    int want_bond = -1;
    const double want = g.PeakUtilisationByRowBound(&want_bond);
    std::uniform_int_distribution<int> any(-1, g.size() - 1);
    for (const int hint : {-1, want_bond, any(rng), any(rng), g.size() + 3}) {
      int bond = -2;
      const double got = g.PeakUtilisation(&bond, hint);
      EXPECT_EQ(std::memcmp(&got, &want, sizeof got), 0)
          << "trial " << trial << " hint " << hint << ": " << got << " vs " << want;
      EXPECT_EQ(bond, want_bond) << "trial " << trial << " hint " << hint;
      EXPECT_EQ(g.PeakUtilisation(nullptr, hint), want) << "trial " << trial;
    }
    compared += want_bond >= 0 && want > 0.0 ? 1 : 0;
  }
  EXPECT_GT(compared, 250);  // most trials have a finite peak on a bond (not unsupported)
}

// A released grid carries no stress: bonded again, it reads the utilisation of no load (0), as
// a new grid does, until the next load; the load then reads the same as on a new grid.
TEST(PadStress, AReleasedGridBondedAgainCarriesNoStressUntilTheNextLoad) {
  PadParams p = Pad(0.025, 0.025, 16, 16);
  p.sigma_t_pa = 1.0e4;
  const PadLoad load{.fn_n = 0.5, .fx_n = -0.6, .fy_n = 0.2, .mx_nm = 0.001, .my_nm = -0.002};
  BondGrid used(p), fresh(p);
  used.BondAll();
  used.Update(load);
  ASSERT_GT(used.PeakUtilisation(), 0.1);
  used.Release();
  used.BondAll();
  fresh.BondAll();
  EXPECT_EQ(used.PeakUtilisation(), 0.0);
  EXPECT_EQ(fresh.PeakUtilisation(), 0.0);
  used.Update(load);
  fresh.Update(load);
  EXPECT_EQ(used.PeakUtilisation(), fresh.PeakUtilisation());
}

TEST(PadParamsValidation, RejectsBadValuesNamingKeyAndValue) {
  const PadParams good = Pad(0.02, 0.02, 8, 8);
  EXPECT_NO_THROW(ValidatePadParams(good));
  PadParams p = good;
  p.width_m = -0.01;
  ExpectRejected(p, "adhesion.width_m must be > 0 and finite, got -0.01");
  p = good;
  p.length_m = std::nan("");
  ExpectRejected(p, "adhesion.length_m must be > 0 and finite, got nan");
  p = good;
  p.grid_x = 0;
  ExpectRejected(p, "adhesion.grid_x must be in [1, 1024], got 0");
  p = good;
  p.grid_y = 1025;
  ExpectRejected(p, "adhesion.grid_y must be in [1, 1024], got 1025");
  p = good;
  p.sigma_t_pa = -3;
  ExpectRejected(p, "adhesion.sigma_t_pa must be > 0, got -3");
  p = good;
  p.mu = -0.5;
  ExpectRejected(p, "adhesion.mu must be >= 0, got -0.5");
  p = good;
  p.min_bonds = 65;
  ExpectRejected(p, "adhesion.min_bonds: must be <= grid_x * grid_y = 64, got 65");
  p = good;
  p.min_bonds = 0;
  ExpectRejected(p, "adhesion.min_bonds");
  ExpectRejected(PadParams{}, "adhesion.width_m");  // the geometry has no default
}

}  // namespace
}  // namespace climbsim::adhesion
