// Spindle-like and GTO-like laws against their closed forms (reflex.h). Inputs, gains and
// thresholds are exact in binary, so the expected outputs are exact too: EXPECT_EQ throughout.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include <cmath>

#include "reflex/reflex.h"

namespace climbsim::reflex {
namespace {

constexpr double kLawDt = 0.001;

SpindleParams Spindle(double kl, double l0, double kv, double v0, int delay_samples) {
  return {.length_gain = kl,
          .velocity_gain_s = kv,
          .length_threshold_rad = l0,
          .velocity_threshold_rad_per_s = v0,
          .delay_s = delay_samples * kLawDt};
}

// offset = −K_L·(q̃ − L0) appears exactly Δ after a stretch step, for several Δ/dt.
TEST(ReflexSpindle, StretchStepAppearsAfterExactlyTheDelayScaled) {
  for (int n : {0, 1, 5, 10, 20}) {
    SpindleReflex spindle(Spindle(2.0, 0.125, 0.0, 0.0, n), kLawDt);
    ASSERT_EQ(spindle.delay_samples(), n);
    const int k0 = 3;
    for (int k = 0; k < k0 + n + 5; ++k) {
      const double offset = spindle.Update(k >= k0 ? 0.625 : 0.0, 0.0);
      EXPECT_EQ(offset, k >= k0 + n ? -1.0 : 0.0) << "n = " << n << ", k = " << k;
    }
  }
}

TEST(ReflexSpindle, VelocityStepAppearsAfterExactlyTheDelayScaled) {
  for (int n : {0, 2, 7}) {
    SpindleReflex spindle(Spindle(0.0, 0.0, 0.25, 0.5, n), kLawDt);
    const int k0 = 2;
    for (int k = 0; k < k0 + n + 5; ++k) {
      const double offset = spindle.Update(0.0, k >= k0 ? 4.5 : 0.0);
      EXPECT_EQ(offset, k >= k0 + n ? -1.0 : 0.0) << "n = " << n << ", k = " << k;
    }
  }
}

// Below or at a threshold the term is exactly zero (+0.0, not −0.0).
TEST(ReflexSpindle, BelowThresholdIsExactlyZero) {
  SpindleReflex spindle(Spindle(3.0, 0.25, 2.0, 1.0, 0), kLawDt);
  for (double q : {0.0, 0.1, 0.25, -0.25, -0.1}) {
    for (double v : {0.0, 0.5, 1.0, -1.0, -0.75}) {
      const double offset = spindle.Update(q, v);
      EXPECT_EQ(offset, 0.0) << q << ", " << v;
      EXPECT_FALSE(std::signbit(offset)) << q << ", " << v;
    }
  }
  EXPECT_EQ(spindle.Update(0.375, 0.0), -3.0 * 0.125);  // just above: the dead zone is removed
}

TEST(ReflexSpindle, GainsAreLinear) {
  for (double kl : {0.5, 1.0, 2.0, 4.0}) {
    SpindleReflex single(Spindle(kl, 0.125, 0.0, 0.0, 1), kLawDt);
    SpindleReflex doubled(Spindle(2.0 * kl, 0.125, 0.0, 0.0, 1), kLawDt);
    for (double q : {0.3, 0.7, -0.9}) {
      EXPECT_EQ(2.0 * single.Update(q, 0.0), doubled.Update(q, 0.0));
    }
  }
  for (double kv : {0.01, 0.02}) {
    SpindleReflex single(Spindle(0.0, 0.0, kv, 0.5, 1), kLawDt);
    SpindleReflex doubled(Spindle(0.0, 0.0, 2.0 * kv, 0.5, 1), kLawDt);
    for (double v : {0.8, 3.0, -2.0}) {
      EXPECT_EQ(2.0 * single.Update(0.0, v), doubled.Update(0.0, v));
    }
  }
}

// Each term has its own dead zone: one can act while the other is clipped.
TEST(ReflexSpindle, VelocityTermClipsIndependentlyOfLengthTerm) {
  SpindleReflex spindle(Spindle(2.0, 0.125, 0.5, 1.0, 0), kLawDt);
  EXPECT_EQ(spindle.Update(0.625, 0.5), -1.0);  // length only
  EXPECT_EQ(spindle.length_term_rad(), -1.0);
  EXPECT_EQ(spindle.velocity_term_rad(), 0.0);
  EXPECT_EQ(spindle.Update(0.0625, 3.0), -1.0);  // velocity only
  EXPECT_EQ(spindle.length_term_rad(), 0.0);
  EXPECT_EQ(spindle.velocity_term_rad(), -1.0);
  EXPECT_EQ(spindle.Update(0.625, 3.0), -2.0);  // both: the sum
  EXPECT_EQ(spindle.Update(0.625, -3.0), 0.0);  // stretched but moving back fast: they cancel
}

// The offset moves the target against the stretch, both ways (antagonist pair).
TEST(ReflexSpindle, OffsetResistsTheStretchInBothDirections) {
  SpindleReflex spindle(Spindle(2.0, 0.125, 0.5, 1.0, 0), kLawDt);
  EXPECT_LT(spindle.Update(0.5, 2.0), 0.0);
  EXPECT_GT(spindle.Update(-0.5, -2.0), 0.0);
  EXPECT_EQ(spindle.Update(-0.625, -3.0), 2.0);
}

TEST(ReflexSpindle, NonFiniteInputsAreTreatedAsZero) {
  SpindleReflex spindle(Spindle(2.0, 0.0, 1.0, 0.0, 0), kLawDt);
  EXPECT_EQ(spindle.Update(std::nan(""), INFINITY), 0.0);
  EXPECT_EQ(spindle.nonfinite_inputs(), 2);
}

TEST(ReflexSpindle, ResetClearsTheDelayedSamples) {
  SpindleReflex spindle(Spindle(2.0, 0.0, 0.0, 0.0, 3), kLawDt);
  for (int k = 0; k < 5; ++k) spindle.Update(1.0, 0.0);
  spindle.Reset();
  EXPECT_EQ(spindle.Update(0.0, 0.0), 0.0);
}

GtoParams Gto(double gain, double threshold, int delay_samples) {
  return {.gain = gain, .threshold = threshold, .delay_s = delay_samples * kLawDt};
}

TEST(ReflexGto, LoadStepAppearsAfterExactlyTheDelayScaled) {
  for (int n : {0, 1, 10, 20}) {
    GtoReflex gto(Gto(0.25, 0.5, n), kLawDt);
    const int k0 = 5;
    for (int k = 0; k < k0 + n + 5; ++k) {
      const double u = gto.Update(k >= k0 ? 4.5 : 0.0);
      EXPECT_EQ(u, k >= k0 + n ? 1.0 : 0.0) << "n = " << n << ", k = " << k;
      EXPECT_EQ(gto.loaded(), k >= k0 + n) << "n = " << n << ", k = " << k;
    }
  }
}

// F̃ = F0 exactly is unloaded with u = 0; the next double up is loaded.
TEST(ReflexGto, ThresholdIsExact) {
  GtoReflex gto(Gto(2.0, 0.15, 0), kLawDt);
  EXPECT_EQ(gto.Update(0.15), 0.0);
  EXPECT_FALSE(gto.loaded());
  EXPECT_EQ(gto.Update(0.149), 0.0);
  EXPECT_FALSE(gto.loaded());
  const double just_above = std::nextafter(0.15, 1.0);
  EXPECT_GT(gto.Update(just_above), 0.0);
  EXPECT_TRUE(gto.loaded());
  EXPECT_EQ(gto.Update(-3.0), 0.0);  // pressed instead of pulled: unloaded
  EXPECT_FALSE(gto.loaded());
}

TEST(ReflexGto, GainIsLinear) {
  for (double gain : {0.1, 0.2, 1.5}) {
    GtoReflex single(Gto(gain, 0.25, 2), kLawDt);
    GtoReflex doubled(Gto(2.0 * gain, 0.25, 2), kLawDt);
    for (double f : {0.3, 1.0, 7.0, 0.1, 2.0}) {
      EXPECT_EQ(2.0 * single.Update(f), doubled.Update(f));
    }
  }
}

TEST(ReflexGto, NegativeGainIsNegativeForceFeedback) {
  GtoReflex gto(Gto(-0.5, 1.0, 0), kLawDt);
  EXPECT_EQ(gto.Update(3.0), -1.0);
  EXPECT_TRUE(gto.loaded());
}

// Posture: a step of pull over weight P reaches the law after exactly the delay, and the crouch
// then follows the first-order lag to min(c_max, K_P (P - P0)) in closed form.
TEST(ReflexPosture, StepOfPullLowersTheBodyAlongTheLag) {
  PostureParams p;
  p.enabled = true;
  p.pull = {.gain = 0.05, .threshold = 0.1, .delay_s = 0.003};  // 3 periods at 1 ms
  p.max_crouch_m = 0.0125;
  p.time_constant_s = 0.2;
  constexpr double kDt1 = 0.001;
  PostureReflex posture(p, kDt1);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(posture.Update(0.3), 0.0) << k;  // still in the delay
  const double target = 0.05 * (0.3 - 0.1);                              // 0.01 m < c_max
  const double keep = std::exp(-kDt1 / 0.2);
  for (int k = 1; k <= 400; ++k) {
    EXPECT_NEAR(posture.Update(0.3), target * (1.0 - std::pow(keep, k)), 1e-15) << k;
  }
  // A larger pull is capped; a pull under P0 lets the body up again, along the same lag.
  PostureReflex capped(p, kDt1);
  for (int k = 0; k < 5000; ++k) capped.Update(2.0);
  EXPECT_NEAR(capped.crouch_m(), 0.0125, 1e-12);
  for (int k = 0; k < 3; ++k) capped.Update(0.05);  // the delay still holds the pull
  const double before = capped.crouch_m();
  EXPECT_NEAR(before, 0.0125, 1e-10);
  EXPECT_NEAR(capped.Update(0.05), before * keep, 1e-17);  // now P < P0: the target is 0
  posture.Reset();
  EXPECT_EQ(posture.crouch_m(), 0.0);
  EXPECT_EQ(posture.Update(1.0), 0.0);  // the delay line was cleared too
}

TEST(ReflexPosture, OffStaysUpAndBadParamsAreRefusedByName) {
  PostureParams p;
  p.enabled = false;
  PostureReflex off(p, 0.001);
  for (int k = 0; k < 100; ++k) EXPECT_EQ(off.Update(1.0), 0.0);
  PostureParams bad;
  bad.time_constant_s = 0.0;
  EXPECT_THROW(
      {
        try {
          PostureReflex(bad, 0.001);
        } catch (const std::invalid_argument& e) {
          EXPECT_NE(std::string(e.what()).find("posture.time_constant_s"), std::string::npos);
          throw;
        }
      },
      std::invalid_argument);
  bad = PostureParams{};
  bad.max_crouch_m = -0.01;
  EXPECT_THROW(PostureReflex(bad, 0.001), std::invalid_argument);
  bad = PostureParams{};
  bad.pull.gain = -1.0;
  EXPECT_THROW(PostureReflex(bad, 0.001), std::invalid_argument);
}

}  // namespace
}  // namespace climbsim::reflex
