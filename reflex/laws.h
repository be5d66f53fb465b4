// The reflex laws on one signal: the delay line, the spindle-like (stretch) law and the
// GTO-like (load) law, each with its parameters and their keys (reflex.h has the notation,
// the delays' rounding and the references).
#ifndef CLIMBSIM_REFLEX_LAWS_H_
#define CLIMBSIM_REFLEX_LAWS_H_

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string_view>
#include <vector>

#include "keys/keys.h"

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

// The range of a law's gain (spindle K_L and K_V, the GTO channels' K_F): >= 0, up to the
// largest double; however large, the leg clamps its summed offset (tests/hard).
inline Range GainRange() { return {0.0, std::numeric_limits<double>::max(), false, false}; }

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
  template <class A>
  void Serialize(A* a) {
    a->Visit({"length_gain", "rad/rad", "K_L", GainRange()}, &length_gain);
    a->Visit({"velocity_gain_s", "s", "K_V", GainRange()}, &velocity_gain_s);
    a->Visit({"length_threshold_rad", "rad", "L_0", Range::NonNegative()}, &length_threshold_rad);
    a->Visit({"velocity_threshold_rad_per_s", "rad/s", "V_0", Range::NonNegative()},
             &velocity_threshold_rad_per_s);
    a->Visit({"delay_s", "s", "transmission delay D", Range::NonNegative()}, &delay_s);
  }
};

// Throws std::invalid_argument ("<name>.<key> must be >= 0, got <value>") unless every key is
// in its declared range (Serialize) and the delay fits a DelayLine at dt_s.
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
  // The law's own check, any finite gain and threshold (a leg's channels and the posture
  // declare their keys by channel, with their own ranges).
  template <class A>
  void Serialize(A* a) {
    const Range finite{-std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
    a->Visit({"gain", "", "K_F", finite}, &gain);
    a->Visit({"threshold", "", "F_0", finite}, &threshold);
    a->Visit({"delay_s", "s", "transmission delay D", Range::NonNegative()}, &delay_s);
  }
};

// Throws std::invalid_argument unless every key is in its declared range (finite; the delay
// >= 0) and the delay fits a DelayLine at dt_s.
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

}  // namespace climbsim::reflex

#endif  // CLIMBSIM_REFLEX_LAWS_H_
