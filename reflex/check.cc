#include "reflex/check.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace climbsim::reflex::internal {
namespace {

// Longest duration held as a sample count: far below INT_MAX so that products stay in range.
constexpr double kMaxDurationSamples = 1e8;

}  // namespace

std::string FormatValue(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.9g", value);
  return text;
}

std::string FieldPath(std::string_view name, std::string_view field) {
  std::string path(name);
  if (!path.empty()) path += '.';
  path += field;
  return path;
}

void ThrowInvalid(std::string_view path, std::string_view requirement, double value) {
  throw std::invalid_argument(std::string(path) + " must be " + std::string(requirement) +
                              ", got " + FormatValue(value));
}

void CheckFinite(std::string_view path, double value) {
  if (!std::isfinite(value)) ThrowInvalid(path, "finite", value);
}

void CheckNonNegative(std::string_view path, double value) {
  if (!std::isfinite(value) || value < 0.0) ThrowInvalid(path, "finite and >= 0", value);
}

void CheckPositive(std::string_view path, double value) {
  if (!std::isfinite(value) || value <= 0.0) ThrowInvalid(path, "finite and > 0", value);
}

void CheckRange(std::string_view path, double value, double low, double high, bool open_low,
                bool open_high) {
  const bool below = open_low ? !(value > low) : !(value >= low);
  const bool above = open_high ? !(value < high) : !(value <= high);
  if (!std::isfinite(value) || below || above) {
    const std::string requirement = "in " + std::string(open_low ? "(" : "[") + FormatValue(low) +
                                    ", " + FormatValue(high) + (open_high ? ")" : "]");
    ThrowInvalid(path, requirement, value);
  }
}

void CheckPeriod(double dt_s) { CheckPositive("dt_s", dt_s); }

int DurationToSamples(std::string_view path, double duration_s, double dt_s, bool at_least_one) {
  CheckPeriod(dt_s);
  CheckNonNegative(path, duration_s);
  const double samples = duration_s / dt_s;
  if (samples > kMaxDurationSamples) {
    ThrowInvalid(path,
                 "at most " + FormatValue(kMaxDurationSamples * dt_s) +
                     " s (1e8 control periods of dt_s = " + FormatValue(dt_s) + " s)",
                 duration_s);
  }
  const int n = static_cast<int>(std::lround(samples));
  if (at_least_one && n < 1) {
    ThrowInvalid(path, "at least one control period (dt_s = " + FormatValue(dt_s) + " s)",
                 duration_s);
  }
  return n;
}

}  // namespace climbsim::reflex::internal
