// The GTO's robot-level channels: load sharing among the attached pads (internal forces in
// the null space of the grasp map), the posture (the pads' pull lowers the body) and force
// tracking's gripping-shear targets, each with its parameters and their keys.
#ifndef CLIMBSIM_REFLEX_LOAD_SHARING_H_
#define CLIMBSIM_REFLEX_LOAD_SHARING_H_

#include <Eigen/Core>
#include <array>
#include <string>
#include <string_view>

#include "keys/keys.h"
#include "reflex/laws.h"

namespace climbsim::reflex {

// ---------------------------------------------------------------------------------------------
// Load sharing among attached pads (the GTO's robot-level channel)
// ---------------------------------------------------------------------------------------------

// Once two or more pads are welded, legs and body form closed chains: the pads' forces f_i
// (what each leg puts on its pad, world frame) hold the body when G·f = w (the body's wrench;
// G the grasp map, a block [I; [r_i]×] per pad), and any change λ with G·λ = 0 is an INTERNAL
// force: it moves load from pad to pad without moving the body (docs/control.md, "Load sharing
// among contacts"). Position servos realise it exactly: a target change Δq_i = Kp⁻¹·J_iᵀ·λ_i
// on each leg (J_i its Jacobian at the pad) changes the leg's force by λ_i while the joints
// and the body stay put, and since Σλ = 0 and Σ r×λ = 0 the body has nothing to move for.
//
// The law chooses λ to keep every pad away from its limit. With U_i each pad's utilisation
// (peak bond demand over threshold, ≥ 1 breaks) and ∇U_i its gradient with respect to f_i
// (adhesion: PadUtilisationGradient), it drives down the soft maximum
//   S = U_max + ln Σ_i exp(β·(U_i − U_max)) / β            (≥ max U_i, → max as β → ∞)
// while S is above the threshold U_S, along the internal part of its gradient
// g_i = w_i·∇U_i (w the softmax weights): with P the projector onto ker G,
//   dλ/dt = −K·[S − U_S]₊ · P·g / |P·g|²  −  λ/τ
// so that, to first order, dS/dt = −K·[S − U_S]₊ from the sharing alone. The leak τ lets a
// request that is no longer needed fade. λ is projected onto ker G of the pads attached now
// at every update (a pad that lets go takes its share of λ with it), and scaled down as a
// whole (which keeps it internal) so that no pad's request exceeds max_force_n. Fewer than
// two attached pads: no internal force exists, λ = 0.
//
// Unlike a law at each leg alone (tried first: each pad descending its own U shifted load onto
// whichever pad the chain's stiffness chose and raised the worst pad's utilisation, 0.50 →
// 0.77 on the gecko hanging with a payload), this sees every pad the internal force touches.
//
// FORCE TRACKING (mode kForceTracking, for directional pads): the caller gives each pad the
// error e_i = f*_i − f_i between the force it wants on the pad and the one measured, and
//   dλ/dt = K·P·e  −  λ/τ
// moves the internal force towards the internal part of the request at rate K (per second),
// without the threshold, the soft maximum or max_rate_n_per_s. λ itself is not projected
// again when the attached set changes: the forces it set are already in balance, and
// re-projecting it when a pad lets go would jolt the others (measured: a released front pad
// pulled its hind neighbour off). A directional pad's limit is a cone, not a bond stress, and
// it holds nothing at zero load, so the utilisation's gradient cannot steer it: the targets
// (sim/reflex_effect.cc, ShareLoad) give each pad its least gripping shear plus a share of the
// rest (docs/climbing.md, "Directional pads").
enum class SharingMode { kUtilisation, kForceTracking };

struct LoadSharingParams {
  SharingMode mode = SharingMode::kUtilisation;
  double gain_per_s = 100.0;   // K, > 0 switches the law on; 0 = off
  double threshold = 0.3;      // U_S: the soft maximum above which load is shared
  double leak_s = 0.5;         // τ > 0
  double softmax_beta = 20.0;  // β > 0 (20: pads within ~0.05 of the worst share its weight)
  double max_force_n = 1.0;    // > 0, the largest internal force asked of one pad
  double max_rate_n_per_s = 20.0;  // > 0, the fastest a pad's request may change (where
                                   // little of the gradient is internal, the step above grows)
  double period_s = 0.005;  // > 0, how often the law runs (the simulator rounds it to whole
                            // control periods and holds the legs' offsets in between)
  // Force tracking's targets (sim/reflex_effect.cc with GripShearTargets): the share of a
  // pressed pad's friction that may be spent on reversed shear, and the least gripping shear
  // of every pad (N, 0 = off).
  double friction_credit = 0.5;
  double min_grip_n = 0.0;

  template <class A>
  void Serialize(A* a) {
    // The mode as its name; written back only when it changes (a const struct checked by
    // keys::Validate is never written).
    std::string mode_name = mode == SharingMode::kForceTracking ? "force_tracking" : "utilisation";
    a->Choice({"mode", "",
               "utilisation: drive down the worst pad's utilisation (bond stress); "
               "force_tracking (adhesion.law frictional): move each directional pad's gripping "
               "shear towards the least its pull needs plus an equal share of the rest (of the "
               "net force, when the pads grip in different directions), and a pad being let go "
               "towards no load (reflex/reflex.h)"},
              &mode_name, {"utilisation", "force_tracking"});
    const SharingMode read =
        mode_name == "force_tracking" ? SharingMode::kForceTracking : SharingMode::kUtilisation;
    if (read != mode) mode = read;
    a->Visit({"gain_per_s", "1/s",
              "K. utilisation: while the soft maximum S of the attached pads' utilisations is "
              "above the threshold, internal forces between the pads (the null space of the grasp "
              "map, set through the legs' servo targets) drive it down at K [S - threshold]+ per "
              "second. force_tracking: the internal force follows the internal part of the pads' "
              "force errors at rate K; 0 = off",
              Range::NonNegative()},
             &gain_per_s);
    a->Visit({"friction_credit", "",
              "force_tracking: share of a pressed pad's friction (mu times its press) that may be "
              "spent on reversed shear",
              Range::Closed(0, 1)},
             &friction_credit);
    a->Visit({"min_grip_n", "N",
              "force_tracking: every gripping pad's target shear is at least this; pads opposed "
              "in pairs (under a ceiling) then hold a grasp before their pull arrives; 0 = off",
              Range::NonNegative()},
             &min_grip_n);
    a->Visit(
        {"threshold", "", "U_S: the soft maximum of the utilisations above which load is shared"},
        &threshold);
    a->Visit({"leak_s", "s", "time constant with which an internal force no longer needed fades",
              Range::Positive()},
             &leak_s);
    a->Visit({"softmax_beta", "", "sharpness of the soft maximum (large: the worst pad alone)",
              Range::Positive()},
             &softmax_beta);
    a->Visit({"max_force_n", "N", "largest internal force asked of one pad", Range::Positive()},
             &max_force_n);
    a->Visit({"max_rate_n_per_s", "N/s", "fastest change of one pad's internal force",
              Range::Positive()},
             &max_rate_n_per_s);
    a->Visit({"period_s", "s",
              "how often the law runs, rounded to whole control periods (the legs' offsets are "
              "held in between)",
              Range::Positive()},
             &period_s);
  }
};

// Throws std::invalid_argument naming the field unless every field is finite and in range.
void Validate(const LoadSharingParams& params, double dt_s, std::string_view name = "share");

// The most legs LoadSharing takes (the buffers are fixed: nothing allocates).
inline constexpr int kMaxSharingLegs = 8;

// One leg as LoadSharing sees it in a control period.
struct SharingLeg {
  bool active = false;  // its pad is attached and it is in stance (not peeling)
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();  // the point where the leg holds its
                                                          // pad (the ankle), world frame
  double utilisation = 0.0;                                // U_i
  Eigen::Vector3d gradient_per_n = Eigen::Vector3d::Zero();  // ∂U_i/∂f_i, world frame
  // Added to U_i in the soft maximum. A pad about to be let go (an active-release peel) gets
  // a bias of 1: it dominates S, and the descent moves its load to the others first.
  double bias = 0.0;
  // kForceTracking: the wanted minus the measured force the leg puts on its pad, world, N.
  Eigen::Vector3d force_error_n = Eigen::Vector3d::Zero();
};

class LoadSharing {
 public:
  // Throws std::invalid_argument via Validate().
  LoadSharing(const LoadSharingParams& params, double dt_s);

  // One control period; legs.size() <= kMaxSharingLegs (more are ignored). Returns λ_i per leg
  // (world frame, N; zero for inactive legs), valid until the next Update. Never allocates.
  const std::array<Eigen::Vector3d, kMaxSharingLegs>& Update(const SharingLeg* legs, int count);
  void Reset();

  const LoadSharingParams& params() const { return params_; }
  // The soft maximum S of the last Update (0 with fewer than two active legs).
  double soft_max() const { return soft_max_; }
  bool enabled() const { return params_.gain_per_s > 0.0; }

 private:
  LoadSharingParams params_;
  double dt_s_;
  void CapLambda(int count);  // scales λ as a whole so that no pad's exceeds max_force_n

  std::array<Eigen::Vector3d, kMaxSharingLegs> lambda_;
  double soft_max_ = 0.0;
};

// GTO posture channel (robot level): the pads' pull lowers the body. A climber's weight acts
// at its centre of mass, a standoff h above the surface, and its moment about the hind feet
// (m·g·h on a wall) is held by the front feet pulling off the surface (climbing geckos, frogs
// and primates: a pulling forelimb, a pushing hindlimb): every millimetre of h is pull on the
// pads that tear first. Animals on slopes lower their body (cats, rats, squirrels, tree frogs,
// iguanas, stick insects and desert ants; J Exp Biol 224:jeb242677, 2021, "a geometric
// strategy against toppling"). The load signal is P = Σ [F_n,i]₊ / (m·g), the pull of the
// attached pads that carry the robot (not of one its own leg peels) over its own weight (0 on
// a floor, ~0.4 on a wall, 1 under a ceiling), and
//   c*(t) = min(c_max, K_P·[P̃(t−Δ) − P0]₊),   dc/dt = (c* − c)/τ
// is the crouch the simulator gives the CPG's stance and swing feet (cpg.crouch_m plus c):
// all feet at once, so on welded feet it moves the body, not the pads against each other.
// Off by default: it changes a gait's geometry, and a gait tuned upright can lose its footing
// (spider_wall_fast.yaml climbs 0.007 m/s with it instead of 0.17); the wall examples switch
// it on (docs/climbing.md, "Posture").
struct PostureParams {
  bool enabled = false;
  GtoParams pull{.gain = 0.05, .threshold = 0.1, .delay_s = 0.01};  // m, -, s; gain >= 0
  double max_crouch_m = 0.0125;   // c_max >= 0
  double time_constant_s = 0.3;   // τ > 0: the body lowers over about a second
  // Keys flattened: gain_m is pull.gain (the GTO law on the pull).
  template <class A>
  void Serialize(A* a) {
    a->Visit({"enabled", "",
              "lower the body as the pads are pulled off the surface (foot-space gaits, "
              "cpg.stride_m): the crouch c = min(max_crouch_m, gain_m [P(t-D) - threshold]+), "
              "lagged by time_constant_s, is added to cpg.crouch_m; P is the attached pads' pull "
              "over the robot's own weight, payload not counted (0 on a floor, about 0.4 on a "
              "wall, 1 under a ceiling)"},
             &enabled);
    a->Visit({"gain_m", "m", "K_P: crouch per unit of pull over weight", Range::NonNegative()},
             &pull.gain);
    a->Visit({"threshold", "", "P_0: pull over weight below which the body stands"},
             &pull.threshold);
    a->Visit({"delay_s", "s", "transmission delay of the pull", Range::NonNegative()},
             &pull.delay_s);
    a->Visit({"max_crouch_m", "m", "the largest crouch", Range::Closed(0, 0.03)}, &max_crouch_m);
    a->Visit({"time_constant_s", "s", "time constant with which the body follows the crouch",
              Range::Positive()},
             &time_constant_s);
  }
};

// Throws std::invalid_argument naming the field unless every field is finite and in range.
void Validate(const PostureParams& params, double dt_s, std::string_view name = "posture");

class PostureReflex {
 public:
  // Throws std::invalid_argument via Validate().
  PostureReflex(const PostureParams& params, double dt_s);

  // One control period: the pull over weight P; returns the crouch c (m). Never allocates.
  double Update(double pull_over_weight);
  void Reset();

  const PostureParams& params() const { return params_; }
  double crouch_m() const { return crouch_m_; }

 private:
  PostureParams params_;
  GtoReflex law_;
  double keep_;  // exp(−dt/τ)
  double crouch_m_ = 0.0;
};

// The gripping-shear targets of force tracking. Each directional pad i has a unit gripping
// direction g_i (world), its gripping shear F_t,i = f_i·g_i and a shear it keeps, k_i: a
// sharing pad's least need (its pull over tan α*, or a set least grasp), a pad being let go
// what it keeps of its shear. What the pads carry beyond that is shared equally among the
// n sharing pads, whose targets are
//   common direction (every g_i the same in its pad's frame: a wall):
//     F*_t,i = k_i + Σ_j (F_t,j − k_j) / n                 a scalar along that direction;
//   different directions (pads opposed in pairs under a ceiling):
//     F*_t,i = k_i + g_i·Σ_j (F_t,j − k_j)·g_j / n          the net force's vector.
// With opposed pads the gripping shears are mostly internal forces, which the scalar sum
// would count as load to share: two pads squeezing each other at any force would be on
// target. The vector sum sees only the net force, so they are driven to k_i each.
struct GripShare {
  bool active = false;   // attached and tracked
  bool shares = false;   // takes a share (false: being let go)
  Eigen::Vector3d grip = Eigen::Vector3d::Zero();  // g_i, unit, world
  double shear_n = 0.0;  // F_t,i
  double keep_n = 0.0;   // k_i
};
// Writes target_n[i] for every active sharing pad of pads[0, count) (others untouched);
// returns n. Pure, allocation-free.
int GripShearTargets(const GripShare* pads, int count, bool common_direction, double* target_n);

}  // namespace climbsim::reflex

#endif  // CLIMBSIM_REFLEX_LOAD_SHARING_H_
