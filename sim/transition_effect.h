// Surface transitions: the scenario's `transition:` block in a run. Part of the built-in
// controller (sim/controller.h). The manoeuvre itself (watching for a corner or an edge, the
// planned free gait round it, the hand-back to the gait) is transition/manoeuvre.h; this
// effect is its adapter: it passes it the pads' signals, reads the world and the adhesion
// effect for it (base pose, pad faces, contacts and loads, joint angles, the gait's targets),
// and writes its servo targets (with the GTO unload law on the stance legs' stiffness) and its
// events (events.csv). summary.json's "transition" block has the times and pads. Nothing
// allocates in Watch or Update.
#ifndef CLIMBSIM_SIM_TRANSITION_EFFECT_H_
#define CLIMBSIM_SIM_TRANSITION_EFFECT_H_

#include <array>
#include <span>
#include <vector>

#include "scenario/scenario.h"
#include "sim/adhesion_effect.h"
#include "sim/cpg_effect.h"
#include "sim/effect.h"
#include "transition/manoeuvre.h"

namespace climbsim::sim {

class TransitionEffect final : public Effect {
 public:
  // Throws InputError at the transition key when the robot has no ankle tilt servos, a leg
  // has no sticky pad or the scenario no adhesion block. `period_s` is the control period;
  // `event_pad` each leg's pad in the EventLog.
  // `cpg`: the gait the feet are handed back to (then: gait), foot space.
  TransitionEffect(const Scenario& scenario, const TransitionParams& params, const World& world,
                   AdhesionEffect* adhesion, const CpgEffect* cpg, double period_s,
                   std::vector<int> event_pad);
  const char* name() const override { return "transition"; }
  void Reset(World& world, RunContext& ctx) override;
  // While the gait runs, at each control tick after it: true when the manoeuvre starts now
  // (it has written this tick's targets; the caller then suspends the gait and the reflexes).
  bool Watch(World& world, RunContext& ctx);
  // One control tick of the manoeuvre (every leg servo and ankle tilt).
  void Update(World& world, RunContext& ctx);
  bool active() const { return manoeuvre_.active(); }
  // then: gait. After the tick that handed the feet back: the phases the gait goes on from
  // (CpgEffect::Resume); the caller clears it.
  bool resume_pending() const { return manoeuvre_.resume_pending(); }
  std::span<const double> resume_theta() const { return manoeuvre_.resume_theta(); }
  void ClearResume() { manoeuvre_.ClearResume(); }
  void Summarise(const World& world, nlohmann::json* summary) const override;

 private:
  class Io;  // the manoeuvre's senses and commands over one tick's world

  // The pads' signals of this tick for the manoeuvre.
  void SensePads(const RunContext& ctx);
  void WriteTargets(World& world) const;
  void RestoreKp(World& world) const;

  TransitionParams params_;
  AdhesionEffect* adhesion_;
  const CpgEffect* cpg_;
  std::vector<int> event_pad_;
  std::vector<std::array<double, 3>> kp_;  // each leg servo's kp as compiled
  CornerManoeuvre manoeuvre_;
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_TRANSITION_EFFECT_H_
