// climbsim::reflex: leg-level reflex laws and the leg-level climbing reflex state machine.
//
// Pure controller code: Eigen only, no MuJoCo. Every object here is built once from a Params
// struct and a fixed control period `dt_s`, validated in the constructor (bad Params throw
// std::invalid_argument naming the field and the value), and then updated once per control
// period with `Update(...)`, which never allocates and never throws. `Reset()` returns an
// object to the state it had just after construction.
//
// Notation (docs/control.md): [z]₊ = max(0, z); X(t−Δ) is X delayed by Δ.
//
// Delays. The controller runs at a fixed period dt_s, so a transmission delay Δ is held as a
// whole number of samples n = round(Δ / dt_s), rounded to nearest with ties away from zero
// (std::lround): Δ = 5 ms at dt = 2 ms becomes 3 samples (6 ms). The delay that acts is
// therefore n·dt_s, within dt_s/2 of the one asked for; `delay_samples()` reports it. A delay
// is rounded rather than rejected so that one Params set works at any control period (the
// optimiser may change dt_s); Geyer and Herr's 20/10/5 ms are exact at dt = 1 ms.
//
// Joint convention for the three joints of a leg, indexed by `Joint`:
//   hip_yaw   + moves the foot forward,
//   hip_pitch + lifts the foot away from the surface,
//   knee      + lifts the foot (flexion).
// So "press into the surface" is a negative hip_pitch/knee offset, "lift" a positive one.
// Every offset below is in rad and is added to the CPG's joint target.
//
// References.
//   Geyer H, Herr H (2010) IEEE TNSRE 18:263, a reflex-based neuromuscular biped: delayed
//     length (spindle) and force (GTO) feedback, positive force feedback in stance.
//   SCONE's reflex form: u = C0 + K_F·[F̃(t−Δ) − F0] + K_L·[l̃(t−Δ) − L0] + K_V·[ṽ(t−Δ) − V0]₊.
//   Ekeberg Ö, Pearson K (2005) J Neurophysiol 94:4256: a leg leaves stance when unloaded.
//   Tian Y et al. (2006) PNAS 103:19320: geckos detach by rolling their toes up and back
//     (hyperextension), which cuts adhesion by orders of magnitude; Autumn K et al. (2006)
//     J Exp Biol 209:3569 find the toe releases at a critical angle rather than like tape.
//   Kendall K (1975) J Phys D 8:1449: peeling needs far less force than a normal pull-off.
//   Dürr V (2001) J Exp Biol 204:1589: a leg that finds no ground searches in rhythmic loops.
#ifndef CLIMBSIM_REFLEX_REFLEX_H_
#define CLIMBSIM_REFLEX_REFLEX_H_

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

namespace climbsim::reflex {

// ---------------------------------------------------------------------------------------------
// Delays
// ---------------------------------------------------------------------------------------------

// Largest delay a DelayLine accepts, in samples (10 s at 1 ms): bounds the buffer size.
inline constexpr int kMaxDelaySamples = 10000;

// n = round(delay_s / dt_s), ties away from zero (see the file comment).
// Throws std::invalid_argument if dt_s is not finite and > 0, if delay_s is not finite and
// >= 0, or if n > kMaxDelaySamples. `name` prefixes the message (e.g. "spindle.delay_s").
int DelayToSamples(double delay_s, double dt_s, std::string_view name = "delay_s");

// A pure transmission delay of n samples over a ring buffer sized at construction:
//   y_k = x_{k−n} for k >= n,   y_k = fill for k < n,
// where k counts Update calls since construction or Reset. n = 0 passes the input through.
// The output is bit-for-bit the input n samples ago. Update never allocates.
class DelayLine {
 public:
  // Throws std::invalid_argument if delay_samples is outside [0, kMaxDelaySamples].
  explicit DelayLine(int delay_samples, double fill = 0.0);

  // Pushes x(t) and returns x(t − n·dt).
  double Update(double input);

  // Every stored sample back to `fill`.
  void Reset();

  int delay_samples() const { return static_cast<int>(buffer_.size()); }
  double fill() const { return fill_; }

 private:
  std::vector<double> buffer_;  // sized once; buffer_[head_] is the oldest sample
  int head_ = 0;
  double fill_ = 0.0;
};

// ---------------------------------------------------------------------------------------------
// Spindle-like (stretch) law
// ---------------------------------------------------------------------------------------------

// One joint's stretch reflex (Geyer and Herr 2010; SCONE's K_L, L0, K_V, V0 terms).
// Defaults suit the ~100 g gecko robot: a 0.2 rad stretch gives a 0.075 rad offset after 10 ms.
struct SpindleParams {
  double length_gain = 0.5;                   // K_L, rad of offset per rad of stretch, >= 0
  double velocity_gain_s = 0.02;              // K_V, rad of offset per rad/s of stretch rate, >= 0
  double length_threshold_rad = 0.05;         // L0, dead zone on the stretch, >= 0
  double velocity_threshold_rad_per_s = 0.5;  // V0, dead zone on the stretch rate, >= 0
  double delay_s = 0.01;                      // Δ, >= 0, rounded to whole samples
};

// Throws std::invalid_argument ("<name>.<field> must be ..., got <value>") unless every field is
// finite and >= 0 and the delay fits a DelayLine at dt_s.
void Validate(const SpindleParams& params, double dt_s, std::string_view name = "spindle");

// Stretch q̃ = q − q_target (rad) is the joint angle minus the CPG's target, NOT including
// reflex offsets (feeding the offset back into q̃ closes a positive loop of gain K_L);
// q̇ (rad/s) its rate. A joint has two antagonist spindles with the same Params, one stretched
// by q̃ > 0 and one by q̃ < 0. With the signed dead zone D(x, x0) = sign(x)·[|x| − x0]₊:
//
//   offset(t) = −K_L·D(q̃(t−Δ), L0) − K_V·D(q̇(t−Δ), V0)          (rad)
//
// so for q̃, q̇ >= 0 it is exactly −(K_L·[q̃(t−Δ) − L0]₊ + K_V·[q̇(t−Δ) − V0]₊): the target moves
// against the stretch, resisting it. The length and velocity terms clip independently.
// Non-finite inputs are replaced by 0 (and counted) before they enter the delay.
class SpindleReflex {
 public:
  // Throws std::invalid_argument via Validate().
  SpindleReflex(const SpindleParams& params, double dt_s);

  // Returns the target offset (rad) for this control period. Never allocates.
  double Update(double stretch_rad, double stretch_velocity_rad_per_s);
  void Reset();

  const SpindleParams& params() const { return params_; }
  int delay_samples() const { return stretch_delay_.delay_samples(); }
  // The two terms of the last Update, signed as in the offset: offset = length + velocity.
  double length_term_rad() const { return length_term_rad_; }
  double velocity_term_rad() const { return velocity_term_rad_; }
  // q̃(t−Δ) seen by the last Update (rad).
  double delayed_stretch_rad() const { return delayed_stretch_rad_; }
  // Number of non-finite inputs replaced by 0 since construction or Reset.
  int64_t nonfinite_inputs() const { return nonfinite_inputs_; }

 private:
  SpindleParams params_;
  DelayLine stretch_delay_;
  DelayLine velocity_delay_;
  double delayed_stretch_rad_ = 0.0;
  double length_term_rad_ = 0.0;
  double velocity_term_rad_ = 0.0;
  int64_t nonfinite_inputs_ = 0;
};

// ---------------------------------------------------------------------------------------------
// GTO-like (load) law
// ---------------------------------------------------------------------------------------------

// Force feedback (Geyer and Herr 2010; SCONE's K_F, F0 terms). The load is a pad normal load
// (N) or a joint torque (N·m), so the units follow the channel: for a pad, gain in rad/N and
// threshold in N. Defaults: a pad load 0.5 N above threshold gives a 0.1 rad offset.
struct GtoParams {
  double gain = 0.2;       // K_F, output per unit load (rad/N for a pad); any finite sign
  double threshold = 0.0;  // F0, in the load's unit; any finite value
  double delay_s = 0.01;   // Δ, >= 0, rounded to whole samples
};

// Throws std::invalid_argument unless every field is finite, the delay >= 0 and it fits.
// A negative gain is allowed here (negative force feedback, as Geyer and Herr's SOL→TA); the
// LegReflex's GTO channels require gain >= 0 (positive feedback: the stance-holding reflex).
void Validate(const GtoParams& params, double dt_s, std::string_view name = "gto");

// The GTO law on one sample, u = K_F·[F − F0]₊ (GtoReflex adds the delay and the checks;
// the corner manoeuvre applies it to a pad's utilisation as it is).
inline double GtoLaw(double load, double gain, double threshold) {
  return load > threshold ? gain * (load - threshold) : 0.0;
}

// The GTO's unload channel: a loaded leg yields, its servos' kp scaled by max(min, 1 − u).
inline double GtoUnloadKpFraction(double u, double min_kp_fraction) {
  return std::max(min_kp_fraction, 1.0 - u);
}

//   u(t) = K_F·[F̃(t−Δ) − F0]₊
// Positive force feedback (K_F > 0) keeps a loaded leg pressing. `loaded()` is the strict test
// F̃(t−Δ) > F0 on the same delayed sample: at F̃ = F0 exactly, u = 0 and the leg is unloaded.
// Non-finite inputs are replaced by 0 (and counted) before they enter the delay.
class GtoReflex {
 public:
  // Throws std::invalid_argument via Validate().
  GtoReflex(const GtoParams& params, double dt_s);

  // Returns u for this control period. Never allocates.
  double Update(double load);
  void Reset();

  const GtoParams& params() const { return params_; }
  int delay_samples() const { return load_delay_.delay_samples(); }
  bool loaded() const { return loaded_; }                // F̃(t−Δ) > F0 at the last Update
  double delayed_load() const { return delayed_load_; }  // F̃(t−Δ) at the last Update
  int64_t nonfinite_inputs() const { return nonfinite_inputs_; }

 private:
  GtoParams params_;
  DelayLine load_delay_;
  bool loaded_ = false;
  double delayed_load_ = 0.0;
  int64_t nonfinite_inputs_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Leg-level climbing reflexes
// ---------------------------------------------------------------------------------------------

// Joint indices in every 3-vector of this module.
enum Joint : int { kHipYaw = 0, kHipPitch = 1, kKnee = 2 };
inline constexpr int kLegJoints = 3;

// Press on touchdown (and on re-grip) until the pad attaches or a limit is reached.
// The offset ramps linearly from 1/n_ramp of full at the first period to full after ramp_s.
struct PreloadParams {
  bool enabled = true;                // the touchdown preload; re-grip presses even if false
  double hip_pitch_press_rad = 0.15;  // full press on hip pitch, >= 0, applied as −0.15 rad
  double knee_press_rad = 0.10;       // full press on the knee, >= 0, applied as −0.10 rad
  double ramp_s = 0.05;               // time to full press, >= 0 (0: full at once)
  double force_limit_n = 1.0;         // stop once the compressive preload reaches this, > 0
  double max_duration_s = 0.2;        // stop after this long, >= one control period
  // Fade of the press once the preload ends, >= 0 (0: at once). A press dropped at once on an
  // attach pulls the fresh pad off its surface by kp·press: harmless for a von Mises pad,
  // whose pull-off is σ_T·A, fatal for a directional one, which holds no pull before its
  // shear has built.
  double release_s = 0.0;
};

// Search when a swing ends without touchdown: reach further towards the surface, with a lift
// in each attempt so that the pad is re-placed rather than dragged. Attempt k = 0..N−1 runs
// for n_a samples; with s = (sample within the attempt)/n_a ∈ [0, 1) and the reach fraction
// ρ = (k + s)/N, which grows without jumps from 0 (the first period: no offset) towards 1:
//   hip_yaw   = +reach_yaw_rad·ρ
//   hip_pitch = −reach_pitch_rad·ρ + lift_rad·sin(π·s)
//   knee      = −reach_knee_rad·ρ  + lift_rad·sin(π·s)
// When the pad touches, the offset reached is held until the swing starts, then released
// linearly over release_s (as after the last attempt fails).
struct SearchParams {
  bool enabled = true;
  double reach_yaw_rad = 0.10;       // full forward reach, >= 0
  double reach_pitch_rad = 0.20;     // full extension towards the surface on hip pitch, >= 0
  double reach_knee_rad = 0.10;      // full extension towards the surface on the knee, >= 0
  double lift_rad = 0.08;            // peak lift within each attempt, >= 0
  double attempt_duration_s = 0.15;  // one attempt, >= one control period
  int max_attempts = 3;              // N >= 1
  double release_s = 0.1;            // fade of the held offset, >= 0 (0: at once)
};

// Peel at swing onset while still attached. The leg's phase is held at the start of its
// swing (hold_phase) while the pad holds, and the offsets rise with the smooth step
// r(t) = 3u² − 2u³, u = min(1, t / ramp_s), t the time since swing onset:
//   hip_yaw = hip_yaw_rad·r    hip_pitch = +hip_pitch_lift_rad·r    knee = +knee_lift_rad·r
// A negative hip yaw draws the foot back, so the pad is pulled nearly along the surface from
// the top of its ankle post: the pull puts a moment on the pad that lifts its front (toe)
// edge first, the way a gecko peels its toes from the tips (Tian et al. 2006; Autumn et al.
// 2006 find the release at a critical angle). Over a bonded b×h pad the edge stress is
// F/(b·h) + 6·M/(b·h²) (docs/design.md §3), so the edge row breaks and the crack runs across the
// pad at a pull far below the normal pull-off σ_T·b·h (Kendall 1975; `climbsim pulloff`
// with --arm-m shows it). The peel ends when the pad lets go (peel_end, detached) or after
// max_duration_s (peel_end, time_limit); the offsets then fade to zero over release_s while
// the swing goes on. Which edge a pull lifts depends on the robot (mjcf/README.md, "Feet").
struct PeelParams {
  bool enabled = true;
  double hip_yaw_rad = -0.2;         // signed: negative draws the foot back, the pull that peels
  double hip_pitch_lift_rad = 0.05;  // lift at full peel, >= 0
  double knee_lift_rad = 0.05;       // knee flexion at full peel, >= 0
  double ramp_s = 0.2;               // time to full peel (smooth step), > 0
  double max_duration_s = 0.6;       // give up (peel_end, time_limit), >= one control period
  double release_s = 0.1;            // fade of the offsets once the peel ends, >= 0
  // A foot with an ACTIVE RELEASE (a toe-peeling tendon as on Stickybot, a membrane that
  // buckles the adhesive): the pad is let go by its own mechanism, not torn by the leg. While
  // the peel holds the phase, the leg asks the other pads to take its pad's load
  // (LegReflexOutput::unload_pad, for the load sharing), and lets the pad go
  // (release_pad) once the force on it is at most release_load_n, or when max_duration_s is
  // up. Released unloaded, the pad drops little load on the others at once; a torn pad drops
  // the pull that peels it, its whole capacity.
  bool active_release = false;
  double release_load_n = 0.1;  // >= 0
};

// Re-grip: a pad that loses bonds during stance while it was attached (it should be holding)
// is pressed again with the preload profile (PreloadParams, even if preload.enabled is false),
// and the other legs are asked to stay in stance for hold_others_s.
// A pad that lets go ENTIRELY in stance (bonds all lost: overload, a failure) cannot attach
// again by being pressed: adhesion asks for a new touchdown (adhesion/README.md, "Attachment").
// So the re-grip then re-places the foot: a lift of lift_rad on hip pitch and knee,
// lift·sin²(π·s) over replace_s (s from 0 to 1), holding the leg in stance; the foot that
// comes down touches down again and the touchdown preload attaches it.
// The same re-place serves a foot that touched down in stance and has not attached
// replace_after_s later (its landing was rejected: on an edge, too fast): adhesion would not
// try again before the pad leaves the surface.
struct RegripParams {
  bool enabled = true;
  double hold_others_s = 0.2;  // how long hold_others stays raised, >= 0
  double lift_rad = 0.08;      // re-place lift on hip pitch and knee, >= 0 (0: press only)
  double replace_s = 0.25;     // duration of the re-place, >= one control period
  double replace_after_s = 0.3;  // a touch without attach this long is re-placed, >= 0
                                 // (0: never)
  double shift_rad = 0.05;  // a re-placed rejected landing moves this much along hip yaw,
                            // ahead and behind in turn, >= 0 (see LegReflex::Regrip)
};

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

// GTO load reflexes (Ekeberg and Pearson 2005's load rule; Geyer and Herr 2010's positive
// force feedback), four channels on the pad:
//  hold:    F̃ = the adhesive load normal_load_n (or, with count_compression, the larger of
//           |normal_load_n| and preload_n). Loaded (F̃(t−Δ) > F0) ⇒ hold_stance and press:
//           hip_pitch −= min(u, hold_max_offset); unloaded ⇒ the leg may swing. Only for a
//           pad that is not attached (a foot that can still move: floors), unless
//           load_attached: on a welded foot the press is only internal force between the pads
//           (docs/control.md "Reflexes on a closed chain"), and on a wall the front pads hang in
//           tension all the time, so the hold stalled the gait; the support channel decides
//           for attached pads instead.
//  press:   F̃ = the compressive preload_n. While the pad is building its bond (stance,
//           attached, bonded_fraction < full_bond_fraction): hip_pitch −= min(u, press_max).
//  unload:  F̃ = the pad's utilisation U (peak bond demand over threshold, 1 breaks). While
//           the pad is attached in stance, u = K_U·[U(t−Δ) − U0]₊ lowers the leg's servo
//           stiffness: kp_fraction ×= max(unload_min_kp_fraction, 1 − u). The leg yields and
//           the pads with margin take its load (load sharing through stiffness).
//  support: F̃ = support_utilisation, the largest utilisation among the pads that carry this
//           leg's swing. Above its threshold (delayed) a stance leg holds stance: lifting it
//           would shift its load onto pads already near their limit.
// Load sharing among the attached pads is the GTO's robot-level channel: LoadSharing above,
// which the simulator runs across the legs.
// With require_partner_attached, a leg whose partner is not attached also holds stance (lifting
// it would leave the pair without a grip).
struct GtoHoldParams {
  bool enabled = true;
  GtoParams hold{.gain = 0.2, .threshold = 0.15, .delay_s = 0.01};  // rad/N, N, s; gain >= 0
  double hold_max_offset_rad = 0.15;                                // >= 0
  bool count_compression = false;  // true on floors: a weight-bearing leg is loaded too
  bool load_attached = false;     // the hold channel acts on an attached (welded) pad too
  GtoParams press{.gain = 0.1, .threshold = 0.05, .delay_s = 0.01};  // rad/N, N, s; gain >= 0
  double press_max_offset_rad = 0.10;                                // >= 0
  double full_bond_fraction = 0.95;  // bond counts as built from here, in (0, 1]
  bool require_partner_attached = true;
  GtoParams unload{.gain = 2.0, .threshold = 0.8, .delay_s = 0.01};  // 1/utilisation, -, s
  double unload_min_kp_fraction = 0.2;                               // in (0, 1]
  GtoParams support{.gain = 1.0, .threshold = 0.8, .delay_s = 0.01};  // gain unused; -, s
};

// The spindle law on each joint, indexed by Joint. Where the stretch of a joint means what:
//  * foot in the air (swing, or a stance foot searching): a stretch beyond
//    swing_threshold_rad on any joint means the leg is
//    blocked or tripping (Forssberg's stumbling-corrective reaction: lift and re-place). With
//    s = max_j [|q̃_j(t−Δ)| − swing_threshold]₊ the foot is lifted: hip_pitch += K_L,pitch·s,
//    knee += K_L,knee·s. (Resisting every stretch in swing, the law below, set the free foot
//    chattering against its own servo lag with the 10 ms delay.)
//  * with `resist` (off by default), a stance foot in the air gets instead the law of
//    SpindleReflex on each joint, against the stretch. Off because resisting the lag of a
//    commanded motion speeds it up: a searching foot hit the ceiling at 0.45 m/s (too fast to
//    attach) and the gait stalled. A foot that touches without a bond gets nothing: the
//    preload presses it, and resisting the contact's stretch bounced the spider's feet off
//    the wall (it fell).
//  * pad attached (stance or a peel): no offset (a welded foot cannot follow one; it would
//    only load the other pads). In stance a delayed stretch |q̃(t−Δ)| beyond stance_band_rad
//    on any joint means the body is being pushed: the leg asks every leg to stay in stance
//    (hold_others) while it lasts and for hold_s after, so that no pad leaves the surface
//    while the body is pushed.
struct LegSpindleParams {
  bool enabled = true;
  std::array<SpindleParams, kLegJoints> joints{};
  double swing_threshold_rad = 0.3;  // >= 0
  bool resist = false;               // the per-joint law on a stance foot in the air
  double stance_band_rad = 0.15;     // >= 0
  double hold_s = 0.2;               // >= 0
};

// Stance compliance (docs/control.md, "Reflexes on a closed chain"): the servos' stiffness is
// scheduled by phase, full in swing (accurate placement) and lowered to stance_kp_fraction
// while the pad is attached in stance, so that welded feet and the body settle without
// internal force. LegReflexOutput::kp_fraction (per joint, in (0, 1]) multiplies each
// servo's kp; it moves towards its target at 1/ramp_s per second (no jump in torque).
struct ComplianceParams {
  bool enabled = false;  // off by default: see docs/climbing.md for what it did on the wall
  double stance_kp_fraction = 0.5;  // in (0, 1]
  double ramp_s = 0.02;             // >= 0 (0: at once)
};

struct LegReflexParams {
  PreloadParams preload;
  SearchParams search;
  PeelParams peel;
  RegripParams regrip;
  GtoHoldParams gto;
  LegSpindleParams spindle;
  ComplianceParams compliance;
  double max_offset_rad = 0.4;  // |summed offset| per joint is clamped to this, > 0
};

// Throws std::invalid_argument ("<name>.<reflex>.<field> must be ..., got <value>") on the
// first bad field: non-finite numbers, negative gains, magnitudes or times, fractions out of
// range, durations shorter than one control period where one is needed.
void Validate(const LegReflexParams& params, double dt_s, std::string_view name = "leg_reflex");

// What the simulator tells a leg once per control period.
struct LegSensing {
  bool stance = false;           // the CPG's phase for this leg: true = stance, false = swing
  double phase_progress = 0.0;   // progress within the current phase, 0..1 (clamped)
  bool touching = false;         // the pad touches a surface
  bool attached = false;         // the pad is attached (weld on)
  double bonded_fraction = 0.0;  // bonded share of the pad, 0..1
  double normal_load_n = 0.0;    // pad normal force, N; + pulls the pad off (adhesive load)
  double preload_n = 0.0;        // compressive contact force pressing the pad on, N, >= 0
  double load_n = 0.0;           // size of the force on the attached pad, |F|, N
  bool bonds_lost = false;       // the pad lost bonds this period
  // q − q_cpg per Joint; the spindles see it less the other reflexes' offsets of the last
  // period (the stretch from the target the leg was given).
  Eigen::Vector3d stretch_rad = Eigen::Vector3d::Zero();
  Eigen::Vector3d stretch_velocity_rad_per_s = Eigen::Vector3d::Zero();
  bool partner_attached = true;  // the partner leg's pad is attached
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
  bool hold_others = false;  // re-grip, or a pushed stance leg: every leg should stay in stance
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
  bool peeling = false;
  bool released = false;  // an active release let the pad go in this swing
  int peel_samples = 0;                              // periods since the swing onset
  Eigen::Vector3d peel_offset_rad = Eigen::Vector3d::Zero();  // when the peel ended
  int peel_release_left = 0;
  int regrip_left = 0;  // periods of hold_others left
  int replace_left = 0;  // periods of a re-place (lift and put down) left
  bool replace_lifted = false;  // the re-placed foot has left the surface
  int unattached_touch = 0;     // periods in stance without a bond since the foot touched
  int replace_count = 0;        // re-places of rejected landings in this stance
  double replace_shift = 0.0;   // their hip-yaw shift (rad), held until the swing
  double replace_shift_from = 0.0;
  bool gto_holding = false;
  bool gto_unloading = false;
  bool spindle_active = false;
  int pushed_left = 0;        // periods of the spindle's hold_others left
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
//            |                                 | hold_phase           | max time (time_limit)
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
//            | stance_band_rad (pushed)        | offset)              | hold_s
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
  Eigen::Vector3d Preload(const Sensed& in, LegReflexOutput* out);
  Eigen::Vector3d Peel(const Sensed& in, LegReflexOutput* out);
  Eigen::Vector3d Gto(const Sensed& in, const Laws& laws, LegReflexOutput* out);
  Eigen::Vector3d Spindle(const Sensed& in, const Laws& laws, LegReflexOutput* out);
  void Compliance(const Sensed& in, LegReflexOutput* out);
  void StartSearchRelease();
  void Finish(const Sensed& in, const Eigen::Vector3d& offset, LegReflexOutput* out);
};

}  // namespace climbsim::reflex

#endif  // CLIMBSIM_REFLEX_REFLEX_H_
