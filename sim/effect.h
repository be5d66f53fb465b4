// Effects: the pieces a scenario composes around mj_step. Each is constructed only when the
// scenario names it, sized in its constructor, and then never allocates. The order is fixed
// (docs/design.md §1): BeforeStep in pipeline order, mj_step, AfterStep in pipeline order.
#ifndef CLIMBSIM_SIM_EFFECT_H_
#define CLIMBSIM_SIM_EFFECT_H_

#include <nlohmann/json.hpp>

#include <array>
#include <string>
#include <vector>

#include "reflex/reflex.h"
#include "sim/events.h"
#include "sim/world.h"

namespace climbsim::sim {

// What the effects tell each other about one leg during a step. Written by the effect that
// owns the signal, read by the others; the step loop never resizes it.
struct LegSignals {
  // CPG.
  double phase_rad = 0.0;
  bool stance = true;
  double progress = 0.0;                   // within the current stance or swing, 0..1
  std::array<double, 3> cpg_target_rad{};  // hip_yaw, hip_pitch, knee before reflexes
  std::array<double, 3> offset_rad{};      // reflex offsets added to the targets
  std::array<double, 3> kp_fraction{1, 1, 1};  // servo stiffness over its own kp (reflexes)
  // Adhesion.
  bool touching = false;
  bool attached = false;
  double bonded_fraction = 0.0;
  double touched_fraction = 1.0;           // share of the face that touched at the attach:
                                           // the most bonded_fraction can reach (partial
                                           // contact); 1 on a flat surface
  double bondable_fraction = 1.0;          // what bonded_fraction can still reach: the
                                           // touched share less the bonds torn since the
                                           // attach
  double normal_load_n = 0.0;              // pad load along its normal, + pulls it off
  double preload_n = 0.0;                  // compressive contact force on the pad
  double load_n = 0.0;                     // size of the force the weld carries, |F|, N (0
                                           // when not welded)
  bool bonds_lost = false;                 // lost bonds since the reflexes last looked
  reflex::Refusal refusal = reflex::Refusal::kNone;  // why the touch on the surface was
                                                      // refused, if it was
  double utilisation = 0.0;                // the pad's peak bond demand / threshold (σ_vM/σ_T
                                           // in tension, √3τ/(σ_T + μ|σ|) in compression) in
                                           // the last step; a bond breaks at 1; 0 when not
                                           // attached; capped at kUtilisationCap
  // Reflexes → CPG.
  bool hold_stance = false;                // do not leave stance yet
  bool hold_phase = false;                 // hold the phase where it is (a peel in progress)
};

// The largest utilisation a LegSignals or trajectory.csv carries (a load the bond model cannot
// hold at all, adhesion's +inf, is written as this).
inline constexpr double kUtilisationCap = 10.0;

struct RunContext {
  long step = 0;          // steps completed before this one
  double time_s = 0.0;    // simulated time at the start of this step
  std::vector<LegSignals>* legs = nullptr;
  EventLog* events = nullptr;
  bool hold_all_stance = false;  // a re-grip asks every leg to stay in stance
  double crouch_m = 0.0;          // the GTO posture's crouch, added to the CPG's (reflexes → CPG)
};

class Effect {
 public:
  virtual ~Effect() = default;
  // The effect's name in summary.json's "effects" list and in `bench speed`.
  virtual const char* name() const = 0;
  // Which hooks the pipeline calls (an effect without one costs nothing there).
  virtual bool has_before_step() const { return false; }
  virtual bool has_after_step() const { return false; }

  // After mj_resetData, before any effect's Reset: place the robot (joint angles) in the
  // pose the effect starts from; the Resets (welds of start-attached pads) see that pose.
  virtual void InitialPose(World& world, RunContext& ctx) { (void)world, (void)ctx; }
  // After every InitialPose, before the first step: set initial state (ctrl, welds).
  virtual void Reset(World& world, RunContext& ctx) { (void)world, (void)ctx; }
  virtual void BeforeStep(World& world, RunContext& ctx) { (void)world, (void)ctx; }
  virtual void AfterStep(World& world, RunContext& ctx) { (void)world, (void)ctx; }

  // Extra columns of trajectory.csv (names once; values each recorded row).
  virtual void TrajectoryColumns(std::vector<std::string>* names) const { (void)names; }
  virtual void TrajectoryValues(const World& world, double* out) const {
    (void)world, (void)out;
  }
  // Effect-specific figures for summary.json.
  virtual void Summarise(const World& world, nlohmann::json* summary) const {
    (void)world, (void)summary;
  }
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_EFFECT_H_
