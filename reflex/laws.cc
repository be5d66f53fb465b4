// Delay line, spindle-like and GTO-like laws (equations in laws.h).
#include <cmath>
#include <stdexcept>
#include <string>

#include "keys/keys.h"
#include "reflex/check.h"
#include "reflex/laws.h"

namespace climbsim::reflex {
namespace {

// D(x, x0) = sign(x)·[|x| − x0]₊ for x0 >= 0.
double SignedDeadZone(double x, double x0) {
  if (x > x0) return x - x0;
  if (x < -x0) return x + x0;
  return 0.0;
}

using internal::Sanitize;

}  // namespace

// Round to the nearest sample, ties away from zero; bounded so that the buffer stays small.
int DelayToSamples(double delay_s, double dt_s, std::string_view name) {
  internal::CheckPeriod(dt_s);
  if (const std::string problem = internal::DelayProblem(delay_s, dt_s); !problem.empty()) {
    throw std::invalid_argument(std::string(name) + " " + problem);
  }
  return static_cast<int>(std::lround(delay_s / dt_s));
}

DelayLine::DelayLine(int delay_samples, double fill) : fill_(fill) {
  if (delay_samples < 0 || delay_samples > kMaxDelaySamples) {
    throw std::invalid_argument("DelayLine delay_samples must be in [0, " +
                                std::to_string(kMaxDelaySamples) + "], got " +
                                std::to_string(delay_samples));
  }
  buffer_.assign(static_cast<size_t>(delay_samples), fill);
}

// buffer_[head_] holds x_{k−n}: read it, overwrite it with x_k, advance.
double DelayLine::Update(double input) {
  if (buffer_.empty()) return input;
  const double output = buffer_[head_];
  buffer_[head_] = input;
  head_ = head_ + 1 == static_cast<int>(buffer_.size()) ? 0 : head_ + 1;
  return output;
}

void DelayLine::Reset() {
  for (double& x : buffer_) x = fill_;
  head_ = 0;
}

// The ranges as declared (Serialize), then the delay's fit to dt_s.
void Validate(const SpindleParams& params, double dt_s, std::string_view name) {
  internal::CheckPeriod(dt_s);
  keys::Validate(params, name);
  DelayToSamples(params.delay_s, dt_s, keys::KeyPath(name, "delay_s"));
}

void Validate(const GtoParams& params, double dt_s, std::string_view name) {
  internal::CheckPeriod(dt_s);
  keys::Validate(params, name);
  DelayToSamples(params.delay_s, dt_s, keys::KeyPath(name, "delay_s"));
}

namespace {
// The parameters, validated (throws), for a constructor's initialiser list.
template <class Params>
const Params& Validated(const Params& params, double dt_s) {
  Validate(params, dt_s);
  return params;
}
}  // namespace

SpindleReflex::SpindleReflex(const SpindleParams& params, double dt_s)
    : params_(Validated(params, dt_s)),
      stretch_delay_(DelayToSamples(params.delay_s, dt_s)),
      velocity_delay_(DelayToSamples(params.delay_s, dt_s)) {}

// offset = −K_L·D(q̃(t−Δ), L0) − K_V·D(q̇(t−Δ), V0); "0.0 −" keeps a silent term at +0.
double SpindleReflex::Update(double stretch_rad, double stretch_velocity_rad_per_s) {
  const double q = stretch_delay_.Update(Sanitize(stretch_rad, &nonfinite_inputs_));
  delayed_stretch_rad_ = q;
  const double v = velocity_delay_.Update(Sanitize(stretch_velocity_rad_per_s, &nonfinite_inputs_));
  length_term_rad_ = 0.0 - params_.length_gain * SignedDeadZone(q, params_.length_threshold_rad);
  velocity_term_rad_ =
      0.0 - params_.velocity_gain_s * SignedDeadZone(v, params_.velocity_threshold_rad_per_s);
  return length_term_rad_ + velocity_term_rad_;
}

void SpindleReflex::Reset() {
  stretch_delay_.Reset();
  velocity_delay_.Reset();
  length_term_rad_ = 0.0;
  velocity_term_rad_ = 0.0;
  delayed_stretch_rad_ = 0.0;
  nonfinite_inputs_ = 0;
}

GtoReflex::GtoReflex(const GtoParams& params, double dt_s)
    : params_(Validated(params, dt_s)), load_delay_(DelayToSamples(params.delay_s, dt_s)) {}

// u = K_F·[F̃(t−Δ) − F0]₊; loaded ⇔ F̃(t−Δ) > F0 (so F̃ − F0 > 0 exactly when loaded).
double GtoReflex::Update(double load) {
  delayed_load_ = load_delay_.Update(Sanitize(load, &nonfinite_inputs_));
  loaded_ = delayed_load_ > params_.threshold;
  return GtoLaw(delayed_load_, params_.gain, params_.threshold);
}

void GtoReflex::Reset() {
  load_delay_.Reset();
  loaded_ = false;
  delayed_load_ = 0.0;
  nonfinite_inputs_ = 0;
}

}  // namespace climbsim::reflex
