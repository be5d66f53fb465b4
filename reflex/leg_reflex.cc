// Leg-level climbing reflex state machine (the table is in reflex.h).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "reflex/check.h"
#include "reflex/reflex.h"

namespace climbsim::reflex {
namespace {

using internal::CheckFinite;
using internal::CheckNonNegative;
using internal::CheckPositive;
using internal::CheckRange;
using internal::DurationToSamples;
using internal::FieldPath;

double Sanitize(double x, int64_t* count) {
  if (std::isfinite(x)) return x;
  ++*count;
  return 0.0;
}

void Emit(LegReflexOutput* out, LegEventType type, LegEventReason reason = LegEventReason::kNone) {
  // Each type is emitted at most once per Update, so this never overflows (tested).
  if (out->events.count < kMaxLegEvents) out->events.items[out->events.count++] = {type, reason};
}

void Fire(LegReflexOutput* out, Reflex reflex) { out->fired |= 1u << static_cast<int>(reflex); }

const LegReflexParams& Validated(const LegReflexParams& params, double dt_s) {
  Validate(params, dt_s);
  return params;
}

}  // namespace

void Validate(const LegReflexParams& params, double dt_s, std::string_view name) {
  internal::CheckPeriod(dt_s);

  // Preload.
  const std::string preload = FieldPath(name, "preload");
  CheckNonNegative(FieldPath(preload, "hip_pitch_press_rad"), params.preload.hip_pitch_press_rad);
  CheckNonNegative(FieldPath(preload, "knee_press_rad"), params.preload.knee_press_rad);
  DurationToSamples(FieldPath(preload, "ramp_s"), params.preload.ramp_s, dt_s, false);
  CheckPositive(FieldPath(preload, "force_limit_n"), params.preload.force_limit_n);
  DurationToSamples(FieldPath(preload, "max_duration_s"), params.preload.max_duration_s, dt_s,
                    true);

  // Search.
  const std::string search = FieldPath(name, "search");
  CheckNonNegative(FieldPath(search, "reach_yaw_rad"), params.search.reach_yaw_rad);
  CheckNonNegative(FieldPath(search, "reach_pitch_rad"), params.search.reach_pitch_rad);
  CheckNonNegative(FieldPath(search, "reach_knee_rad"), params.search.reach_knee_rad);
  CheckNonNegative(FieldPath(search, "lift_rad"), params.search.lift_rad);
  const int attempt = DurationToSamples(FieldPath(search, "attempt_duration_s"),
                                        params.search.attempt_duration_s, dt_s, true);
  CheckRange(FieldPath(search, "max_attempts"), params.search.max_attempts, 1, 1000);
  if (static_cast<double>(attempt) * params.search.max_attempts > 1e8) {
    internal::ThrowInvalid(FieldPath(search, "max_attempts"),
                           "such that max_attempts * attempt_duration_s <= 1e8 control periods",
                           params.search.max_attempts);
  }
  DurationToSamples(FieldPath(search, "release_s"), params.search.release_s, dt_s, false);

  // Peel.
  const std::string peel = FieldPath(name, "peel");
  CheckFinite(FieldPath(peel, "hip_yaw_rad"), params.peel.hip_yaw_rad);
  CheckNonNegative(FieldPath(peel, "hip_pitch_lift_rad"), params.peel.hip_pitch_lift_rad);
  CheckNonNegative(FieldPath(peel, "knee_lift_rad"), params.peel.knee_lift_rad);
  CheckPositive(FieldPath(peel, "ramp_s"), params.peel.ramp_s);
  DurationToSamples(FieldPath(peel, "max_duration_s"), params.peel.max_duration_s, dt_s, true);
  DurationToSamples(FieldPath(peel, "release_s"), params.peel.release_s, dt_s, false);

  // Re-grip.
  DurationToSamples(FieldPath(FieldPath(name, "regrip"), "hold_others_s"),
                    params.regrip.hold_others_s, dt_s, false);

  // GTO stance holding: both channels are positive force feedback.
  const std::string gto = FieldPath(name, "gto");
  Validate(params.gto.hold, dt_s, FieldPath(gto, "hold"));
  CheckNonNegative(FieldPath(gto, "hold.gain"), params.gto.hold.gain);
  CheckNonNegative(FieldPath(gto, "hold_max_offset_rad"), params.gto.hold_max_offset_rad);
  Validate(params.gto.press, dt_s, FieldPath(gto, "press"));
  CheckNonNegative(FieldPath(gto, "press.gain"), params.gto.press.gain);
  CheckNonNegative(FieldPath(gto, "press_max_offset_rad"), params.gto.press_max_offset_rad);
  CheckRange(FieldPath(gto, "full_bond_fraction"), params.gto.full_bond_fraction, 0.0, 1.0, true);

  // Spindles.
  for (int j = 0; j < kLegJoints; ++j) {
    Validate(params.spindle.joints[j], dt_s,
             FieldPath(name, "spindle.joints[" + std::to_string(j) + "]"));
  }

  CheckPositive(FieldPath(name, "max_offset_rad"), params.max_offset_rad);
}

LegReflex::LegReflex(const LegReflexParams& params, double dt_s)
    : params_(Validated(params, dt_s)),
      dt_s_(dt_s),
      preload_ramp_samples_(DurationToSamples("", params.preload.ramp_s, dt_s, false)),
      preload_max_samples_(DurationToSamples("", params.preload.max_duration_s, dt_s, true)),
      search_attempt_samples_(DurationToSamples("", params.search.attempt_duration_s, dt_s, true)),
      search_release_samples_(DurationToSamples("", params.search.release_s, dt_s, false)),
      regrip_samples_(DurationToSamples("", params.regrip.hold_others_s, dt_s, false)),
      peel_max_samples_(DurationToSamples("", params.peel.max_duration_s, dt_s, true)),
      peel_release_samples_(DurationToSamples("", params.peel.release_s, dt_s, false)),
      hold_gto_(params.gto.hold, dt_s),
      press_gto_(params.gto.press, dt_s),
      spindles_{SpindleReflex(params.spindle.joints[0], dt_s),
                SpindleReflex(params.spindle.joints[1], dt_s),
                SpindleReflex(params.spindle.joints[2], dt_s)} {}

void LegReflex::Reset() {
  hold_gto_.Reset();
  press_gto_.Reset();
  for (SpindleReflex& spindle : spindles_) spindle.Reset();
  state_ = LegReflexState{};
}

LegReflexOutput LegReflex::Update(const LegSensing& sensing) {
  LegReflexOutput out;
  LegReflexState& st = state_;
  const LegReflexParams& p = params_;

  // Sensing, with non-finite values replaced by 0 and counted.
  int64_t* bad = &st.nonfinite_inputs;
  const bool stance = sensing.stance;
  Sanitize(sensing.phase_progress, bad);  // counted like every input; the peel runs on time
  const double bonded = std::clamp(Sanitize(sensing.bonded_fraction, bad), 0.0, 1.0);
  const double normal_load_n = Sanitize(sensing.normal_load_n, bad);
  const double preload_n = Sanitize(sensing.preload_n, bad);
  const bool swing_onset = st.prev_stance && !stance;
  const bool stance_onset = !st.prev_stance && stance;
  const bool touchdown = stance && sensing.touching && !(st.prev_stance && st.prev_touching);
  const bool attach_edge = sensing.attached && !st.prev_attached;

  // The laws run every period (when enabled) so that their delays stay exact.
  double hold_u = 0.0;
  double press_u = 0.0;
  if (p.gto.enabled) {
    const double hold_load_n =
        p.gto.count_compression ? std::max(std::abs(normal_load_n), preload_n) : normal_load_n;
    hold_u = hold_gto_.Update(hold_load_n);
    press_u = press_gto_.Update(preload_n);
  }
  Eigen::Vector3d spindle_rad = Eigen::Vector3d::Zero();
  if (p.spindle.enabled) {
    for (int j = 0; j < kLegJoints; ++j) {
      spindle_rad[j] = spindles_[j].Update(Sanitize(sensing.stretch_rad[j], bad),
                                           Sanitize(sensing.stretch_velocity_rad_per_s[j], bad));
    }
  }

  const auto start_release = [&] {
    st.search_holding = false;
    st.search_release_left = search_release_samples_;
  };

  // Swing onset ends the stance reflexes and starts a peel if the pad is still attached.
  if (swing_onset) {
    if (st.preloading) {
      st.preloading = false;
      Emit(&out, LegEventType::kPreloadEnd, LegEventReason::kSwingStarted);
    }
    if (st.searching) {
      st.searching = false;
      Emit(&out, LegEventType::kSearchEnd, LegEventReason::kSwingStarted);
      start_release();
    } else if (st.search_holding) {
      start_release();
    }
    if (p.peel.enabled && sensing.attached) {
      st.peeling = true;
      st.peel_samples = 0;
      st.peel_release_left = 0;
      Emit(&out, LegEventType::kPeel);
    }
  }

  // Preload limits, from the period after the start on.
  if (st.preloading) {
    ++st.preload_samples;
    LegEventReason reason = LegEventReason::kNone;
    if (attach_edge) {
      reason = LegEventReason::kAttached;
    } else if (preload_n >= p.preload.force_limit_n) {
      reason = LegEventReason::kForceLimit;
    } else if (st.preload_samples >= preload_max_samples_) {
      reason = LegEventReason::kTimeLimit;
    }
    if (reason != LegEventReason::kNone) {
      st.preloading = false;
      Emit(&out, LegEventType::kPreloadEnd, reason);
    }
  }

  // Search: found, or out of attempts; a new one at a stance onset without touchdown.
  if (st.searching) {
    ++st.search_samples;
    if (sensing.touching || sensing.attached) {
      st.searching = false;
      st.search_holding = true;  // keep the foot where it found the surface
      Emit(&out, LegEventType::kSearchEnd, LegEventReason::kFound);
    } else if (st.search_samples >= p.search.max_attempts * search_attempt_samples_) {
      st.searching = false;
      Emit(&out, LegEventType::kSearchEnd, LegEventReason::kAttemptsExhausted);
      start_release();
    }
  }
  if (p.search.enabled && stance_onset && !sensing.touching && !sensing.attached) {
    st.searching = true;
    st.search_samples = 0;
    st.search_holding = false;
    st.search_release_left = 0;
    st.search_offset_rad.setZero();
    Emit(&out, LegEventType::kSearchStart);
  }

  // Re-grip: bonds lost in stance by a pad that was holding. A new episode (no re-grip hold or
  // re-grip preload running) emits regrip and starts a preload; a running one is extended.
  if (p.regrip.enabled && stance && sensing.bonds_lost && st.prev_attached) {
    const bool regrip_preload = st.preloading && st.preload_trigger == LegEventReason::kRegrip;
    if (st.regrip_left == 0 && !regrip_preload) Emit(&out, LegEventType::kRegrip);
    st.regrip_left = regrip_samples_;
    if (!st.preloading) {
      st.preloading = true;
      st.preload_samples = 0;
      st.preload_trigger = LegEventReason::kRegrip;
      Emit(&out, LegEventType::kPreloadStart, LegEventReason::kRegrip);
    }
  }

  // Touchdown preload.
  if (p.preload.enabled && touchdown && !sensing.attached && !st.preloading) {
    st.preloading = true;
    st.preload_samples = 0;
    st.preload_trigger = LegEventReason::kTouchdown;
    Emit(&out, LegEventType::kPreloadStart, LegEventReason::kTouchdown);
  }

  // Offsets. Preload: linear ramp, (m + 1)/n_ramp of full at the m-th period.
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  if (st.preloading) {
    const double ramp = preload_ramp_samples_ == 0
                            ? 1.0
                            : std::min(1.0, (st.preload_samples + 1.0) / preload_ramp_samples_);
    offset[kHipPitch] -= p.preload.hip_pitch_press_rad * ramp;
    offset[kKnee] -= p.preload.knee_press_rad * ramp;
    Fire(&out, st.preload_trigger == LegEventReason::kRegrip ? Reflex::kRegrip : Reflex::kPreload);
  }

  // Search: reach ρ = m/(N·n_a) plus a lift bump sin(π·s) within each attempt.
  if (st.searching) {
    const int m = st.search_samples;
    const double rho = static_cast<double>(m) / (p.search.max_attempts * search_attempt_samples_);
    const double s = static_cast<double>(m % search_attempt_samples_) / search_attempt_samples_;
    const double lift = p.search.lift_rad * std::sin(std::numbers::pi * s);
    st.search_offset_rad = {p.search.reach_yaw_rad * rho, lift - p.search.reach_pitch_rad * rho,
                            lift - p.search.reach_knee_rad * rho};
    offset += st.search_offset_rad;
    Fire(&out, Reflex::kSearch);
  } else if (st.search_holding) {
    offset += st.search_offset_rad;
    Fire(&out, Reflex::kSearch);
  } else if (st.search_release_left > 0) {
    --st.search_release_left;
    if (st.search_release_left > 0) {
      offset += st.search_offset_rad *
                (static_cast<double>(st.search_release_left) / search_release_samples_);
      Fire(&out, Reflex::kSearch);
    }
  }

  // Peel: pull back and lift with a smooth step while the pad holds, the phase held; then
  // fade out. A stance (the CPG went on regardless) ends it too.
  if (st.peeling) {
    const double u = std::min(1.0, st.peel_samples * dt_s_ / p.peel.ramp_s);
    const double r = u * u * (3.0 - 2.0 * u);
    const Eigen::Vector3d peel(p.peel.hip_yaw_rad * r, p.peel.hip_pitch_lift_rad * r,
                               p.peel.knee_lift_rad * r);
    LegEventReason reason = LegEventReason::kNone;
    if (!sensing.attached || stance) {
      reason = LegEventReason::kDetached;
    } else if (st.peel_samples >= peel_max_samples_) {
      reason = LegEventReason::kTimeLimit;
    }
    if (reason == LegEventReason::kNone) {
      offset += peel;
      out.hold_phase = true;
      ++st.peel_samples;
    } else {
      st.peeling = false;
      st.peel_offset_rad = peel;
      st.peel_release_left = peel_release_samples_;
      Emit(&out, LegEventType::kPeelEnd, reason);
    }
    Fire(&out, Reflex::kPeel);
  }
  if (!st.peeling && st.peel_release_left > 0) {
    offset += st.peel_offset_rad * (static_cast<double>(st.peel_release_left) /
                                    (peel_release_samples_ + 1));
    --st.peel_release_left;
    Fire(&out, Reflex::kPeel);
  }

  // GTO: a loaded leg (or one whose partner has no grip) holds stance and presses; a pad
  // building its bond is pressed in proportion to its preload.
  bool gto_holding = false;
  if (p.gto.enabled && stance) {
    const bool loaded = hold_gto_.loaded();
    const bool partner_hold = p.gto.require_partner_attached && !sensing.partner_attached;
    gto_holding = loaded || partner_hold;
    if (loaded) offset[kHipPitch] -= std::min(hold_u, p.gto.hold_max_offset_rad);
    if (gto_holding) Fire(&out, Reflex::kGtoHold);
    if (gto_holding && !st.gto_holding) {
      Emit(&out, LegEventType::kGtoHold,
           loaded ? LegEventReason::kLoad : LegEventReason::kPartnerDetached);
    }
    if (sensing.attached && bonded < p.gto.full_bond_fraction && press_u > 0.0) {
      offset[kHipPitch] -= std::min(press_u, p.gto.press_max_offset_rad);
      Fire(&out, Reflex::kGtoPress);
    }
  }
  st.gto_holding = gto_holding;

  // Spindles: one event at the onset of activity on any joint.
  bool spindle_active = false;
  if (p.spindle.enabled) {
    spindle_active = (spindle_rad.array() != 0.0).any();
    if (spindle_active) {
      offset += spindle_rad;
      Fire(&out, Reflex::kSpindle);
      if (!st.spindle_active) Emit(&out, LegEventType::kSpindle);
    }
  }
  st.spindle_active = spindle_active;

  // The inputs are finite (sanitised), but gains and amounts have no upper bound: two opposing
  // terms that each overflow to ±inf sum to NaN, which no clamp would catch. They cancel.
  for (int j = 0; j < kLegJoints; ++j) {
    if (std::isnan(offset[j])) offset[j] = 0.0;
  }
  out.target_offset_rad = offset.cwiseMax(-p.max_offset_rad).cwiseMin(p.max_offset_rad);
  out.hold_stance = stance && (st.preloading || st.searching || gto_holding);
  out.hold_others = st.regrip_left > 0;
  if (st.regrip_left > 0) {
    --st.regrip_left;
    Fire(&out, Reflex::kRegrip);
  }

  st.prev_stance = stance;
  st.prev_touching = sensing.touching;
  st.prev_attached = sensing.attached;
  return out;
}

bool LegEvents::Contains(LegEventType type) const {
  for (const LegEvent& event : *this) {
    if (event.type == type) return true;
  }
  return false;
}

std::string_view EventName(LegEventType type) {
  switch (type) {
    case LegEventType::kPreloadStart:
      return "preload_start";
    case LegEventType::kPreloadEnd:
      return "preload_end";
    case LegEventType::kSearchStart:
      return "search_start";
    case LegEventType::kSearchEnd:
      return "search_end";
    case LegEventType::kPeel:
      return "peel";
    case LegEventType::kPeelEnd:
      return "peel_end";
    case LegEventType::kRegrip:
      return "regrip";
    case LegEventType::kGtoHold:
      return "gto_hold";
    case LegEventType::kSpindle:
      return "spindle";
  }
  return "unknown";
}

std::string_view ReasonName(LegEventReason reason) {
  switch (reason) {
    case LegEventReason::kNone:
      return "";
    case LegEventReason::kTouchdown:
      return "touchdown";
    case LegEventReason::kRegrip:
      return "regrip";
    case LegEventReason::kAttached:
      return "attached";
    case LegEventReason::kForceLimit:
      return "force_limit";
    case LegEventReason::kTimeLimit:
      return "time_limit";
    case LegEventReason::kSwingStarted:
      return "swing_started";
    case LegEventReason::kFound:
      return "found";
    case LegEventReason::kAttemptsExhausted:
      return "attempts_exhausted";
    case LegEventReason::kLoad:
      return "load";
    case LegEventReason::kPartnerDetached:
      return "partner_detached";
    case LegEventReason::kDetached:
      return "detached";
  }
  return "unknown";
}

std::string_view ReflexName(Reflex reflex) {
  switch (reflex) {
    case Reflex::kPreload:
      return "preload";
    case Reflex::kSearch:
      return "search";
    case Reflex::kPeel:
      return "peel";
    case Reflex::kRegrip:
      return "regrip";
    case Reflex::kGtoHold:
      return "gto_hold";
    case Reflex::kGtoPress:
      return "gto_press";
    case Reflex::kSpindle:
      return "spindle";
  }
  return "unknown";
}

}  // namespace climbsim::reflex
