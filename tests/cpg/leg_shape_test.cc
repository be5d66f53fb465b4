// ShapeLeg: phase → stride, lift and joint targets, for any duty factor.
#include <gtest/gtest.h>

#include <cmath>

#include "cpg/cpg.h"
#include "tests/cpg/test_util.h"

namespace climbsim::cpg {
namespace {

using testing::kPi;
using testing::kTwoPi;

LegShape Shape(double duty_factor) {
  LegShape shape;
  shape.duty_factor = duty_factor;
  shape.stride_rad = {0.4, -0.2, 0.1};
  shape.lift_rad = {0.0, 0.5, -0.7};
  return shape;
}

constexpr double kDutyFactors[] = {0.5, 2.0 / 3, 0.75, 5.0 / 6, 0.2};

TEST(CpgLegShape, StanceShareOfTheCycleIsTheDutyFactor) {
  for (double duty : kDutyFactors) {
    const LegShape shape = Shape(duty);
    // Cell-centred samples of [0, 2π): the share is exact to one sample, 1/N.
    const int samples = 100000;
    int stance = 0;
    for (int k = 0; k < samples; ++k) {
      stance += ShapeLeg(shape, kTwoPi * (k + 0.5) / samples, 1.0).stance ? 1 : 0;
    }
    EXPECT_NEAR(static_cast<double>(stance) / samples, duty, 1.0 / samples) << duty;
    // And the boundary sits where the convention says: swing [0, 2π(1−D)), stance after.
    const double boundary = kTwoPi * (1.0 - duty);
    EXPECT_FALSE(ShapeLeg(shape, 0.0, 1.0).stance);
    EXPECT_FALSE(ShapeLeg(shape, std::nextafter(boundary, 0.0), 1.0).stance);
    EXPECT_TRUE(ShapeLeg(shape, boundary, 1.0).stance);
    EXPECT_TRUE(ShapeLeg(shape, std::nextafter(kTwoPi, 0.0), 1.0).stance);
  }
}

TEST(CpgLegShape, StrideAndLiftAreContinuousAtBothTransitions) {
  for (double duty : kDutyFactors) {
    const LegShape shape = Shape(duty);
    const double boundary = kTwoPi * (1.0 - duty);
    const double eps = 1e-9;
    // Touch-down (swing → stance): stride +1 on both sides, lift 0. The stride's slope is
    // bounded (≤ π/(2·2π(1−D)) per rad in swing, 1/(πD) in stance), so over 2·eps it moves
    // ≤ ~1e-9; lift ~ (π·eps/boundary)², far smaller.
    const LegCommand before_td = ShapeLeg(shape, boundary - eps, 1.0);
    const LegCommand after_td = ShapeLeg(shape, boundary + eps, 1.0);
    EXPECT_NEAR(before_td.stride, 1.0, 1e-8);
    EXPECT_NEAR(after_td.stride, 1.0, 1e-8);
    EXPECT_NEAR(before_td.lift, 0.0, 1e-15);
    EXPECT_EQ(after_td.lift, 0.0);
    // Lift-off (stance → swing, across θ = 2π ≡ 0): stride −1 on both sides.
    const LegCommand before_lo = ShapeLeg(shape, kTwoPi - eps, 1.0);
    const LegCommand after_lo = ShapeLeg(shape, eps, 1.0);
    EXPECT_NEAR(before_lo.stride, -1.0, 1e-8);
    EXPECT_NEAR(after_lo.stride, -1.0, 1e-8);
    EXPECT_NEAR(after_lo.lift, 0.0, 1e-15);
    // The joint targets follow.
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(before_td.joint_rad[k], after_td.joint_rad[k], 1e-8);
      EXPECT_NEAR(before_lo.joint_rad[k], after_lo.joint_rad[k], 1e-8);
    }
  }
}

TEST(CpgLegShape, StanceIsFlatOnTheGroundAndLinearInPhase) {
  for (double duty : kDutyFactors) {
    const LegShape shape = Shape(duty);
    const double start = kTwoPi * (1.0 - duty);
    for (int k = 0; k < 1000; ++k) {
      const double q = k / 1000.0;
      const LegCommand c = ShapeLeg(shape, start + q * kTwoPi * duty, 1.0);
      ASSERT_TRUE(c.stance);
      EXPECT_EQ(c.lift, 0.0);
      // Linear: constant foot speed on the ground, 2/(2πD) of stride per rad.
      EXPECT_NEAR(c.stride, 1.0 - 2.0 * q, 1e-12);
      EXPECT_NEAR(c.progress, q, 1e-12);
    }
  }
}

TEST(CpgLegShape, SwingRisesAndLandsWithZeroSpeed) {
  const LegShape shape = Shape(0.75);
  const double swing = kTwoPi * 0.25;
  const LegCommand top = ShapeLeg(shape, swing / 2, 1.0);
  EXPECT_NEAR(top.lift, 1.0, 1e-15);
  EXPECT_NEAR(top.stride, 0.0, 1e-15);
  EXPECT_NEAR(top.progress, 0.5, 1e-15);
  // Slope of lift and stride at the ends: central differences ~ O(h), zero in the limit.
  const double h = 1e-6;
  EXPECT_NEAR((ShapeLeg(shape, h, 1.0).lift - ShapeLeg(shape, 0.0, 1.0).lift) / h, 0.0, 1e-4);
  EXPECT_NEAR((ShapeLeg(shape, swing, 1.0).stride - ShapeLeg(shape, swing - h, 1.0).stride) / h,
              0.0, 1e-4);
}

TEST(CpgLegShape, JointTargetsEqualTheFormula) {
  const LegShape shape = Shape(2.0 / 3);
  for (double theta : {-1.0, 0.0, 0.7, 2.0, 3.0, 4.5, 6.0, 9.0}) {
    for (double amplitude : {0.0, 0.6, 1.0, 1.4}) {
      const LegCommand c = ShapeLeg(shape, theta, amplitude);
      // The profile, recomputed here from the documented formula.
      const double wrapped = theta - kTwoPi * std::floor(theta / kTwoPi);
      const double s = kTwoPi / 3;
      const bool stance = wrapped >= s;
      const double stride =
          stance ? 1.0 - 2.0 * (wrapped - s) / (kTwoPi * 2.0 / 3) : -std::cos(kPi * wrapped / s);
      const double lift = stance ? 0.0 : std::pow(std::sin(kPi * wrapped / s), 2);
      EXPECT_EQ(c.stance, stance) << theta;
      EXPECT_NEAR(c.stride, stride, 1e-12) << theta;
      EXPECT_NEAR(c.lift, lift, 1e-12) << theta;
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(c.joint_rad[k],
                    amplitude * stride * shape.stride_rad[k] + lift * shape.lift_rad[k], 1e-12);
      }
    }
  }
}

// Lift–move–place: with a = 0.2 of the swing to rise and to land, the foot stays at the back
// of its stride while it rises (p ≤ a), is fully lifted while it moves (a ≤ p ≤ 1 − a), and
// is at the front while it lands; both curves are continuous through the swing.
TEST(CpgLegShape, LiftMovePlaceSwingRisesBeforeItMoves) {
  LegShape shape;
  shape.duty_factor = 0.75;
  shape.lift_share = 0.2;
  const double swing_end = 2 * M_PI * 0.25;
  double last_stride = -1.0, last_lift = 0.0;
  for (int i = 0; i <= 1000; ++i) {
    const double p = i / 1000.0;
    const LegCommand c = ShapeLeg(shape, std::fmin(p, 0.999999) * swing_end, 1.0);
    if (p <= 0.2) {
      EXPECT_EQ(c.stride, -1.0) << p;
    }
    if (p >= 0.2 && p <= 0.8) {
      EXPECT_EQ(c.lift, 1.0) << p;
    }
    if (p >= 0.8) {
      EXPECT_NEAR(c.stride, 1.0, 1e-12) << p;
    }
    // Continuous: steps of 1/1000 of the swing move by at most 1.5/(1000·0.2) (r' ≤ 1.5).
    EXPECT_LE(std::abs(c.stride - last_stride), 2 * 1.5 / (1000 * 0.6) + 1e-12) << p;
    EXPECT_LE(std::abs(c.lift - last_lift), 1.5 / (1000 * 0.2) + 1e-12) << p;
    last_stride = c.stride;
    last_lift = c.lift;
  }
  EXPECT_NEAR(ShapeLeg(shape, 0.0, 1.0).lift, 0.0, 1e-15);
  EXPECT_NEAR(ShapeLeg(shape, 0.1 * swing_end, 1.0).lift, 0.5, 1e-15);  // r(1/2) = 1/2
  shape.lift_share = 0.5;
  EXPECT_THROW(ShapeLeg(shape, 0.0, 1.0), std::invalid_argument);
}

TEST(CpgLegShape, BadShapeThrows) {
  EXPECT_THROW(ShapeLeg(Shape(0.0), 1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(ShapeLeg(Shape(1.0), 1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(ShapeLeg(Shape(0.5), std::nan(""), 1.0), std::invalid_argument);
  LegShape bad = Shape(0.5);
  bad.lift_rad[1] = INFINITY;
  EXPECT_THROW(ValidateLegShape(bad), std::invalid_argument);
  EXPECT_NO_THROW(ValidateLegShape(Shape(0.5)));
}

}  // namespace
}  // namespace climbsim::cpg
