// Private to climbsim_reflex (not part of the API, which is reflex.h): what the reflexes check
// beyond their keys' declared ranges (keys::Validate), the fit of a duration or a delay to the
// control period, and the messages' wording
//   "<name>.<field> must be <requirement>, got <value>".
#ifndef CLIMBSIM_REFLEX_CHECK_H_
#define CLIMBSIM_REFLEX_CHECK_H_

#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>

#include "keys/keys.h"

namespace climbsim::reflex::internal {

// "must be <requirement>, got <value>" (the value as keys::FormatValue prints it).
std::string Requirement(std::string_view requirement, double value);

[[noreturn]] void ThrowInvalid(std::string_view path, std::string_view requirement, double value);

void CheckPeriod(double dt_s);  // "dt_s must be finite and > 0"

// What a duration (finite, >= 0, at most 1e8 control periods; with at_least_one, not shorter
// than half a period) lacks at the control period dt_s: a Requirement, or "" when it fits.
std::string DurationProblem(double duration_s, double dt_s, bool at_least_one);
// The same for a delay: finite, >= 0 and at most kMaxDelaySamples periods.
std::string DelayProblem(double delay_s, double dt_s);

// A duration as a whole number of control periods, rounded like the delays; throws
// std::invalid_argument "<path> <DurationProblem>" unless it fits.
int DurationToSamples(std::string_view path, double duration_s, double dt_s, bool at_least_one);

// A sensor value as the laws take it: a non-finite one becomes 0 ("no stretch", "no load") and
// is counted in *count.
inline double Sanitize(double x, int64_t* count) {
  if (std::isfinite(x)) return x;
  ++*count;
  return 0.0;
}

// A Checker whose failures are std::invalid_argument "<name>.<key> <message>" (a module's own
// checks, as keys::Validate words a range).
class ThrowingChecker : public Checker {
 public:
  explicit ThrowingChecker(std::string_view name) : name_(name) {}
  [[noreturn]] void Fail(std::string_view key, const std::string& message) const override;
  bool Has(std::string_view) const override { return true; }

 private:
  std::string_view name_;
};

}  // namespace climbsim::reflex::internal

#endif  // CLIMBSIM_REFLEX_CHECK_H_
