// The adhesion effect: the scenario's `adhesion:` block on top of adhesion::AdhesionSystem
// (adhesion/adhesion_system.h). First in the pipeline:
//
//   BeforeStep  contacts of the last step → touchdown, attach decisions (weld on / actuator
//               on), bond build-up; LegSignals of each leg's pad
//   AfterStep   the weld's wrench of this step → bond stresses → broken bonds → detach;
//               LegSignals again
//
// It writes events.csv rows (touchdown, attach, attach_rejected, bonds_lost, detach), seven
// trajectory columns per pad (<pad>_bonded_fraction, <pad>_utilisation, and the load the
// bond layer carries, PadLoad in the pad frame: <pad>_fn_n, _fx_n, _fy_n, _mx_nm, _my_nm, 0
// when not attached) and summary.json's
// "adhesion" block (per pad counts, peak utilisation, and the utilisation split into stance
// and peel, below). The controller side reads each leg's
// pad through LegSignals (touching, attached, bonded_fraction, normal_load_n, preload_n,
// bonds_lost, utilisation) and lets a pad go with RequestRelease.
//
// Utilisation: the peak over the pad's bonds of demand over threshold in the field of the
// last AfterStep (adhesion::StressSummary::peak_utilisation: σ_vM/σ_T for a bond in tension,
// √3·τ/(σ_T + μ·|σ|) in compression), 1 where a bond breaks; 0 for a pad not attached or with
// model mujoco (no bonds); a load the grid cannot carry at all (+inf) is kUtilisationCap.
//
// Stance against peel: a pad is peeling while its controller says so (SetPeelingLeg: the peel
// reflex's hold phase, a transition's peel), and its utilisation then climbs to 1 on purpose.
// summary.json keeps the two apart per pad: utilisation_stance_peak and utilisation_stance_p99
// over the steps the pad was attached and not peeling (the margin a designer asks about),
// utilisation_peel_peak over the steps it was attached and peeling. The 99th percentile is the
// nearest rank over those steps, read from a histogram of kStanceBins bins on [0, 1) (sized
// once: the step loop allocates nothing) as its bin's upper edge, never above the peak;
// demands ≥ 1 fall in one more bin, whose upper edge is the peak. 0 when there was no such
// step.
//
// Disturbances (`climbsim bench robustness`): with adhesion.pad_failure_probability p each
// attach draws (from the seed, the pad and its attach count) whether it fails and when
// (uniform in [0, pad_failure_window_s)); at that time, if still attached, the pad fails
// (StickyPad::Fail: bonds_lost, detach cause "failure"). With scene.weak_patches each attach
// sets the pad's σ_T scale from the patch under its face centre (sim/surface.h). Both are
// decided in the attach event and checked each AfterStep without allocating.
//
// Values that change nothing in the MJCF's structure (weld solref, actuator gains) are set
// on the run's own model copy, so one compiled model serves scenarios that differ only in
// them.
#ifndef CLIMBSIM_SIM_ADHESION_EFFECT_H_
#define CLIMBSIM_SIM_ADHESION_EFFECT_H_

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "adhesion/adhesion.h"
#include "sim/effect.h"
#include "scenario/scenario.h"
#include "sim/world.h"

namespace climbsim::sim {

// The pads of the scenario with their parameters, resolved against a compiled model that holds
// the robot (default pads: every leg's pad body, then an adhesive tail tip's tail_pad;
// overrides applied; default actuator gain σ_T·A of each pad). Throws InputError at the
// adhesion key at fault.
std::vector<adhesion::PadSpec> AdhesionPadSpecs(const Scenario& scenario,
                                                const AdhesionParams& params, const mjModel* model,
                                                const RobotInfo& robot);

// The MJCF the adhesion block adds (welds or actuators, one per pad). Compiles the robot and
// scene once to find the pads; throws InputError like AdhesionPadSpecs.
void AddAdhesionMjcf(const Scenario& scenario, const AdhesionParams& params,
                     MjcfAdditions* additions);

class AdhesionEffect final : public Effect, private adhesion::PadEventSink {
 public:
  // Throws InputError at the adhesion key at fault (a pad or surface that does not exist).
  AdhesionEffect(const Scenario& scenario, const AdhesionParams& params, World& world);

  const char* name() const override { return "adhesion"; }
  bool has_before_step() const override { return true; }
  bool has_after_step() const override { return true; }
  void Reset(World& world, RunContext& ctx) override;
  void BeforeStep(World& world, RunContext& ctx) override;
  void AfterStep(World& world, RunContext& ctx) override;
  void TrajectoryColumns(std::vector<std::string>* names) const override;
  void TrajectoryValues(const World& world, double* out) const override;
  void Summarise(const World& world, nlohmann::json* summary) const override;

  // --- For controllers and tests ---
  // Lets pad `pad` go now (weld off, or actuator off), event detach with cause "released";
  // the pad attaches again only after it has left the surface. False when it was not
  // attached. Allocates nothing; call it from an effect's BeforeStep (the release then acts
  // in this step's mj_step) or between steps.
  bool RequestRelease(int pad);
  // The same for the pad of leg `leg` (robot leg order); false when that leg has no sticky
  // pad or it was not attached.
  bool RequestReleaseLeg(int leg);

  int pad_count() const { return system_->size(); }
  const std::string& pad_name(int pad) const { return system_->pad_name(pad); }
  // Tells the pad of leg `leg` that its controller is peeling it: a detach meanwhile has cause
  // "peel" (adhesion/sticky_pad.h). No-op for a leg without a sticky pad.
  void SetPeelingLeg(int leg, bool peeling) {
    const int pad = pad_of_leg(leg);
    if (pad < 0) return;
    system_->pad(pad).SetPeeling(peeling);
    peeling_[pad] = peeling;
  }
  // The pad of leg `leg` is disengaged (adhesion/sticky_pad.h: SetDisengaged): its touches
  // are ordinary contacts until engaged again. No-op for a leg without a sticky pad.
  void SetDisengagedLeg(int leg, bool disengaged) {
    const int pad = pad_of_leg(leg);
    if (pad >= 0) system_->pad(pad).SetDisengaged(disengaged);
  }
  // The same for pad `pad` (a pad that is no leg's: an adhesive tail tip).
  void SetDisengaged(int pad, bool disengaged) { system_->pad(pad).SetDisengaged(disengaged); }
  // Pad `pad`'s utilisation after the last step (see above).
  double utilisation(int pad) const { return utilisation_[pad]; }
  // The bond carrying it (von Mises law; −1 otherwise or when not attached), for the
  // utilisation's gradient (StickyPad::UtilisationGradient).
  int peak_bond(int pad) const { return peak_bond_[pad]; }
  // Its largest value over the run so far.
  double peak_utilisation(int pad) const { return peak_utilisation_[pad]; }
  // The same split into the steps the pad was attached and not peeling (stance) and attached
  // and peeling (peel), and the stance's 99th percentile (see above); 0 without such steps.
  double stance_peak_utilisation(int pad) const { return stance_peak_[pad]; }
  double peel_peak_utilisation(int pad) const { return peel_peak_[pad]; }
  double stance_p99_utilisation(int pad) const;
  // Bins of the stance histogram on [0, 1): the 99th percentile's resolution is 1/kStanceBins.
  static constexpr int kStanceBins = 1000;
  // The pad of a leg, or −1; the leg of a pad, or −1.
  int pad_of_leg(int leg) const {
    return leg < 0 || leg >= static_cast<int>(pad_of_leg_.size()) ? -1 : pad_of_leg_[leg];
  }
  int leg_of_pad(int pad) const { return leg_of_pad_[pad]; }
  const adhesion::StickyPad& pad(int pad) const { return system_->pad(pad); }
  const adhesion::AdhesionSystem& system() const { return *system_; }

 private:
  void OnPadEvent(int pad, const adhesion::PadEvent& e) override;
  void FillSignals();
  void UpdateUtilisation();

  void DrawDisturbances(int pad, double time_s);

  AdhesionParams params_;
  int seed_ = 0;
  std::optional<WeakPatchParams> weak_patches_;
  std::vector<double> fail_at_s_;     // per pad: when this attachment fails; +inf: it does not
  std::vector<long> attach_count_;    // per pad, since Reset: the draws' index
  World* world_;
  std::unique_ptr<adhesion::AdhesionSystem> system_;
  std::vector<int> pad_of_leg_;
  std::vector<int> peak_bond_;
  std::vector<int> leg_of_pad_;
  std::vector<double> utilisation_;       // per pad, sized once
  std::vector<double> peak_utilisation_;  // per pad, over the run
  std::vector<uint8_t> peeling_;          // per pad: its controller is peeling it
  std::vector<double> stance_peak_;       // per pad, over the run's stance steps
  std::vector<double> peel_peak_;         // per pad, over the run's peel steps
  std::vector<long> stance_histogram_;    // per pad, kStanceBins + 1 counts (the last: ≥ 1)
  std::vector<LegSignals>* legs_ = nullptr;
  EventLog* events_ = nullptr;
};

// The adhesion effect of a simulation's pipeline, or nullptr when the scenario has none.
AdhesionEffect* FindAdhesion(const std::vector<std::unique_ptr<Effect>>& effects);

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_ADHESION_EFFECT_H_
