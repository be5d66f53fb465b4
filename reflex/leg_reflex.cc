// Leg-level climbing reflex state machine (the table is in leg_reflex.h).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "reflex/check.h"
#include "reflex/leg_reflex.h"

namespace climbsim::reflex {
namespace {

using internal::DurationToSamples;
using internal::Sanitize;

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

LegReflex::LegReflex(const LegReflexParams& params, double dt_s)
    : params_(Validated(params, dt_s)),
      dt_s_(dt_s),
      preload_ramp_samples_(DurationToSamples("", params.preload.ramp_s, dt_s, false)),
      preload_max_samples_(DurationToSamples("", params.preload.max_duration_s, dt_s, true)),
      preload_release_samples_(DurationToSamples("", params.preload.release_s, dt_s, false)),
      search_attempt_samples_(DurationToSamples("", params.search.attempt_duration_s, dt_s, true)),
      search_release_samples_(DurationToSamples("", params.search.release_s, dt_s, false)),
      regrip_samples_(DurationToSamples("", params.regrip.hold_others_s, dt_s, false)),
      replace_samples_(DurationToSamples("", params.regrip.replace_s, dt_s, true)),
      replace_after_samples_(DurationToSamples("", params.regrip.replace_after_s, dt_s, false)),
      peel_max_samples_(DurationToSamples("", params.peel.max_duration_s, dt_s, true)),
      peel_release_samples_(DurationToSamples("", params.peel.release_s, dt_s, false)),
      pushed_hold_samples_(DurationToSamples("", params.spindle.hold_s, dt_s, false)),
      pushed_max_samples_(DurationToSamples("", params.spindle.max_hold_s, dt_s, false)),
      hold_gto_(params.gto.hold, dt_s),
      press_gto_(params.gto.press, dt_s),
      unload_gto_(params.gto.unload, dt_s),
      support_gto_(params.gto.support, dt_s),
      spindles_{SpindleReflex(params.spindle.joints[0], dt_s),
                SpindleReflex(params.spindle.joints[1], dt_s),
                SpindleReflex(params.spindle.joints[2], dt_s)} {}

void LegReflex::Reset() {
  hold_gto_.Reset();
  press_gto_.Reset();
  unload_gto_.Reset();
  support_gto_.Reset();
  for (SpindleReflex& spindle : spindles_) spindle.Reset();
  state_ = LegReflexState{};
}

// The reflexes composed: each function below is one reflex (its state, events and offset).
LegReflexOutput LegReflex::Update(const LegSensing& sensing) {
  LegReflexOutput out;
  const Sensed in = Sense(sensing);
  const Laws laws = RunLaws(in);
  SwingOnset(in, &out);
  PreloadLimits(in, &out);
  Eigen::Vector3d offset = Search(in, &out);
  offset += Regrip(in, &out);
  offset += Preload(in, &out);
  offset += Peel(in, &out);
  offset += Gto(in, laws, &out);
  state_.other_offset_rad = offset;  // the spindles' reference for the next period
  offset += Spindle(in, laws, &out);
  Compliance(in, &out);
  Finish(in, offset, &out);
  return out;
}

// Sensing, with non-finite values replaced by 0 and counted, and this period's edges.
LegReflex::Sensed LegReflex::Sense(const LegSensing& sensing) {
  LegReflexState& st = state_;
  int64_t* bad = &st.nonfinite_inputs;
  Sensed in;
  in.raw = &sensing;
  in.stance = sensing.stance;
  Sanitize(sensing.phase_progress, bad);  // counted like every input; the peel runs on time
  in.bonded = std::clamp(Sanitize(sensing.bonded_fraction, bad), 0.0, 1.0);
  in.normal_load_n = Sanitize(sensing.normal_load_n, bad);
  in.preload_n = Sanitize(sensing.preload_n, bad);
  in.swing_onset = st.prev_stance && !in.stance;
  in.stance_onset = !st.prev_stance && in.stance;
  in.touchdown = in.stance && sensing.touching && !(st.prev_stance && st.prev_touching);
  in.attach_edge = sensing.attached && !st.prev_attached;
  return in;
}

// The laws run every period (when enabled) so that their delays stay exact.
LegReflex::Laws LegReflex::RunLaws(const Sensed& in) {
  const LegReflexParams& p = params_;
  int64_t* bad = &state_.nonfinite_inputs;
  Laws laws;
  if (p.gto.enabled) {
    const double hold_load_n = p.gto.count_compression
                                   ? std::max(std::abs(in.normal_load_n), in.preload_n)
                                   : in.normal_load_n;
    laws.hold_u = hold_gto_.Update(hold_load_n);
    laws.press_u = press_gto_.Update(in.preload_n);
    laws.unload_u = unload_gto_.Update(Sanitize(in.raw->utilisation, bad));
    support_gto_.Update(Sanitize(in.raw->support_utilisation, bad));
  }
  if (p.spindle.enabled) {
    for (int j = 0; j < kLegJoints; ++j) {
      laws.spindle_rad[j] =
          spindles_[j].Update(Sanitize(in.raw->stretch_rad[j], bad) - state_.other_offset_rad[j],
                              Sanitize(in.raw->stretch_velocity_rad_per_s[j], bad));
    }
  }
  return laws;
}

// Swing onset ends the stance reflexes and starts a peel if the pad is still attached.
void LegReflex::SwingOnset(const Sensed& in, LegReflexOutput* out) {
  LegReflexState& st = state_;
  if (!in.swing_onset) return;
  if (st.preloading) {
    st.preloading = false;
    st.preload_release_left = preload_release_samples_;
    Emit(out, LegEventType::kPreloadEnd, LegEventReason::kSwingStarted);
  }
  if (st.searching) {
    st.searching = false;
    Emit(out, LegEventType::kSearchEnd, LegEventReason::kSwingStarted);
    StartSearchRelease();
  } else if (st.search_holding) {
    StartSearchRelease();
  }
  if (params_.peel.enabled && in.raw->attached) {
    st.peeling = true;
    st.peel_samples = 0;
    st.peel_release_left = 0;
    Emit(out, LegEventType::kPeel);
  }
}

// Preload limits, from the period after the start on.
void LegReflex::PreloadLimits(const Sensed& in, LegReflexOutput* out) {
  LegReflexState& st = state_;
  if (!st.preloading) return;
  ++st.preload_samples;
  LegEventReason reason = LegEventReason::kNone;
  if (in.attach_edge) {
    reason = LegEventReason::kAttached;
  } else if (in.preload_n >= params_.preload.force_limit_n) {
    reason = LegEventReason::kForceLimit;
  } else if (st.preload_samples >= preload_max_samples_) {
    reason = LegEventReason::kTimeLimit;
  }
  if (reason != LegEventReason::kNone) {
    st.preloading = false;
    st.preload_release_left = preload_release_samples_;
    Emit(out, LegEventType::kPreloadEnd, reason);
  }
}

// Search: found, or out of attempts; a new one at a stance onset without touchdown. Reach
// ρ = m/(N·n_a) plus a lift bump sin(π·s) within each attempt; held once found; released.
Eigen::Vector3d LegReflex::Search(const Sensed& in, LegReflexOutput* out) {
  LegReflexState& st = state_;
  const SearchParams& p = params_.search;
  const LegSensing& sensing = *in.raw;
  if (st.searching) {
    ++st.search_samples;
    if (sensing.touching || sensing.attached) {
      st.searching = false;
      st.search_holding = true;  // keep the foot where it found the surface
      Emit(out, LegEventType::kSearchEnd, LegEventReason::kFound);
    } else if (st.search_samples >= p.max_attempts * search_attempt_samples_) {
      st.searching = false;
      st.search_ran_out = true;
      Emit(out, LegEventType::kSearchEnd, LegEventReason::kAttemptsExhausted);
      StartSearchRelease();
    }
  }
  if (in.stance_onset) st.search_ran_out = false;
  // A leg that gave up while a peel waits for its pad searches again: the body that the other
  // pads hold may since have come nearer the surface, and giving up would stall the gait.
  const bool again = st.search_ran_out && sensing.waited_on;
  const bool start = in.stance_onset || st.search_after_replace || again;
  st.search_after_replace = false;
  if (p.enabled && start && in.stance && !sensing.touching && !sensing.attached) {
    st.searching = true;
    st.search_ran_out = false;
    st.search_samples = 0;
    st.search_holding = false;
    st.search_release_left = 0;
    st.search_offset_rad.setZero();
    Emit(out, LegEventType::kSearchStart);
  }

  if (st.searching) {
    const int m = st.search_samples;
    const double rho = static_cast<double>(m) / (p.max_attempts * search_attempt_samples_);
    const double s = static_cast<double>(m % search_attempt_samples_) / search_attempt_samples_;
    const double lift = p.lift_rad * std::sin(std::numbers::pi * s);
    st.search_offset_rad = {p.reach_yaw_rad * rho, lift - p.reach_pitch_rad * rho,
                            lift - p.reach_knee_rad * rho};
    Fire(out, Reflex::kSearch);
    return st.search_offset_rad;
  }
  if (st.search_holding) {
    Fire(out, Reflex::kSearch);
    return st.search_offset_rad;
  }
  if (st.search_release_left > 0) {
    --st.search_release_left;
    if (st.search_release_left > 0) {
      Fire(out, Reflex::kSearch);
      return st.search_offset_rad *
             (static_cast<double>(st.search_release_left) / search_release_samples_);
    }
  }
  return Eigen::Vector3d::Zero();
}

void LegReflex::StartSearchRelease() {
  state_.search_holding = false;
  state_.search_release_left = search_release_samples_;
}

// Re-grip: bonds lost in stance by a pad that was holding. A new episode (no re-grip hold or
// re-grip preload running) emits regrip; a running one is extended. A pad still attached is
// pressed (a preload); one that let go entirely is re-placed (lift and put down), since it
// can attach again only at a new touchdown.
void LegReflex::RegripOnBondLoss(const Sensed& in, LegReflexOutput* out) {
  LegReflexState& st = state_;
  const RegripParams& p = params_.regrip;
  if (!(p.enabled && in.stance && in.raw->bonds_lost && st.prev_attached)) return;
  const bool replace = !in.raw->attached && p.lift_rad > 0.0;
  if (replace && st.preloading) {
    st.preloading = false;  // the touchdown after the lift starts a fresh preload
    Emit(out, LegEventType::kPreloadEnd, LegEventReason::kRegrip);
  }
  const bool regrip_preload = st.preloading && st.preload_trigger == LegEventReason::kRegrip;
  if (st.regrip_left == 0 && !regrip_preload && st.replace_left == 0) {
    Emit(out, LegEventType::kRegrip);
  }
  st.regrip_left = regrip_samples_;
  if (replace) {
    if (st.replace_left == 0) {
      st.replace_left = replace_samples_;
      st.replace_lifted = false;
    }
  } else if (!st.preloading) {
    st.preloading = true;
    st.preload_samples = 0;
    st.preload_trigger = LegEventReason::kRegrip;
    Emit(out, LegEventType::kPreloadStart, LegEventReason::kRegrip);
  }
}

// A foot that touched down in stance and has not bonded replace_after_s later (its contact
// may chatter on an edge meanwhile): re-place it too, each time shifted along hip yaw.
void LegReflex::ReplaceRejectedLanding(const Sensed& in, LegReflexOutput* out) {
  LegReflexState& st = state_;
  const RegripParams& p = params_.regrip;
  if (!in.stance || in.raw->attached || st.replace_left > 0) {
    st.unattached_touch = 0;
    st.refusal = Refusal::kNone;
  } else if (st.unattached_touch > 0 || in.raw->touching) {
    ++st.unattached_touch;
    // The last refusal of the touches counted: a foot bounces off a fast landing, and the
    // pad forgets its refusal once it leaves the surface.
    if (in.raw->refusal != Refusal::kNone) st.refusal = in.raw->refusal;
  }
  if (!(p.enabled && p.lift_rad > 0.0 && replace_after_samples_ > 0 &&
        st.unattached_touch >= replace_after_samples_)) {
    return;
  }
  st.unattached_touch = 0;
  if (st.refusal == Refusal::kContacts) ++st.contact_replaces;
  const bool shift = p.shift_approach_refusals || st.refusal != Refusal::kApproach;
  st.refusal = Refusal::kNone;
  StartReplace(out, LegEventReason::kTouchdown, shift);
}

// A landing that attached touching less than min_touched_share of its face holds only that
// share of the load it will be handed: let it go now, while its bonds are fresh, and place it
// again shifted, the others holding stance meanwhile. A pad that attaches as its swing ends is
// let go at once too, so that no support rule counts it; its re-place starts with its stance.
// The release is the controller lifting the foot (adhesion's cause released).
void LegReflex::ReplacePartialLanding(const Sensed& in, LegReflexOutput* out) {
  LegReflexState& st = state_;
  const RegripParams& p = params_.regrip;
  if (in.swing_onset) st.partial_count = 0;
  if (p.enabled && p.lift_rad > 0.0 && in.attach_edge &&
      in.raw->touched_fraction < p.min_touched_share && st.partial_count < p.partial_replaces) {
    ++st.partial_count;
    out->release_pad = true;
    st.partial_pending = true;
  }
  if (!(st.partial_pending && in.stance)) return;
  st.partial_pending = false;
  st.regrip_left = std::max(st.regrip_left, replace_samples_);
  StartReplace(out, LegEventReason::kPartialContact, true);
}

// A re-place (lift and put down) of a foot whose landing is not kept.
void LegReflex::StartReplace(LegReflexOutput* out, LegEventReason reason, bool shift) {
  LegReflexState& st = state_;
  st.replace_left = replace_samples_;
  st.replace_lifted = false;
  if (st.preloading) {
    st.preloading = false;
    Emit(out, LegEventType::kPreloadEnd, LegEventReason::kRegrip);
  }
  Emit(out, LegEventType::kRegrip, reason);
  // Where it was rejected it would be again (an edge stays an edge): each re-place of the
  // same stance lands the foot shift_rad further along hip yaw, ahead and behind in turn
  // (+1, −1, +2, −2 … shifts). Without `shift` it comes down where it is.
  st.replace_shift_from = st.replace_shift;
  if (!shift) return;
  ++st.replace_count;
  const int k = (st.replace_count + 1) / 2;
  st.replace_shift = params_.regrip.shift_rad * (st.replace_count % 2 == 1 ? k : -k);
}

// The re-grip's episodes start above; here the re-place's lift and shift.
Eigen::Vector3d LegReflex::Regrip(const Sensed& in, LegReflexOutput* out) {
  LegReflexState& st = state_;
  const RegripParams& p = params_.regrip;
  RegripOnBondLoss(in, out);
  ReplaceRejectedLanding(in, out);
  ReplacePartialLanding(in, out);
  if (!in.stance) {
    st.replace_count = st.contact_replaces = 0;  // a new stance: the foot lands where its
                                                 // swing puts it
    st.replace_shift = st.replace_shift_from = 0.0;
  }
  // A pad let go this period is still attached in its sensing.
  const bool holds = in.raw->attached && !out->release_pad;
  if (st.replace_left == 0 || !in.stance || holds) {
    st.replace_left = 0;  // the gait took the leg, or the pad holds again
    st.replace_shift_from = st.replace_shift;
    if (st.replace_shift == 0.0) return Eigen::Vector3d::Zero();
    Fire(out, Reflex::kRegrip);
    return {st.replace_shift, 0.0, 0.0};  // held where the foot landed, until the swing
  }
  const double s = 1.0 - static_cast<double>(st.replace_left) / replace_samples_;
  // Off the surface on the way up (not the one blind step right after a weld lets go).
  st.replace_lifted |= !in.raw->touching && s >= 0.25;
  const double bump = std::sin(std::numbers::pi * s);
  const double lift = p.lift_rad * bump * bump;
  // The shift moves with the lift: r(s) = 3s² − 2s³ from the last shift to the new one.
  const double r = s * s * (3.0 - 2.0 * s);
  --st.replace_left;
  // Put down where the surface is not (the body moved while the pad was gone): the foot
  // searches for it as after a swing that ended short.
  if (st.replace_left == 0 && !in.raw->touching) st.search_after_replace = true;
  Fire(out, Reflex::kRegrip);
  return {st.replace_shift_from + r * (st.replace_shift - st.replace_shift_from), lift, lift};
}

// Touchdown preload; the press is a linear ramp, (m + 1)/n_ramp of full at the m-th period.
Eigen::Vector3d LegReflex::Preload(const Sensed& in, LegReflexOutput* out) {
  LegReflexState& st = state_;
  const PreloadParams& p = params_.preload;
  // A re-placed foot is pressed when it comes down, not while it still leaves the surface.
  const bool replacing = st.replace_left > 0 && !st.replace_lifted;
  const bool touchdown = in.touchdown && !in.raw->attached;
  // A pad already pressed to the force limit is bonding: no new press until it is not.
  const bool awaited = p.press_awaited_bond && in.stance && in.raw->attached &&
                       in.raw->bond_awaited && in.preload_n < p.force_limit_n;
  if (p.enabled && (touchdown || awaited) && !st.preloading && !replacing) {
    st.preloading = true;
    st.preload_samples = 0;
    st.preload_trigger = touchdown ? LegEventReason::kTouchdown : LegEventReason::kBondAwaited;
    Emit(out, LegEventType::kPreloadStart, st.preload_trigger);
  }
  if (!st.preloading) {
    // The press fades linearly after the preload ends (release_s).
    if (st.preload_release_left <= 0) return Eigen::Vector3d::Zero();
    const Eigen::Vector3d fade = st.preload_offset_rad * (static_cast<double>(
                                                              st.preload_release_left) /
                                                          (preload_release_samples_ + 1));
    --st.preload_release_left;
    Fire(out, Reflex::kPreload);
    return fade;
  }
  st.preload_release_left = 0;
  const double ramp = preload_ramp_samples_ == 0
                          ? 1.0
                          : std::min(1.0, (st.preload_samples + 1.0) / preload_ramp_samples_);
  Fire(out, st.preload_trigger == LegEventReason::kRegrip ? Reflex::kRegrip : Reflex::kPreload);
  const double press =
      st.contact_replaces == 0
          ? ramp
          : ramp * std::min(1.0 + p.retry_gain * st.contact_replaces, p.retry_max_scale);
  st.preload_offset_rad = {0.0, 0.0 - p.hip_pitch_press_rad * press,
                           0.0 - p.knee_press_rad * press};
  return st.preload_offset_rad;
}

// Peel: pull back and lift with a smooth step while the pad holds, the phase held; then
// fade out. A stance (the CPG went on regardless) ends it too.
Eigen::Vector3d LegReflex::Peel(const Sensed& in, LegReflexOutput* out) {
  LegReflexState& st = state_;
  const PeelParams& p = params_.peel;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  if (st.peeling) {
    const double u = std::min(1.0, st.peel_samples * dt_s_ / p.ramp_s);
    const double r = u * u * (3.0 - 2.0 * u);
    const Eigen::Vector3d peel(p.hip_yaw_rad * r, p.hip_pitch_lift_rad * r, p.knee_lift_rad * r);
    LegEventReason reason = LegEventReason::kNone;
    if (!in.raw->attached || in.stance) {
      reason = LegEventReason::kDetached;
    } else if (st.peel_samples >= peel_max_samples_) {
      reason = LegEventReason::kTimeLimit;
    }
    if (reason == LegEventReason::kNone) {
      offset = peel;
      out->hold_phase = true;
      // A support leg's pad let go: this pad carries again, its release and clock wait.
      const bool wait = p.wait_for_support && !in.raw->partner_attached;
      if (p.active_release && !wait) {
        out->unload_pad = true;
        out->release_pad = (st.peel_samples > 0 && in.raw->load_n <= p.release_load_n) ||
                           st.peel_samples + 1 >= peel_max_samples_;
        st.released |= out->release_pad;
      }
      if (!wait) ++st.peel_samples;
    } else {
      st.peeling = false;
      st.peel_offset_rad = peel;
      st.peel_release_left = peel_release_samples_;
      Emit(out, LegEventType::kPeelEnd, reason);
    }
    Fire(out, Reflex::kPeel);
  }
  if (in.stance) st.released = false;
  out->disengage_pad = st.released;
  if (!st.peeling && st.peel_release_left > 0) {
    offset = st.peel_offset_rad *
             (static_cast<double>(st.peel_release_left) / (peel_release_samples_ + 1));
    --st.peel_release_left;
    Fire(out, Reflex::kPeel);
  }
  return offset;
}

// GTO: a loaded leg (or one whose partner has no grip, or whose support pads are near their
// limit) holds stance, and presses if its foot can move; a pad building its bond is pressed
// in proportion to its preload; a pad near its bond limit is unloaded (the leg yields).
Eigen::Vector3d LegReflex::Gto(const Sensed& in, const Laws& laws, LegReflexOutput* out) {
  LegReflexState& st = state_;
  const GtoHoldParams& p = params_.gto;
  const bool attached = in.raw->attached;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  bool holding = false;
  bool unloading = false;
  if (p.enabled && in.stance) {
    const bool loaded = hold_gto_.loaded() && (!attached || p.load_attached);
    const bool partner_hold = p.require_partner_attached && !in.raw->partner_attached;
    const bool support_hold = support_gto_.loaded();
    holding = loaded || partner_hold || support_hold;
    if (loaded) offset[kHipPitch] -= std::min(laws.hold_u, p.hold_max_offset_rad);
    if (holding) Fire(out, Reflex::kGtoHold);
    if (holding && !st.gto_holding) {
      Emit(out, LegEventType::kGtoHold,
           loaded         ? LegEventReason::kLoad
           : partner_hold ? LegEventReason::kPartnerDetached
                          : LegEventReason::kSupport);
    }
    if (attached && in.bonded < p.full_bond_fraction && laws.press_u > 0.0) {
      offset[kHipPitch] -= std::min(laws.press_u, p.press_max_offset_rad);
      Fire(out, Reflex::kGtoPress);
    }
    unloading = attached && laws.unload_u > 0.0;
    if (unloading) {
      out->kp_fraction *= GtoUnloadKpFraction(laws.unload_u, p.unload_min_kp_fraction);
      Fire(out, Reflex::kGtoUnload);
      if (!st.gto_unloading) Emit(out, LegEventType::kGtoUnload);
    }
  }
  st.gto_holding = holding;
  st.gto_unloading = unloading;
  return offset;
}

// Spindles. Pad attached: no offset (also in a peel); in stance a stretch beyond the stance
// band (the body pushed) holds every leg in stance. Foot in the air: a stretch beyond the
// swing threshold lifts the foot (stumble); with resist, a stance foot in the air gets the
// stretch law on each joint instead. A foot touching without a bond: nothing (the preload
// presses it). One event at the onset of activity.
Eigen::Vector3d LegReflex::Spindle(const Sensed& in, const Laws& laws, LegReflexOutput* out) {
  LegReflexState& st = state_;
  const LegSpindleParams& p = params_.spindle;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  bool active = false;
  if (p.enabled) {
    if (!in.raw->attached) st.pushed_run = 0;  // a run of stretch ends with the bond
    if (in.raw->attached) {
      bool pushed = false;
      for (int j = 0; j < kLegJoints; ++j) {
        pushed |= std::abs(spindles_[j].delayed_stretch_rad()) > p.stance_band_rad;
      }
      pushed &= in.stance;
      // Pushed for longer than max_hold_s: the leg's posture, not a push (LegSpindleParams).
      st.pushed_run = pushed ? std::min(st.pushed_run, pushed_max_samples_) + 1 : 0;
      const bool posture = pushed_max_samples_ > 0 && st.pushed_run > pushed_max_samples_;
      if (pushed && !posture) {
        st.pushed_left = pushed_hold_samples_ + 1;
        if (!st.spindle_active) Emit(out, LegEventType::kSpindle, LegEventReason::kPushed);
        active = true;
      }
    } else if (!in.raw->touching && !(in.stance && p.resist)) {
      double excess = 0.0;
      for (int j = 0; j < kLegJoints; ++j) {
        excess = std::max(
            excess, std::abs(spindles_[j].delayed_stretch_rad()) - p.swing_threshold_rad);
      }
      if (excess > 0.0) {
        offset[kHipPitch] = p.joints[kHipPitch].length_gain * excess;
        offset[kKnee] = p.joints[kKnee].length_gain * excess;
      }
      active = offset[kHipPitch] != 0.0 || offset[kKnee] != 0.0;  // a lift, not zero gains
      if (active) {
        if (!st.spindle_active) Emit(out, LegEventType::kSpindle, LegEventReason::kStumble);
      }
    } else if (!in.raw->touching) {  // resist: a stance foot in the air
      active = (laws.spindle_rad.array() != 0.0).any();
      if (active) {
        offset = laws.spindle_rad;
        if (!st.spindle_active) Emit(out, LegEventType::kSpindle);
      }
    }
    if (active) Fire(out, Reflex::kSpindle);
  }
  st.spindle_active = active;
  return offset;
}

// Stance compliance: the stiffness fraction moves towards its target (stance fraction while
// attached in stance, 1 otherwise) by at most dt/ramp_s per period.
void LegReflex::Compliance(const Sensed& in, LegReflexOutput* out) {
  LegReflexState& st = state_;
  const ComplianceParams& p = params_.compliance;
  if (!p.enabled) return;
  const double target = in.stance && in.raw->attached ? p.stance_kp_fraction : 1.0;
  const double step = p.ramp_s > 0.0 ? dt_s_ / p.ramp_s : 1.0;
  st.kp_fraction = st.kp_fraction < target ? std::min(target, st.kp_fraction + step)
                                           : std::max(target, st.kp_fraction - step);
  out->kp_fraction *= st.kp_fraction;
  if (st.kp_fraction < 1.0) Fire(out, Reflex::kCompliance);
}

// The summed offset clamped; the holds; the state the next period compares against.
void LegReflex::Finish(const Sensed& in, const Eigen::Vector3d& summed, LegReflexOutput* out) {
  LegReflexState& st = state_;
  const LegReflexParams& p = params_;
  Eigen::Vector3d offset = summed;
  // The inputs are finite (sanitised), but gains and amounts have no upper bound: two opposing
  // terms that each overflow to ±inf sum to NaN, which no clamp would catch. They cancel.
  for (int j = 0; j < kLegJoints; ++j) {
    if (std::isnan(offset[j])) offset[j] = 0.0;
  }
  out->target_offset_rad = offset.cwiseMax(-p.max_offset_rad).cwiseMin(p.max_offset_rad);
  out->hold_stance =
      in.stance && (st.preloading || st.searching || st.gto_holding || st.replace_left > 0);
  out->regrip_hold = st.regrip_left > 0;
  out->pushed = st.pushed_left > 0;
  if (st.regrip_left > 0) {
    --st.regrip_left;
    Fire(out, Reflex::kRegrip);
  }
  if (st.pushed_left > 0) --st.pushed_left;

  st.prev_stance = in.stance;
  st.prev_touching = in.raw->touching;
  st.prev_attached = in.raw->attached;
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
    case LegEventType::kGtoUnload:
      return "gto_unload";
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
    case LegEventReason::kBondAwaited:
      return "bond_awaited";
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
    case LegEventReason::kSupport:
      return "support";
    case LegEventReason::kPushed:
      return "pushed";
    case LegEventReason::kStumble:
      return "stumble";
    case LegEventReason::kPartialContact:
      return "partial_contact";
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
    case Reflex::kGtoUnload:
      return "gto_unload";
    case Reflex::kCompliance:
      return "compliance";

  }
  return "unknown";
}

}  // namespace climbsim::reflex
