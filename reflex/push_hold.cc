#include "reflex/push_hold.h"

#include <algorithm>

#include "reflex/check.h"

namespace climbsim::reflex {

PushHold::PushHold(int legs, double max_hold_s, double dt_s)
    : pushed_(legs, 0),
      posture_(legs, 0),
      max_periods_(internal::DurationToSamples("", max_hold_s, dt_s, false)) {}

void PushHold::SetLeg(int i, bool pushed, bool planted) {
  pushed_[i] = pushed;
  if (!planted) posture_[i] = 0;
}

bool PushHold::Update() {
  const bool pushed = std::find(pushed_.begin(), pushed_.end(), 1) != pushed_.end();
  run_ = pushed ? std::min(run_, max_periods_) + 1 : 0;
  const bool posture = max_periods_ > 0 && run_ > max_periods_;
  bool holds = false;
  for (size_t i = 0; i < pushed_.size(); ++i) {
    posture_[i] |= posture && pushed_[i];
    holds |= pushed_[i] && !posture_[i];
  }
  return holds;
}

void PushHold::Reset() {
  std::fill(pushed_.begin(), pushed_.end(), 0);
  std::fill(posture_.begin(), posture_.end(), 0);
  run_ = 0;
}

}  // namespace climbsim::reflex
