// The quasi-static pull-off experiment (adhesion/pulloff.h) against closed forms.
//
// Why first break = pull-off for a central pull (L = 0). σ = F cosθ/A_B is uniform over
// any bonded set and the crack starts on the centre line, where τ_x peaks. With the bonds
// left at |y| ≥ a (continuum), the front sees
//     τ(a) = (3F sinθ/2b)·(h + 2a)/((h − 2a)(h + a))     and     |σ| = F|cosθ|/(b(h − 2a)).
// θ ≤ 90°: both grow with a, so σ² + 3τ² at the front only rises: the crack runs through.
// θ > 90°: multiply the rule sqrt(3)τ ≥ σ_T + μ|σ| by b(h − 2a): the left side
// (3·sqrt(3)/2)·F sinθ·(h + 2a)/(h + a) rises with a, the right side σ_T·b(h − 2a) + μF|cosθ|
// falls: once the centre line breaks, so does everything.
// (bond_grid_test.cc checks the same cascade row by row on the grid.)
#include "adhesion/pulloff.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "tests/adhesion/closed_forms.h"

namespace climbsim::adhesion {
namespace {

using testing::kDeg;
using testing::Kappa;
using testing::PullRatioTension;
using testing::PushDenominator;

PadParams SquareGridPad(double width_m, double length_m, int n) {
  PadParams p;
  p.width_m = width_m;
  p.length_m = length_m;
  p.grid_x = n;
  p.grid_y = n;
  return p;
}

// Search tolerance: the bisection stops at 1e-6 relative; compare discrete closed forms to
// 2e-6 (the bracket plus rounding of the threshold test).
constexpr double kSearchTol = 2e-6;

TEST(PullOff, StraightPullIsSigmaTTimesArea) {
  for (int n : {8, 16, 32}) {
    const PulloffResult r = PullOff(SquareGridPad(0.02, 0.02, n), PullSetup{});
    ASSERT_TRUE(r.detaches);
    // Uniform σ = F/A: every bond reaches σ_T at F = σ_T·A together (brief: within 1 %; the
    // grid makes no error here, only the search does).
    EXPECT_NEAR(r.force_per_capacity, 1.0, kSearchTol) << n;
    EXPECT_EQ(r.rounds, 1);
    EXPECT_EQ(r.sequence.size(), static_cast<size_t>(n * n));
    EXPECT_LE(r.holding_force_n, r.force_n);
    EXPECT_LE(r.force_n - r.holding_force_n, 1e-6 * r.force_n);
  }
}

// Central pull at θ: pull-off/(σ_T·A) = 1/sqrt(cos²θ + 6.75 sin²θ) (closed_forms.h; the
// peak parabolic shear 1.5·F sinθ/A sits on the centre line where σ is uniform, and the
// cascade argument above makes first break = pull-off). On 32x32 the grid's shear peak is
// κ(32) = 0.99854 of the continuum one: the continuum form holds within 0.15 %, checked at
// 2 % as asked; the grid's own form (κ exact) within the search tolerance.
TEST(PullOff, CentralPullAtAngleMatchesClosedForm) {
  for (const auto& [b, h] : {std::pair{0.02, 0.02}, std::pair{0.06, 0.02}, std::pair{0.02, 0.06}}) {
    for (double deg : {0.0, 10.0, 30.0, 45.0, 60.0, 80.0, 90.0}) {
      const PulloffResult r = PullOff(SquareGridPad(b, h, 32), PullSetup{.angle_rad = deg * kDeg});
      ASSERT_TRUE(r.detaches);
      EXPECT_NEAR(r.force_per_capacity / PullRatioTension(deg * kDeg), 1.0, 0.02) << deg;
      EXPECT_NEAR(r.force_per_capacity / PullRatioTension(deg * kDeg, Kappa(32)), 1.0, kSearchTol)
          << b << "x" << h << " at " << deg;
      EXPECT_EQ(r.sequence.size(), 1024u);  // the whole pad
      if (deg > 0) {
        // Round 1 is the centre line (both centre rows).
        for (const BrokenBondAt& s : r.sequence) {
          if (s.round == 1) {
            EXPECT_DOUBLE_EQ(std::abs(s.y_m), h / 64) << deg;
          }
        }
      }
    }
  }
  // The seed's figure-6 shape at 90°: 0.385·σ_T·A.
  const PulloffResult r90 =
      PullOff(SquareGridPad(0.02, 0.02, 32), PullSetup{.angle_rad = 90 * kDeg});
  EXPECT_NEAR(r90.force_per_capacity, 0.385, 0.002);
}

// A lever L lifts the trailing edge. At 90°: σ at the trailing column (x₀ = −b/2 + dx/2)
// is L·F·(b/2 − dx/2)/I_y with I_y = h·b³/12·(1 − 1/N²), the centre-line shear 1.5κF/A; the
// first break there is F₁ = σ_T/sqrt(σ₁² + 3τ₁²) per newton. For short arms the crack can
// arrest after the first bonds (pull-off ≥ F₁); from L = b on it runs through at F₁.
TEST(PullOff, LeverArmLowersPullOffAndPeelsFromTheTrailingEdge) {
  const int n = 32;
  const double b = 0.02, h = 0.02, area = b * h, dx = b / n;
  const PadParams pad = SquareGridPad(b, h, n);
  double previous = INFINITY;
  for (double arm : {0.0, 0.0025, 0.005, 0.01, 0.02, 0.04, 0.1}) {
    const PulloffResult r = PullOff(pad, PullSetup{.angle_rad = 90 * kDeg, .arm_m = arm});
    ASSERT_TRUE(r.detaches);
    EXPECT_LT(r.force_n, previous) << arm;
    previous = r.force_n;
    const double i_y = h * b * b * b / 12.0 * (1.0 - 1.0 / (n * n));
    const double sigma1 = arm * (b / 2 - dx / 2) / i_y;
    const double tau1 = 1.5 * Kappa(n) / area;
    const double f1 = pad.sigma_t_pa / std::sqrt(sigma1 * sigma1 + 3 * tau1 * tau1);
    EXPECT_GE(r.force_n, f1 * (1 - kSearchTol)) << arm;
    if (arm >= b) {
      EXPECT_NEAR(r.force_n / f1, 1.0, kSearchTol) << arm;
    }
    // Continuum: 1/sqrt(6.75 + 36 L²/b²); the outermost bond sits dx/2 inside the edge, so
    // the grid's moment stress is up to 1/N = 3.1 % lower.
    if (arm >= b) {
      EXPECT_NEAR(r.force_per_capacity * std::sqrt(6.75 + 36 * arm * arm / (b * b)), 1.0, 0.035);
    }
    if (arm > 0) {
      // The first round breaks only trailing-edge bonds (−x: the pull is along +x).
      int first = 0;
      for (const BrokenBondAt& s : r.sequence) {
        if (s.round != 1) continue;
        ++first;
        EXPECT_DOUBLE_EQ(s.x_m, -b / 2 + dx / 2) << arm;
      }
      EXPECT_GT(first, 0);
    }
    EXPECT_EQ(r.sequence.size(), static_cast<size_t>(n * n));
  }
}

// Pulled along +y (azimuth 90°) with an arm, the trailing edge is −y: M_x = −L·F_y.
TEST(PullOff, LeverArmAlongYPeelsTheMinusYEdge) {
  const PadParams pad = SquareGridPad(0.02, 0.02, 16);
  const PulloffResult r =
      PullOff(pad, PullSetup{.angle_rad = 60 * kDeg, .azimuth_rad = 90 * kDeg, .arm_m = 0.02});
  ASSERT_TRUE(r.detaches);
  for (const BrokenBondAt& s : r.sequence) {
    if (s.round == 1) {
      EXPECT_DOUBLE_EQ(s.y_m, -0.01 + 0.02 / 32);
    }
  }
  const PadLoad load = PullLoad(2.0, PullSetup{.angle_rad = 90 * kDeg, .azimuth_rad = 90 * kDeg,
                                               .arm_m = 0.5});
  EXPECT_NEAR(load.fy_n, 2.0, 1e-15);
  EXPECT_NEAR(load.mx_nm, -1.0, 1e-15);
  EXPECT_NEAR(load.my_nm, 0.0, 1e-15);
}

// Pushing (θ > 90°): the centre line breaks first at F₁ = σ_T·A/(2.598κ·sinθ − μ|cosθ|)
// (closed_forms.h). The grid adds one condition the continuum does not have: the last row
// pair (|y| = h/2 − dy/2) carries UNIFORM shear F_x/A_B (one row per side cannot hold a
// parabola; the continuum's last strip has front/mean → 2), so it breaks only when
//     sqrt(3)·F sinθ/A_B ≥ σ_T + μ·F|cosθ|/A_B,  A_B = 2·N_x·dA = (2/N_y)·A
//     ⇒  F_L = σ_T·A·(2/N_y) / (sqrt(3)·sinθ − μ|cosθ|).
// Pull-off on the grid = max(F₁, F_L), never if either denominator is ≤ 0; it equals the
// continuum σ_T·A/(2.598 sinθ − μ|cosθ|) within 2 % wherever F₁ ≥ F_L (all angles for
// μ = 0; up to about 165° for μ = 0.3, 160° for μ = 0.5, 145° for μ = 1 on 32x32). The
// band μ|cotθ| ∈ [sqrt(3), 2.598κ) never detaches on any grid (adhesion/README.md).
TEST(PullOff, PushingNeedsMoreForceAndCanNeverDetach) {
  const int n = 32;
  int continuum_checked = 0, band = 0;
  for (double mu : {0.0, 0.1, 0.3, 0.5, 1.0, 2.0}) {
    PadParams pad = SquareGridPad(0.02, 0.02, n);
    pad.mu = mu;
    for (double deg = 95.0; deg <= 180.0; deg += 5.0) {
      const double theta = deg * kDeg;
      const PulloffResult r = PullOff(pad, PullSetup{.angle_rad = theta});
      const double den_first = PushDenominator(theta, mu, Kappa(n));
      const double den_last = std::sqrt(3.0) * std::sin(theta) - mu * std::abs(std::cos(theta));
      if (den_first <= 1e-9 || den_last <= 1e-9) {
        EXPECT_FALSE(r.detaches) << mu << " " << deg;
        EXPECT_EQ(r.force_n, INFINITY);
        if (den_first > 1e-9) ++band;
        continue;
      }
      const double first = 1.0 / den_first, last = (2.0 / n) / den_last;
      if (std::max(first, last) > 900) continue;  // beyond the search cap (1000 σ_T·A)
      ASSERT_TRUE(r.detaches) << mu << " " << deg;
      EXPECT_NEAR(r.force_per_capacity / std::max(first, last), 1.0, kSearchTol)
          << mu << " " << deg;
      EXPECT_EQ(r.sequence.size(), 1024u);
      if (first >= last) {
        EXPECT_NEAR(r.force_per_capacity * PushDenominator(theta, mu), 1.0, 0.02)
            << mu << " " << deg;
        ++continuum_checked;
      }
    }
  }
  EXPECT_GT(continuum_checked, 80);
  EXPECT_GT(band, 3);  // the never-detaching band is really exercised
}

TEST(PullOff, SweepCoversTheSeedRange) {
  const auto sweep = PulloffSweep(SquareGridPad(0.02, 0.02, 16), PullSetup{});
  ASSERT_EQ(sweep.size(), 37u);
  EXPECT_EQ(sweep.front().angle_deg, 0.0);
  EXPECT_EQ(sweep.back().angle_deg, 180.0);
  EXPECT_NEAR(sweep[18].angle_deg, 90.0, 1e-12);
  // Without an arm the weakest direction is pure shear (90°), the strongest straight pull
  // (below 90°) and pushing (above).
  for (size_t k = 1; k < sweep.size(); ++k) {
    if (sweep[k].angle_deg <= 90) {
      EXPECT_LT(sweep[k].result.force_n, sweep[k - 1].result.force_n);
    } else if (sweep[k].result.detaches) {
      EXPECT_GT(sweep[k].result.force_n, sweep[k - 1].result.force_n);
    }
  }
  EXPECT_FALSE(sweep.back().result.detaches);  // 180°: pushing straight in
  const auto custom = PulloffSweep(SquareGridPad(0.02, 0.02, 8), PullSetup{.arm_m = 0.01},
                                   SweepRange{.from_deg = 30, .to_deg = 60, .step_deg = 10});
  ASSERT_EQ(custom.size(), 4u);
  EXPECT_EQ(custom[3].angle_deg, 60.0);
}

TEST(PullOff, OneByOneAndLargeGridsAreSensible) {
  // One bond: σ = F cosθ/A, τ = F sinθ/A (no parabola to resolve):
  //   F = σ_T·A/sqrt(cos²θ + 3 sin²θ), 1/sqrt(3) at 90°.
  for (double deg : {0.0, 45.0, 90.0}) {
    const double t = deg * kDeg;
    const PulloffResult r = PullOff(SquareGridPad(0.02, 0.02, 1), PullSetup{.angle_rad = t});
    EXPECT_NEAR(
        r.force_per_capacity * std::sqrt(std::pow(std::cos(t), 2) + 3 * std::pow(std::sin(t), 2)),
        1.0, kSearchTol)
        << deg;
  }
  // With an arm, one bond is a hinge: it holds no moment, so any pull with a lever peels it.
  const PulloffResult hinge =
      PullOff(SquareGridPad(0.02, 0.02, 1), PullSetup{.angle_rad = 90 * kDeg, .arm_m = 0.01});
  EXPECT_TRUE(hinge.detaches);
  EXPECT_LT(hinge.force_per_capacity, 1e-6);
  // 128x128: κ(128) = 1 − 9e-5, so the continuum closed form holds to 1e-4.
  const PulloffResult big =
      PullOff(SquareGridPad(0.02, 0.02, 128), PullSetup{.angle_rad = 45 * kDeg});
  EXPECT_NEAR(big.force_per_capacity / PullRatioTension(45 * kDeg), 1.0, 1e-4);
  EXPECT_EQ(big.sequence.size(), 128u * 128u);
}

TEST(PullOff, RejectsBadInput) {
  const PadParams pad = SquareGridPad(0.02, 0.02, 4);
  EXPECT_THROW(PullOff(pad, PullSetup{.arm_m = -1}), std::invalid_argument);
  EXPECT_THROW(PullOff(pad, PullSetup{.angle_rad = NAN}), std::invalid_argument);
  EXPECT_THROW(PullOff(pad, PullSetup{}, PulloffOptions{.rel_tol = 0}), std::invalid_argument);
  EXPECT_THROW(PullOff(pad, PullSetup{}, PulloffOptions{.max_force_factor = 0.5}),
               std::invalid_argument);
  EXPECT_THROW(PullOff(PadParams{}, PullSetup{}), std::invalid_argument);
  EXPECT_THROW(PulloffSweep(pad, PullSetup{}, SweepRange{.step_deg = 0}), std::invalid_argument);
  EXPECT_THROW(PulloffSweep(pad, PullSetup{}, SweepRange{.from_deg = 10, .to_deg = 5}),
               std::invalid_argument);
  try {
    PullOff(pad, PullSetup{.arm_m = -1});
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "pulloff.arm_m must be >= 0 and finite, got -1");
  }
}

}  // namespace
}  // namespace climbsim::adhesion
