// TabulatedParams' checks and the azimuth wrap they share with the law: apart from
// tabulated_law.cc so that the scenario loader (and its fuzzer) link without the bond grid.
#include <cmath>
#include <numbers>
#include <string>

#include "adhesion/tabulated_law.h"

namespace climbsim::adhesion {

double WrapAzimuthRad(double azimuth_rad) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  double a = std::fmod(azimuth_rad, kTwoPi);
  if (a < 0.0) a += kTwoPi;
  return a >= kTwoPi ? 0.0 : a;
}

void TabulatedParams::Validate(const Checker& c) const {
  if (pulloff_n.size() != angle_from_normal_deg.size()) {
    c.Fail("pulloff_n", "must hold one force per angle (" +
                            std::to_string(angle_from_normal_deg.size()) + " angles), got " +
                            std::to_string(pulloff_n.size()));
  }
  if (!azimuth_deg.empty() && azimuth_deg.size() != angle_from_normal_deg.size()) {
    c.Fail("azimuth_deg", "must be empty or hold one azimuth per angle (" +
                              std::to_string(angle_from_normal_deg.size()) + "), got " +
                              std::to_string(azimuth_deg.size()));
  }
  for (size_t i = 0; i < angle_from_normal_deg.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      const bool same_azimuth =
          azimuth_deg.empty() ||
          std::abs(WrapAzimuthRad(azimuth_deg[i] * kDegToRad) -
                   WrapAzimuthRad(azimuth_deg[j] * kDegToRad)) < kSameAzimuthRad;
      if (same_azimuth && angle_from_normal_deg[i] == angle_from_normal_deg[j]) {
        c.Fail("angle_from_normal_deg",
               "rows " + std::to_string(j + 1) + " and " + std::to_string(i + 1) +
                   " give the same angle (and azimuth) twice: average repeats first");
      }
    }
  }
}

}  // namespace climbsim::adhesion
