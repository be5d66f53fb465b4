// The pieces of a pad's utilisation gradient (the GTO share reflex's direction): the linear
// influence of the load on one bond, the bond that carries the peak, and the gradient itself,
// each against an independent evaluation of the same field.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>

#include "adhesion/bond_grid.h"
#include "adhesion/frictional_law.h"

namespace climbsim::adhesion {
namespace {

PadParams GradientPad(int nx, int ny, double mu) {
  PadParams p;
  p.width_m = 0.025;
  p.length_m = 0.02;
  p.grid_x = nx;
  p.grid_y = ny;
  p.sigma_t_pa = 1.0e4;
  p.mu = mu;
  return p;
}

Eigen::Matrix<double, 5, 1> Vec(const PadLoad& l) {
  Eigen::Matrix<double, 5, 1> v;
  v << l.fn_n, l.fx_n, l.fy_n, l.mx_nm, l.my_nm;
  return v;
}

std::string Fmt(const Eigen::Matrix<double, 5, 1>& v) {
  char b[200];
  std::snprintf(b, sizeof b, "[%.4g %.4g %.4g %.4g %.4g]", v[0], v[1], v[2], v[3], v[4]);
  return b;
}

PadLoad LoadOf(const Eigen::Matrix<double, 5, 1>& v) { return {v[0], v[1], v[2], v[3], v[4]}; }

// Random loads of a size the pads carry (a few N, a few mN·m), on random bonded sets: the
// full pad, a thinned one, and a line (a hinge: its moment about the line is unsupported,
// so the loads there have none).
struct Case {
  BondGrid grid;
  PadLoad load;
};

Case RandomCase(std::mt19937* rng, int trial) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::bernoulli_distribution keep(0.7);
  Case c{BondGrid(GradientPad(4 + trial % 13, 3 + trial % 9, 0.5 * (trial % 3))), {}};
  c.grid.BondAll();
  if (trial % 3 == 1) {
    for (int i = 0; i < c.grid.size(); ++i) c.grid.SetBonded(i, keep(*rng));
    c.grid.SetBonded(0, true);  // never empty
  }
  c.load = {.fn_n = unit(*rng), .fx_n = unit(*rng), .fy_n = unit(*rng),
            .mx_nm = 0.004 * unit(*rng), .my_nm = 0.004 * unit(*rng)};
  if (trial % 3 == 2) {
    // One row bonded: a line along x. The moment about it (M_x about the row's centroid)
    // must vanish for the load to be supported.
    for (int i = 0; i < c.grid.size(); ++i) c.grid.SetBonded(i, c.grid.iy_of(i) == 1);
    c.load.mx_nm = c.grid.bond_y_m(c.grid.index(0, 1)) * c.load.fn_n;
  }
  return c;
}

TEST(BondInfluence, MatchesTheFieldOfEvaluateAtEveryBond) {
  std::mt19937 rng(7);
  int checked = 0;
  for (int trial = 0; trial < 120; ++trial) {
    Case c = RandomCase(&rng, trial);
    for (const bool uniform : {false, true}) {
      const StressSummary sum = c.grid.Evaluate(c.load);
      ASSERT_FALSE(sum.load_unsupported) << "trial " << trial;
      const double area = c.grid.bonded_area_m2();
      for (int i = 0; i < c.grid.size(); ++i) {
        Eigen::Matrix<double, 3, 5> a;
        if (!c.grid.bonded(i)) {
          EXPECT_FALSE(c.grid.Influence(i, uniform, &a));
          continue;
        }
        ASSERT_TRUE(c.grid.Influence(i, uniform, &a));
        const Eigen::Vector3d s = a * Vec(c.load);
        const BondStress want = c.grid.stress(i);
        // The same sums in another order: agreement to rounding of the largest term.
        const double scale = 1e-9 * (std::abs(c.load.fn_n) + 1.0) / area * 1e3;
        EXPECT_NEAR(s[0], want.sigma_pa, scale) << "trial " << trial << " bond " << i;
        if (uniform) {
          EXPECT_NEAR(s[1], c.load.fx_n / area, scale);
          EXPECT_NEAR(s[2], c.load.fy_n / area, scale);
        } else {
          EXPECT_NEAR(s[1], want.tau_x_pa, scale);
          EXPECT_NEAR(s[2], want.tau_y_pa, scale);
        }
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 8000);
}

// Influence reads the bonded set's geometry and shear sums that the last field kept; a grid
// whose set was never loaded computes them afresh: the two must agree bit for bit.
TEST(BondInfluence, KeptSetGeometryGivesTheFreshInfluenceBitForBit) {
  std::mt19937 rng(20261127);
  for (int trial = 0; trial < 60; ++trial) {
    Case c = RandomCase(&rng, trial);
    BondGrid fresh = c.grid;  // the same set, no field computed on it yet
    c.grid.Evaluate(c.load);  // keeps the set's geometry
    for (const bool uniform : {false, true}) {
      for (int i = 0; i < c.grid.size(); ++i) {
        Eigen::Matrix<double, 3, 5> kept, again;
        kept.setConstant(7.0), again.setConstant(7.0);
        ASSERT_EQ(c.grid.Influence(i, uniform, &kept), fresh.Influence(i, uniform, &again));
        EXPECT_EQ(std::memcmp(kept.data(), again.data(), sizeof(double) * 15), 0)
            << "trial " << trial << " bond " << i;
      }
    }
  }
}

TEST(BondInfluence, PeakBondCarriesThePeakUtilisationBitForBit) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    Case c = RandomCase(&rng, trial);
    c.grid.Update(c.load);
    int bond = -2;
    const double peak = c.grid.PeakUtilisation(&bond);
    if (c.grid.bonded_count() == 0) {
      EXPECT_EQ(bond, -1);
      continue;
    }
    ASSERT_GE(bond, 0) << "trial " << trial;
    EXPECT_EQ(peak, c.grid.PeakUtilisation()) << "trial " << trial;
    EXPECT_DOUBLE_EQ(c.grid.stress(bond).utilisation, peak) << "trial " << trial;
    // The largest σ, by a scan.
    double best = -1e300;
    for (int i = 0; i < c.grid.size(); ++i) {
      if (c.grid.bonded(i)) best = std::max(best, c.grid.sigma_pa(i));
    }
    EXPECT_EQ(c.grid.sigma_pa(c.grid.PeakSigmaBond()), best) << "trial " << trial;
  }
}

// U(load) of the law, by brute force over the bonds (no influence matrix, no peak search).
double BruteUtilisation(BondGrid* grid, const FrictionalLaw* law, const PadLoad& load) {
  grid->Evaluate(load);
  const double area = grid->bonded_area_m2();
  double u = 0.0;
  for (int i = 0; i < grid->size(); ++i) {
    if (!grid->bonded(i)) continue;
    u = std::max(u, law == nullptr ? grid->stress(i).utilisation
                                   : law->Utilisation(grid->sigma_pa(i), load.fx_n / area,
                                                      load.fy_n / area));
  }
  return u;
}

// The gradient against central differences of the brute-force utilisation. Where the peak
// moves to another bond within the difference step, or a law switches branch, the two
// differ; such cases are counted and must stay rare.
void CheckGradient(const FrictionalLaw* law, uint32_t seed) {
  std::mt19937 rng(seed);
  int matched = 0, total = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Case c = RandomCase(&rng, trial);
    if (law != nullptr && trial % 2 == 0) {
      c.load.fx_n = -std::abs(c.load.fx_n) - 0.5;  // gripping shear along the default −x
      c.load.fn_n = 0.3 * std::abs(c.load.fn_n);
    }
    if (!std::isfinite(BruteUtilisation(&c.grid, law, c.load))) continue;
    Eigen::Matrix<double, 5, 1> grad;
    if (!PadUtilisationGradient(c.grid, law, c.load, &grad)) continue;
    const Eigen::Matrix<double, 5, 1> x = Vec(c.load);
    Eigen::Matrix<double, 5, 1> fd;
    for (int k = 0; k < 5; ++k) {
      const double h = (k < 3 ? 1e-6 : 1e-8);
      Eigen::Matrix<double, 5, 1> up = x, down = x;
      up[k] += h;
      down[k] -= h;
      fd[k] = (BruteUtilisation(&c.grid, law, LoadOf(up)) -
               BruteUtilisation(&c.grid, law, LoadOf(down))) /
              (2 * h);
    }
    c.grid.Evaluate(c.load);
    if (!fd.allFinite()) continue;  // a hinge: a moment step makes the load unsupported
    ++total;
    if ((grad - fd).norm() <= 1e-4 * (fd.norm() + 1e-3)) {
      ++matched;
    } else if (getenv("GRAD_DEBUG")) {
      std::printf("trial %d grad %s fd %s\n", trial, Fmt(grad).c_str(), Fmt(fd).c_str());
    }
  }
  EXPECT_GT(total, 150);
  EXPECT_GE(matched, 0.95 * total) << matched << " of " << total;
}

TEST(PadUtilisationGradient, VonMisesMatchesCentralDifferences) { CheckGradient(nullptr, 3); }

TEST(PadUtilisationGradient, FrictionalMatchesCentralDifferences) {
  FrictionalParams p;
  p.moment_share = 1.0;
  const FrictionalLaw law(p);
  CheckGradient(&law, 5);
}

// The closed form of the directional law on a pulled pad without moments: U = F_n/(F_t tan α*)
// so ∂U/∂F_n = 1/(F_t tan α*) and ∂U/∂F_x = −U/F_t·∂F_t/∂F_x with F_t = −F_x (grip −x).
TEST(PadUtilisationGradient, DirectionalPadNearItsAngleAsksForGrippingShear) {
  const FrictionalLaw law(FrictionalParams{});
  BondGrid grid(GradientPad(16, 16, 0.0));
  grid.BondAll();
  const PadLoad load{.fn_n = 0.2, .fx_n = -0.5, .fy_n = 0.0, .mx_nm = 0.0, .my_nm = 0.0};
  grid.Evaluate(load);
  Eigen::Matrix<double, 5, 1> grad;
  ASSERT_TRUE(PadUtilisationGradient(grid, &law, load, &grad));
  const double t = std::tan(30.0 * M_PI / 180.0);
  EXPECT_NEAR(grad[0], 1.0 / (0.5 * t), 1e-6);
  EXPECT_NEAR(grad[1], 0.2 / (0.5 * 0.5 * t), 1e-6);  // more −x (gripping) shear relieves it
  EXPECT_NEAR(grad[2], 0.0, 1e-6);
}

}  // namespace
}  // namespace climbsim::adhesion
