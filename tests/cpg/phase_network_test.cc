// PhaseNetwork against the closed forms of its law (Ijspeert et al. 2007):
//   dθ_i/dt = 2πf + Σ_j w_ij r_j sin(θ_j − θ_i − φ_ij) + feedback_i,  dr_i/dt = a(R_i − r_i).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "cpg/cpg.h"
#include "tests/cpg/test_util.h"

namespace climbsim::cpg {
namespace {

using testing::ClosedFormPhaseDifference;
using testing::kTwoPi;
using testing::TwoOscillators;
using testing::WrapPi;

constexpr Stepper kAllSteppers[] = {Stepper::kEuler, Stepper::kRk4, Stepper::kDopri5};

TEST(CpgPhaseNetwork, UncoupledOscillatorsAdvanceAtExactlyTwoPiF) {
  for (Stepper stepper : kAllSteppers) {
    PhaseNetworkParams p;
    p.frequency_hz = 1.7;
    p.coupling_per_s = Eigen::MatrixXd::Zero(3, 3);
    p.phase_bias_rad = Eigen::MatrixXd::Zero(3, 3);
    p.target_amplitude = Eigen::VectorXd::Ones(3);
    p.stepper.type = stepper;
    PhaseNetwork network(p);
    std::mt19937 rng(7);
    const Eigen::VectorXd theta0 = testing::RandomPhases(rng, 3);
    network.Reset(theta0, Eigen::VectorXd::Ones(3));
    const double dt_s = 1e-3;
    testing::RunFor(network, 10.0, dt_s);
    ASSERT_EQ(network.status(), StepStatus::kOk);
    ASSERT_NEAR(network.time_s(), 10.0, 1e-9);
    for (int i = 0; i < 3; ++i) {
      // dθ/dt is the constant 2πf, which every stepper integrates exactly; what is left is
      // rounding, ~1e-15 rad per step over 10⁴ steps: 1e-9 is far above it.
      const double expected = kTwoPi * p.frequency_hz * network.time_s();
      EXPECT_NEAR(network.phase_unwrapped_rad()[i] - theta0[i], expected, 1e-9);
      // The wrapped phase is the same angle, in [0, 2π).
      EXPECT_GE(network.phase_rad()[i], 0.0);
      EXPECT_LT(network.phase_rad()[i], kTwoPi);
      EXPECT_NEAR(WrapPi(network.phase_rad()[i] - theta0[i] - expected), 0.0, 1e-9);
    }
  }
}

TEST(CpgPhaseNetwork, TwoCoupledOscillatorsFollowClosedFormAndLockToBias) {
  const double w_per_s = 2.0;
  const double biases_rad[] = {0.0, kTwoPi / 4.0, kTwoPi / 2.0, -kTwoPi / 3.0, 2.5};
  for (double phi : biases_rad) {
    for (unsigned seed = 0; seed < 40; ++seed) {
      PhaseNetwork network(TwoOscillators(phi, w_per_s, 1.0, 10.0, Stepper::kRk4));
      std::mt19937 rng(seed);
      const Eigen::VectorXd theta0 = testing::RandomPhases(rng, 2);
      network.Reset(theta0, Eigen::VectorXd::Ones(2));  // r = R: the e^{−2wrt} form holds
      const double psi0 = theta0[1] - theta0[0];
      for (double t_end : {0.25, 0.5, 1.0, 2.0, 4.0, 8.0}) {
        testing::RunFor(network, t_end - network.time_s(), 1e-3);
        const double psi = network.phase_rad()[1] - network.phase_rad()[0];
        const double expected =
            ClosedFormPhaseDifference(psi0, phi, w_per_s, 1.0, 1.0, 10.0, network.time_s());
        // RK4 at 1 ms with rates below 15 rad/s: local error ~(15·1e-3)⁵/120 ≈ 6e-12, over
        // 8000 steps of a contracting system < 1e-8.
        EXPECT_NEAR(WrapPi(psi - expected), 0.0, 1e-8) << "phi " << phi << " seed " << seed;
      }
      // Locked: after 8 s the closed form is within tan((ψ0−φ)/2)·e^{−32} of φ.
      const double psi = network.phase_rad()[1] - network.phase_rad()[0];
      EXPECT_NEAR(WrapPi(psi - phi), 0.0, 1e-6) << "phi " << phi << " seed " << seed;
    }
  }
}

// The right-hand side takes sin and cos of each phase with one sincos call: glibc's sincos
// must give sin's and cos's own bits over the phases' range (wrapped [0, 2π) plus a stage's
// step either side), or every gait would change. Called through pointers so that the compiler
// cannot merge the reference calls into a sincos of its own.
TEST(CpgPhaseNetwork, SincosIsSinAndCosBitForBit) {
  double (*volatile sin_fn)(double) = std::sin;
  double (*volatile cos_fn)(double) = std::cos;
  std::mt19937_64 rng(20261127);
  std::uniform_real_distribution<double> phase(-1.0, 8.0);
  std::vector<double> x = {0.0, -0.0, 1e-300, 0.855469, 2.426265, M_PI / 2, M_PI, kTwoPi,
                           std::nextafter(kTwoPi, 0.0)};
  for (int i = 0; i < 2000000; ++i) x.push_back(phase(rng));
  long mismatches = 0;
  for (double v : x) {
    double s = 0.0, c = 0.0;
    ::sincos(v, &s, &c);
    const double want_s = sin_fn(v), want_c = cos_fn(v);
    mismatches += std::memcmp(&s, &want_s, sizeof s) != 0 || std::memcmp(&c, &want_c, sizeof c);
  }
  EXPECT_EQ(mismatches, 0);
}

TEST(CpgPhaseNetwork, AmplitudeConvergesToTargetAtRateA) {
  PhaseNetworkParams p;
  p.coupling_per_s = AllToAllCoupling(3, 1.0);
  p.phase_bias_rad = PhaseBiasFromOffsets({0.0, 0.3, 0.6});
  p.target_amplitude = Eigen::Vector3d(1.0, 0.5, 2.0);
  p.amplitude_rate_per_s = 4.0;
  PhaseNetwork network(p);
  const Eigen::Vector3d r0(0.0, 1.5, 0.25);
  network.Reset(Eigen::Vector3d(0.1, 0.2, 0.3), r0);
  for (double t_end : {0.1, 0.3, 1.0, 3.0}) {
    testing::RunFor(network, t_end - network.time_s(), 1e-3);
    for (int i = 0; i < 3; ++i) {
      const double big_r = p.target_amplitude[i];
      const double expected = big_r + (r0[i] - big_r) * std::exp(-4.0 * network.time_s());
      // RK4 on a linear ODE with a·dt = 4e-3: relative error per step (a dt)⁵/120 ≈ 1e-14.
      EXPECT_NEAR(network.amplitude()[i], expected, 1e-10) << "oscillator " << i;
    }
  }
}

TEST(CpgPhaseNetwork, DefaultStartIsTheLockedPatternAtZeroAmplitude) {
  const Gait gait = GaitPreset("lateral_sequence", 4);
  PhaseNetwork network(PhaseNetworkParamsForGait(gait, 1.0, 2.0));
  for (int j = 0; j < 4; ++j) {
    // θ_j − θ_0 = φ_0j = 2π(offset_0 − offset_j).
    const double expected = kTwoPi * (gait.offsets_cycles[0] - gait.offsets_cycles[j]);
    EXPECT_NEAR(WrapPi(network.phase_rad()[j] - network.phase_rad()[0] - expected), 0.0, 1e-12);
    EXPECT_EQ(network.amplitude()[j], 0.0);
  }
  EXPECT_EQ(network.phase_duty_factor(), std::nullopt);
}

// Error of ψ at t = 1 s against the closed form with amplitude dynamics, for one stepper and dt.
double PhaseDifferenceError(Stepper stepper, double dt_s) {
  const double phi = 1.0, w = 3.0, big_r = 1.0, a = 5.0, r0 = 0.2;
  PhaseNetwork network(TwoOscillators(phi, w, big_r, a, stepper));
  const Eigen::Vector2d theta0(0.3, 0.3 + 2.8);  // ψ0 − φ = 1.8 rad: far from the lock
  network.Reset(theta0, Eigen::Vector2d::Constant(r0));
  testing::RunFor(network, 1.0, dt_s);
  const double psi = network.phase_rad()[1] - network.phase_rad()[0];
  return std::abs(WrapPi(psi - ClosedFormPhaseDifference(2.8, phi, w, r0, big_r, a, 1.0)));
}

TEST(CpgPhaseNetwork, Rk4ErrorFallsSixteenfoldAndEulerTwofoldWhenDtHalves) {
  // Orders of convergence: global error ∝ dt⁴ (RK4) and ∝ dt (Euler). The next term of the
  // error expansion is one order higher, so at these dt the ratios sit within a few percent of
  // 16 and 2; the brackets leave room for that and nothing more.
  for (double dt : {0.02, 0.01}) {
    const double rk4 = PhaseDifferenceError(Stepper::kRk4, dt);
    const double rk4_half = PhaseDifferenceError(Stepper::kRk4, dt / 2);
    const double euler = PhaseDifferenceError(Stepper::kEuler, dt);
    const double euler_half = PhaseDifferenceError(Stepper::kEuler, dt / 2);
    RecordProperty("rk4_ratio_dt_" + std::to_string(dt), std::to_string(rk4 / rk4_half));
    RecordProperty("euler_ratio_dt_" + std::to_string(dt), std::to_string(euler / euler_half));
    std::printf("dt %.4f: RK4 error %.3e -> %.3e (ratio %.2f); Euler %.3e -> %.3e (ratio %.3f)\n",
                dt, rk4, rk4_half, rk4 / rk4_half, euler, euler_half, euler / euler_half);
    EXPECT_GT(rk4 / rk4_half, 12.0);
    EXPECT_LT(rk4 / rk4_half, 20.0);
    EXPECT_GT(euler / euler_half, 1.8);
    EXPECT_LT(euler / euler_half, 2.2);
  }
}

TEST(CpgPhaseNetwork, Dopri5MeetsItsTolerance) {
  // Weak coupling (w = 0.4/s) so that the phase difference is still far from the lock at the
  // end: contraction towards the lock would otherwise wipe out the error being measured.
  const double phi = 1.0, w = 0.4, big_r = 1.0, a = 5.0, r0 = 0.2;
  double previous_error = 1.0;
  for (double tol : {1e-4, 1e-6, 1e-8, 1e-10}) {
    PhaseNetworkParams p = TwoOscillators(phi, w, big_r, a, Stepper::kDopri5);
    p.stepper.abs_tol = tol;
    p.stepper.rel_tol = tol;
    PhaseNetwork network(p);
    network.Reset(Eigen::Vector2d(0.3, 3.1), Eigen::Vector2d::Constant(r0));
    // dt_s = 0.5 s: several internal steps per Step, the last cut to land on the Step's end.
    double error = 0.0;
    for (int k = 0; k < 8; ++k) {
      network.Step(0.5, {});
      const double psi = network.phase_rad()[1] - network.phase_rad()[0];
      const double expected =
          ClosedFormPhaseDifference(2.8, phi, w, r0, big_r, a, network.time_s());
      error = std::max(error, std::abs(WrapPi(psi - expected)));
    }
    ASSERT_EQ(network.status(), StepStatus::kOk);
    const IntegrationStats stats = network.stats();
    // Each accepted step errs by at most tol·(1 + |x| + h·|dx/dt|) per component: |x| ≤ 2π,
    // h·|dx/dt| ≤ 0.5·9 = 4.5, so ≤ 11.8·tol, and ψ takes the errors of two phases. The
    // phase difference does not grow errors (it contracts towards the lock), so they add up
    // at most: global ≤ accepted steps · 2 · 11.8·tol.
    const double bound = static_cast<double>(stats.accepted_steps) * 2.0 * 11.8 * tol;
    std::printf("tol %.0e: max error %.3e, bound %.3e, %lld accepted, %lld rejected steps\n", tol,
                error, bound, static_cast<long long>(stats.accepted_steps),
                static_cast<long long>(stats.rejected_steps));
    EXPECT_LT(error, bound) << "tol " << tol;
    // Tighter tolerances buy accuracy, down to where rounding (~1e-13 here) shows.
    if (previous_error > 1e-11) {
      EXPECT_LT(error, previous_error) << "tol " << tol;
    }
    previous_error = error;
  }
}

TEST(CpgPhaseNetwork, TegotaeFeedbackChangesThePhaseRateByExactlyMinusSigmaNCosTheta) {
  // One Euler step: Δθ = dt·dθ/dt exactly, so the difference of two steps from the same state,
  // with and without feedback, is dt·feedback up to rounding of θ (~1e-15 rad).
  PhaseNetworkParams p = PhaseNetworkParamsForGait(GaitPreset("trot", 4), 1.0, 2.0);
  p.stepper.type = Stepper::kEuler;
  const Eigen::Vector4d theta0(0.3, 2.0, 3.5, 5.9);
  const Eigen::Vector4d r0(0.5, 0.8, 1.0, 1.2);
  const double sigma = 6.0;  // rad/(N·s), Owaki and Ishiguro 2017
  const std::vector<double> load_n = {0.0, 1.5, 3.0, 0.7};
  std::vector<double> feedback(4);
  for (int i = 0; i < 4; ++i) feedback[i] = TegotaeFeedback(sigma, load_n[i], theta0[i]);
  const double dt_s = 1e-3;

  PhaseNetwork without(p);
  without.Reset(theta0, r0);
  without.Step(dt_s, {});
  PhaseNetwork with(p);
  with.Reset(theta0, r0);
  with.Step(dt_s, feedback);
  for (int i = 0; i < 4; ++i) {
    EXPECT_DOUBLE_EQ(feedback[i], -sigma * load_n[i] * std::cos(theta0[i]));
    const double change = with.phase_unwrapped_rad()[i] - without.phase_unwrapped_rad()[i];
    EXPECT_NEAR(change, dt_s * feedback[i], 1e-14) << "leg " << i;
    // Feedback acts on the phase only.
    EXPECT_DOUBLE_EQ(with.amplitude()[i], without.amplitude()[i]);
  }
}

TEST(CpgPhaseNetwork, FeedbackIsHeldOverTheStepAndDopri5SeesEachNewValue) {
  // Constant feedback f on uncoupled oscillators: θ advances at 2πf_0 + f, exactly, with every
  // stepper; switching f between Steps must not leave Dopri5 with the old derivative (first
  // same as last), which would show as an error of order f·h in the first internal step.
  for (Stepper stepper : kAllSteppers) {
    PhaseNetworkParams p;
    p.coupling_per_s = Eigen::MatrixXd::Zero(2, 2);
    p.phase_bias_rad = Eigen::MatrixXd::Zero(2, 2);
    p.target_amplitude = Eigen::VectorXd::Ones(2);
    p.stepper.type = stepper;
    PhaseNetwork network(p);
    network.Reset(Eigen::Vector2d::Zero(), Eigen::Vector2d::Ones());
    double expected0 = 0.0, expected1 = 0.0;
    for (int k = 0; k < 200; ++k) {
      const double f = (k % 3 == 0) ? 0.0 : (k % 3 == 1 ? 2.0 : -1.5);
      const std::vector<double> feedback = {f, -f};
      network.Step(0.01, feedback);
      expected0 += 0.01 * (kTwoPi + f);
      expected1 += 0.01 * (kTwoPi - f);
      // The right-hand side is constant within a Step: exact up to rounding (~1e-15 a step).
      ASSERT_NEAR(network.phase_unwrapped_rad()[0], expected0, 1e-11) << "step " << k;
      ASSERT_NEAR(network.phase_unwrapped_rad()[1], expected1, 1e-11) << "step " << k;
    }
  }
}

TEST(CpgPhaseNetwork, ResetClearsTimeCountersAndStatus) {
  PhaseNetwork network(PhaseNetworkParamsForGait(GaitPreset("tripod", 6), 1.0, 1.0));
  testing::RunFor(network, 0.5, 1e-3);
  EXPECT_GT(network.stats().steps, 0);
  network.Reset(Eigen::VectorXd::Constant(6, 7.0), Eigen::VectorXd::Ones(6));
  EXPECT_EQ(network.time_s(), 0.0);
  EXPECT_EQ(network.stats().steps, 0);
  EXPECT_EQ(network.status(), StepStatus::kOk);
  // 7 rad wrapped.
  EXPECT_NEAR(network.phase_rad()[0], 7.0 - kTwoPi, 1e-15);
}

TEST(CpgPhaseNetwork, NonFiniteFeedbackIsReportedNotThrown) {
  PhaseNetwork network(PhaseNetworkParamsForGait(GaitPreset("trot", 4), 1.0, 1.0));
  const std::vector<double> feedback = {0.0, std::nan(""), 0.0, 0.0};
  EXPECT_NO_THROW(network.Step(1e-3, feedback));
  EXPECT_EQ(network.status(), StepStatus::kNonFinite);
}

}  // namespace
}  // namespace climbsim::cpg

namespace climbsim::cpg {
namespace {

// A held oscillator keeps its state exactly, phase and amplitude, while the others advance;
// released, it goes on from where it was.
TEST(CpgHold, HeldOscillatorsKeepTheirStateExactly) {
  for (bool hopf : {false, true}) {
    const Gait gait = GaitPreset("trot", 4);
    std::unique_ptr<OscillatorNetwork> net;
    if (hopf) {
      net = std::make_unique<HopfNetwork>(HopfNetworkParamsForGait(gait, 1.0, 2.0));
    } else {
      net = std::make_unique<PhaseNetwork>(PhaseNetworkParamsForGait(gait, 1.0, 2.0));
    }
    for (int k = 0; k < 100; ++k) net->Step(1e-3, {});  // RK4 at 1 ms: Hopf's α = 50/s is stiff
    const std::vector<double> before(net->phase_rad().begin(), net->phase_rad().end());
    const std::vector<double> amp(net->amplitude().begin(), net->amplitude().end());
    const std::vector<uint8_t> held = {1, 0, 1, 0};
    for (int k = 0; k < 200; ++k) net->Step(1e-3, {}, held);
    EXPECT_EQ(net->phase_rad()[0], before[0]) << hopf;
    EXPECT_EQ(net->phase_rad()[2], before[2]) << hopf;
    EXPECT_EQ(net->amplitude()[0], amp[0]) << hopf;
    // The free ones went on: 0.2 s at about 2π rad/s.
    const double moved = std::remainder(net->phase_rad()[1] - before[1], 2 * M_PI);
    EXPECT_GT(moved, 0.5) << hopf;
    net->Step(1e-3, {});
    EXPECT_NE(net->phase_rad()[0], before[0]) << hopf;
  }
  PhaseNetwork p(PhaseNetworkParamsForGait(GaitPreset("trot", 4), 1.0, 2.0));
  const std::vector<uint8_t> wrong = {1, 0};
  EXPECT_THROW(p.Step(1e-3, {}, wrong), std::invalid_argument);
}

}  // namespace
}  // namespace climbsim::cpg
