#include <cmath>
#include <string>

#include "cpg/cpg.h"
#include "cpg/internal/checks.h"

namespace climbsim::cpg {
namespace {

using internal::kPi;
using internal::kTwoPi;

void CheckDutyFactor(double duty_factor) {
  if (!(duty_factor > 0.0 && duty_factor < 1.0)) {
    internal::Fail("LegShape.duty_factor", "in (0, 1)", duty_factor);
  }
}

void CheckLiftShare(double lift_share) {
  if (!(lift_share >= 0.0 && lift_share < 0.5)) {
    internal::Fail("LegShape.lift_share", "in [0, 0.5)", lift_share);
  }
}

// 3u² − 2u³ on [0, 1], 0 below, 1 above.
double SmoothStep(double u) {
  u = std::fmin(1.0, std::fmax(0.0, u));
  return u * u * (3.0 - 2.0 * u);
}

}  // namespace

void ValidateLegShape(const LegShape& shape) {
  CheckDutyFactor(shape.duty_factor);
  CheckLiftShare(shape.lift_share);
  for (int k = 0; k < 3; ++k) {
    internal::CheckFinite("LegShape.stride_rad[" + std::to_string(k) + "]", shape.stride_rad[k]);
    internal::CheckFinite("LegShape.lift_rad[" + std::to_string(k) + "]", shape.lift_rad[k]);
  }
}

LegCommand ShapeLeg(const LegShape& shape, double theta_rad, double amplitude) {
  CheckDutyFactor(shape.duty_factor);
  CheckLiftShare(shape.lift_share);
  internal::CheckFinite("ShapeLeg: theta_rad", theta_rad);
  const double theta = internal::WrapTwoPi(theta_rad);
  const double swing_end_rad = kTwoPi * (1.0 - shape.duty_factor);
  LegCommand command{};
  if (theta < swing_end_rad) {
    const double p = theta / swing_end_rad;
    command.stance = false;
    command.progress = p;
    if (shape.lift_share > 0.0) {
      const double a = shape.lift_share;
      command.stride = 2.0 * SmoothStep((p - a) / (1.0 - 2.0 * a)) - 1.0;
      command.lift = SmoothStep(p / a) * SmoothStep((1.0 - p) / a);
    } else {
      const double s = std::sin(kPi * p);  // only here: a smoothstep lift needs no sine
      command.stride = -std::cos(kPi * p);
      command.lift = s * s;
    }
  } else {
    // min: θ just below 2π can round q up to 1; progress stays in [0, 1).
    const double q =
        std::fmin((theta - swing_end_rad) / (kTwoPi * shape.duty_factor), std::nextafter(1.0, 0.0));
    command.stance = true;
    command.progress = q;
    command.stride = 1.0 - 2.0 * q;
    command.lift = 0.0;
  }
  for (int k = 0; k < 3; ++k) {
    command.joint_rad[k] =
        amplitude * command.stride * shape.stride_rad[k] + command.lift * shape.lift_rad[k];
  }
  return command;
}

}  // namespace climbsim::cpg
