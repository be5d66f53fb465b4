// The tail reflex's law (reflex/tail_reflex.h): a trigger presses after exactly the delay,
// the press holds hold_s after the last trigger, then ramps back to rest over ease_s.
#include "reflex/tail_reflex.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace climbsim::reflex {
namespace {

constexpr double kTailDt = 0.01;

TailReflexParams TailParams() {
  TailReflexParams p;
  p.rest_rad = -0.1;
  p.press_rad = 0.3;
  p.pitch_threshold_rad = 0.05;
  p.delay_s = 0.02;  // 2 ticks
  p.hold_s = 0.05;   // 5 ticks
  p.ease_s = 0.04;   // 4 ticks
  return p;
}

// A front pad lost at tick 0: rest for the 2 delay ticks, the press (one event) from tick 2,
// held 5 ticks, the release at tick 7, then 4 ticks of a linear ramp back to rest.
TEST(ReflexTail, PadLossPressesAfterTheDelayHoldsAndEasesBack) {
  TailReflex tail(TailParams(), kTailDt);
  std::vector<TailOutput> out;
  for (int k = 0; k < 14; ++k) out.push_back(tail.Update({.front_pad_lost = k == 0}));
  EXPECT_EQ(out[0].command_rad, -0.1);
  EXPECT_EQ(out[1].command_rad, -0.1);
  EXPECT_EQ(out[2].event, TailEventType::kPress);
  EXPECT_EQ(out[2].trigger, TailTrigger::kFrontPadLoss);
  for (int k = 2; k < 7; ++k) EXPECT_EQ(out[k].command_rad, 0.3) << k;
  EXPECT_EQ(out[7].event, TailEventType::kRelease);
  for (int k = 8; k < 11; ++k) {
    EXPECT_NEAR(out[k].command_rad, -0.1 + 0.4 * (11 - k) / 4.0, 1e-12) << k;
  }
  EXPECT_EQ(out[11].command_rad, -0.1);
  int events = 0;
  for (const TailOutput& o : out) events += o.event != TailEventType::kNone;
  EXPECT_EQ(events, 2);
}

// A pitch beyond the threshold presses for as long as it lasts (one press event) and hold_s
// after; a pitch at the threshold does not; on_front_pad_loss false ignores a lost pad.
TEST(ReflexTail, PitchHoldsThePressWhileItLasts) {
  TailReflexParams p = TailParams();
  p.on_front_pad_loss = false;
  TailReflex tail(p, kTailDt);
  int presses = 0, pressing_ticks = 0;
  for (int k = 0; k < 40; ++k) {
    const double pitch = k < 5 ? 0.05 : (k < 20 ? 0.06 : 0.0);
    const TailOutput o = tail.Update({.front_pad_lost = true, .pitch_rad = pitch});
    presses += o.event == TailEventType::kPress;
    if (o.command_rad == p.press_rad) ++pressing_ticks;
    if (o.event == TailEventType::kPress) {
      EXPECT_EQ(o.trigger, TailTrigger::kPitch);
    }
  }
  EXPECT_EQ(presses, 1);
  // Pitched from tick 5 to 19, seen 2 ticks late (7 to 21), held 5 ticks more, and the first
  // tick of the ease still at full press.
  EXPECT_EQ(pressing_ticks, 15 + 5);
}

// yaw_rad: a pad loss on the right (-1) swings the tip right by yaw_rad with the press, and
// back with the ramp; a pitch press alone (no pad lost) does not swing it.
TEST(ReflexTail, PadLossSwingsTheTipTowardsTheLostSide) {
  TailReflexParams p = TailParams();
  p.yaw_rad = 0.4;
  TailReflex tail(p, kTailDt);
  std::vector<TailOutput> out;
  for (int k = 0; k < 14; ++k) {
    out.push_back(tail.Update({.front_pad_lost = k == 0, .lost_side = -1}));
  }
  EXPECT_EQ(out[1].yaw_command_rad, 0.0);
  for (int k = 2; k < 8; ++k) EXPECT_EQ(out[k].yaw_command_rad, -0.4) << k;
  EXPECT_NEAR(out[9].yaw_command_rad, -0.4 * 2 / 4.0, 1e-12);
  EXPECT_EQ(out[11].yaw_command_rad, 0.0);
  TailReflex pitched(p, kTailDt);
  for (int k = 0; k < 10; ++k) {
    EXPECT_EQ(pitched.Update({.pitch_rad = 0.2}).yaw_command_rad, 0.0) << k;
  }
}

TEST(ReflexTail, RejectsAHoldShorterThanHalfAPeriod) {
  TailReflexParams p = TailParams();
  p.hold_s = 0.001;
  EXPECT_THROW(TailReflex(p, kTailDt), std::invalid_argument);
  p = TailParams();
  p.press_rad = 2.0;
  EXPECT_THROW(TailReflex(p, kTailDt), std::invalid_argument);
}

}  // namespace
}  // namespace climbsim::reflex
