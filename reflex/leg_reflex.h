// One leg's climbing reflexes: what the simulator tells a leg, what the leg answers, and the
// state machine that runs the reflexes of leg_params.h once per control period.
#ifndef CLIMBSIM_REFLEX_LEG_REFLEX_H_
#define CLIMBSIM_REFLEX_LEG_REFLEX_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string_view>

#include "reflex/laws.h"
#include "reflex/leg_params.h"

namespace climbsim::reflex {

// Why adhesion refused a landing: how it came (too fast, too oblique), or where it landed: too
// few contacts (a pad met with its edge or corner: tilted, or on a bump's edge), or too little
// of the face touching (a bump's top).
enum class Refusal : uint8_t { kNone, kApproach, kContacts, kShare };

// What the simulator tells a leg once per control period.
struct LegSensing {
  bool stance = false;           // the CPG's phase for this leg: true = stance, false = swing
  double phase_progress = 0.0;   // progress within the current phase, 0..1 (clamped)
  bool touching = false;         // the pad touches a surface
  bool attached = false;         // the pad is attached (weld on)
  double bonded_fraction = 0.0;  // bonded share of the pad, 0..1
  double touched_fraction = 1.0;  // share of the pad's face that touched at its last attach
                                  // (1 on a flat surface)
  double normal_load_n = 0.0;    // pad normal force, N; + pulls the pad off (adhesive load)
  double preload_n = 0.0;        // compressive contact force pressing the pad on, N, >= 0
  double load_n = 0.0;           // size of the force on the attached pad, |F|, N
  bool bonds_lost = false;       // the pad lost bonds this period
  Refusal refusal = Refusal::kNone;  // why adhesion refused the touch on the surface, if it did
  // q − q_cpg per Joint; the spindles see it less the other reflexes' offsets of the last
  // period (the stretch from the target the leg was given).
  Eigen::Vector3d stretch_rad = Eigen::Vector3d::Zero();
  Eigen::Vector3d stretch_velocity_rad_per_s = Eigen::Vector3d::Zero();
  bool partner_attached = true;  // the partner leg's pad is attached
  // A peel with wait_for_support waits for this leg's pad (it is not attached): a search that
  // ran out in this stance starts again.
  bool waited_on = false;
  // The gait waits for this attached pad to bond (cpg.wait_for_support, below its
  // support_bond_fraction).
  bool bond_awaited = false;
  double utilisation = 0.0;       // the pad's peak bond demand / threshold, >= 0 (1 breaks)
  double support_utilisation = 0.0;  // the largest utilisation among the support legs' pads
};

enum class LegEventType : uint8_t {
  kPreloadStart,
  kPreloadEnd,
  kSearchStart,
  kSearchEnd,
  kPeel,     // a peel starts: swing onset with the pad attached
  kPeelEnd,  // it ends: the pad let go (detached) or time ran out (time_limit)
  kRegrip,
  kGtoHold,    // onset of GTO stance holding
  kSpindle,    // onset of spindle activity on any joint (reason pushed: stance, attached)
  kGtoUnload,  // onset of GTO unloading (the pad's utilisation above its threshold)
};

enum class LegEventReason : uint8_t {
  kNone,
  kTouchdown,          // preload_start: the pad touched down in stance, not attached
  kRegrip,             // preload_start: started by a re-grip
  kAttached,           // preload_end: the pad attached during the preload
  kForceLimit,         // preload_end: preload_n reached force_limit_n
  kTimeLimit,          // preload_end/peel_end: max_duration_s elapsed
  kSwingStarted,       // preload_end/search_end: the CPG left stance anyway
  kFound,              // search_end: the pad touched (or attached)
  kAttemptsExhausted,  // search_end: max_attempts done without touching
  kLoad,               // gto_hold: the delayed load is above threshold
  kPartnerDetached,    // gto_hold: the partner is not attached (and the leg is not loaded)
  kDetached,           // peel_end: the pad let go
  kSupport,            // gto_hold: the support pads' utilisation is above threshold
  kPushed,             // spindle: stretch beyond the stance band on an attached leg
  kStumble,            // spindle: stretch beyond the swing threshold on a free swing leg
  kPartialContact,     // regrip: a landing touching too little of its face is re-placed
  kBondAwaited,        // preload_start: the gait waits for this attached pad to bond
};

enum class Reflex : uint8_t {
  kPreload,
  kSearch,
  kPeel,
  kRegrip,
  kGtoHold,
  kGtoPress,
  kSpindle,
  kGtoUnload,
  kCompliance,
};

// Names as logged in events.csv: "preload_start", "search_end", "gto_hold", ...; reasons as
// "touchdown", "force_limit", "attempts_exhausted", ...; "" for kNone.
std::string_view EventName(LegEventType type);
std::string_view ReasonName(LegEventReason reason);
std::string_view ReflexName(Reflex reflex);

struct LegEvent {
  LegEventType type;
  LegEventReason reason;
  friend bool operator==(const LegEvent&, const LegEvent&) = default;
};

// Each event type occurs at most once per Update, so one slot per type always suffices.
inline constexpr int kMaxLegEvents = 10;

// This period's events, in the order: preload_end, search_end, peel, search_start, regrip,
// preload_start, gto_hold, gto_unload, spindle.
struct LegEvents {
  std::array<LegEvent, kMaxLegEvents> items{};
  int count = 0;
  const LegEvent* begin() const { return items.data(); }
  const LegEvent* end() const { return items.data() + count; }
  int size() const { return count; }
  bool Contains(LegEventType type) const;
};

struct LegReflexOutput {
  Eigen::Vector3d target_offset_rad = Eigen::Vector3d::Zero();  // add to the CPG's targets
  bool hold_stance = false;  // only ever true in stance: do not let this leg leave stance yet
  bool hold_phase = false;   // hold this leg's phase where it is (a peel that has not let go)
  bool regrip_hold = false;  // a re-grip: every leg should stay in stance
  bool pushed = false;       // the spindle: this attached stance leg is pushed (the robot's
                             // PushHold decides whether every leg stays in stance for it)
  bool unload_pad = false;   // an active-release peel: move this pad's load to the others
  bool release_pad = false;  // an active-release peel: let this pad go now
  bool disengage_pad = false;  // an active release keeps the pad disengaged from its release
                               // to the next stance (the toe stays peeled through the swing)
  // Servo stiffness per joint as a fraction of the servo's own kp, in (0, 1] (compliance and
  // GTO unloading; 1 when both are off).
  Eigen::Vector3d kp_fraction = Eigen::Vector3d::Ones();
  uint32_t fired = 0;        // bit (1 << Reflex) for each reflex that acted this period
  LegEvents events;
  bool Fired(Reflex reflex) const { return fired & (1u << static_cast<int>(reflex)); }
  // A re-grip or a pushed stance leg: every leg should stay in stance.
  bool hold_others() const { return regrip_hold || pushed; }
};

// What a LegReflex remembers between periods; times are counted in control periods.
struct LegReflexState {
  // Preload: running, periods since its start, and what started it (kTouchdown or kRegrip).
  bool preloading = false;
  int preload_samples = 0;
  LegEventReason preload_trigger = LegEventReason::kNone;
  Eigen::Vector3d preload_offset_rad = Eigen::Vector3d::Zero();  // the press when it ended
  int preload_release_left = 0;
  // Search: running, periods since its start, the last offset (held once found, until the
  // swing starts), and the periods of release left.
  bool searching = false;
  int search_samples = 0;
  Eigen::Vector3d search_offset_rad = Eigen::Vector3d::Zero();
  bool search_holding = false;
  int search_release_left = 0;
  bool search_after_replace = false;  // a re-place put the foot down on nothing: search next
  bool search_ran_out = false;  // a search ran out of attempts in this stance
  bool peeling = false;
  bool released = false;  // an active release let the pad go in this swing
  int peel_samples = 0;                              // periods since the swing onset
  Eigen::Vector3d peel_offset_rad = Eigen::Vector3d::Zero();  // when the peel ended
  int peel_release_left = 0;
  int regrip_left = 0;  // periods of hold_others left
  int replace_left = 0;  // periods of a re-place (lift and put down) left
  bool replace_lifted = false;  // the re-placed foot has left the surface
  int unattached_touch = 0;     // periods in stance without a bond since the foot touched
  int replace_count = 0;        // re-places of rejected landings in this stance, shifted
  int contact_replaces = 0;     // those refused for too few contacts (the retry press)
  int partial_count = 0;        // partly touching landings let go since the swing started
  bool partial_pending = false;  // one was let go in the swing: re-place it at the stance
  double replace_shift = 0.0;   // their hip-yaw shift (rad), held until the swing
  double replace_shift_from = 0.0;
  bool gto_holding = false;
  bool gto_unloading = false;
  bool spindle_active = false;
  int pushed_left = 0;        // periods of the spindle's hold_others left
  int pushed_run = 0;         // periods in a row the attached stance leg was stretched
  Refusal refusal = Refusal::kNone;  // the last refusal of the unattached touch being timed
  // The last period's offsets of every reflex but the spindles: the spindles measure the
  // stretch from the target so commanded (a peel or a search is not a stretch).
  Eigen::Vector3d other_offset_rad = Eigen::Vector3d::Zero();
  double kp_fraction = 1.0;   // compliance: the stiffness fraction reached (before unloading)
  // The last period's sensing; the first Update behaves as if the leg had been in stance, in
  // the air, detached: a leg that starts in swing with its pad attached (a robot placed on a
  // wall) peels it like any other swing onset.
  bool prev_stance = true;
  bool prev_touching = false;
  bool prev_attached = false;
  int64_t nonfinite_inputs = 0;  // non-finite sensing values replaced by 0
};

// One leg's climbing reflexes, updated once per control period. The state machine
// (touchdown = stance ∧ touching now, not both last period):
//
//  reflex    | starts when                     | acts                 | ends when (reason)
//  ----------+---------------------------------+----------------------+------------------------
//  preload   | touchdown ∧ ¬attached           | press ramp,          | attach edge (attached),
//            |                                 | hold_stance          | preload_n >= limit
//            |                                 |                      | (force_limit), time
//            |                                 |                      | (time_limit), swing
//  search    | (swing → stance, or a re-place  | reach + lift,        | touching ∨ attached
//            | ends) ¬touching ∧ ¬attached     | hold_stance          | (found), N attempts
//            |                                 |                      | (attempts_exhausted),
//            |                                 |                      | swing (swing_started)
//  peel      | stance → swing ∧ attached       | pull back and lift,  | detached (detached),
//            |                                 | hold_phase           | max time (time_limit;
//            |                                 |                      | wait_for_support stops
//            |                                 |                      | its clock)
//  regrip    | stance ∧ bonds_lost ∧ attached  | preload (regrip),    | hold_others_s elapsed
//            | last period                     | hold_others          |
//  gto hold  | stance ∧ (delayed load > F0 ∨   | hold_stance, press   | unloaded ∧ partner
//            | partner detached ∨ delayed      | if loaded and not    | attached ∧ support
//            | support utilisation > U_s)      | attached             | below U_s
//  gto press | stance ∧ attached ∧             | press ∝ delayed      | bond built
//            | bonded < full_bond_fraction     | preload              |
//  gto unload| stance ∧ attached ∧ delayed     | kp_fraction ×        | utilisation <= U0
//            | utilisation > U0                | max(min, 1 − u)      |
//  spindle   | in the air: |q̃(t−Δ)| > L_sw     | lift (stumble)       | inside L_sw
//            | with resist, stance in the air: | resist the stretch   | inside the dead zones
//            | |q̃(t−Δ)| > L0 ∨
//            | |q̇(t−Δ)| > V0                   |                      |
//            | attached in stance: |q̃(t−Δ)| >  | hold_others (no      | inside the band, then
//            | stance_band_rad (pushed)        | offset)              | hold_s; or after
//            |                                 |                      | max_hold_s pushed
//  compliance| stance ∧ attached               | kp_fraction → stance | swing or detached
//            |                                 | fraction, ramped     | (ramped back to 1)
//
// A reflex whose `enabled` is false never acts and emits nothing. gto_hold, gto_unload and
// spindle emit one event at onset (not every period); `fired` says every period which
// reflexes act. The summed offset is clamped to ±max_offset_rad per joint.
class LegReflex {
 public:
  // Throws std::invalid_argument via Validate().
  LegReflex(const LegReflexParams& params, double dt_s);

  // One control period. Never allocates, never throws.
  LegReflexOutput Update(const LegSensing& sensing);
  void Reset();

  const LegReflexParams& params() const { return params_; }
  const LegReflexState& state() const { return state_; }
  double dt_s() const { return dt_s_; }

 private:
  LegReflexParams params_;
  double dt_s_;
  // Durations in control periods, rounded once at construction like the delays.
  int preload_ramp_samples_;
  int preload_max_samples_;
  int preload_release_samples_;
  int search_attempt_samples_;
  int search_release_samples_;
  int regrip_samples_;
  int replace_samples_;
  int replace_after_samples_;
  int peel_max_samples_;
  int peel_release_samples_;
  int pushed_hold_samples_;
  int pushed_max_samples_;  // 0: no limit
  GtoReflex hold_gto_;
  GtoReflex press_gto_;
  GtoReflex unload_gto_;
  GtoReflex support_gto_;
  std::array<SpindleReflex, kLegJoints> spindles_;
  LegReflexState state_;

  // One period's sensing, sanitised, with its edges; and the laws' outputs.
  struct Sensed {
    const LegSensing* raw;
    bool stance, swing_onset, stance_onset, touchdown, attach_edge;
    double bonded, normal_load_n, preload_n;
  };
  struct Laws {
    double hold_u = 0.0, press_u = 0.0, unload_u = 0.0;
    Eigen::Vector3d spindle_rad = Eigen::Vector3d::Zero();
  };
  // One function per reflex, in the order Update composes them (their events keep the order
  // of LegEvents).
  Sensed Sense(const LegSensing& sensing);
  Laws RunLaws(const Sensed& in);
  void SwingOnset(const Sensed& in, LegReflexOutput* out);
  void PreloadLimits(const Sensed& in, LegReflexOutput* out);
  Eigen::Vector3d Search(const Sensed& in, LegReflexOutput* out);
  Eigen::Vector3d Regrip(const Sensed& in, LegReflexOutput* out);
  void RegripOnBondLoss(const Sensed& in, LegReflexOutput* out);
  void ReplaceRejectedLanding(const Sensed& in, LegReflexOutput* out);
  void ReplacePartialLanding(const Sensed& in, LegReflexOutput* out);
  void StartReplace(LegReflexOutput* out, LegEventReason reason, bool shift);
  Eigen::Vector3d Preload(const Sensed& in, LegReflexOutput* out);
  Eigen::Vector3d Peel(const Sensed& in, LegReflexOutput* out);
  Eigen::Vector3d Gto(const Sensed& in, const Laws& laws, LegReflexOutput* out);
  Eigen::Vector3d Spindle(const Sensed& in, const Laws& laws, LegReflexOutput* out);
  void Compliance(const Sensed& in, LegReflexOutput* out);
  void StartSearchRelease();
  void Finish(const Sensed& in, const Eigen::Vector3d& offset, LegReflexOutput* out);
};

}  // namespace climbsim::reflex

#endif  // CLIMBSIM_REFLEX_LEG_REFLEX_H_
