#include "adhesion/tabulated_law.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "adhesion/frictional_law.h"  // kFrictionalCap, ShearFieldCascade

namespace climbsim::adhesion {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
}  // namespace

void ValidateTabulatedParams(const TabulatedParams& params) {
  keys::Validate(params, "adhesion.tabulated");
  if (params.angle_from_normal_deg.empty()) {
    throw std::invalid_argument(
        "adhesion.tabulated.angle_from_normal_deg: law tabulated needs at least one row");
  }
}

TabulatedLaw::TabulatedLaw(const TabulatedParams& params) : params_(params) {
  ValidateTabulatedParams(params_);
  const double area = params_.width_m * params_.length_m;
  for (size_t i = 0; i < params_.angle_from_normal_deg.size(); ++i) {
    const double az =
        params_.azimuth_deg.empty() ? 0.0 : WrapAzimuthRad(params_.azimuth_deg[i] * kDegToRad);
    auto it = std::find_if(curves_.begin(), curves_.end(), [&](const Curve& c) {
      return std::abs(c.azimuth_rad - az) < kSameAzimuthRad;
    });
    if (it == curves_.end()) {
      curves_.push_back(Curve{.azimuth_rad = az, .angle_rad = {}, .traction_pa = {}});
      it = curves_.end() - 1;
    }
    it->angle_rad.push_back(params_.angle_from_normal_deg[i] * kDegToRad);
    it->traction_pa.push_back(params_.pulloff_n[i] / area);
  }
  for (Curve& c : curves_) {  // angles ascending, the tractions with them
    std::vector<size_t> order(c.angle_rad.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return c.angle_rad[a] < c.angle_rad[b]; });
    Curve sorted{.azimuth_rad = c.azimuth_rad, .angle_rad = {}, .traction_pa = {}};
    for (size_t k : order) {
      sorted.angle_rad.push_back(c.angle_rad[k]);
      sorted.traction_pa.push_back(c.traction_pa[k]);
    }
    c = std::move(sorted);
  }
  std::sort(curves_.begin(), curves_.end(),
            [](const Curve& a, const Curve& b) { return a.azimuth_rad < b.azimuth_rad; });
  ShareStraightPull();
}

// A straight pull (θ = 0) has no azimuth: every curve starts at the mean of the rows given
// there, so that the limit is continuous as θ → 0 from any azimuth.
void TabulatedLaw::ShareStraightPull() {
  double sum = 0.0;
  int count = 0;
  for (const Curve& c : curves_) {
    if (c.angle_rad.front() == 0.0) {
      sum += c.traction_pa.front();
      ++count;
    }
  }
  if (count == 0) return;
  for (Curve& c : curves_) {
    if (c.angle_rad.front() == 0.0) {
      c.traction_pa.front() = sum / count;
    } else {
      c.angle_rad.insert(c.angle_rad.begin(), 0.0);
      c.traction_pa.insert(c.traction_pa.begin(), sum / count);
    }
  }
}

double TabulatedLaw::CurveAt(const Curve& c, double angle_rad) const {
  const std::vector<double>& x = c.angle_rad;
  if (angle_rad <= x.front()) return c.traction_pa.front();
  if (angle_rad >= x.back()) return c.traction_pa.back();
  const size_t k = std::upper_bound(x.begin(), x.end(), angle_rad) - x.begin();  // x[k-1] < θ
  const double w = (angle_rad - x[k - 1]) / (x[k] - x[k - 1]);
  return (1.0 - w) * c.traction_pa[k - 1] + w * c.traction_pa[k];
}

double TabulatedLaw::LimitTractionPa(double angle_rad, double azimuth_rad) const {
  if (curves_.size() == 1) return CurveAt(curves_[0], angle_rad);
  const double az = WrapAzimuthRad(azimuth_rad);
  // The curves on either side of az, periodic: from the last one to the first + 2π.
  size_t hi = 0;
  while (hi < curves_.size() && curves_[hi].azimuth_rad <= az) ++hi;
  const size_t lo = hi == 0 ? curves_.size() - 1 : hi - 1;
  if (hi == curves_.size()) hi = 0;
  double z_lo = curves_[lo].azimuth_rad, z_hi = curves_[hi].azimuth_rad;
  double a = az;
  if (z_hi <= z_lo) {  // wraps through 0
    z_hi += kTwoPi;
    if (a < z_lo) a += kTwoPi;
  }
  const double w = (a - z_lo) / (z_hi - z_lo);
  return (1.0 - w) * CurveAt(curves_[lo], angle_rad) + w * CurveAt(curves_[hi], angle_rad);
}

double TabulatedLaw::PulloffCentral(double area_m2, double angle_rad, double azimuth_rad) const {
  return LimitTractionPa(angle_rad, azimuth_rad) * area_m2;
}

double TabulatedLaw::Utilisation(double sigma_pa, double tau_x_pa, double tau_y_pa) const {
  const double tau = std::hypot(tau_x_pa, tau_y_pa);
  const double azimuth = std::atan2(tau_y_pa, tau_x_pa);
  double demand = 0.0, limit = 0.0;
  if (sigma_pa > 0.0) {
    demand = std::hypot(tau, sigma_pa);
    limit = LimitTractionPa(std::atan2(tau, sigma_pa), azimuth);
  } else {
    demand = tau;
    limit = LimitTractionPa(0.5 * std::numbers::pi, azimuth) - params_.friction_mu * sigma_pa;
  }
  if (demand == 0.0) return 0.0;
  const double u = limit > 0.0 ? demand / limit : kFrictionalCap;
  return std::isnan(u) ? kFrictionalCap : std::min(u, kFrictionalCap);
}

BondGrid::UpdateResult TabulatedUpdate(BondGrid* grid, const TabulatedLaw& law,
                                       const PadLoad& load, double* peak_utilisation) {
  return ShearFieldCascade(
      grid, load,
      [&law](double sigma, double tau_x, double tau_y) {
        return law.Utilisation(sigma, tau_x, tau_y);
      },
      peak_utilisation, /*monotone_in_sigma=*/false);  // a table may fall with σ
}

PulloffResult TabulatedPullOff(const PadParams& pad, const TabulatedParams& table,
                               const PullSetup& setup, const PulloffOptions& options) {
  CheckPullSetup(setup, options);
  const TabulatedLaw law(table);
  BondGrid grid(pad);
  // The search brackets from the table's largest force scaled to this pad (> 0), or 1 N.
  double capacity = 0.0;
  for (double f : table.pulloff_n) capacity = std::max(capacity, f);
  capacity *= grid.pad_area_m2() / (table.width_m * table.length_m);
  if (!(capacity > 0.0)) capacity = 1.0;
  return SearchPulloff(
      &grid, capacity, options,
      {.cascade = [&](double f) { return TabulatedUpdate(&grid, law, PullLoad(f, setup), nullptr); },
       .max_halvings = 60,
       .zero_if_never_holds = true});
}

}  // namespace climbsim::adhesion
