// The leg's parameters checked as a whole: each reflex's keys against their declaration
// (keys::Validate), then their fit to the control period.
#include "reflex/leg_params.h"

#include <cmath>
#include <string>

#include "keys/keys.h"
#include "reflex/check.h"

namespace climbsim::reflex {
namespace {

using internal::DelayProblem;
using internal::DurationProblem;

// checker.Fail(key, problem) unless the problem is "" (the value fits).
void Require(const Checker& checker, std::string_view key, const std::string& problem) {
  if (!problem.empty()) checker.Fail(key, problem);
}

// The foot's reflexes: their durations in whole periods; the search's attempts in all.
void CheckFootPeriods(const LegReflexParams& p, double dt_s, const Checker& c) {
  Require(c, "preload.ramp_s", DurationProblem(p.preload.ramp_s, dt_s, false));
  Require(c, "preload.max_duration_s", DurationProblem(p.preload.max_duration_s, dt_s, true));
  Require(c, "preload.release_s", DurationProblem(p.preload.release_s, dt_s, false));
  Require(c, "search.attempt_duration_s", DurationProblem(p.search.attempt_duration_s, dt_s, true));
  const double attempt = static_cast<double>(std::lround(p.search.attempt_duration_s / dt_s));
  if (attempt * p.search.max_attempts > 1e8) {
    c.Fail(
        "search.max_attempts",
        internal::Requirement("such that max_attempts * attempt_duration_s <= 1e8 control periods",
                              p.search.max_attempts));
  }
  Require(c, "search.release_s", DurationProblem(p.search.release_s, dt_s, false));
  Require(c, "peel.max_duration_s", DurationProblem(p.peel.max_duration_s, dt_s, true));
  Require(c, "peel.release_s", DurationProblem(p.peel.release_s, dt_s, false));
  Require(c, "regrip.hold_others_s", DurationProblem(p.regrip.hold_others_s, dt_s, false));
  Require(c, "regrip.replace_s", DurationProblem(p.regrip.replace_s, dt_s, true));
  Require(c, "regrip.replace_after_s", DurationProblem(p.regrip.replace_after_s, dt_s, false));
}

}  // namespace

void CheckControlPeriod(const LegReflexParams& p, double dt_s, const Checker& c,
                        bool one_spindle_law) {
  internal::CheckPeriod(dt_s);
  CheckFootPeriods(p, dt_s, c);
  Require(c, "gto.hold_delay_s", DelayProblem(p.gto.hold.delay_s, dt_s));
  Require(c, "gto.press_delay_s", DelayProblem(p.gto.press.delay_s, dt_s));
  Require(c, "gto.unload_delay_s", DelayProblem(p.gto.unload.delay_s, dt_s));
  Require(c, "gto.support_delay_s", DelayProblem(p.gto.support.delay_s, dt_s));
  for (int j = 0; j < (one_spindle_law ? 1 : kLegJoints); ++j) {
    Require(c,
            one_spindle_law ? std::string("spindle.delay_s")
                            : "spindle.joints[" + std::to_string(j) + "].delay_s",
            DelayProblem(p.spindle.joints[j].delay_s, dt_s));
  }
  Require(c, "spindle.hold_s", DurationProblem(p.spindle.hold_s, dt_s, false));
  Require(c, "spindle.max_hold_s", DurationProblem(p.spindle.max_hold_s, dt_s, false));
  Require(c, "compliance.ramp_s", DurationProblem(p.compliance.ramp_s, dt_s, false));
}

void Validate(const LegReflexParams& params, double dt_s, std::string_view name) {
  internal::CheckPeriod(dt_s);
  keys::Validate(params.preload, keys::KeyPath(name, "preload"));
  keys::Validate(params.search, keys::KeyPath(name, "search"));
  keys::Validate(params.peel, keys::KeyPath(name, "peel"));
  keys::Validate(params.regrip, keys::KeyPath(name, "regrip"));
  keys::Validate(params.gto, keys::KeyPath(name, "gto"));
  const std::string spindle = keys::KeyPath(name, "spindle");
  for (int j = 0; j < kLegJoints; ++j) {
    keys::Validate(params.spindle.joints[j], spindle + ".joints[" + std::to_string(j) + "]");
  }
  keys::Validate(params.spindle, spindle);
  keys::Validate(params.compliance, keys::KeyPath(name, "compliance"));
  keys::Validate(params, name);  // max_offset_rad
  CheckControlPeriod(params, dt_s, internal::ThrowingChecker(name));
}

}  // namespace climbsim::reflex
