#include "reflex/check.h"

#include <cmath>
#include <stdexcept>

#include "reflex/laws.h"

namespace climbsim::reflex::internal {
namespace {

// Longest duration held as a sample count: far below INT_MAX so that products stay in range.
constexpr double kMaxDurationSamples = 1e8;

}  // namespace

std::string Requirement(std::string_view requirement, double value) {
  return "must be " + std::string(requirement) + ", got " + keys::FormatValue(value);
}

void ThrowInvalid(std::string_view path, std::string_view requirement, double value) {
  throw std::invalid_argument(std::string(path) + " " + Requirement(requirement, value));
}

void CheckPeriod(double dt_s) {
  if (!std::isfinite(dt_s) || dt_s <= 0.0) ThrowInvalid("dt_s", "finite and > 0", dt_s);
}

std::string DurationProblem(double duration_s, double dt_s, bool at_least_one) {
  if (!std::isfinite(duration_s) || duration_s < 0.0) {
    return Requirement("finite and >= 0", duration_s);
  }
  const double samples = duration_s / dt_s;
  if (samples > kMaxDurationSamples) {
    return Requirement("at most " + keys::FormatValue(kMaxDurationSamples * dt_s) +
                           " s (1e8 control periods of dt_s = " + keys::FormatValue(dt_s) + " s)",
                       duration_s);
  }
  if (at_least_one && std::lround(samples) < 1) {
    return Requirement("at least one control period (dt_s = " + keys::FormatValue(dt_s) + " s)",
                       duration_s);
  }
  return "";
}

std::string DelayProblem(double delay_s, double dt_s) {
  if (!std::isfinite(delay_s) || delay_s < 0.0) return Requirement("finite and >= 0", delay_s);
  const double samples = delay_s / dt_s;
  if (!(samples < kMaxDelaySamples + 0.5)) {
    return Requirement("at most " + std::to_string(kMaxDelaySamples) +
                           " control periods (dt_s = " + keys::FormatValue(dt_s) + " s)",
                       delay_s);
  }
  return "";
}

int DurationToSamples(std::string_view path, double duration_s, double dt_s, bool at_least_one) {
  CheckPeriod(dt_s);
  if (const std::string problem = DurationProblem(duration_s, dt_s, at_least_one);
      !problem.empty()) {
    throw std::invalid_argument(std::string(path) + " " + problem);
  }
  return static_cast<int>(std::lround(duration_s / dt_s));
}

void ThrowingChecker::Fail(std::string_view key, const std::string& message) const {
  throw std::invalid_argument(keys::KeyPath(name_, key) + " " + message);
}

}  // namespace climbsim::reflex::internal
