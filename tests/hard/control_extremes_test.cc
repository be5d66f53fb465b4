// The controllers at the edges of their keys: the CPG at the extreme frequencies and
// couplings a scenario accepts (cpg.frequency_hz 0.01 and 20, cpg.coupling_per_s 0 and 1000,
// every stepper), and the leg reflexes with every gain at 0 and very large. Phases and
// amplitudes stay finite and bounded, an uncoupled oscillator advances at exactly 2πf, and the
// reflexes' summed offset never leaves ±max_offset_rad.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>

#include "cpg/cpg.h"
#include "reflex/reflex.h"
#include "sim/sim.h"
#include "tests/hard/hard_util.h"
#include "tests/common/test_util.h"

namespace climbsim {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

struct Stepped {
  cpg::Stepper stepper;
  const char* name;
};
constexpr Stepped kSteppers[] = {{cpg::Stepper::kEuler, "euler"},
                                 {cpg::Stepper::kRk4, "rk4"},
                                 {cpg::Stepper::kDopri5, "dopri5"}};

// The phase network of the scenario's CPG (lateral sequence, all-to-all coupling w, target
// amplitude R = 1, rate a = 5/s as cpg.amplitude_rate_per_s) from random phases and a start
// amplitude of 0.4, 2 s at 1 ms. Checked every step:
//   - phases and amplitudes finite, phases in [0, 2π);
//   - r between its start and R (dr/dt = a(R − r) moves it monotonically there; Euler too,
//     since a·dt = 0.005 < 1): amplitudes bounded by max(R, start);
//   - |Δθ| per step ≤ 2·(2πf + Σ_j w·r_j)·dt: the phase rate is bounded by the law, and a
//     step is a combination of rates with weights summing in magnitude to 1 (Euler, RK4) or
//     1.64 (Dopri5's b, one negative);
//   - uncoupled (w = 0): θ advances at exactly 2πf, every step (to rounding).
TEST(HardCpgExtremes, PhaseNetworkAtExtremeFrequencyAndCouplingStaysFiniteAndBounded) {
  const cpg::Gait gait = cpg::GaitPreset("lateral_sequence", 4);
  for (double f : {20.0, 0.01}) {
    for (double w : {0.0, 1000.0}) {
      for (const Stepped& st : kSteppers) {
        SCOPED_TRACE(std::string(st.name) + ", f = " + std::to_string(f) +
                     " Hz, w = " + std::to_string(w) + "/s");
        cpg::PhaseNetworkParams p = cpg::PhaseNetworkParamsForGait(gait, f, w, 1.0);
        p.amplitude_rate_per_s = 5.0;
        p.stepper.type = st.stepper;
        cpg::PhaseNetwork net(p);
        std::mt19937 rng(11);
        std::uniform_real_distribution<double> u(0.0, kTwoPi);
        Eigen::VectorXd theta0(4);
        for (int i = 0; i < 4; ++i) theta0[i] = u(rng);
        const double start = 0.4, target = 1.0;
        net.Reset(theta0, Eigen::VectorXd::Constant(4, start));
        const double dt = 1e-3;
        bool finite = true, in_range = true, amp_bounded = true, rate_bounded = true;
        double worst_uncoupled_error = 0;
        std::vector<double> before(4);
        for (int k = 0; k < 2000; ++k) {
          double r_sum = 0;
          for (int i = 0; i < 4; ++i) {
            before[i] = net.phase_unwrapped_rad()[i];
            r_sum += net.amplitude()[i];
          }
          net.Step(dt, {});
          const double rate_bound = 2.0 * (kTwoPi * f + w * r_sum) * dt;
          for (int i = 0; i < 4; ++i) {
            const double th = net.phase_rad()[i], r = net.amplitude()[i];
            const double step = net.phase_unwrapped_rad()[i] - before[i];
            finite = finite && std::isfinite(th) && std::isfinite(r) && std::isfinite(step);
            in_range = in_range && th >= 0.0 && th < kTwoPi;
            amp_bounded = amp_bounded && r >= start - 1e-12 && r <= target + 1e-12;
            rate_bounded = rate_bounded && std::abs(step) <= rate_bound;
            if (w == 0.0) {
              worst_uncoupled_error =
                  std::max(worst_uncoupled_error, std::abs(step - kTwoPi * f * dt));
            }
          }
        }
        EXPECT_EQ(net.status(), cpg::StepStatus::kOk);
        EXPECT_TRUE(finite);
        EXPECT_TRUE(in_range);
        EXPECT_TRUE(amp_bounded);
        EXPECT_TRUE(rate_bounded);
        if (w == 0.0) {
          // 2πf·dt is at most 0.126 rad; the unwrapped phase is at most 2πf·2 s + 2π = 258
          // rad, where one ulp is 6e-14: 1e-12 rad per step is rounding only.
          EXPECT_LT(worst_uncoupled_error, 1e-12);
          for (int i = 0; i < 4; ++i) {
            EXPECT_NEAR(net.phase_unwrapped_rad()[i] - theta0[i], kTwoPi * f * net.time_s(), 1e-9);
          }
        }
      }
    }
  }
}

// The same extremes through a scenario: the gecko on the floor, 0.5 s, each stepper, phase
// and Hopf oscillators. Every run either stays stable to the end (no MuJoCo warning, finite
// state) or, where the integration cannot be stable, stops with the step, the time and the
// cause: never an exception out of the step loop (STYLE.md 6).
//
// Which runs must stop: the Hopf coupling pulls each of the 4 oscillators towards its
// targets with rate (n − 1)·k = 3000/s at k = 1000/s, so an explicit step of 1 ms has
// h·λ = 3, beyond Euler's stability limit (2) and RK4's (2.79 on the real axis): the state
// blows up within about 40 steps, the network reports kNonFinite, the targets turn bad, and
// MuJoCo flags the ctrl (mjWARN_BADCTRL). Dopri5 shortens its steps and stays stable. The
// phase network's coupling only acts through sin(), so its phases stay finite at any k (its
// amplitudes do not depend on k).
TEST(HardCpgExtremes, ScenarioRunsAtExtremeFrequencyAndCouplingStayStableOrStopWithACause) {
  for (const char* oscillator : {"phase", "hopf"}) {
    for (double f : {20.0, 0.01}) {
      for (double w : {0.0, 1000.0}) {
        for (const Stepped& st : kSteppers) {
          const std::string text = std::string("robot: gecko\nscene: floor\nduration_s: 0.5\n") +
                                   "outputs: {trajectory_rate_hz: 0}\ncpg:\n  gait: trot\n" +
                                   "  oscillator: " + oscillator +
                                   "\n  frequency_hz: " + std::to_string(f) +
                                   "\n  coupling_per_s: " + std::to_string(w) +
                                   "\n  start_amplitude: 1\n  stepper: " + st.name + "\n";
          SCOPED_TRACE(text);
          const sim::Scenario s =
              sim::LoadScenario(climbsim::testing::WriteFile("cpg_x.yaml", text));
          auto model = sim::CompileScenario(s);
          sim::Simulation run(s, *model);
          sim::RunResult r;
          ASSERT_NO_THROW(r = run.Run());
          const bool must_stop =
              std::string(oscillator) == "hopf" && w > 0 && st.stepper != cpg::Stepper::kDopri5;
          if (must_stop) {
            EXPECT_FALSE(r.stable);
            EXPECT_LT(r.steps, 500);
            EXPECT_EQ(r.failure.rfind("step " + std::to_string(r.steps) + ", t = ", 0), 0u)
                << r.failure;
            EXPECT_NE(r.failure.find("mjWARN_BADCTRL"), std::string::npos) << r.failure;
          } else {
            EXPECT_TRUE(r.stable) << r.failure;
            EXPECT_EQ(r.steps, 500);
            EXPECT_TRUE(climbsim::testing::StateFinite(run.world().model(), run.world().data()));
            EXPECT_EQ(climbsim::testing::WarningsRaised(run.world().data()), "");
          }
        }
      }
    }
  }
}

// Every reflex on, every gain (spindle K_L and K_V, both GTO channels' K_F) at 0 and then
// large (1e6, 1e300 and the largest double, all of which the keys accept: ">= 0"), driven by
// 20 000 periods of random sensing (stance and swing, touches, attachment, loads up to ±50 N,
// stretches up to ±3 rad and ±50 rad/s): the summed offset on each joint stays finite and
// within ±max_offset_rad, and a large gain drives it to the clamp. With every gain 0 the
// spindle and the GTO press never act (the other reflexes have no gains and still do). At the
// largest double a length term and a velocity term of opposite signs both overflow, to −inf
// and +inf: their sum was NaN and passed the clamp; it now counts as 0 (reflex/leg_reflex.cc).
TEST(HardReflexExtremes, GainsAtZeroAndLargeKeepTheOffsetClamped) {
  for (double gain : {0.0, 1e6, 1e300, std::numeric_limits<double>::max()}) {
    SCOPED_TRACE("gain " + std::to_string(gain));
    reflex::LegReflexParams p;
    for (auto& j : p.spindle.joints) {
      j.length_gain = gain;
      j.velocity_gain_s = gain;
    }
    p.gto.hold.gain = gain;
    p.gto.press.gain = gain;
    p.spindle.stance_band_rad = 1e9;  // the push hold is a threshold, not a gain: out of play
    p.max_offset_rad = 0.4;
    reflex::LegReflex leg(p, 0.001);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> unit(0.0, 1.0), sym(-1.0, 1.0);
    bool clamped = true, finite = true, gain_reflex_fired = false;
    double peak = 0;
    for (int k = 0; k < 20000; ++k) {
      reflex::LegSensing s;
      s.stance = (k / 300) % 2 == 0;  // 0.3 s phases
      s.phase_progress = (k % 300) / 300.0;
      s.touching = unit(rng) < 0.7;
      s.attached = s.touching && unit(rng) < 0.8;
      s.bonded_fraction = s.attached ? unit(rng) : 0.0;
      s.normal_load_n = 50.0 * sym(rng);
      s.preload_n = 50.0 * unit(rng);
      s.bonds_lost = unit(rng) < 0.01;
      s.partner_attached = unit(rng) < 0.9;
      for (int j = 0; j < 3; ++j) {
        s.stretch_rad[j] = 3.0 * sym(rng);
        s.stretch_velocity_rad_per_s[j] = 50.0 * sym(rng);
      }
      const reflex::LegReflexOutput out = leg.Update(s);
      gain_reflex_fired = gain_reflex_fired || out.Fired(reflex::Reflex::kSpindle) ||
                          out.Fired(reflex::Reflex::kGtoPress);
      for (int j = 0; j < 3; ++j) {
        const double o = out.target_offset_rad[j];
        finite = finite && std::isfinite(o);
        clamped = clamped && std::abs(o) <= p.max_offset_rad;
        if (std::isfinite(o)) peak = std::max(peak, std::abs(o));
      }
    }
    EXPECT_TRUE(finite);
    EXPECT_TRUE(clamped);
    if (gain > 0) {
      EXPECT_EQ(peak, p.max_offset_rad) << "a large gain saturates the clamp";
    } else {
      EXPECT_FALSE(gain_reflex_fired);
    }
    std::printf("reflex gains %g: peak |offset| %.6g rad\n", gain, peak);
  }
}

}  // namespace
}  // namespace climbsim
