#include "reflex/reflex_params.h"

#include "reflex/check.h"

namespace climbsim::reflex {

LegReflexParams ReflexParams::Leg() const {
  LegReflexParams p;
  p.preload = preload;
  p.search = search;
  p.peel = peel;
  p.regrip = regrip;
  p.gto = gto;
  p.spindle = spindle;
  p.spindle.joints = {spindle.law, spindle.law, spindle.law};
  p.compliance = compliance;
  p.max_offset_rad = max_offset_rad;
  return p;
}

void ReflexParams::CheckControlPeriod(double dt_s, const Checker& checker) const {
  reflex::CheckControlPeriod(Leg(), dt_s, checker, /*one_spindle_law=*/true);
  if (tail) CheckTailControlPeriod(*tail, dt_s, checker, "tail.");
  if (!PostureOn()) return;  // the posture's law is built only when it acts
  if (const std::string problem = internal::DelayProblem(gto.posture.pull.delay_s, dt_s);
      !problem.empty()) {
    checker.Fail("gto.posture.delay_s", problem);
  }
}

}  // namespace climbsim::reflex
