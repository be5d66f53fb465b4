// The directional pad law (adhesion/frictional_law.h) against its closed forms: the limit
// F_n = F_t·tan α* on either side of ε, no hold without gripping shear, the shear limit, the
// friction side, the pull-off force against angle, and peeling bond by bond under a lever.
#include "adhesion/frictional_law.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>
#include <stdexcept>

#include "tests/adhesion/closed_forms.h"
#include "tests/common/alloc_counter.h"

namespace climbsim::adhesion {
namespace {

using testing::kDeg;

PadParams LawPad(int n = 16) {
  PadParams p;
  p.width_m = 0.02;
  p.length_m = 0.03;
  p.grid_x = n;
  p.grid_y = n;
  return p;
}

FrictionalParams Law(double alpha_deg, double grip_x = 0.0, double grip_y = -1.0) {
  FrictionalParams f;
  f.critical_angle_deg = alpha_deg;
  f.shear_limit_pa = 8e3;
  f.friction_mu = 0.6;
  f.grip_x = grip_x;
  f.grip_y = grip_y;
  return f;
}

// A fully bonded grid under a central load (no moment): does it hold, and how did it go?
BondGrid::UpdateResult Load(const FrictionalParams& f, double fn,
                            double fx, double fy, BondGrid* grid) {
  grid->BondAll();
  return FrictionalUpdate(grid, FrictionalLaw(f), PadLoad{.fn_n = fn, .fx_n = fx, .fy_n = fy},
                          nullptr);
}

TEST(FrictionalLaw, HoldsJustInsideTheCriticalAngleAndLetsGoJustOutside) {
  const PadParams pad = LawPad();
  BondGrid grid(pad);
  const double area = pad.width_m * pad.length_m;
  for (double alpha : {10.0, 25.0, 30.0, 45.0, 70.0}) {
    for (double eps : {1e-3, 1e-6}) {
      // Gripping direction: −y, then an oblique one.
      for (double grip_deg : {-90.0, 30.0}) {
        const FrictionalParams f = Law(alpha, std::cos(grip_deg * kDeg), std::sin(grip_deg * kDeg));
        const FrictionalLaw law(f);
        const double ft = 0.5 * f.shear_limit_pa * area;  // half the shear limit
        const double fx = ft * law.grip_x(), fy = ft * law.grip_y();
        const double fn_limit = ft * std::tan(alpha * kDeg);
        SCOPED_TRACE(::testing::Message() << "alpha " << alpha << " eps " << eps << " grip "
                                        << grip_deg);
        // Pad level.
        EXPECT_TRUE(law.PadHolds({.fn_n = fn_limit * (1 - eps), .fx_n = fx, .fy_n = fy}, area));
        EXPECT_FALSE(law.PadHolds({.fn_n = fn_limit * (1 + eps), .fx_n = fx, .fy_n = fy}, area));
        // On the grid: every bond holds, then every bond goes in the first round (a central
        // load loads every bond alike).
        BondGrid::UpdateResult r = Load(f, fn_limit * (1 - eps), fx, fy, &grid);
        EXPECT_EQ(r.broken, 0);
        EXPECT_FALSE(r.detached);
        EXPECT_EQ(grid.bonded_count(), grid.size());
        r = Load(f, fn_limit * (1 + eps), fx, fy, &grid);
        EXPECT_TRUE(r.detached);
        EXPECT_EQ(r.broken, grid.size());
        EXPECT_EQ(r.rounds, 1);
      }
    }
  }
}

TEST(FrictionalLaw, NoHoldWithZeroOrReversedShearWhenPulled) {
  const PadParams pad = LawPad();
  BondGrid grid(pad);
  const FrictionalParams f = Law(30.0);  // grips along −y
  const double area = pad.width_m * pad.length_m;
  const double small = 1e-3 * f.shear_limit_pa * area;
  const double big = 0.5 * f.shear_limit_pa * area;
  // Pulled with no shear, with reversed shear (+y), with lateral shear only (x): all let go.
  for (auto [fx, fy] : {std::pair{0.0, 0.0}, std::pair{0.0, big}, std::pair{0.0, small},
                        std::pair{big, 0.0}, std::pair{-big, 0.0}}) {
    SCOPED_TRACE(::testing::Message() << "fx " << fx << " fy " << fy);
    EXPECT_FALSE(FrictionalLaw(f).PadHolds({.fn_n = small, .fx_n = fx, .fy_n = fy}, area));
    const BondGrid::UpdateResult r = Load(f, small, fx, fy, &grid);
    EXPECT_TRUE(r.detached);
    EXPECT_EQ(r.broken, grid.size());
  }
  // The same pull with the shear along the gripping direction holds.
  EXPECT_FALSE(Load(f, small, 0.0, -big, &grid).detached);
  // Release by unloading: the pad that held lets go once the gripping shear falls below
  // F_n / tan α*, at the same pull.
  const double fn = 0.5 * big * std::tan(30.0 * kDeg);
  EXPECT_FALSE(Load(f, fn, 0.0, -big, &grid).detached);
  EXPECT_FALSE(Load(f, fn, 0.0, -0.5 * big * (1 + 1e-6), &grid).detached);
  EXPECT_TRUE(Load(f, fn, 0.0, -0.5 * big * (1 - 1e-6), &grid).detached);
}

// The least gripping shear that holds a normal load is the law's own edge: pulled, the pad
// holds just above it and lets go just below; pressed, it may carry reversed shear up to the
// spent share of its friction, and the pad-level law holds there.
TEST(FrictionalLaw, LeastGripShearIsTheEdgeOfTheHoldingCone) {
  const PadParams pad = LawPad();
  const double area = pad.width_m * pad.length_m;
  const FrictionalLaw law(Law(30.0));  // grips along −y: F_t = −fy
  const double fn = 0.2;
  const double least = law.LeastGripShear(fn, 0.5);
  EXPECT_NEAR(least, fn / std::tan(30.0 * kDeg), 1e-12);
  EXPECT_TRUE(law.PadHolds({.fn_n = fn, .fx_n = 0.0, .fy_n = -least * (1 + 1e-6)}, area));
  EXPECT_FALSE(law.PadHolds({.fn_n = fn, .fx_n = 0.0, .fy_n = -least * (1 - 1e-6)}, area));
  // Pressed by 0.2 N with μ = 0.6: credit 1 spends all the friction (reversed shear 0.12 N
  // holds, a little more slides), credit 0.5 half of it, credit 0 none.
  EXPECT_NEAR(law.LeastGripShear(-fn, 1.0), -0.6 * fn, 1e-15);
  EXPECT_NEAR(law.LeastGripShear(-fn, 0.5), -0.3 * fn, 1e-15);
  EXPECT_EQ(law.LeastGripShear(-fn, 0.0), 0.0);
  EXPECT_TRUE(law.PadHolds({.fn_n = -fn, .fx_n = 0.0, .fy_n = 0.6 * fn * (1 - 1e-6)}, area));
  EXPECT_FALSE(law.PadHolds({.fn_n = -fn, .fx_n = 0.0, .fy_n = 0.6 * fn * (1 + 1e-3)}, area));
}

TEST(FrictionalLaw, ShearLimitAndFrictionWhenPressed) {
  const PadParams pad = LawPad();
  BondGrid grid(pad);
  const FrictionalParams f = Law(30.0);
  const FrictionalLaw law(f);
  const double area = pad.width_m * pad.length_m;
  const double ft_max = f.shear_limit_pa * area;
  const double eps = 1e-6;
  // Unloaded normally: the shear limit, in the gripping direction and laterally.
  EXPECT_FALSE(Load(f, 0.0, 0.0, -ft_max * (1 - eps), &grid).detached);
  EXPECT_TRUE(Load(f, 0.0, 0.0, -ft_max * (1 + eps), &grid).detached);
  // A small pull inside the cone: the same shear limit.
  EXPECT_FALSE(Load(f, 0.1 * ft_max, 0.0, -ft_max * (1 - eps), &grid).detached);
  EXPECT_TRUE(Load(f, 0.1 * ft_max, 0.0, -ft_max * (1 + eps), &grid).detached);
  // Pressed with C: the limit rises to F_t,max + μC along d; reversed, Coulomb μC.
  const double c = 0.7 * ft_max;
  const double along = ft_max + f.friction_mu * c, against = f.friction_mu * c;
  EXPECT_FALSE(Load(f, -c, 0.0, -along * (1 - eps), &grid).detached);
  EXPECT_TRUE(Load(f, -c, 0.0, -along * (1 + eps), &grid).detached);
  EXPECT_FALSE(Load(f, -c, 0.0, against * (1 - eps), &grid).detached);
  EXPECT_TRUE(Load(f, -c, 0.0, against * (1 + eps), &grid).detached);
  EXPECT_NEAR(law.Utilisation(-c / area, 0.0, against / area), 1.0, 1e-12);
  // Zero load holds; the utilisation of a pull without gripping shear is the cap.
  EXPECT_FALSE(Load(f, 0.0, 0.0, 0.0, &grid).detached);
  EXPECT_EQ(law.Utilisation(1.0, 0.0, 0.0), kFrictionalCap);
}

TEST(FrictionalLaw, PulloffAgainstAngleMatchesTheClosedFormAtEveryAngle) {
  const PadParams pad = LawPad();
  const double area = pad.width_m * pad.length_m;
  PulloffOptions options;
  options.max_force_factor = 50.0;
  for (double alpha : {27.0, 30.0}) {
    const FrictionalParams f = Law(alpha, 1.0, 0.0);  // grips along +x
    const FrictionalLaw law(f);
    int zero = 0, finite = 0, never = 0;
    for (double azimuth_deg : {0.0, 180.0, 60.0}) {
      for (int deg = 0; deg <= 180; ++deg) {
        const PullSetup setup{.angle_rad = deg * kDeg, .azimuth_rad = azimuth_deg * kDeg};
        const double closed = law.PulloffClosedForm(area, setup.angle_rad, setup.azimuth_rad);
        const PulloffResult r = FrictionalPullOff(pad, f, setup, options);
        SCOPED_TRACE(::testing::Message() << "alpha " << alpha << " azimuth " << azimuth_deg
                                        << " angle " << deg << " closed " << closed);
        if (closed == 0.0) {
          ++zero;
          EXPECT_EQ(r.force_n, 0.0);
        } else if (closed > options.max_force_factor * f.shear_limit_pa * area) {
          ++never;
          EXPECT_TRUE(std::isinf(r.force_n));
        } else {
          ++finite;
          EXPECT_NEAR(r.force_n / closed, 1.0, 0.01);  // the brief's 1 %
          EXPECT_NEAR(r.force_n / closed, 1.0, 2e-6);  // what the search delivers
          EXPECT_EQ(r.rounds, 1);                      // a central pull: all at once
        }
      }
    }
    // All three regimes occur: too steep (and reversed), shear-limited, inside the cone.
    EXPECT_GT(zero, 100);
    EXPECT_GT(finite, 100);
    EXPECT_GT(never, 10);
    // Along d, the onset of adhesion is at 90° − α* from the normal.
    EXPECT_EQ(law.PulloffClosedForm(area, (90.0 - alpha - 0.5) * kDeg, 0.0), 0.0);
    EXPECT_GT(law.PulloffClosedForm(area, (90.0 - alpha + 0.5) * kDeg, 0.0), 0.0);
  }
}

TEST(FrictionalLaw, ALeverPeelsBondByBondFromTheTrailingEdge) {
  PadParams pad = LawPad();
  pad.width_m = pad.length_m = 0.02;
  const FrictionalParams f = Law(30.0, 1.0, 0.0);  // grips along +x
  // θ = 80° along +x: held to the shear limit without a lever; with L = 0.08 b the moment
  // L·F_x tensions the −x edge past σ ≤ τ_t tan α* (cos θ + 6 (L/b) sin θ > sin θ tan α*).
  PullSetup setup{.angle_rad = 80.0 * kDeg, .azimuth_rad = 0.0, .arm_m = 0.0};
  const double area = pad.width_m * pad.length_m;
  const double force = 0.3 * f.shear_limit_pa * area;
  BondGrid grid(pad);
  grid.BondAll();
  EXPECT_FALSE(FrictionalUpdate(&grid, FrictionalLaw(f), PullLoad(force, setup), nullptr).detached);
  setup.arm_m = 0.08 * pad.width_m;
  grid.BondAll();
  const BondGrid::UpdateResult r =
      FrictionalUpdate(&grid, FrictionalLaw(f), PullLoad(force, setup), nullptr);
  EXPECT_TRUE(r.detached);
  EXPECT_GT(r.rounds, 3);  // a peel: round after round, not all at once
  // A compliant toe (moment_share 0) passes no moment: the lever changes nothing.
  FrictionalParams compliant = f;
  compliant.moment_share = 0.0;
  BondGrid other(pad);
  other.BondAll();
  EXPECT_FALSE(
      FrictionalUpdate(&other, FrictionalLaw(compliant), PullLoad(force, setup), nullptr).detached);
  EXPECT_EQ(other.bonded_count(), other.size());
  // The first round breaks the trailing (−x) edge and nothing on the leading half.
  const auto log = grid.last_broken();
  ASSERT_FALSE(log.empty());
  bool edge = false;
  for (const BrokenBond& b : log) {
    if (b.round != 1) continue;
    edge = edge || grid.ix_of(b.index) == 0;
    EXPECT_LT(grid.ix_of(b.index), pad.grid_x / 2);
  }
  EXPECT_TRUE(edge);
  // Rounds run from −x towards +x: the mean column of each round does not go back.
  double last_mean = -1.0;
  for (int round = 1; round <= r.rounds; ++round) {
    double sum = 0.0;
    int count = 0;
    for (const BrokenBond& b : log) {
      if (b.round == round) sum += grid.ix_of(b.index), ++count;
    }
    ASSERT_GT(count, 0);
    EXPECT_GE(sum / count, last_mean);
    last_mean = sum / count;
  }
}

// The boundary's vertices sit on the limit surface: just inside each holds, just outside
// (scaled by 1 + 10⁻⁶ away from the origin) does not; the pull-off closed form at the
// vertices' angles gives the vertices back.
TEST(FrictionalLaw, LimitBoundaryLiesOnTheLimitSurface) {
  const FrictionalParams f = Law(30.0, 1.0, 0.0);
  const FrictionalLaw law(f);
  const double area = 6e-4, ft_max = f.shear_limit_pa * area;
  const auto b = FrictionalLimitBoundary(law, area, 2.0 * ft_max);
  ASSERT_EQ(b.size(), 5u);
  EXPECT_NEAR(b[2].fn_n, ft_max * std::tan(30.0 * kDeg), 1e-12);
  for (size_t i = 0; i < b.size(); ++i) {
    if (i == 1) continue;  // the origin
    SCOPED_TRACE(::testing::Message() << "vertex " << i);
    const PadLoad in{.fn_n = b[i].fn_n * (1 - 1e-6), .fx_n = b[i].ft_n * (1 - 1e-6)};
    const PadLoad out{.fn_n = b[i].fn_n * (1 + 1e-6), .fx_n = b[i].ft_n * (1 + 1e-6)};
    EXPECT_TRUE(law.PadHolds(in, area));
    if (i != 0) {  // the friction ray scales into itself
      EXPECT_FALSE(law.PadHolds(out, area));
    }
  }
  // The corner (F_t,max, F_t,max tan α*) is the pull-off at θ = 90° − α*.
  const double f60 = law.PulloffClosedForm(area, 60.0 * kDeg, 0.0);
  EXPECT_NEAR(f60 * std::sin(60.0 * kDeg), b[2].ft_n, 1e-9 * ft_max);
  EXPECT_NEAR(f60 * std::cos(60.0 * kDeg), b[2].fn_n, 1e-9 * ft_max);
  // The pressed side: the pull-off vector at 120° lies on the shear-limit-plus-friction line.
  const double f120 = law.PulloffClosedForm(area, 120.0 * kDeg, 0.0);
  EXPECT_NEAR(f120 * std::sin(120.0 * kDeg),
              ft_max + f.friction_mu * -f120 * std::cos(120.0 * kDeg), 1e-9 * ft_max);
  // The von Mises closed form used by the plots: σ_T·A at 0°, 0.385 σ_T·A at 90°.
  EXPECT_DOUBLE_EQ(VonMisesPulloffClosedForm(1.0, 0.0, 0.0), 1.0);
  EXPECT_NEAR(VonMisesPulloffClosedForm(1.0, 90.0 * kDeg, 0.0), 1.0 / std::sqrt(6.75), 1e-12);
}

// Utilisation never falls as σ grows at a fixed shear, rounding included: FrictionalUpdate's
// shortcut (the bond of largest σ decides) rests on it. Every shear direction, both signs of
// the gripping shear, σ across zero from tiny to huge, and friction 0.
TEST(FrictionalLaw, UtilisationNeverFallsAsSigmaGrows) {
  std::mt19937 rng(20261127);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<double> sigmas;
  for (double m = 1e-3; m < 1e9; m *= 1.7) {
    sigmas.push_back(m);
    sigmas.push_back(-m);
  }
  sigmas.insert(sigmas.end(), {0.0, -0.0, 5e-324, -5e-324});
  std::sort(sigmas.begin(), sigmas.end());
  int rises = 0;
  for (int trial = 0; trial < 300; ++trial) {
    FrictionalParams f = Law(10.0 + 0.25 * trial, unit(rng), unit(rng));
    if (trial % 4 == 0) f.friction_mu = 0.0;
    const FrictionalLaw law(f);
    const double scale = std::pow(10.0, 1 + trial % 6);
    const double tx = scale * unit(rng), ty = scale * unit(rng);
    double last = -1.0;
    for (double sigma : sigmas) {
      const double u = law.Utilisation(sigma, tx, ty);
      ASSERT_GE(u, last) << "trial " << trial << " sigma " << sigma;
      rises += u > last ? 1 : 0;
      last = u;
    }
  }
  EXPECT_GT(rises, 3000);  // not constant: the law does rise with σ
}

// The cascade with the shortcut (FrictionalUpdate) and the full scan of every bond in every
// round give the same bonds broken, in the same order and rounds, and the same peak, bit for
// bit: random bonded sets and loads, comfortable, peeling and torn off.
TEST(FrictionalLaw, ShortcutEqualsTheFullScanBitForBit) {
  std::mt19937 rng(20261128);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::bernoulli_distribution keep(0.85);
  int held = 0, broke = 0;
  for (int trial = 0; trial < 400; ++trial) {
    PadParams pad = LawPad(2 + trial % 17);
    pad.grid_y = 3 + trial % 11;
    FrictionalParams f = Law(20.0 + trial % 40, unit(rng), unit(rng));
    f.moment_share = trial % 3 == 0 ? 0.0 : 1.0;
    const FrictionalLaw law(f);
    BondGrid fast(pad), full(pad);
    fast.BondAll();
    if (trial % 2 == 1) {
      for (int i = 0; i < fast.size(); ++i) fast.SetBonded(i, keep(rng));
    }
    for (int i = 0; i < fast.size(); ++i) full.SetBonded(i, fast.bonded(i));
    const double capacity = f.shear_limit_pa * pad.width_m * pad.length_m;
    const double s = capacity * (trial % 5 == 0 ? 3.0 : 0.4);
    PadLoad load{.fn_n = s * unit(rng), .fx_n = s * unit(rng), .fy_n = s * unit(rng),
                 .mx_nm = 0.003 * s * unit(rng), .my_nm = 0.003 * s * unit(rng)};
    if (trial % 7 == 0) load.fn_n = -std::abs(load.fn_n);
    double u_fast = -1.0, u_full = -2.0;
    const auto a = FrictionalUpdate(&fast, law, load, &u_fast);
    PadLoad shared = load;
    shared.mx_nm *= f.moment_share;
    shared.my_nm *= f.moment_share;
    const auto b = ShearFieldCascade(
        &full, shared, [&law](double sg, double tx, double ty) { return law.Utilisation(sg, tx, ty); },
        &u_full, /*monotone_in_sigma=*/false);
    ASSERT_EQ(a.broken, b.broken) << "trial " << trial;
    EXPECT_EQ(a.rounds, b.rounds) << "trial " << trial;
    EXPECT_EQ(a.detached, b.detached) << "trial " << trial;
    EXPECT_EQ(u_fast, u_full) << "trial " << trial;
    ASSERT_EQ(fast.last_broken().size(), full.last_broken().size());
    for (size_t k = 0; k < fast.last_broken().size(); ++k) {
      EXPECT_EQ(fast.last_broken()[k].index, full.last_broken()[k].index) << "trial " << trial;
      EXPECT_EQ(fast.last_broken()[k].round, full.last_broken()[k].round) << "trial " << trial;
    }
    held += a.broken == 0 && fast.bonded_count() > 0 ? 1 : 0;
    broke += a.broken > 0 ? 1 : 0;
  }
  EXPECT_GT(held, 100);  // the shortcut decided these
  EXPECT_GT(broke, 50);  // and these fell back to the scan
}

// The frictional cascade allocates nothing (the step loop runs it on every welded pad).
TEST(FrictionalLaw, UpdateNeverAllocates) {
  const PadParams pad = LawPad(32);
  BondGrid grid(pad);
  const FrictionalLaw law(Law(30.0, 1.0, 0.0));
  const double capacity = 8e3 * pad.width_m * pad.length_m;
  long broken = 0;
  double sink = 0.0;
  const auto counts = climbsim::testing::CountAllocations([&] {
    for (int k = 0; k < 500; ++k) {
      if (k % 3 == 0) grid.BondAll();
      if (k % 3 == 1) grid.BondFraction(0.2 + 0.001 * k);
      const double f = capacity * (0.05 + 0.003 * k), angle = 0.006 * k;
      const PadLoad load{.fn_n = f * std::cos(angle), .fx_n = f * std::sin(angle),
                         .fy_n = 0.05 * f, .mx_nm = 1e-4 * f, .my_nm = 2e-3 * f * std::sin(angle)};
      double u = 0.0;
      broken += FrictionalUpdate(&grid, law, load, &u).broken;
      sink += u;
    }
  });
  EXPECT_EQ(counts.total(), 0);
  EXPECT_GT(broken, 500);
  EXPECT_TRUE(std::isfinite(sink));
}

TEST(FrictionalLaw, RejectsBadParameters) {
  FrictionalParams f;
  f.critical_angle_deg = 90.0;
  EXPECT_THROW(ValidateFrictionalParams(f), std::invalid_argument);
  f = FrictionalParams{};
  f.shear_limit_pa = 0.0;
  EXPECT_THROW(ValidateFrictionalParams(f), std::invalid_argument);
  f = FrictionalParams{};
  f.grip_x = f.grip_y = 0.0;
  EXPECT_THROW(FrictionalLaw{f}, std::invalid_argument);
  f = FrictionalParams{};
  f.moment_share = 1.5;
  EXPECT_THROW(ValidateFrictionalParams(f), std::invalid_argument);
  f = FrictionalParams{};
  f.friction_mu = -1.0;
  EXPECT_THROW(ValidateFrictionalParams(f), std::invalid_argument);
  EXPECT_NO_THROW(ValidateFrictionalParams(FrictionalParams{}));
}

}  // namespace
}  // namespace climbsim::adhesion
