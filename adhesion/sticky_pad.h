// One sticky pad in MuJoCo: attachment decision, weld switching, bond build-up, load →
// bonds → detachment, and the events (docs/design.md section 3). Two models share the sensing and
// the attachment conditions:
//
//   kBonds   this project's model: a weld per pad carries the load; the bond grid
//            (bond_grid.h) decides, each step, which bonds break and when the pad lets go.
//   kMujoco  MuJoCo's built-in adhesion actuator (the baseline): while attached its ctrl is
//            on and it pulls the pad onto the surface with gain·ctrl, split over the pad's
//            contacts; there are no bonds and no weld.
//
// THE STEP (the caller runs Sense and Decide for every pad before mj_step, AfterStep after):
//
//   Sense      reads the pad's contacts of the last mj_step (pad_contact.h).
//   Decide     an unattached pad: touchdown, then the attach decision; an attached pad: bond
//              build-up (kBonds) or loss of contact (kMujoco).
//   mj_step
//   AfterStep  kBonds, attached: the weld's wrench of this step → PadLoad (pad frame, about
//              the face centroid) → BondGrid::Update (break, cascade) → bonds_lost, detach.
//
// ATTACHMENT. A touch episode starts at touchdown (the first step with a contact with a
// surface). The approach is judged at touchdown, the contact as it develops:
//
//   1. approach_speed_mps  at touchdown ≤ max_approach_speed_mps   (else rejected at once)
//   2. approach_angle_deg  at touchdown ≤ max_approach_angle_deg   (else rejected at once)
//   3. contacts            now ≥ min_contacts                       (may still come; a
//                          conforming face without them at the window's end: condition 5)
//   4. preload_n           now ≥ min_preload_n                      (may still come)
//   5. contact_share       now ≥ min_contact_share (partial contact: the share of the face
//                          that touches, pad_touch.h; a foot set on an edge)  (may still come)
//
// The pad attaches at the first step of the episode where all five hold. If 1 or 2 fails, or
// 3, 4 or 5 still fails attach_window_s after touchdown, the episode is rejected: an
// attach_rejected event names the FIRST failing condition in this order with its measured
// value (cause "approach_speed_mps=0.42"), and the pad cannot attach again before it has lost
// every contact with the surfaces (a new touchdown). Rejected touches are ordinary contacts,
// slightly spongy through the pad geom's own solref. The same holds after a detachment: a
// pad must leave the surface before it can attach again (the step right after a weld lets go
// is not evidence of that: the pad did not collide in it).
//
// ON ATTACH (kBonds) the weld is written from the current poses (weld.h: no jump), pointed at
// the touched geom's body and switched on; the pad geom's contype and conaffinity are set to
// 0 while the weld holds, so the weld carries the surface's whole wrench (compression
// included, which the bond grid's μ term needs; the ankle sensors then agree with it; and a
// welded pad that also collides costs about a third more per step). The bond grid starts at
// initial_fraction, centre-out. Each step in which the pad is not pulled (F_n ≤ 0 in the last
// step; from the second step after the attach, when the weld's load is known) the target
// fraction f grows as
//
//   f ← 1 − (1 − f)·exp(−Δt / buildup_time_s)          (df/dt = (1 − f)/τ)
//
// and the grid grows to round(f·N) bonds (BondGrid::Grow: centre-out, broken bonds stay
// broken). A pulled pad does not grow.
//
// DETACHMENT CAUSES (event detach, cause column):
//   overload      the pad had lost no bond since it attached, and this step's cascade took
//                 it from holding to fewer than min_bonds: all at once.
//   peel          the step's cascade ended the pad after bonds had already broken in earlier
//                 steps of this attachment (a bonds_lost event came first): progressive; or
//                 the controller was peeling it (SetPeeling): a peel is meant, however fast
//                 the crack runs.
//   released      Release() was called (a controller lifting the leg); no cascade.
//   contact_lost  kMujoco only: the pad lost every contact with the surfaces while on.
// On detach the weld is switched off, the grid released and the pad geom collides again.
//
// EVENTS go to a PadEventSink with the pad's index; kind and cause are enums (PadEventName and
// PadCauseName give their text), so nothing allocates. The load columns are the PadLoad of the last
// step while welded; for an unwelded pad F_n = −preload (compression is negative), the rest 0; for
// kMujoco while on, F_n = gain·ctrl − preload (what the rest of the robot pulls with).
//
// Nothing here allocates after construction; there are no name lookups in the step.
#ifndef CLIMBSIM_ADHESION_STICKY_PAD_H_
#define CLIMBSIM_ADHESION_STICKY_PAD_H_

#include <mujoco/mujoco.h>

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "adhesion/bond_grid.h"
#include "adhesion/frictional_law.h"
#include "adhesion/tabulated_law.h"
#include "adhesion/pad_contact.h"
#include "adhesion/pad_touch.h"

namespace climbsim::adhesion {

enum class AdhesionModel { kBonds, kMujoco };

// The attachment conditions and the build-up (docs/design.md section 3). Defaults: see
// adhesion/README.md for where each comes from.
struct AttachParams {
  int min_contacts = 3;                  // box on plane gives 4; 3 after the seed
  double max_approach_speed_mps = 0.25;  // ≥ 0
  double max_approach_angle_deg = 20.0;  // 0 .. 180
  double min_preload_n = 0.02;           // ≥ 0
  double initial_fraction = 0.3;         // 0 .. 1, bonded at attach
  double buildup_time_s = 0.1;           // τ ≥ 0 (0: full at once)
  double attach_window_s = 0.1;          // ≥ 0, time after touchdown for conditions 3 and 4

  // The scenario keys adhesion.min_contacts .. attach_window_s.
  template <class A>
  void Serialize(A* a) {
    a->Visit({"min_contacts", "",
              "attach condition: contact points with the surface (box on plane gives 4); a leg "
              "pad with foam (robot.pads.foam_m) still short of them when attach_window_s ends "
              "is judged by its touched share",
              Range::Closed(1, 1000)},
             &min_contacts);
    a->Visit(
        {"max_approach_speed_mps", "m/s",
         "attach condition: normal speed towards the surface at touchdown", Range::NonNegative()},
        &max_approach_speed_mps);
    a->Visit({"max_approach_angle_deg", "deg",
              "attach condition: angle between pad normal and surface normal at touchdown",
              Range::Closed(0, 180)},
             &max_approach_angle_deg);
    a->Visit({"min_preload_n", "N", "attach condition: compressive contact force on the pad",
              Range::NonNegative()},
             &min_preload_n);
    a->Visit(
        {"initial_fraction", "", "bonded fraction at attach (centre-out)", Range::Closed(0, 1)},
        &initial_fraction);
    a->Visit({"buildup_time_s", "s",
              "time constant of the growth of the bonded fraction towards 1 while the pad is not "
              "pulled; 0: full at once",
              Range::NonNegative()},
             &buildup_time_s);
    a->Visit({"attach_window_s", "s",
              "after touchdown, how long contacts and preload may take to meet their conditions "
              "before the attach is rejected",
              Range::NonNegative()},
             &attach_window_s);
  }
};

struct StickyPadParams {
  AdhesionModel model = AdhesionModel::kBonds;
  PadParams bonds;  // width_m and length_m are taken from the pad's box geom
  AttachParams attach;
  double actuator_gain_n = 0.0;  // kMujoco: force at ctrl 1 (N, > 0)
  double actuator_ctrl = 1.0;    // kMujoco: ctrl while attached, 0 .. 1
  // kBonds: which law breaks the bonds (frictional_law.h); frictional is checked only when
  // it is the law.
  PadLaw law = PadLaw::kVonMises;
  FrictionalParams frictional;
  TabulatedParams tabulated;  // law kTabulated: the measured table (tabulated_law.h)
  // kBonds: after a release (detach cause "released") the pad collides again only this much
  // later (s, ≥ 0; rounded to whole steps). The weld holds a pad at the depth its landing
  // pressed it into the surface's soft contact; given back its contact at once, the pad is
  // pushed out by that depth in one step, a kick the other pads feel (measured on the
  // directional gecko: a released front pad's kick pulled its hind neighbour off). A peeling
  // pad leaves the surface in that time.
  double release_contact_delay_s = 0.0;
  // kBonds: bond only the cells that touch the surface at attach (pad_touch.h).
  PartialContactParams contact;
  // Not a key: how far beyond contact_gap_m the face follows relief (a soft foam in the
  // backing, the model's climbsim_pad_conform_m; the caller adds it to contact_gap_m too).
  // Such a face that still lacks min_contacts when the attach window ends is judged by the
  // share of it that reaches the surface (condition 5): a box on rock touches two or three
  // summits however well a foam-backed face would lie on them. Within the window it is
  // judged as a rigid pad, so a landing the press lays flat attaches as it did.
  double conform_m = 0.0;
};

// Throws std::invalid_argument naming the key and the value (ValidatePadParams for the grid).
void ValidateStickyPadParams(const StickyPadParams& params);

enum class PadEventKind : uint8_t { kTouchdown, kAttach, kAttachRejected, kBondsLost, kDetach };
const char* PadEventName(PadEventKind kind);  // "touchdown", "attach", ...

// Why an event happened. PadCauseName gives the text of events.csv's cause column and of
// summary.json's keys (for a rejection, the measured quantity).
enum class PadCause : uint8_t {
  kNone,           // ""                    touchdown; an attach that met every condition
  kApproachSpeed,  // "approach_speed_mps"  attach_rejected: condition 1
  kApproachAngle,  // "approach_angle_deg"  attach_rejected: condition 2
  kContacts,       // "contacts"            attach_rejected: condition 3
  kPreload,        // "preload_n"           attach_rejected: condition 4
  kContactShare,   // "contact_share"       attach_rejected: condition 5
  kFractionLost,   // "fraction_lost"       bonds_lost
  kStartAttached,  // "start_attached"      attach at t = 0
  kForced,         // "forced"              attach by ForceAttach otherwise
  kPeel,           // "peel"                detach (see DETACHMENT CAUSES above)
  kOverload,       // "overload"            detach
  kReleased,       // "released"            detach
  kContactLost,    // "contact_lost"        detach (kMujoco)
  kFailure,        // "failure"             detach: Fail(), every bond broken at once
};
const char* PadCauseName(PadCause cause);

struct PadEvent {
  double time_s = 0.0;
  PadEventKind kind = PadEventKind::kTouchdown;
  PadCause cause = PadCause::kNone;
  double cause_value = 0.0;
  bool has_cause_value = false;
  int surface_geom = -1;
  double bonded_fraction = 0.0;
  PadLoad load;
};

class PadEventSink {
 public:
  virtual void OnPadEvent(int pad, const PadEvent& event) = 0;

 protected:
  ~PadEventSink() = default;
};

// Counts since the last Reset.
struct PadCounts {
  long touchdown = 0;
  long attach = 0;
  long attach_rejected = 0;
  // attach_rejected events by the condition that failed first
  long rejected_approach_speed = 0;
  long rejected_approach_angle = 0;
  long rejected_contacts = 0;
  long rejected_preload = 0;
  long rejected_contact_share = 0;
  long bonds_lost = 0;  // steps that lost bonds
  long detach_peel = 0;
  long detach_overload = 0;
  long detach_released = 0;
  long detach_contact_lost = 0;
  long detach_failure = 0;
};

class StickyPad {
 public:
  // `index` is the pad's number in events. `weld_eq` (kBonds) or `actuator` (kMujoco) must
  // exist in `m`; the other may be −1. Validates params (std::invalid_argument); sizes the
  // bond grid from the pad's box.
  StickyPad(const mjModel* m, int index, const PadGeometry& geometry, const StickyPadParams& params,
            int weld_eq, int actuator);

  // Detached, weld off, collision bits and ctrl restored, counts zeroed. Call after
  // mj_resetData (which does not reset model-level switches).
  void Reset(mjModel* m, mjData* d);

  // The geoms the pad sticks to (one entry per geom, as Sense's sticks_to): the targets of
  // partial contact's rays. By default every geom but the pad's own; AdhesionSystem sets its
  // surfaces. Allocates: call it at setup.
  void SetSurfaces(const std::vector<uint8_t>& sticks_to) { surfaces_ = sticks_to; }

  // --- The step (see the file comment) ---
  void Sense(const mjModel* m, const mjData* d, const std::vector<uint8_t>& sticks_to);
  // `kinematics_current`: whether xpos/xquat already describe the current qpos (an attach
  // runs mj_kinematics once and sets it).
  void Decide(mjModel* m, mjData* d, double time_s, bool* kinematics_current, PadEventSink* sink);
  void AfterStep(mjModel* m, mjData* d, double time_s, PadEventSink* sink);

  // Attaches to `surface_geom` now, skipping the conditions, with `fraction` of the bonds
  // (start_attached, the pull-off rig). With partial contact the cells that touch are those
  // within `standoff_m` + contact_gap_m of the surface (pad_touch.h; start_attached:
  // start_gap_m). `seat`: the contact that placed it there (start_attached's widened-margin
  // contact): the pad is then seated on its rest plane like a landing one
  // (TouchProbe::MeasureSeated); null: measured as it stands.
  // False if already attached.
  bool ForceAttach(mjModel* m, mjData* d, double time_s, int surface_geom, double fraction,
                   PadCause cause, bool* kinematics_current, PadEventSink* sink,
                   double standoff_m = 0.0, const ContactSense* seat = nullptr);
  // The controller is peeling this pad (a detach while it is counts as "peel").
  void SetPeeling(bool peeling) { peeling_ = peeling; }
  // The pad's adhesive is disengaged (an active-release foot keeps its toe peeled through the
  // swing that follows a release): while it is, an unattached pad's touches are ordinary
  // contacts, no touchdown and no attach; a touch still under way when it is engaged again
  // starts a new episode then, judged on that step's approach.
  void SetDisengaged(bool disengaged) { disengaged_ = disengaged; }
  bool disengaged() const { return disengaged_; }
  // Detaches with cause "released". False (and nothing happens) when not attached.
  bool Release(mjModel* m, mjData* d, double time_s, PadEventSink* sink);
  // A pad that fails (a defect, dirt; a disturbance of `climbsim bench robustness`): every
  // bond breaks now, event bonds_lost (the whole bonded fraction) then detach with cause
  // "failure". False (and nothing happens) when not attached.
  bool Fail(mjModel* m, mjData* d, double time_s, PadEventSink* sink);
  // σ_T of this pad's bonds times `scale` (> 0) until changed (a weak patch of the surface
  // under it). Applied by giving the bond grid the load divided by `scale`: with
  // σ_vM ≥ σ_T and √3·τ ≥ σ_T − μσ both sides scale alike, so this is exact. load() stays the
  // real load. 1 (the default, and after Reset) is the material's own σ_T. kBonds only.
  void SetStrengthScale(double scale) { strength_scale_ = scale; }
  double strength_scale() const { return strength_scale_; }

  // --- State ---
  int index() const { return index_; }
  const PadGeometry& geometry() const { return geometry_; }
  const StickyPadParams& params() const { return params_; }
  bool attached() const { return attached_; }
  bool touching() const { return attached_ || sense_.contacts > 0; }
  // kBonds: the grid's bonded fraction; kMujoco: 1 while on, else 0.
  double bonded_fraction() const;
  // The share of the face that touched the surface at the last attach (partial contact,
  // pad_touch.h): the most bonded_fraction can reach in this attachment. 1 for kMujoco and
  // for a pad that touched everywhere (exactly 1.0: the whole grid).
  double touched_fraction() const;
  // What bonded_fraction can still reach: touched less torn since the attach. 1 for kMujoco.
  double bondable_fraction() const;
  // Why the attach of the touch now on the surface was refused (kNone: it was not, or the pad
  // is off the surface).
  PadCause refused_cause() const { return refused_cause_; }
  const PadLoad& load() const { return load_; }  // pad frame, + F_n pulls off
  const ContactSense& sense() const { return sense_; }
  bool bonds_lost_this_step() const { return bonds_lost_; }
  int surface_geom() const { return surface_geom_; }
  const BondGrid& grid() const { return grid_; }
  const PadCounts& counts() const { return counts_; }
  double buildup_target() const { return buildup_; }
  // The approach of the current (or last) touch episode, measured at its touchdown.
  double touchdown_time_s() const { return touchdown_time_s_; }
  double touchdown_speed_mps() const { return touchdown_speed_mps_; }
  double touchdown_angle_deg() const { return touchdown_angle_deg_; }
  // law kFrictional or kTabulated: the largest bond utilisation left after the last AfterStep
  // while attached (frictional_law.h, tabulated_law.h); read it only while attached (0 after
  // Reset).
  double frictional_utilisation() const { return frictional_utilisation_; }
  // The directional law as prepared (unit gripping direction, tan α*); the default law's
  // parameters unless params().law is kFrictional.
  const FrictionalLaw& frictional_law() const { return frictional_law_; }
  // The GRADIENT of the pad's utilisation with respect to its load, ∂U/∂(F_n, F_x, F_y, M_x,
  // M_y) in the pad frame (per N and per N·m): at the bond that carries the peak utilisation
  // of the last AfterStep (the law's: von Mises or frictional), through the bond's influence
  // (BondGrid::Influence; the load the grid sees, scaled by the strength scale and, for the
  // frictional law, with its moment share) and the law's derivative there. It is the
  // direction in which the rest of the robot should change the pad's load to relieve it:
  // the reflexes' load sharing (reflex.h, GTO share) moves the load along −∇U. False (grad
  // unchanged) unless attached (kBonds) with a supported load, and for the tabulated law
  // (no gradient: its limit is interpolated). Never allocates.
  // `peak_bond`: the bond of the peak when already known (PadUtilisationGradient).
  bool UtilisationGradient(Eigen::Matrix<double, 5, 1>* grad, int peak_bond = -1) const;

 private:
  bool peeling_ = false;
  bool disengaged_ = false;
  double strength_scale_ = 1.0;
  enum class Episode : uint8_t { kNone, kPending, kClosed };

  // How an attaching pad meets the surface (pad_touch.h): its stand-off, how far its contacts
  // press it in, and whether it is seated on its rest plane (TouchProbe::MeasureSeated).
  struct Seating {
    double standoff_m = 0.0;
    double pressed_m = 0.0;
    bool seated = false;
    bool measured = false;  // touching_ already holds this attach's touched set
  };
  void Attach(mjModel* m, mjData* d, double time_s, int surface_geom, double fraction,
              PadCause cause, bool* kinematics_current, PadEventSink* sink, Seating seating);
  // kBonds with partial contact: the grid's touching set from the current poses.
  void MeasureTouching(const mjModel* m, const mjData* d, const Seating& seating);
  // Decide for an attached pad: the build-up (kBonds), or contact lost (kMujoco).
  void WhileAttached(mjModel* m, mjData* d, double time_s, PadEventSink* sink);
  // Condition 5 for a landing pad: measures touching_ (seated) and returns the share of the
  // face that touches; 1 without partial contact or for kMujoco.
  double LandingContactShare(const mjModel* m, mjData* d, bool* kinematics_current);
  void Detach(mjModel* m, mjData* d, double time_s, PadCause cause, PadEventSink* sink);
  void Emit(PadEventSink* sink, double time_s, PadEventKind kind, PadCause cause, double value,
            bool has_value) const;
  void SetUnweldedLoad();

  int index_;
  PadGeometry geometry_;
  StickyPadParams params_;
  int weld_eq_;
  int actuator_;
  int contype_, conaffinity_;  // of the pad geom, as compiled
  double grow_decay_ = 0.0;    // exp(−Δt/τ), set by Reset
  int release_contact_steps_ = 0;  // release_contact_delay_s in steps, set by Reset
  int contact_off_steps_ = 0;      // steps left before a released pad collides again

  BondGrid grid_;
  TouchProbe probe_;
  std::vector<uint8_t> touching_;  // per cell, the last measure
  std::vector<uint8_t> surfaces_;  // per geom: the rays' targets (SetSurfaces)
  ContactSense sense_;
  PadLoad load_;
  bool load_known_ = false;  // the weld has carried at least one step since the attach
  bool attached_ = false;
  bool bonds_lost_ = false;
  int surface_geom_ = -1;
  Episode episode_ = Episode::kNone;
  PadCause refused_cause_ = PadCause::kNone;  // why this touch's attach was refused, if it was
  bool blind_ = false;  // the next Sense reads a step without the pad's contacts
  double touchdown_time_s_ = 0.0;
  double touchdown_speed_mps_ = 0.0;
  double touchdown_angle_deg_ = 0.0;
  double buildup_ = 0.0;
  long lost_since_attach_ = 0;
  PadCounts counts_;
  FrictionalLaw frictional_law_;  // the default law unless params.law is kFrictional
  double frictional_utilisation_ = 0.0;
  std::optional<TabulatedLaw> tabulated_law_;  // law kTabulated only
};

}  // namespace climbsim::adhesion

#endif  // CLIMBSIM_ADHESION_STICKY_PAD_H_
