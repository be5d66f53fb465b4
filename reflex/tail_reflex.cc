#include "reflex/tail_reflex.h"

#include <cmath>

#include "reflex/check.h"

namespace climbsim::reflex {
namespace {

const TailReflexParams& Validated(const TailReflexParams& params, double dt_s) {
  internal::CheckPeriod(dt_s);
  keys::Validate(params, "tail");
  CheckTailControlPeriod(params, dt_s, internal::ThrowingChecker("tail"), "");
  return params;
}

int DelaySamples(double delay_s, double dt_s) {
  return static_cast<int>(std::lround(delay_s / dt_s));
}

}  // namespace

std::string_view TailEventName(TailEventType type) {
  switch (type) {
    case TailEventType::kPress:
      return "tail_press";
    case TailEventType::kRelease:
      return "tail_release";
    case TailEventType::kNone:
      break;
  }
  return "";
}

std::string_view TailTriggerName(TailTrigger trigger) {
  switch (trigger) {
    case TailTrigger::kFrontPadLoss:
      return "front_pad_lost";
    case TailTrigger::kPitch:
      return "pitch";
    case TailTrigger::kNone:
      break;
  }
  return "";
}

void CheckTailControlPeriod(const TailReflexParams& params, double dt_s, const Checker& checker,
                            std::string_view prefix) {
  const std::string at(prefix);
  if (const std::string p = internal::DelayProblem(params.delay_s, dt_s); !p.empty()) {
    checker.Fail(at + "delay_s", p);
  }
  if (const std::string p = internal::DurationProblem(params.hold_s, dt_s, true); !p.empty()) {
    checker.Fail(at + "hold_s", p);
  }
  if (const std::string p = internal::DurationProblem(params.ease_s, dt_s, false); !p.empty()) {
    checker.Fail(at + "ease_s", p);
  }
}

TailReflex::TailReflex(const TailReflexParams& params, double dt_s)
    : params_(Validated(params, dt_s)),
      pad_lost_(DelaySamples(params.delay_s, dt_s)),
      pitch_(DelaySamples(params.delay_s, dt_s)),
      hold_samples_(internal::DurationToSamples("tail.hold_s", params.hold_s, dt_s, true)),
      ease_samples_(internal::DurationToSamples("tail.ease_s", params.ease_s, dt_s, false)) {}

void TailReflex::Reset() {
  pad_lost_.Reset();
  pitch_.Reset();
  hold_left_ = ease_left_ = side_ = 0;
}

// Trigger (delayed) → press, held hold_s after the last trigger → release: a linear ramp
// back to rest over ease_s. A trigger during the ramp presses again.
TailOutput TailReflex::Update(const TailSensing& in) {
  const int side = in.lost_side >= 0 ? 1 : -1;
  const double lost_side =
      pad_lost_.Update(in.front_pad_lost && params_.on_front_pad_loss ? side : 0.0);
  const bool lost = std::abs(lost_side) > 0.5;
  const bool pitched = pitch_.Update(in.pitch_rad) > params_.pitch_threshold_rad;
  TailOutput out;
  if (lost) side_ = lost_side > 0 ? 1 : -1;
  if (lost || pitched) {
    if (hold_left_ == 0) {
      out.event = TailEventType::kPress;
      out.trigger = lost ? TailTrigger::kFrontPadLoss : TailTrigger::kPitch;
    }
    hold_left_ = hold_samples_;
    ease_left_ = 0;
  } else if (hold_left_ > 0 && --hold_left_ == 0) {
    out.event = TailEventType::kRelease;
    ease_left_ = ease_samples_;
    if (ease_left_ == 0) side_ = 0;
  } else if (ease_left_ > 0 && --ease_left_ == 0) {
    side_ = 0;
  }
  double press = 0.0;
  if (hold_left_ > 0) {
    press = 1.0;
  } else if (ease_left_ > 0) {
    press = static_cast<double>(ease_left_) / ease_samples_;
  }
  // Exact at either end: the press and the rest commands as given.
  out.command_rad = press * params_.press_rad + (1.0 - press) * params_.rest_rad;
  out.yaw_command_rad = press * side_ * params_.yaw_rad;
  return out;
}

}  // namespace climbsim::reflex
