// HopfNetwork (Righetti and Ijspeert 2008, rotation-matrix coupling of Chung and Slotine
// 2010) against what its law implies in closed form or by quadrature.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "cpg/cpg.h"
#include "tests/cpg/test_util.h"

namespace climbsim::cpg {
namespace {

using testing::kPi;
using testing::kTwoPi;
using testing::WrapPi;

HopfNetworkParams Uncoupled(int n, double f_stance_hz, double f_swing_hz, Stepper stepper) {
  HopfNetworkParams p;
  p.stance_frequency_hz = f_stance_hz;
  p.swing_frequency_hz = f_swing_hz;
  p.coupling_per_s = Eigen::MatrixXd::Zero(n, n);
  p.phase_bias_rad = Eigen::MatrixXd::Zero(n, n);
  p.stepper.type = stepper;
  return p;
}

// ∫ dϑ/ω(sqrt(μ)·sin ϑ) over [ϑ0, ϑ1] by Simpson's rule: the time a half cycle takes on the
// limit cycle, computed independently of any ODE stepper. The integrand changes over
// Δϑ ~ 1/(b·sqrt(μ)) = 0.01 rad near y = 0; 2·10⁴ panels resolve that to ~1e-12.
double HalfCycleDuration(const HopfNetworkParams& p, double from_rad, double to_rad) {
  const int panels = 20000;
  const double h = (to_rad - from_rad) / panels;
  auto integrand = [&](double v) {
    const double y = std::sqrt(p.mu) * std::sin(v);
    const double omega = kTwoPi * p.stance_frequency_hz / (std::exp(-p.b * y) + 1.0) +
                         kTwoPi * p.swing_frequency_hz / (std::exp(p.b * y) + 1.0);
    return 1.0 / omega;
  };
  double sum = integrand(from_rad) + integrand(to_rad);
  for (int k = 1; k < panels; ++k) sum += integrand(from_rad + k * h) * (k % 2 ? 4.0 : 2.0);
  return sum * h / 3.0;
}

TEST(CpgHopf, ConvergesToLimitCycleOfRadiusSqrtMu) {
  for (Stepper stepper : {Stepper::kRk4, Stepper::kDopri5}) {
    HopfNetworkParams p = Uncoupled(4, 0.5, 1.5, stepper);
    p.mu = 2.25;  // radius 1.5
    p.stepper.abs_tol = 1e-10;
    p.stepper.rel_tol = 1e-10;
    HopfNetwork network(p);
    std::mt19937 rng(3);
    network.Reset(testing::RandomPhases(rng, 4), Eigen::Vector4d(0.05, 0.5, 1.3, 2.0));
    // From r = 0.075 the radius grows like e^{αμt} = e^{112 t}: on the cycle well within 1 s.
    testing::RunFor(network, 3.0, 1e-3);
    double worst = 0.0;
    for (int k = 0; k < 1500; ++k) {  // more than one cycle (1/0.75 Hz)
      network.Step(1e-3, {});
      for (int i = 0; i < 4; ++i) {
        const double r = std::hypot(network.x()[i], network.y()[i]);
        worst = std::max(worst, std::abs(r - 1.5));
        EXPECT_NEAR(network.amplitude()[i], r / 1.5, 1e-15);
      }
    }
    std::printf("stepper %d: max |r - sqrt(mu)| over a cycle %.3e\n", static_cast<int>(stepper),
                worst);
    // The circle r = sqrt(μ) is invariant for the exact flow; the stepper's truncation error
    // pushes off it and the pull 2αμ = 225/s pulls back. RK4 at 1 ms errs most where ω
    // switches (dω/dy up to b·Δω/4 ≈ 160/s per unit y): measured 9e-8 there; bound 1e-6.
    // Dopri5 at tolerances 1e-10: measured 6e-11.
    EXPECT_LT(worst, 1e-6);
  }
}

TEST(CpgHopf, StanceAndSwingLastHalfCyclesAtTheirOwnFrequencies) {
  // f_stance 0.5 Hz, f_swing 1.5 Hz: π/ω_stance = 1 s of stance, π/ω_swing = ⅓ s of swing,
  // D = 0.75, stride frequency 0.75 Hz, in the b → ∞ limit.
  HopfNetworkParams p = Uncoupled(1, 0.5, 1.5, Stepper::kRk4);
  HopfNetwork network(p);
  EXPECT_DOUBLE_EQ(network.duty_factor(), 0.75);
  EXPECT_DOUBLE_EQ(network.stride_frequency_hz(), 0.75);
  EXPECT_EQ(network.phase_duty_factor(), 0.5);
  const double dt_s = 1e-4;
  testing::RunFor(network, 2.0, dt_s);
  // Times where y changes sign, interpolated linearly (y is linear in t there to O(dt²)).
  std::vector<double> stance_starts, stance_ends;
  for (int k = 0; k < 60000; ++k) {
    const double y0 = network.y()[0];
    const double t0 = network.time_s();
    network.Step(dt_s, {});
    const double y1 = network.y()[0];
    const double t_cross = t0 + dt_s * y0 / (y0 - y1);
    if (y0 <= 0.0 && y1 > 0.0) stance_starts.push_back(t_cross);
    if (y0 > 0.0 && y1 <= 0.0) stance_ends.push_back(t_cross);
    // The phase says the same: stance is θ ∈ [π, 2π) exactly when y > 0.
    if (std::abs(y1) > 1e-9) {
      EXPECT_EQ(network.phase_rad()[0] >= kPi, y1 > 0.0);
    }
  }
  ASSERT_GE(stance_starts.size(), 3u);
  ASSERT_GE(stance_ends.size(), 3u);
  if (stance_ends.front() < stance_starts.front()) stance_ends.erase(stance_ends.begin());
  const double stance_s = stance_ends[1] - stance_starts[1];
  const double swing_s = stance_starts[2] - stance_ends[1];
  const double stance_quadrature = HalfCycleDuration(p, 0.0, kPi);
  const double swing_quadrature = HalfCycleDuration(p, -kPi, 0.0);
  std::printf("stance %.9f s (quadrature %.9f), swing %.9f s (quadrature %.9f)\n", stance_s,
              stance_quadrature, swing_s, swing_quadrature);
  // Against the quadrature of the same ω(y): RK4 at 0.1 ms resolves the ω switch (~1.6 ms
  // wide at b = 100) to 3e-7 s measured, crossings interpolated to O(dt²); bound 1e-6 s.
  EXPECT_NEAR(stance_s, stance_quadrature, 1e-6);
  EXPECT_NEAR(swing_s, swing_quadrature, 1e-6);
  // Against π/ω: the sigmoid blends the two rates over |ϑ| ≲ 5/(b·sqrt(μ)) = 0.05 rad at each
  // end of a half cycle, which shifts a half cycle by at most 2·0.05·|1/ω_swing − 1/ω_stance|
  // = 0.021 s: 2 % of the stance, 6 % of the swing.
  EXPECT_NEAR(stance_s, 1.0, 0.021);
  EXPECT_NEAR(swing_s, 1.0 / 3.0, 0.021);
  EXPECT_NEAR(stance_s / (stance_s + swing_s), 0.75, 0.02);
}

TEST(CpgHopf, FeedbackAddsExactlyToThePhaseRateAndNotToTheRadius) {
  // One Euler step: Δz = dt·dz/dt exactly, so (x·Δy − y·Δx)/(r²·dt) is dϑ/dt and
  // (x·Δx + y·Δy)/(r·dt) is dr/dt at the start, to rounding (~1e-16/dt ≈ 1e-13).
  HopfNetworkParams p = HopfNetworkParamsForGait(GaitPreset("trot", 4), 1.0, 2.0);
  p.stepper.type = Stepper::kEuler;
  const Eigen::Vector4d theta0(0.3, 2.0, 3.5, 5.9);
  const Eigen::Vector4d amplitude0(0.5, 1.0, 1.2, 0.9);  // on and off the cycle
  const double sigma = 6.0;
  const std::vector<double> load_n = {0.0, 1.5, 3.0, 0.7};
  std::vector<double> feedback(4);
  for (int i = 0; i < 4; ++i) feedback[i] = TegotaeFeedback(sigma, load_n[i], theta0[i]);
  const double dt_s = 1e-3;

  auto rates = [&](std::span<const double> fb, std::vector<double>* phase_rate,
                   std::vector<double>* radius_rate) {
    HopfNetwork network(p);
    network.Reset(theta0, amplitude0);
    const std::vector<double> x0(network.x().begin(), network.x().end());
    const std::vector<double> y0(network.y().begin(), network.y().end());
    network.Step(dt_s, fb);
    for (int i = 0; i < 4; ++i) {
      const double dx = network.x()[i] - x0[i], dy = network.y()[i] - y0[i];
      const double r2 = x0[i] * x0[i] + y0[i] * y0[i];
      (*phase_rate)[i] = (x0[i] * dy - y0[i] * dx) / (r2 * dt_s);
      (*radius_rate)[i] = (x0[i] * dx + y0[i] * dy) / (std::sqrt(r2) * dt_s);
    }
  };
  std::vector<double> phase_without(4), radius_without(4), phase_with(4), radius_with(4);
  rates({}, &phase_without, &radius_without);
  rates(feedback, &phase_with, &radius_with);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(phase_with[i] - phase_without[i], feedback[i], 1e-10) << "leg " << i;
    EXPECT_NEAR(radius_with[i], radius_without[i], 1e-10) << "leg " << i;
  }
}

// The law of cpg.h written out the plain way (W and W⁻¹ as functions, one sin/cos per pair):
// dz/dt at z, with feedback u. A second algorithm for what HopfNetwork computes.
std::vector<double> LawWrittenOut(const HopfNetworkParams& p, const std::vector<double>& x,
                                  const std::vector<double>& y, const std::vector<double>& u) {
  const int n = static_cast<int>(x.size());
  const double w_st = kTwoPi * p.stance_frequency_hz, w_sw = kTwoPi * p.swing_frequency_hz;
  const double duty = w_sw / (w_st + w_sw);
  auto wrap = [](double a) { return a - kTwoPi * std::floor(a / kTwoPi); };
  auto warp = [&](double theta) {  // W: θ → Φ
    return theta < kPi ? 2.0 * (1.0 - duty) * theta
                       : kTwoPi * (1.0 - duty) + 2.0 * duty * (theta - kPi);
  };
  auto unwarp = [&](double phase) {  // W⁻¹
    return phase < kTwoPi * (1.0 - duty) ? phase / (2.0 * (1.0 - duty))
                                         : kPi + (phase - kTwoPi * (1.0 - duty)) / (2.0 * duty);
  };
  std::vector<double> dz(2 * n);
  for (int i = 0; i < n; ++i) {
    const double r2 = x[i] * x[i] + y[i] * y[i];
    const double omega = w_st / (std::exp(-p.b * y[i]) + 1.0) + w_sw / (std::exp(p.b * y[i]) + 1.0);
    double dx = p.alpha_per_s * (p.mu - r2) * x[i] - omega * y[i] - u[i] * y[i];
    double dy = p.beta_per_s * (p.mu - r2) * y[i] + omega * x[i] + u[i] * x[i];
    for (int j = 0; j < n; ++j) {
      const double k = p.coupling_per_s(i, j), phi = p.phase_bias_rad(i, j);
      double cx, cy;
      if (p.coupling_form == HopfCoupling::kRotation) {
        cx = std::cos(-phi) * x[j] - std::sin(-phi) * y[j];
        cy = std::sin(-phi) * x[j] + std::cos(-phi) * y[j];
      } else {
        const double theta_j = wrap(std::atan2(y[j], x[j]) + kPi);
        const double target = unwarp(wrap(warp(theta_j) - phi));
        const double r_j = std::hypot(x[j], y[j]);
        cx = r_j * std::cos(target - kPi);
        cy = r_j * std::sin(target - kPi);
      }
      dx += k * (cx - x[i]);
      dy += k * (cy - y[i]);
    }
    dz[i] = dx;
    dz[n + i] = dy;
  }
  return dz;
}

TEST(CpgHopf, EulerIncrementEqualsTheLawWrittenOut) {
  // One Euler step is z + dt·dz/dt exactly, so (z1 − z0)/dt is the network's right-hand side,
  // up to rounding of z (1e-16) over dt (1e-3), ~1e-13; bound 1e-10·(1 + |rate|).
  for (HopfCoupling form : {HopfCoupling::kTimeWarpedRotation, HopfCoupling::kRotation}) {
    for (const char* name : {"lateral_sequence", "wave", "trot"}) {
      const int legs = std::string(name) == "wave" ? 6 : 4;
      HopfNetworkParams p = HopfNetworkParamsForGait(GaitPreset(name, legs), 0.9, 1.7);
      p.coupling_form = form;
      p.stepper.type = Stepper::kEuler;
      std::mt19937 rng(5);
      const Eigen::VectorXd theta0 = testing::RandomPhases(rng, legs);
      const Eigen::VectorXd amplitude0 = testing::RandomAmplitudes(rng, legs, 0.2, 1.8);
      std::vector<double> u(legs);
      for (int i = 0; i < legs; ++i) u[i] = 0.7 * i - 1.0;
      HopfNetwork network(p);
      network.Reset(theta0, amplitude0);
      const std::vector<double> x0(network.x().begin(), network.x().end());
      const std::vector<double> y0(network.y().begin(), network.y().end());
      const double dt_s = 1e-3;
      network.Step(dt_s, u);
      const std::vector<double> expected = LawWrittenOut(p, x0, y0, u);
      for (int i = 0; i < legs; ++i) {
        EXPECT_NEAR((network.x()[i] - x0[i]) / dt_s, expected[i],
                    1e-10 * (1 + std::abs(expected[i])))
            << name << " form " << static_cast<int>(form) << " leg " << i;
        EXPECT_NEAR((network.y()[i] - y0[i]) / dt_s, expected[legs + i],
                    1e-10 * (1 + std::abs(expected[legs + i])))
            << name << " form " << static_cast<int>(form) << " leg " << i;
      }
    }
  }
}

TEST(CpgHopf, PhaseMapsRighettiStanceToTheSecondHalf) {
  HopfNetwork network(Uncoupled(1, 1.0, 1.0, Stepper::kRk4));
  // Reset places θ on the circle at ϑ = θ − π: θ = 0 is (−sqrt(μ), 0), θ = π/2 is (0, −1)
  // (mid-swing, y < 0), θ = 3π/2 is (0, 1) (mid-stance, y > 0).
  for (double theta : {0.0, kPi / 2, kPi, 3 * kPi / 2}) {
    network.Reset(Eigen::VectorXd::Constant(1, theta), Eigen::VectorXd::Ones(1));
    EXPECT_NEAR(network.x()[0], std::cos(theta - kPi), 1e-15);
    EXPECT_NEAR(network.y()[0], std::sin(theta - kPi), 1e-15);
    EXPECT_NEAR(WrapPi(network.phase_rad()[0] - theta), 0.0, 1e-15);
  }
}

// One cycle of a locked network, measured from swing onsets (θ crossing 0) and the time leg
// `ref` spends with y > 0.
struct Cycle {
  double period_s;
  std::vector<double> lag_cycles;  // onset of leg i after leg ref's, in cycles
  double stance_share;             // of leg ref
  double min_amplitude, max_amplitude;
};

Cycle MeasureCycle(HopfNetwork& network, int ref, double dt_s) {
  const int n = network.size();
  const auto onsets = testing::SwingOnsetTimes(network, 3.0, dt_s);
  Cycle cycle;
  const double t_ref = onsets[ref][onsets[ref].size() - 2];
  cycle.period_s = onsets[ref].back() - t_ref;
  for (int i = 0; i < n; ++i) {
    const auto after = std::lower_bound(onsets[i].begin(), onsets[i].end(), t_ref - 1e-9);
    cycle.lag_cycles.push_back(after == onsets[i].end() ? NAN : (*after - t_ref) / cycle.period_s);
  }
  // Stance share: one more period, y sign changes interpolated.
  double stance_s = 0.0;
  cycle.min_amplitude = 1e9;
  cycle.max_amplitude = 0.0;
  const int steps = static_cast<int>(std::lround(cycle.period_s / dt_s));
  for (int k = 0; k < steps; ++k) {
    const double y0 = network.y()[ref];
    network.Step(dt_s, {});
    const double y1 = network.y()[ref];
    if (y0 > 0.0 && y1 > 0.0) stance_s += dt_s;
    if ((y0 > 0.0) != (y1 > 0.0)) stance_s += dt_s * std::max(y0, y1) / std::abs(y1 - y0);
    for (int i = 0; i < n; ++i) {
      cycle.min_amplitude = std::min(cycle.min_amplitude, network.amplitude()[i]);
      cycle.max_amplitude = std::max(cycle.max_amplitude, network.amplitude()[i]);
    }
  }
  cycle.stance_share = stance_s / (steps * dt_s);
  return cycle;
}

int ReferenceLeg(const Gait& gait) {
  return static_cast<int>(std::min_element(gait.offsets_cycles.begin(), gait.offsets_cycles.end()) -
                          gait.offsets_cycles.begin());
}

const std::vector<std::pair<std::string, int>> kPresets = {
    {"trot", 4}, {"lateral_sequence", 4}, {"tripod", 6}, {"tetrapod", 6}, {"wave", 6}};

TEST(CpgHopf, CoupledNetworkLocksToEveryGaitsOffsetsInTime) {
  for (HopfCoupling form : {HopfCoupling::kTimeWarpedRotation, HopfCoupling::kRotation}) {
    for (const auto& [name, legs] : kPresets) {
      const Gait gait = GaitPreset(name, legs);
      const int ref = ReferenceLeg(gait);
      for (unsigned seed = 0; seed < 5; ++seed) {
        HopfNetworkParams p = HopfNetworkParamsForGait(gait, 1.0, 2.0);
        p.coupling_form = form;
        HopfNetwork network(p);
        std::mt19937 rng(seed);
        network.Reset(testing::RandomPhases(rng, legs),
                      testing::RandomAmplitudes(rng, legs, 0.3, 1.5));
        const double dt_s = 1e-3;
        testing::RunFor(network, 30.0, dt_s);
        ASSERT_EQ(network.status(), StepStatus::kOk);
        const Cycle cycle = MeasureCycle(network, ref, dt_s);
        for (int i = 0; i < legs; ++i) {
          // Locked in time: leg i starts swing offset_i·T after the reference leg. Onsets are
          // interpolated within 1 ms steps; measured errors are below 5e-5 cycles; 1e-3
          // cycles (1 ms at 1 Hz) is one step.
          const double expected = gait.offsets_cycles[i] - gait.offsets_cycles[ref];
          const double error =
              cycle.lag_cycles[i] - expected - std::round(cycle.lag_cycles[i] - expected);
          EXPECT_NEAR(error, 0.0, 1e-3)
              << name << " form " << static_cast<int>(form) << " seed " << seed << " leg " << i;
        }
      }
    }
  }
}

TEST(CpgHopf, TimeWarpedCouplingKeepsPeriodDutyFactorAndRadiusAtAnyStrength) {
  for (const auto& [name, legs] : kPresets) {
    const Gait gait = GaitPreset(name, legs);
    const int ref = ReferenceLeg(gait);
    // The uncoupled oscillator's own period and stance share, by quadrature.
    const HopfNetworkParams base = HopfNetworkParamsForGait(gait, 1.0, 0.0);
    const double stance_s = HalfCycleDuration(base, 0.0, kPi);
    const double period_s = stance_s + HalfCycleDuration(base, -kPi, 0.0);
    for (double k : {0.3, 2.0, 5.0}) {
      HopfNetwork network(HopfNetworkParamsForGait(gait, 1.0, k));
      std::mt19937 rng(11);
      network.Reset(testing::RandomPhases(rng, legs), Eigen::VectorXd::Ones(legs));
      testing::RunFor(network, 40.0, 1e-3);
      const Cycle cycle = MeasureCycle(network, ref, 1e-3);
      std::printf(
          "%-16s k %.1f: period %.5f s (own %.5f), stance share %.5f (own %.5f, D %.4f),"
          " amplitude [%.5f, %.5f]\n",
          name.c_str(), k, cycle.period_s, period_s, cycle.stance_share, stance_s / period_s,
          gait.duty_factor, cycle.min_amplitude, cycle.max_amplitude);
      // W assumes b → ∞; at b = 100 the coupling does not quite vanish in the ±0.05 rad
      // where ω switches, and the residue grows with k. Measured worst (wave, k = 5/s):
      // period 2.5e-4 s short, stance share 2.1e-3 low, radius 1.5e-4 low. Bounds: 2e-3 s,
      // 5e-3, 2e-3. (Plain rotation coupling misses by 0.11 s and 0.09: next test.)
      EXPECT_NEAR(cycle.period_s, period_s, 2e-3) << name << " k " << k;
      EXPECT_NEAR(cycle.stance_share, stance_s / period_s, 5e-3) << name << " k " << k;
      EXPECT_NEAR(cycle.min_amplitude, 1.0, 2e-3) << name << " k " << k;
      EXPECT_NEAR(cycle.max_amplitude, 1.0, 2e-3) << name << " k " << k;
      // And that share is the gait's duty factor, up to the sigmoid's blend (cpg.h).
      EXPECT_NEAR(cycle.stance_share, gait.duty_factor, 0.01) << name;
    }
  }
}

TEST(CpgHopf, DefaultStartIsAlreadyTheLockedGait) {
  // From the constructor's state the gait's lags hold from the start. Coupling 0.01/s, so
  // that it could not correct a wrong start within the three cycles measured.
  for (const auto& [name, legs] : kPresets) {
    const Gait gait = GaitPreset(name, legs);
    const int ref = ReferenceLeg(gait);
    HopfNetwork network(HopfNetworkParamsForGait(gait, 1.0, 0.01));
    const Cycle cycle = MeasureCycle(network, ref, 1e-3);
    for (int i = 0; i < legs; ++i) {
      const double expected = gait.offsets_cycles[i] - gait.offsets_cycles[ref];
      const double error =
          cycle.lag_cycles[i] - expected - std::round(cycle.lag_cycles[i] - expected);
      // W⁻¹ is the b → ∞ map; at b = 100 the blend near the switches moves a start by up to
      // 3e-3 cycles (measured, wave). A geometric start would be off by 0.12 (lateral
      // sequence) to 0.20 cycles (wave).
      EXPECT_NEAR(error, 0.0, 5e-3) << name << " leg " << i;
    }
  }
}

TEST(CpgHopf, PlainRotationCouplingSpeedsUpAndEvensOutUnequalHalves) {
  // Pins the reason for the default (cpg.h, Coupling): with ω_stance ≠ ω_swing, plain
  // rotation coupling at k = 2/s shortens the period and pulls the stance share towards ½.
  const Gait gait = GaitPreset("lateral_sequence", 4);
  HopfNetworkParams p = HopfNetworkParamsForGait(gait, 1.0, 2.0);
  p.coupling_form = HopfCoupling::kRotation;
  HopfNetwork network(p);
  testing::RunFor(network, 40.0, 1e-3);
  const Cycle cycle = MeasureCycle(network, ReferenceLeg(gait), 1e-3);
  std::printf("plain rotation, lateral_sequence k 2: period %.4f s, stance share %.4f\n",
              cycle.period_s, cycle.stance_share);
  EXPECT_LT(cycle.period_s, 0.95);
  EXPECT_LT(cycle.stance_share, 0.7);
  // With D = ½ (trot) both forms coincide and nothing is distorted.
  HopfNetworkParams trot = HopfNetworkParamsForGait(GaitPreset("trot", 4), 1.0, 2.0);
  trot.coupling_form = HopfCoupling::kRotation;
  HopfNetwork trotting(trot);
  testing::RunFor(trotting, 20.0, 1e-3);
  EXPECT_NEAR(MeasureCycle(trotting, 0, 1e-3).period_s, 1.0, 1e-3);
}

}  // namespace
}  // namespace climbsim::cpg
