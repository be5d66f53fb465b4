// Private to climbsim_reflex (not part of the API, which is reflex.h): the checks that
// Validate() uses, each throwing std::invalid_argument as
//   "<name>.<field> must be <requirement>, got <value>".
#ifndef CLIMBSIM_REFLEX_CHECK_H_
#define CLIMBSIM_REFLEX_CHECK_H_

#include <string>
#include <string_view>

namespace climbsim::reflex::internal {

// A double as printed in messages ("%.9g": -3, 0.1, nan, inf).
std::string FormatValue(double value);

// "<name>.<field>", or "<field>" when name is empty.
std::string FieldPath(std::string_view name, std::string_view field);

[[noreturn]] void ThrowInvalid(std::string_view path, std::string_view requirement, double value);

void CheckFinite(std::string_view path, double value);
void CheckNonNegative(std::string_view path, double value);  // finite and >= 0
void CheckPositive(std::string_view path, double value);     // finite and > 0
// finite and in [low, high] (or (low, high] when open_low, [low, high) when open_high).
void CheckRange(std::string_view path, double value, double low, double high, bool open_low = false,
                bool open_high = false);
void CheckPeriod(double dt_s);  // "dt_s must be finite and > 0"

// A duration (finite, >= 0) as a whole number of control periods, rounded like the delays.
// With at_least_one, a duration shorter than half a period is rejected.
int DurationToSamples(std::string_view path, double duration_s, double dt_s, bool at_least_one);

}  // namespace climbsim::reflex::internal

#endif  // CLIMBSIM_REFLEX_CHECK_H_
