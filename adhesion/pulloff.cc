#include "adhesion/pulloff.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace climbsim::adhesion {
namespace {

void Check(bool ok, const char* what, double value) {
  if (ok) return;
  std::ostringstream message;
  message << "pulloff." << what << ", got " << value;
  throw std::invalid_argument(message.str());
}

void ValidateSetup(const PullSetup& setup, const PulloffOptions& options) {
  Check(std::isfinite(setup.angle_rad), "angle_rad must be finite", setup.angle_rad);
  Check(std::isfinite(setup.azimuth_rad), "azimuth_rad must be finite", setup.azimuth_rad);
  Check(std::isfinite(setup.arm_m) && setup.arm_m >= 0.0, "arm_m must be >= 0 and finite",
        setup.arm_m);
  Check(options.rel_tol > 0.0 && options.rel_tol <= 0.1, "rel_tol must be in (0, 0.1]",
        options.rel_tol);
  Check(std::isfinite(options.max_force_factor) && options.max_force_factor > 1.0,
        "max_force_factor must be > 1 and finite", options.max_force_factor);
}

// One evaluation of the search's predicate: does a fully bonded grid come off under the
// pull force_n (the law's cascade)?
bool Detaches(BondGrid* grid, const PulloffSearchLaw& law, double force_n,
              PulloffResult* result) {
  ++result->evaluations;
  grid->BondAll();
  return law.cascade(force_n).detached;
}

enum class Bracket { kFound, kNeverHolds, kHoldsUpToCap };

// Brackets the pull-off from *hi = the capacity: [*lo, *hi] with lo holding and hi detaching,
// halving down (to 0 for a hinge) or doubling up to cap_n.
Bracket BracketPulloff(BondGrid* grid, const PulloffSearchLaw& law, double cap_n,
                       PulloffResult* result, double* lo, double* hi) {
  if (Detaches(grid, law, *hi, result)) {
    *lo = 0.5 * *hi;
    int halvings = 0;
    while (Detaches(grid, law, *lo, result)) {
      *hi = *lo;
      *lo *= 0.5;
      if (++halvings > law.max_halvings) {  // lets go at any force worth the name
        if (law.zero_if_never_holds) return Bracket::kNeverHolds;
        *lo = 0.0;  // a hinge: bisect down to the smallest force that still lets go
        break;
      }
    }
    return Bracket::kFound;
  }
  *lo = *hi;
  while (true) {
    *hi = std::min(2.0 * *lo, cap_n);
    if (Detaches(grid, law, *hi, result)) return Bracket::kFound;
    if (*hi >= cap_n) return Bracket::kHoldsUpToCap;
    *lo = *hi;
  }
}

}  // namespace

PadLoad PullLoad(double force_n, const PullSetup& setup) {
  const double in_plane = force_n * std::sin(setup.angle_rad);
  const double fx = in_plane * std::cos(setup.azimuth_rad);
  const double fy = in_plane * std::sin(setup.azimuth_rad);
  // r × F with r = (0, 0, L): (−L·F_y, L·F_x, 0).
  return PadLoad{.fn_n = force_n * std::cos(setup.angle_rad),
                 .fx_n = fx,
                 .fy_n = fy,
                 .mx_nm = -setup.arm_m * fy,
                 .my_nm = setup.arm_m * fx};
}

PulloffResult SearchPulloff(BondGrid* grid, double capacity_n, const PulloffOptions& options,
                            const PulloffSearchLaw& law) {
  PulloffResult result;
  const double cap_n = options.max_force_factor * capacity_n;
  const auto detaches = [&](double force_n) { return Detaches(grid, law, force_n, &result); };

  double lo = 0.0;
  double hi = capacity_n;
  switch (BracketPulloff(grid, law, cap_n, &result, &lo, &hi)) {
    case Bracket::kNeverHolds:
      result.detaches = true;
      return result;  // force_n = holding_force_n = 0
    case Bracket::kHoldsUpToCap:
      result.detaches = false;
      result.force_n = std::numeric_limits<double>::infinity();
      result.holding_force_n = cap_n;
      result.force_per_capacity = result.force_n;
      return result;
    case Bracket::kFound:
      break;
  }

  // Bisection of the predicate.
  while (hi - lo > options.rel_tol * hi) {
    const double mid = 0.5 * (lo + hi);
    if (detaches(mid)) {
      hi = mid;
    } else {
      lo = mid;
    }
  }

  // The detaching cascade once more, for its log.
  grid->BondAll();
  const BondGrid::UpdateResult last = law.cascade(hi);
  ++result.evaluations;
  result.detaches = true;
  result.force_n = hi;
  result.holding_force_n = lo;
  result.force_per_capacity = hi / capacity_n;
  result.rounds = last.rounds;
  result.sequence.reserve(grid->last_broken().size());
  for (const BrokenBond& b : grid->last_broken()) {
    result.sequence.push_back(BrokenBondAt{
        .x_m = grid->bond_x_m(b.index), .y_m = grid->bond_y_m(b.index), .round = b.round});
  }
  return result;
}

PulloffResult PullOff(const PadParams& pad, const PullSetup& setup,
                      const PulloffOptions& options) {
  ValidateSetup(setup, options);
  BondGrid grid(pad);  // validates pad
  return SearchPulloff(&grid, pad.sigma_t_pa * grid.pad_area_m2(), options,
                       {.cascade = [&](double f) { return grid.Update(PullLoad(f, setup)); },
                        .max_halvings = 100,
                        .zero_if_never_holds = false});
}

std::vector<double> SweepAnglesDeg(const SweepRange& range) {
  Check(std::isfinite(range.from_deg), "sweep from_deg must be finite", range.from_deg);
  Check(std::isfinite(range.to_deg) && range.to_deg >= range.from_deg,
        "sweep to_deg must be finite and >= from_deg", range.to_deg);
  Check(std::isfinite(range.step_deg) && range.step_deg > 0.0, "sweep step_deg must be > 0",
        range.step_deg);
  const double span = range.to_deg - range.from_deg;
  const long steps = std::lround(std::floor(span / range.step_deg + 1e-3));
  Check(steps < 1000000, "sweep has too many angles; step_deg", range.step_deg);
  std::vector<double> angles_deg;
  angles_deg.reserve(steps + 1);
  for (long k = 0; k <= steps; ++k) {
    angles_deg.push_back(std::min(range.from_deg + k * range.step_deg, range.to_deg));
  }
  return angles_deg;
}

double CentralPulloffPerCapacity(double angle_rad, double mu) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  if (c >= 0) return 1.0 / std::sqrt(c * c + 6.75 * s * s);
  const double den = 1.5 * std::sqrt(3.0) * s - mu * std::abs(c);
  return den > 0 ? 1.0 / den : std::numeric_limits<double>::infinity();
}

std::vector<SweepPoint> PulloffSweep(const PadParams& pad, const PullSetup& base,
                                     const SweepRange& range, const PulloffOptions& options) {
  std::vector<SweepPoint> points;
  for (const double angle_deg : SweepAnglesDeg(range)) {
    PullSetup setup = base;
    setup.angle_rad = angle_deg * std::numbers::pi / 180.0;
    points.push_back(SweepPoint{.angle_deg = angle_deg, .result = PullOff(pad, setup, options)});
  }
  return points;
}

}  // namespace climbsim::adhesion
