// The figure-6 experiment in MuJoCo (adhesion/pulloff_rig.h) against closed forms: the pull
// goes through the weld, the load the bond grid sees is the weld's constraint force, so these
// tests check the whole MuJoCo side (weld switching, wrench extraction, frames, signs) and not
// only the pure core (pulloff_test.cc).
//
// Error budget of the MuJoCo pull-off against the quasi-static one: the ramp rises by
// σ_T·A·Δt/ramp_time_s per step (0.05 % with ramp 2 s, Δt 1 ms), and the recorded force is
// that of the first step that lets go, so the MuJoCo value is above the quasi-static one by
// at most one ramp step plus the weld's lag (measured: < 0.15 %).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "adhesion/adhesion.h"
#include "tests/adhesion/closed_forms.h"
#include "tests/adhesion/mujoco_rig.h"

namespace climbsim::adhesion {
namespace {

using testing::kDeg;

PulloffRigParams Rig(double width_m, double length_m, int grid) {
  PulloffRigParams p;
  p.pad.width_m = width_m;
  p.pad.length_m = length_m;
  p.pad.grid_x = p.pad.grid_y = grid;
  return p;
}

// Central pull straight off: every bond carries F/A, so the grid breaks all at once at
// exactly σ_T·A on any grid; the MuJoCo value may exceed it by one ramp step (0.05 %) plus the
// weld's lag. Tolerance 1 % (issue 3).
TEST(PulloffRig, CentralPullStraightOffIsSigmaTTimesArea) {
  for (const auto& [w, h, grid] : std::vector<std::tuple<double, double, int>>{
           {0.025, 0.025, 8}, {0.025, 0.025, 16}, {0.030, 0.010, 8}, {0.035, 0.035, 12}}) {
    PulloffRig rig(AdhesionModel::kBonds, Rig(w, h, grid));
    const PulloffRun r = rig.Run(0.0);
    ASSERT_TRUE(r.detached);
    const double capacity = 10e3 * w * h;
    EXPECT_NEAR(r.force_n, capacity, 0.01 * capacity) << w << " x " << h << ", grid " << grid;
    EXPECT_GE(r.force_n, capacity * (1 - 1e-12)) << "it must not let go below sigma_T*A";
    EXPECT_STREQ(r.cause, PadCauseName(PadCause::kOverload))
        << "a uniform load breaks every bond in one step";
    EXPECT_EQ(r.steps_losing_bonds, 1);
  }
}

// Central pull at θ on a 32 × 32 grid, square and 3:1 pads: F/(σ_T·A) =
// 1/sqrt(cos²θ + 6.75 sin²θ) (pulling) and 1/(2.598 sinθ) (pushing, μ = 0). The grid's shear
// peak is κ(32) = 0.9985 of the continuum's (+0.15 % on F), plus the ramp step: 2 % (issue 3)
// leaves room.
TEST(PulloffRig, AngleLawOnA32GridWithinTwoPercent) {
  for (const auto& [w, h] :
       std::vector<std::pair<double, double>>{{0.025, 0.025}, {0.030, 0.010}}) {
    PulloffRig rig(AdhesionModel::kBonds, Rig(w, h, 32));
    for (double deg : {0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 90.0, 105.0, 135.0, 165.0}) {
      const double theta = deg * kDeg;
      const PulloffRun r = rig.Run(theta);
      ASSERT_TRUE(r.detached) << deg;
      const double expected = deg <= 90 ? testing::PullRatioTension(theta)
                                        : 1.0 / testing::PushDenominator(theta, /*mu=*/0.0);
      const double ratio = r.force_n / (10e3 * w * h);
      EXPECT_NEAR(ratio, expected, 0.02 * expected) << w << " x " << h << " at " << deg << " deg";
      // 0.385 at 90° (issue 3).
      if (deg == 90.0) {
        EXPECT_NEAR(ratio, 0.385, 0.02 * 0.385);
      }
    }
  }
}

// The MuJoCo experiment agrees with the quasi-static search of the same grid (pulloff.h) to
// the ramp step plus the weld's lag, with and without a lever: 0.3 %.
TEST(PulloffRig, MatchesTheQuasiStaticSearch) {
  for (double arm : {0.0, 0.005}) {
    PulloffRigParams p = Rig(0.025, 0.025, 16);
    p.arm_m = arm;
    PulloffRig rig(AdhesionModel::kBonds, p);
    for (double deg : {0.0, 30.0, 60.0, 90.0, 120.0, 150.0}) {
      const PulloffRun r = rig.Run(deg * kDeg);
      const PulloffResult q = PullOff(p.pad, {.angle_rad = deg * kDeg, .arm_m = arm});
      EXPECT_NEAR(r.force_n, q.force_n, 3e-3 * q.force_n) << "arm " << arm << ", " << deg;
    }
  }
}

// Pure shear held below pull-off: the τ over the bonded points sums to the applied shear
// (the weld carries the pull; Σ τ dA is then F by construction of the normalisation), for a
// square and a 3:1 pad, along x and along y. The weld's force equals the applied one to the
// block's inertia (at rest): 1e-3.
TEST(PulloffRig, ShearOverTheBondsSumsToTheAppliedShear) {
  for (const auto& [w, h, azimuth] : std::vector<std::tuple<double, double, double>>{
           {0.025, 0.025, 0.0}, {0.030, 0.010, 0.0}, {0.030, 0.010, 0.5 * std::numbers::pi}}) {
    PulloffRigParams p = Rig(w, h, 16);
    p.azimuth_rad = azimuth;
    PulloffRig rig(AdhesionModel::kBonds, p);
    const double force = 0.5 * 0.385 * 10e3 * w * h;  // half the pure-shear pull-off
    const StickyPad& pad = rig.Hold(90 * kDeg, force, 0.3);
    ASSERT_TRUE(pad.attached());
    const BondGrid& g = pad.grid();
    double sum_x = 0, sum_y = 0, sum_sigma = 0;
    for (int i = 0; i < g.size(); ++i) {
      if (!g.bonded(i)) continue;
      sum_x += g.stress(i).tau_x_pa * g.cell_area_m2();
      sum_y += g.stress(i).tau_y_pa * g.cell_area_m2();
      sum_sigma += g.stress(i).sigma_pa * g.cell_area_m2();
    }
    const double fx = force * std::cos(azimuth), fy = force * std::sin(azimuth);
    EXPECT_NEAR(sum_x, fx, 1e-3 * force) << w << " x " << h << ", azimuth " << azimuth;
    EXPECT_NEAR(sum_y, fy, 1e-3 * force) << w << " x " << h << ", azimuth " << azimuth;
    EXPECT_NEAR(sum_sigma, 0.0, 1e-3 * force) << "no normal load in pure shear";
    EXPECT_NEAR(pad.load().fx_n, fx, 1e-3 * force);
    EXPECT_NEAR(pad.load().fy_n, fy, 1e-3 * force);
  }
}

class EventLog final : public PadEventSink {
 public:
  void OnPadEvent(int, const PadEvent& e) override { events.push_back(e); }
  std::vector<PadEvent> events;
};

// A lever lowers the pull-off at 90°: the in-plane pull at height L adds the moment L·F that
// tips the block about its leading edge (+x) and tensions the trailing edge (−x). The
// pull-off falls as L grows (2 cm pad, 32 × 32: 0.386, 0.340, 0.261, 0.157 σ_T·A at L = 0, 5,
// 10, 20 mm, within 0.3 % of pulloff.h's quasi-static search). With
// L = 5 mm the pad peels: the first bonds to break are on the trailing edge, the crack runs
// towards +x over several steps (bonds_lost events), and the detach that ends it has cause
// peel.
TEST(PulloffRig, LeverArmLowersThePulloffAndPeelsFromTheTrailingEdge) {
  const double b = 0.02, capacity = 10e3 * b * b;
  const std::vector<double> arms{0.0, 0.005, 0.010, 0.020};
  std::vector<double> forces;
  for (size_t k = 0; k < arms.size(); ++k) {
    PulloffRigParams p = Rig(b, b, 32);
    p.arm_m = arms[k];
    PulloffRig rig(AdhesionModel::kBonds, p);
    EventLog log;
    const PulloffRun r = rig.Run(90 * kDeg, &log);
    ASSERT_TRUE(r.detached);
    forces.push_back(r.force_n);
    const PulloffResult q = PullOff(p.pad, {.angle_rad = 90 * kDeg, .arm_m = arms[k]});
    EXPECT_NEAR(r.force_n, q.force_n, 3e-3 * q.force_n) << "arm " << arms[k];
    std::printf("lever %.3f m: pull-off at 90 deg %.4f sigma_T*A (quasi-static %.4f)\n", arms[k],
                r.force_n / capacity, q.force_n / capacity);
    if (arms[k] != 0.005) continue;

    EXPECT_STREQ(r.cause, PadCauseName(PadCause::kPeel));
    ASSERT_GE(r.steps_losing_bonds, 2);
    // Events: touchdown and attach at the start, then bonds_lost in each losing step, the last
    // in the step of the detach.
    ASSERT_GE(log.events.size(), 4u);
    EXPECT_EQ(log.events[0].kind, PadEventKind::kTouchdown);
    EXPECT_EQ(log.events[1].kind, PadEventKind::kAttach);
    for (size_t i = 2; i + 1 < log.events.size(); ++i) {
      EXPECT_EQ(log.events[i].kind, PadEventKind::kBondsLost) << i;
      if (i > 2) {
        EXPECT_GT(log.events[i].time_s, log.events[i - 1].time_s);
      }
    }
    EXPECT_EQ(log.events.back().kind, PadEventKind::kDetach);
    EXPECT_EQ(log.events.back().cause, PadCause::kPeel);
    EXPECT_GT(log.events[2].bonded_fraction, 0.0) << "the first crack arrests";

    // The first bond to break is on the trailing edge (column 0, x = −b/2 + b/64), and the
    // first losing step breaks only bonds of the trailing half.
    ASSERT_FALSE(r.sequence.empty());
    EXPECT_NEAR(r.sequence.front().x_m, -0.5 * b + 0.5 * b / 32, 1e-12);
    const double first_force = r.sequence_force_n.front();
    double mean_x_first = 0, mean_x_rest = 0;
    int n_first = 0, n_rest = 0;
    for (size_t i = 0; i < r.sequence.size(); ++i) {
      if (r.sequence_force_n[i] == first_force) {
        EXPECT_LT(r.sequence[i].x_m, 0.0) << "bond " << i;
        mean_x_first += r.sequence[i].x_m, ++n_first;
      } else {
        mean_x_rest += r.sequence[i].x_m, ++n_rest;
      }
    }
    ASSERT_GT(n_rest, 0);
    EXPECT_LT(mean_x_first / n_first, mean_x_rest / n_rest) << "the crack runs towards +x";
  }
  for (size_t i = 1; i < forces.size(); ++i) {
    EXPECT_LT(forces[i], forces[i - 1]) << "pull-off must fall as the lever grows, arm #" << i;
  }
}

// Pushing at θ > 90° presses the bonds (σ = F cosθ/A < 0), which raises the shear threshold by
// μ|σ|: √3·τ_peak = σ_T + μ|σ| at the pull-off. With the grid's shear peak 1.5κ·F sinθ/A this
// is F = σ_T·A/(2.598κ sinθ − μ|cosθ|) (pulloff.h; valid where the first break runs through,
// up to 160° for μ = 0.5 on 32 × 32). Measured in MuJoCo against that, to the ramp step: 1 %.
TEST(PulloffRig, CompressionRaisesTheShearNeededByMuTimesSigma) {
  const double kappa = testing::Kappa(32), capacity = 10e3 * 0.025 * 0.025;
  for (double mu : {0.0, 0.5, 1.0}) {
    PulloffRigParams p = Rig(0.025, 0.025, 32);
    p.pad.mu = mu;
    PulloffRig rig(AdhesionModel::kBonds, p);
    for (double deg : {120.0, 135.0}) {
      const double theta = deg * kDeg;
      const PulloffRun r = rig.Run(theta);
      ASSERT_TRUE(r.detached) << mu << " " << deg;
      const double expected = capacity / testing::PushDenominator(theta, mu, kappa);
      EXPECT_NEAR(r.force_n, expected, 0.01 * expected) << "mu " << mu << ", " << deg << " deg";
      // The same statement in stresses: the shear at the break exceeds σ_T by μ|σ|.
      const double sigma = r.force_n * std::abs(std::cos(theta)) / (0.025 * 0.025);
      const double tau_peak = 1.5 * kappa * r.force_n * std::sin(theta) / (0.025 * 0.025);
      EXPECT_NEAR(std::sqrt(3.0) * tau_peak, 10e3 + mu * sigma, 0.01 * (10e3 + mu * sigma));
    }
  }
}

// The baseline in the same experiment: MuJoCo's adhesion actuator (gain σ_T·A, friction 1)
// lets go where lifting, tipping or sliding begins (pulloff_rig.h's closed form). The block
// must move slip_m = 0.5 mm to be counted, which costs (6·m·s·rate²)^(1/3) of extra pull:
// 0.7 % with an 8 s ramp; tolerance 1.5 %.
TEST(PulloffRig, MujocoActuatorLetsGoWhereItsClosedFormSays) {
  PulloffRigParams p = Rig(0.025, 0.025, 8);
  p.ramp_time_s = 8.0;
  PulloffRig rig(AdhesionModel::kMujoco, p);
  for (double deg : {0.0, 45.0, 90.0, 120.0}) {
    const PulloffRun r = rig.Run(deg * kDeg);
    ASSERT_TRUE(r.detached) << deg;
    const double expected =
        MujocoPulloffClosedForm(rig.gain_n(), p.friction, p.pad.width_m, 0.0, deg * kDeg);
    EXPECT_NEAR(r.force_n, expected, 0.015 * expected) << deg << " deg, cause " << r.cause;
    EXPECT_GE(r.force_n, expected * 0.999) << "it held less than its closed form";
  }
  // μ_f·G/(sinθ + μ_f cosθ) diverges at 135° for μ_f = 1: pushing harder holds forever.
  EXPECT_FALSE(rig.Run(150 * kDeg).detached);
}

}  // namespace
}  // namespace climbsim::adhesion
