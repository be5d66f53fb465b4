// Bad Params are rejected at construction with std::invalid_argument naming the key (as
// each struct's Serialize declares it) and the value (STYLE.md §5).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>

#include "reflex/reflex.h"

namespace climbsim::reflex {
namespace {

// Runs `construct`, expects std::invalid_argument, returns its message.
std::string ErrorOf(const std::function<void()>& construct) {
  try {
    construct();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  ADD_FAILURE() << "no std::invalid_argument thrown";
  return "";
}

TEST(ReflexParams, DefaultsAreValid) {
  EXPECT_NO_THROW(SpindleReflex(SpindleParams{}, 0.001));
  EXPECT_NO_THROW(GtoReflex(GtoParams{}, 0.001));
  EXPECT_NO_THROW(LegReflex(LegReflexParams{}, 0.001));
  EXPECT_NO_THROW(LegReflex(LegReflexParams{}, 0.002));
  EXPECT_NO_THROW(LegReflex(LegReflexParams{}, 0.01));
}

TEST(ReflexParams, SpindleRejectsNegativeGainsThresholdsDelaysAndNonFinite) {
  SpindleParams p;
  p.length_gain = -1.0;
  EXPECT_EQ(ErrorOf([&] { SpindleReflex(p, 0.001); }),
            "spindle.length_gain must be >= 0, got -1");
  p = {};
  p.velocity_gain_s = NAN;
  EXPECT_EQ(ErrorOf([&] { SpindleReflex(p, 0.001); }),
            "spindle.velocity_gain_s must be >= 0, got nan");
  p = {};
  p.length_threshold_rad = -0.1;
  EXPECT_EQ(ErrorOf([&] { SpindleReflex(p, 0.001); }),
            "spindle.length_threshold_rad must be >= 0, got -0.1");
  p = {};
  p.velocity_threshold_rad_per_s = INFINITY;
  EXPECT_EQ(ErrorOf([&] { SpindleReflex(p, 0.001); }),
            "spindle.velocity_threshold_rad_per_s must be >= 0, got inf");
  p = {};
  p.delay_s = -0.02;
  EXPECT_EQ(ErrorOf([&] { SpindleReflex(p, 0.001); }),
            "spindle.delay_s must be >= 0, got -0.02");
  p = {};
  EXPECT_EQ(ErrorOf([&] { SpindleReflex(p, 0.0); }), "dt_s must be finite and > 0, got 0");
}

TEST(ReflexParams, GtoRejectsNonFiniteAndNegativeDelayButAllowsNegativeGain) {
  EXPECT_NO_THROW(GtoReflex(GtoParams{.gain = -1.0, .threshold = -0.5, .delay_s = 0.0}, 0.001));
  EXPECT_EQ(ErrorOf([] { GtoReflex(GtoParams{.gain = NAN}, 0.001); }),
            "gto.gain must be finite, got nan");
  EXPECT_EQ(ErrorOf([] { GtoReflex(GtoParams{.threshold = -INFINITY}, 0.001); }),
            "gto.threshold must be finite, got -inf");
  EXPECT_EQ(ErrorOf([] { GtoReflex(GtoParams{.delay_s = -1.0}, 0.001); }),
            "gto.delay_s must be >= 0, got -1");
  EXPECT_EQ(ErrorOf([] { GtoReflex(GtoParams{.delay_s = 20.0}, 0.001); }),
            "gto.delay_s must be at most 10000 control periods (dt_s = 0.001 s), got 20");
}

// The leg's messages carry the path of the field, as a scenario file would spell it.
TEST(ReflexParams, LegReflexNamesTheFieldAndTheValue) {
  const auto error = [](const std::function<void(LegReflexParams&)>& spoil) {
    LegReflexParams p;
    spoil(p);
    return ErrorOf([&] { LegReflex(p, 0.002); });
  };
  EXPECT_EQ(error([](auto& p) { p.preload.hip_pitch_press_rad = -0.1; }),
            "leg_reflex.preload.hip_pitch_press_rad must be >= 0, got -0.1");
  EXPECT_EQ(error([](auto& p) { p.preload.force_limit_n = 0.0; }),
            "leg_reflex.preload.force_limit_n must be > 0, got 0");
  EXPECT_EQ(error([](auto& p) { p.preload.max_duration_s = 0.0005; }),
            "leg_reflex.preload.max_duration_s must be at least one control period "
            "(dt_s = 0.002 s), got 0.0005");
  EXPECT_EQ(error([](auto& p) { p.preload.ramp_s = NAN; }),
            "leg_reflex.preload.ramp_s must be >= 0, got nan");
  EXPECT_EQ(error([](auto& p) { p.search.max_attempts = 0; }),
            "leg_reflex.search.max_attempts must be in [1, 1000], got 0");
  EXPECT_EQ(error([](auto& p) { p.search.reach_pitch_rad = -0.2; }),
            "leg_reflex.search.reach_pitch_rad must be >= 0, got -0.2");
  EXPECT_EQ(error([](auto& p) { p.search.attempt_duration_s = 0.0; }),
            "leg_reflex.search.attempt_duration_s must be > 0, got 0");
  EXPECT_EQ(error([](auto& p) { p.peel.ramp_s = 0.0; }),
            "leg_reflex.peel.ramp_s must be > 0, got 0");
  EXPECT_EQ(error([](auto& p) { p.peel.hip_yaw_rad = NAN; }),
            "leg_reflex.peel.hip_yaw_rad must be finite, got nan");
  EXPECT_EQ(error([](auto& p) { p.peel.knee_lift_rad = INFINITY; }),
            "leg_reflex.peel.knee_lift_rad must be >= 0, got inf");
  EXPECT_EQ(error([](auto& p) { p.regrip.hold_others_s = -0.2; }),
            "leg_reflex.regrip.hold_others_s must be >= 0, got -0.2");
  EXPECT_EQ(error([](auto& p) { p.gto.hold.gain = -0.2; }),
            "leg_reflex.gto.hold_gain_rad_per_n must be >= 0, got -0.2");
  EXPECT_EQ(error([](auto& p) { p.gto.press.delay_s = -0.01; }),
            "leg_reflex.gto.press_delay_s must be >= 0, got -0.01");
  EXPECT_EQ(error([](auto& p) { p.gto.full_bond_fraction = 1.5; }),
            "leg_reflex.gto.full_bond_fraction must be in (0, 1], got 1.5");
  EXPECT_EQ(error([](auto& p) { p.spindle.joints[kKnee].length_gain = -0.5; }),
            "leg_reflex.spindle.joints[2].length_gain must be >= 0, got -0.5");
  EXPECT_EQ(error([](auto& p) { p.max_offset_rad = 0.0; }),
            "leg_reflex.max_offset_rad must be > 0, got 0");
  // The closed-chain reflexes.
  EXPECT_EQ(error([](auto& p) { p.gto.unload.gain = -1.0; }),
            "leg_reflex.gto.unload_gain must be >= 0, got -1");
  EXPECT_EQ(error([](auto& p) { p.gto.unload_min_kp_fraction = 0.0; }),
            "leg_reflex.gto.unload_min_kp_fraction must be in (0, 1], got 0");
  EXPECT_EQ(error([](auto& p) { p.gto.support.delay_s = -0.01; }),
            "leg_reflex.gto.support_delay_s must be >= 0, got -0.01");
  EXPECT_EQ(error([](auto& p) { p.spindle.swing_threshold_rad = -0.1; }),
            "leg_reflex.spindle.swing_threshold_rad must be >= 0, got -0.1");
  EXPECT_EQ(error([](auto& p) { p.spindle.stance_band_rad = NAN; }),
            "leg_reflex.spindle.stance_band_rad must be >= 0, got nan");
  EXPECT_EQ(error([](auto& p) { p.spindle.hold_s = -0.2; }),
            "leg_reflex.spindle.hold_s must be >= 0, got -0.2");
  EXPECT_EQ(error([](auto& p) { p.compliance.stance_kp_fraction = 1.5; }),
            "leg_reflex.compliance.stance_kp_fraction must be in (0, 1], got 1.5");
  EXPECT_EQ(error([](auto& p) { p.compliance.ramp_s = -0.02; }),
            "leg_reflex.compliance.ramp_s must be >= 0, got -0.02");
}

// A switched-off reflex is still validated: Params are checked as a whole, once.
TEST(ReflexParams, DisabledReflexesAreValidatedToo) {
  LegReflexParams p;
  p.peel.enabled = false;
  p.peel.knee_lift_rad = -1.0;
  EXPECT_THROW(LegReflex(p, 0.002), std::invalid_argument);
}

}  // namespace
}  // namespace climbsim::reflex
