// The quasi-static pull-off experiment (seed section 2.3.2.3, figure 6) as pure math: a
// weightless rigid block with the pad under it, fully bonded, pulled by a force F along a
// fixed direction through a point on the pad normal at height L above the pad face. The
// pull-off force is the smallest F at which the cascade of BondGrid::Update, started from a
// fully bonded grid, leaves fewer than min_bonds bonds.
//
// THE PULL, in the pad frame of bond_grid.h (x, y, n right-handed, n from the surface into
// the pad): direction u = (sinθ·cosφ, sinθ·sinφ, cosθ), applied at r = (0, 0, L).
//   θ (angle_rad) from the pad normal: 0 pulls straight off, π/2 is pure shear, θ > π/2
//     also pushes the pad into the surface, π pushes straight in;
//   φ (azimuth_rad) turns the in-plane part from +x towards +y (0: along +x);
//   L (arm_m) ≥ 0, the lever of the in-plane part.
// The load on the bond layer (PullLoad) is F·u with the moment r × F·u about the centroid:
//
//     F_n = F cosθ,  F_x = F sinθ cosφ,  F_y = F sinθ sinφ,
//     M_x = −L·F_y,  M_y = +L·F_x.
//
// With φ = 0, M_y = L·F sinθ > 0 gives σ = F_n/A − M_y·x/I_y: extra tension at −x. The
// block tips about its leading edge (+x, the side it is pulled towards) and the TRAILING
// edge (−x) lifts: the peel starts there (a test asserts it on the broken-bond log).
//
// CLOSED FORMS for a central pull (L = 0) on a fully bonded pad of area A, in the limit of a
// fine grid (τ peaks at 3F_x/(2A) on the centre line, where σ = F cosθ/A is uniform):
//
//     θ ≤ 90°:  F = σ_T·A / sqrt(cos²θ + 6.75·sin²θ)              (0.385·σ_T·A at 90°)
//     θ > 90°:  F = σ_T·A / (2.598·sinθ − μ·|cosθ|)   (2.598 = 3·sqrt(3)/2; never when ≤ 0)
//
// and the first break always runs through the whole pad (the cascade argument is in
// tests/adhesion/pulloff_test.cc), so first break = pull-off.
//
// THE SEARCH. Bracket by doubling from σ_T·A (halving if that already detaches), then
// bisect the predicate "detaches at F" until (hi − lo) ≤ rel_tol·hi. The predicate is
// monotone for the loads above (every stress scales with F; the compression threshold
// σ_T + μ|σ| grows slower than the shear demand when it is reachable at all); for other
// loads the result is a point where it flips from holding (lo) to detaching (hi). If the
// pad holds at max_force_factor·σ_T·A, it is reported as never detaching.
#ifndef CLIMBSIM_ADHESION_PULLOFF_H_
#define CLIMBSIM_ADHESION_PULLOFF_H_

#include <functional>
#include <numbers>
#include <vector>

#include "adhesion/bond_grid.h"

namespace climbsim::adhesion {

// Direction and lever of the pull (see the file comment).
struct PullSetup {
  double angle_rad = 0.0;    // θ from the pad normal, finite
  double azimuth_rad = 0.0;  // φ of the in-plane part, from +x towards +y, finite
  double arm_m = 0.0;        // L ≥ 0, height of the pull point above the pad face
};

struct PulloffOptions {
  double rel_tol = 1e-6;            // bisection stops at (hi − lo) ≤ rel_tol·hi; in (0, 0.1]
  double max_force_factor = 1e3;    // give up above this many σ_T·A; > 1
};

// A broken bond with its place, for event-order checks and plots.
struct BrokenBondAt {
  double x_m = 0.0;
  double y_m = 0.0;
  int round = 0;  // cascade round, from 1
};

struct PulloffResult {
  bool detaches = false;         // false: holds up to max_force_factor·σ_T·A
  double force_n = 0.0;          // smallest force found to detach (hi); +inf if never
  double holding_force_n = 0.0;  // largest force found to hold (lo); the cap if never
  double force_per_capacity = 0.0;  // force_n / (σ_T·A)
  int rounds = 0;                // cascade rounds at force_n
  int evaluations = 0;           // cascades run by the search
  std::vector<BrokenBondAt> sequence;  // bonds broken at force_n, by round then index
};

// The load that the pull F puts on the bond layer (equations in the file comment).
PadLoad PullLoad(double force_n, const PullSetup& setup);

// The search every pad law's pull-off shares: bracket the force from σ_T·A (halving down,
// doubling up to max_force_factor·capacity_n), then bisect to rel_tol; `cascade(F)` loads the
// freshly bonded grid with the pull F and runs the law's cascade (one evaluation each). A pad
// still letting go after max_halvings halvings holds nothing: with zero_if_never_holds the
// result is 0 at once, else the bisection goes on from 0 (a hinge).
struct PulloffSearchLaw {
  std::function<BondGrid::UpdateResult(double force_n)> cascade;
  int max_halvings = 100;
  bool zero_if_never_holds = false;
};
PulloffResult SearchPulloff(BondGrid* grid, double capacity_n, const PulloffOptions& options,
                            const PulloffSearchLaw& law);

// The pull-off force of a fully bonded pad. Throws std::invalid_argument on bad params
// (ValidatePadParams), a non-finite angle, a negative or non-finite arm, or bad options.
PulloffResult PullOff(const PadParams& pad, const PullSetup& setup,
                      const PulloffOptions& options = {});

// Degrees to radians: the keys given in degrees (sweep angles, tabulated laws' angles, the
// directional law's critical angle).
inline constexpr double kDegToRad = std::numbers::pi / 180.0;

struct SweepRange {
  double from_deg = 0.0;
  double to_deg = 180.0;
  double step_deg = 5.0;  // > 0; the last angle is to_deg if it is within step/1000
};

struct SweepPoint {
  double angle_deg = 0.0;
  PulloffResult result;
};

// The angles of a sweep: from_deg, from_deg + step_deg, ... up to to_deg (the last one is
// to_deg when it is within step_deg/1000 of it). Throws std::invalid_argument on a bad range.
std::vector<double> SweepAnglesDeg(const SweepRange& range);

// The closed forms of the file comment: pull-off of a central pull (L = 0) on a fully bonded
// pad, fine-grid limit, over σ_T·A; +inf where a push (θ > 90°) never detaches.
double CentralPulloffPerCapacity(double angle_rad, double mu);

// PullOff over a range of angles θ, azimuth and arm from base (its angle is ignored): the
// seed's figure 6. Throws like PullOff, and on a bad range.
std::vector<SweepPoint> PulloffSweep(const PadParams& pad, const PullSetup& base,
                                     const SweepRange& range = {},
                                     const PulloffOptions& options = {});

}  // namespace climbsim::adhesion

#endif  // CLIMBSIM_ADHESION_PULLOFF_H_
