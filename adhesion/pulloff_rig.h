// The seed's figure-6 experiment in MuJoCo (issue 3, item 6): a weightless block with one
// sticky pad under it rests on the plane z = 0, attached fully, and is pulled by a force that
// rises slowly,
//
//   F(t) = σ_T·A · t / ramp_time_s             (A = b·h; the force of step k is F((k+1)·Δt)),
//
// along the fixed direction u = (sinθ·cosφ, sinθ·sinφ, cosθ) of pulloff.h (θ from the surface
// normal: 0 pulls straight off, 90° is pure shear, above 90° the force also pushes), applied at
// the point L = arm_m above the pad-face centroid (xfrc_applied: the force and its moment
// about the block's centre of mass). The pull-off force is F of the step in which the pad lets
// go. Gravity is off; the block's mass only sets the dynamics.
//
// MODELS.
//   kBonds   this project's model (sticky_pad.h): the weld carries the pull, the bond grid
//            breaks; "lets go" = the pad detaches (cause peel or overload).
//   kMujoco  MuJoCo's adhesion actuator with gain_n (default σ_T·A) and ctrl 1, pad friction
//            `friction`, elliptic cones with noslip iterations (no creep); the block first
//            settles for settle_time_s under the actuator alone, then the ramp starts; "lets
//            go" = a corner of the pad face has moved slip_m from where it settled (it lifted,
//            tipped or slid), or the pad lost every contact.
//
// QUASI-STATIC. The pull rises by σ_T·A·Δt/ramp_time_s per step (0.05 % of σ_T·A with the
// defaults) and the block follows the weld's soft response within a few ms, so the kBonds
// pull-off differs from pulloff.h's quasi-static PullOff() by about one step of the ramp
// (adhesion/README.md reports the measured differences).
//
// CLOSED FORMS of kMujoco for a block whose adhesion gain G is shared by its four corner
// contacts (friction μ_f), pulled in the plane φ = 0:
//   lift / tip about the leading edge:  F = G·(b/2) / (L·sinθ + (b/2)·cosθ)
//   slide:                              F = μ_f·G / (sinθ + μ_f·cosθ)
// whichever is smaller with a positive denominator (MujocoPulloffClosedForm).
#ifndef CLIMBSIM_ADHESION_PULLOFF_RIG_H_
#define CLIMBSIM_ADHESION_PULLOFF_RIG_H_

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "adhesion/adhesion_system.h"
#include "adhesion/pulloff.h"

namespace climbsim::adhesion {

struct PulloffRigParams {
  PadParams pad{.width_m = 0.025, .length_m = 0.025};  // the block's pad and its bond grid
  double arm_m = 0.0;                                  // L ≥ 0
  double azimuth_rad = 0.0;                            // φ
  double ramp_time_s = 2.0;                            // time for the pull to reach σ_T·A (> 0)
  double timestep_s = 0.001;
  double block_mass_kg = 0.05;
  double max_force_factor = 8.0;  // holds up to this many σ_T·A: reported as never (> 1)
  std::array<double, 2> weld_solref = kDefaultWeldSolref;
  // kMujoco only.
  double gain_n = 0.0;     // 0: σ_T·A
  double friction = 1.0;   // pad sliding friction (the gecko's pads: 1.0)
  double slip_m = 0.5e-3;  // a face corner this far from where it settled: let go
  double settle_time_s = 0.2;
  double reach_m = 0.001;                            // pad margin = gap
  std::array<double, 2> contact_solref{0.004, 1.0};  // stiff: the block is light
  int noslip_iterations = 10;
  // The surface: "" is the plane z = 0; otherwise MJCF geoms (world frame) that replace it, all
  // of them surfaces, with the block's face resting at z = 0 (a step edge or a hollow under the
  // pad: partial contact, pad_touch.h).
  std::string surface_mjcf;
  // Where the pull acts: (x, y) in the pad frame, arm_m above the face ((0, 0): its centroid).
  std::array<double, 2> pull_point_m{0.0, 0.0};
  PartialContactParams contact;  // kBonds: which cells bond at the attach
};

// Throws std::invalid_argument naming the bad key.
void ValidatePulloffRigParams(const PulloffRigParams& params);

struct PulloffRun {
  bool detached = false;
  double force_n = 0.0;  // pull of the step that let go; +inf if it never did
  double time_s = 0.0;   // of that step's end
  long steps = 0;
  const char* cause = "";      // kBonds: peel/overload; kMujoco: lift, tip, slide, contact_lost
  int steps_losing_bonds = 0;  // kBonds: steps that broke bonds (the last included)
  std::vector<BrokenBondAt> sequence;    // kBonds: every broken bond in order; round counts
                                         // the cascade rounds over the whole run
  std::vector<double> sequence_force_n;  // the pull when each of those bonds broke
};

class PulloffRig {
 public:
  // Builds and compiles the block model; throws std::invalid_argument on bad params or when
  // MuJoCo rejects the model.
  PulloffRig(AdhesionModel model, const PulloffRigParams& params);
  ~PulloffRig();
  PulloffRig(const PulloffRig&) = delete;
  PulloffRig& operator=(const PulloffRig&) = delete;

  // One pull at θ = angle_rad from a fresh start. `observer` (may be null) sees every pad
  // event of the run in order.
  PulloffRun Run(double angle_rad, PadEventSink* observer = nullptr);
  // A constant pull `force_n` at θ for `duration_s` from a fresh start (kMujoco: after the
  // settling); returns the pad as it is then (its load, its grid, attached or not).
  const StickyPad& Hold(double angle_rad, double force_n, double duration_s);

  const std::string& xml() const { return xml_; }
  const mjModel* model() const { return model_; }
  double capacity_n() const {
    return params_.pad.sigma_t_pa * params_.pad.width_m * params_.pad.length_m;
  }
  double gain_n() const;

 private:
  class Sink;
  // mj_resetData, fresh attachment, kMujoco settling.
  void Start(PadEventSink* sink);
  // One step under the pull `force_n` along u at L above the face centroid.
  void Step(const Eigen::Vector3d& u, double force_n, PadEventSink* sink);
  Eigen::Vector3d Direction(double angle_rad) const;  // u of the file comment
  AdhesionModel model_type_;
  PulloffRigParams params_;
  std::string xml_;
  mjModel* model_ = nullptr;
  mjData* data_ = nullptr;
  std::unique_ptr<AdhesionSystem> system_;
  int block_ = -1;
  int surface_geom_ = -1;
};

// kMujoco's pull-off for a block as above (see the file comment); +inf when neither way
// gives.
double MujocoPulloffClosedForm(double gain_n, double friction, double width_m, double arm_m,
                               double angle_rad);

}  // namespace climbsim::adhesion

#endif  // CLIMBSIM_ADHESION_PULLOFF_RIG_H_
