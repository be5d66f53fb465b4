// DelayLine and DelayToSamples: the delay is exact, in whole control periods.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "reflex/reflex.h"

namespace climbsim::reflex {
namespace {

// A unit step pushed at update k0 appears at update k0 + n, not one sample early or late.
TEST(ReflexDelayLine, StepAppearsAfterExactlyDelaySamples) {
  for (int n : {0, 1, 2, 3, 5, 17, 100}) {
    DelayLine line(n, 0.0);
    const int k0 = 4;
    for (int k = 0; k < k0 + n + 10; ++k) {
      const double y = line.Update(k >= k0 ? 1.0 : 0.0);
      EXPECT_EQ(y, k >= k0 + n ? 1.0 : 0.0) << "n = " << n << ", k = " << k;
    }
  }
}

// The output is bit for bit the input n samples ago, and the fill before that.
TEST(ReflexDelayLine, OutputIsTheInputDelaySamplesAgo) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (int n : {0, 1, 4, 9}) {
    DelayLine line(n, -2.5);
    std::vector<double> inputs;
    for (int k = 0; k < 200; ++k) {
      inputs.push_back(noise(rng));
      const double y = line.Update(inputs.back());
      EXPECT_EQ(y, k >= n ? inputs[k - n] : -2.5) << "n = " << n << ", k = " << k;
    }
  }
}

TEST(ReflexDelayLine, ResetRestoresTheFill) {
  DelayLine line(3, 0.25);
  for (int k = 0; k < 10; ++k) line.Update(k);
  line.Reset();
  EXPECT_EQ(line.Update(9.0), 0.25);
  EXPECT_EQ(line.Update(9.0), 0.25);
  EXPECT_EQ(line.Update(9.0), 0.25);
  EXPECT_EQ(line.Update(1.0), 9.0);
  EXPECT_EQ(line.delay_samples(), 3);
}

TEST(ReflexDelayLine, RejectsNegativeOrHugeDelays) {
  EXPECT_THROW(DelayLine(-1), std::invalid_argument);
  EXPECT_THROW(DelayLine(kMaxDelaySamples + 1, 0.0), std::invalid_argument);
  EXPECT_NO_THROW(DelayLine(kMaxDelaySamples, 0.0));
}

// Rounded to nearest, ties away from zero. Values chosen exact in binary where it matters.
TEST(ReflexDelayToSamples, RoundsToTheNearestSample) {
  EXPECT_EQ(DelayToSamples(0.0, 0.001), 0);
  EXPECT_EQ(DelayToSamples(0.5, 0.125), 4);     // exact multiple
  EXPECT_EQ(DelayToSamples(0.3125, 0.125), 3);  // 2.5 exactly: tie goes up
  EXPECT_EQ(DelayToSamples(0.3, 0.125), 2);     // 2.4
  EXPECT_EQ(DelayToSamples(0.35, 0.125), 3);    // 2.8
  EXPECT_EQ(DelayToSamples(0.0625, 0.125), 1);  // half a period: one sample
  EXPECT_EQ(DelayToSamples(0.05, 0.125), 0);    // less than half: none
  // Geyer and Herr's 20/10/5 ms at 1 ms, and their 5 ms at 2 ms (2.5 samples -> 3).
  EXPECT_EQ(DelayToSamples(0.020, 0.001), 20);
  EXPECT_EQ(DelayToSamples(0.010, 0.001), 10);
  EXPECT_EQ(DelayToSamples(0.005, 0.001), 5);
  EXPECT_EQ(DelayToSamples(0.005, 0.002), 3);
  EXPECT_EQ(DelayToSamples(0.01, 0.002), 5);
}

TEST(ReflexDelayToSamples, RejectsBadDelaysAndPeriods) {
  EXPECT_THROW(DelayToSamples(-0.001, 0.001), std::invalid_argument);
  EXPECT_THROW(DelayToSamples(std::nan(""), 0.001), std::invalid_argument);
  EXPECT_THROW(DelayToSamples(INFINITY, 0.001), std::invalid_argument);
  EXPECT_THROW(DelayToSamples(0.01, 0.0), std::invalid_argument);
  EXPECT_THROW(DelayToSamples(0.01, -0.001), std::invalid_argument);
  EXPECT_THROW(DelayToSamples(0.01, std::nan("")), std::invalid_argument);
  EXPECT_THROW(DelayToSamples(100.0, 0.001), std::invalid_argument);  // 1e5 > kMaxDelaySamples
}

}  // namespace
}  // namespace climbsim::reflex
