// Closed forms the adhesion tests compare against, continuous and for the cell-centred grid.
//
// Grid sums (cell centres y_j = (j + 1/2 − N/2)·h/N, j = 0..N−1):
//   Σ_j y_j² = (h²/12)·(N − 1/N)                       (so I_x = b·h³/12·(1 − 1/N²))
//   Σ_j (h²/4 − y_j²) = h²·(N/6 + 1/(12N))              (so Σ_B w·dA = b·h³·(1/6 + 1/(12N²)))
//   max_j (h²/4 − y_j²) = h²/4·(1 − 1/N²) for even N (nearest centres at ±h/(2N)),
//                         h²/4 for odd N (a centre on the centre line).
// Hence the full-pad shear peak is 3F/(2A)·κ(N_y) with
//   κ(N) = (1 − [N even]/N²) / (1 + 1/(2N²))   (→ 1: 0.99854 at 32, 0.97674 at 8).
#ifndef CLIMBSIM_TESTS_ADHESION_CLOSED_FORMS_H_
#define CLIMBSIM_TESTS_ADHESION_CLOSED_FORMS_H_

#include <cmath>
#include <numbers>

namespace climbsim::adhesion::testing {

inline constexpr double kDeg = std::numbers::pi / 180.0;
inline constexpr double kThreeHalvesRootThree = 1.5 * std::numbers::sqrt3;  // 2.598

inline double Kappa(int n) {
  const double n2 = static_cast<double>(n) * n;
  return (1.0 - (n % 2 == 0 ? 1.0 / n2 : 0.0)) / (1.0 + 0.5 / n2);
}

// Pull-off / (σ_T·A) of a central pull at θ ≤ 90° (no arm): the first break, at the centre
// line where σ = F cosθ/A is uniform and τ peaks at 1.5·κ·F sinθ/A:
//   σ² + 3τ² = σ_T²  ⇒  F = σ_T·A / sqrt(cos²θ + 3·(1.5κ)²·sin²θ)   (κ = 1: 6.75 sin²θ).
inline double PullRatioTension(double theta_rad, double kappa = 1.0) {
  const double c = std::cos(theta_rad);
  const double s = 1.5 * kappa * std::sin(theta_rad);
  return 1.0 / std::sqrt(c * c + 3.0 * s * s);
}

// Pull-off / (σ_T·A) of a central pull at θ > 90° (pushing): σ = F cosθ/A < 0, so the
// compression rule sqrt(3)·τ ≥ σ_T + μ|σ| at the centre line:
//   sqrt(3)·1.5κ·F sinθ/A = σ_T + μ·F|cosθ|/A  ⇒  F = σ_T·A / (2.598κ·sinθ − μ|cosθ|),
// reachable only when the denominator is > 0. Returns the denominator.
inline double PushDenominator(double theta_rad, double mu, double kappa = 1.0) {
  return kThreeHalvesRootThree * kappa * std::sin(theta_rad) - mu * std::abs(std::cos(theta_rad));
}

}  // namespace climbsim::adhesion::testing

#endif  // CLIMBSIM_TESTS_ADHESION_CLOSED_FORMS_H_
