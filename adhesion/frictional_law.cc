#include "adhesion/frictional_law.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace climbsim::adhesion {
namespace {

// A pull at exactly 90° − α* lies on the limit itself (frictional_law.h, kShearLawRoundoff).
constexpr double kRoundoff = kShearLawRoundoff;

}  // namespace

void ValidateFrictionalParams(const FrictionalParams& p) {
  keys::Validate(p, "adhesion.frictional");
}

FrictionalLaw::FrictionalLaw(const FrictionalParams& params) : params_(params) {
  ValidateFrictionalParams(params_);
  tan_critical_ = std::tan(params_.critical_angle_deg * kDegToRad);
  const double norm = std::hypot(params_.grip_x, params_.grip_y);
  dx_ = params_.grip_x / norm;
  dy_ = params_.grip_y / norm;
}

double FrictionalLaw::Utilisation(double sigma_pa, double tau_x_pa, double tau_y_pa) const {
  const double tau_t = GripShear(tau_x_pa, tau_y_pa);
  const double tau_s = std::hypot(tau_x_pa, tau_y_pa);
  const double tau_max = params_.shear_limit_pa;
  double u = 0.0;
  if (sigma_pa > 0.0) {
    if (!(tau_t > 0.0)) return kFrictionalCap;  // pulled without gripping shear
    u = std::max(sigma_pa / (tau_t * tan_critical_), tau_s / tau_max);
  } else {
    const double friction = params_.friction_mu * -sigma_pa;
    u = tau_s / (tau_max + friction);
    if (tau_t < 0.0) u = std::max(u, friction > 0.0 ? -tau_t / friction : kFrictionalCap);
  }
  return std::isnan(u) ? kFrictionalCap : std::min(u, kFrictionalCap);
}

bool FrictionalLaw::PadHolds(const PadLoad& load, double area_m2) const {
  return Utilisation(load.fn_n / area_m2, load.fx_n / area_m2, load.fy_n / area_m2) <=
         1.0 + kRoundoff;
}

double FrictionalLaw::PulloffClosedForm(double area_m2, double angle_rad,
                                        double azimuth_rad) const {
  const double s = std::sin(angle_rad);
  const double fn = std::cos(angle_rad);  // per unit force
  const double ft = s * (std::cos(azimuth_rad) * dx_ + std::sin(azimuth_rad) * dy_);
  const double fs = std::abs(s);
  const double capacity = params_.shear_limit_pa * area_m2;
  if (fn > 0.0) {
    if (!(ft > 0.0) || fn > ft * tan_critical_ * (1.0 + kRoundoff)) return 0.0;
    return capacity / fs;
  }
  const double friction = params_.friction_mu * -fn;
  if (ft < -friction) return 0.0;
  const double den = fs - friction;
  return den > 0.0 ? capacity / den : std::numeric_limits<double>::infinity();
}

BondGrid::UpdateResult FrictionalUpdate(BondGrid* grid, const FrictionalLaw& law,
                                        const PadLoad& full_load, double* peak_utilisation) {
  PadLoad load = full_load;
  load.mx_nm *= law.params().moment_share;
  load.my_nm *= law.params().moment_share;
  return ShearFieldCascade(
      grid, load,
      [&law](double sigma, double tau_x, double tau_y) {
        return law.Utilisation(sigma, tau_x, tau_y);
      },
      peak_utilisation, /*monotone_in_sigma=*/true);
}

void CheckPullSetup(const PullSetup& setup, const PulloffOptions& options) {
  if (!std::isfinite(setup.angle_rad) || !std::isfinite(setup.azimuth_rad) ||
      !(std::isfinite(setup.arm_m) && setup.arm_m >= 0.0) || !(options.rel_tol > 0.0) ||
      options.rel_tol > 0.1 || !(options.max_force_factor > 1.0)) {
    throw std::invalid_argument("pulloff: bad pull setup or options (pulloff.h)");
  }
}

PulloffResult FrictionalPullOff(const PadParams& pad, const FrictionalParams& params,
                                const PullSetup& setup, const PulloffOptions& options) {
  CheckPullSetup(setup, options);
  const FrictionalLaw law(params);
  BondGrid grid(pad);
  return SearchPulloff(
      &grid, params.shear_limit_pa * grid.pad_area_m2(), options,
      {.cascade =
           [&](double f) { return FrictionalUpdate(&grid, law, PullLoad(f, setup), nullptr); },
       .max_halvings = 60,
       .zero_if_never_holds = true});
}

std::vector<LimitVertex> FrictionalLimitBoundary(const FrictionalLaw& law, double area_m2,
                                                 double max_compression_n) {
  const double ft_max = law.params().shear_limit_pa * area_m2;
  const double mu = law.params().friction_mu;
  const double c = max_compression_n;
  return {{-mu * c, -c},
          {0.0, 0.0},
          {ft_max, ft_max * law.tan_critical()},
          {ft_max, 0.0},
          {ft_max + mu * c, -c}};
}

bool PadUtilisationGradient(const BondGrid& grid, const FrictionalLaw* frictional,
                            const PadLoad& load, Eigen::Matrix<double, 5, 1>* grad,
                            int peak_bond) {
  int bond = peak_bond;
  if (frictional != nullptr) {
    bond = grid.PeakSigmaBond();
  } else if (bond < 0 && !std::isfinite(grid.PeakUtilisation(&bond))) {
    return false;  // a load the bonds cannot carry at all
  }
  Eigen::Matrix<double, 3, 5> a;
  if (bond < 0 || !grid.Influence(bond, frictional != nullptr, &a)) return false;
  const Eigen::Vector3d s =
      a * Eigen::Matrix<double, 5, 1>(load.fn_n, load.fx_n, load.fy_n, load.mx_nm, load.my_nm);
  // The law's derivative with respect to the bond's (σ, τ_x, τ_y).
  Eigen::Vector3d dlaw = Eigen::Vector3d::Zero();
  if (frictional != nullptr) {
    // A step of 10⁻⁶ of the stress scale resolves the slope on either side of a kink.
    const double h = 1e-6 * (std::abs(s[0]) + std::abs(s[1]) + std::abs(s[2]) +
                             1e-3 * frictional->params().shear_limit_pa);
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d up = s, down = s;
      up[k] += h;
      down[k] -= h;
      dlaw[k] = (frictional->Utilisation(up[0], up[1], up[2]) -
                 frictional->Utilisation(down[0], down[1], down[2])) /
                (2.0 * h);
    }
  } else {
    const double sigma_t = grid.params().sigma_t_pa;
    const double mu = grid.params().mu;
    const double tau3 = 3.0 * (s[1] * s[1] + s[2] * s[2]);
    if (s[0] >= 0.0) {
      const double vm = std::sqrt(s[0] * s[0] + tau3);
      if (vm > 0.0) dlaw = Eigen::Vector3d(s[0], 3.0 * s[1], 3.0 * s[2]) / (sigma_t * vm);
    } else if (tau3 > 0.0) {
      const double threshold = sigma_t - mu * s[0];
      const double root = std::sqrt(tau3);
      dlaw = Eigen::Vector3d(mu * root / threshold, 3.0 * s[1] / root, 3.0 * s[2] / root) /
             threshold;
    }
  }
  *grad = (dlaw.transpose() * a).transpose();
  return grad->allFinite();
}

double VonMisesPulloffClosedForm(double capacity_n, double angle_rad, double mu) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  if (c >= 0.0) return capacity_n / std::sqrt(c * c + 6.75 * s * s);
  const double den = 1.5 * std::sqrt(3.0) * s - mu * std::abs(c);
  return den > 0.0 ? capacity_n / den : std::numeric_limits<double>::infinity();
}

}  // namespace climbsim::adhesion
