// The tabulated pad law (adhesion.law: tabulated): a pad's limit given as the pull-off force a
// lab measured against the pull angle (and the azimuth, where measured), interpolated, and
// applied bond by bond on the grid of bond_grid.h so that peeling stays progressive. Pure
// math: no MuJoCo. adhesion/README.md ("The tabulated law") has the mapping and its limits.
//
// THE TABLE. Rows (θ_k from the pad normal, φ_k azimuth of the in-plane part from the pad's
// +x towards +y, F_k the pull-off force of a central pull on the measured pad of area
// A_m = width_m·length_m). Each distinct azimuth is one curve F(θ), linear between its
// angles and constant beyond its first and last; between curves the limit is linear in the
// azimuth, periodic over 360° (one azimuth: the same at every azimuth). A straight pull
// (θ = 0) has no azimuth: the rows at 0° are averaged and every curve starts there. Angles lie in
// [0°, 90°] (pulls); the table is stored as the limit TRACTION T(θ, φ) = F/A_m, so a pad of
// another size scales with its area.
//
// PER BOND (TabulatedUpdate), the field of the frictional law: σ_i from bond_grid.h's
// linear field (F_n/A_B plus the moments' gradient) and one shear τ = (F_x, F_y)/A_B on every
// bond. Bond i's traction t_i = (τ_x, τ_y, σ_i) has the angle θ_i = atan2(|τ|, σ_i) from the
// normal and the azimuth φ_i = atan2(τ_y, τ_x):
//   σ_i > 0 (pulled):   it breaks when |t_i| > T(θ_i, φ_i);
//   σ_i ≤ 0 (pressed):  it breaks when |τ| > T(90°, φ_i) + friction_mu·|σ_i| (a push never
//                       breaks a bond by itself; the table says nothing about pushes).
// A central pull on a fully bonded pad puts the same traction F·u/A on every bond, so the pad
// lets go all at once at F = T(θ, φ)·A: exactly the table (interpolated) for a pad of the
// measured size. A moment (a lever, a leg's torque) tensions one edge more, and θ_i differs
// from bond to bond: that edge reaches its limit first and the pad peels round by round.
//
// UTILISATION of a bond: |t_i|/T(θ_i, φ_i) pulled, |τ|/(T(90°) + μ|σ|) pressed; a limit of 0
// reads as kFrictionalCap. Nothing here allocates after construction.
#ifndef CLIMBSIM_ADHESION_TABULATED_LAW_H_
#define CLIMBSIM_ADHESION_TABULATED_LAW_H_

#include <string>
#include <vector>

#include "adhesion/bond_grid.h"
#include "adhesion/pulloff.h"
#include "keys/keys.h"

namespace climbsim::adhesion {

// The table as a scenario writes it (adhesion.tabulated.*); `climbsim fit-adhesion` writes
// one (fitted.yaml).
struct TabulatedParams {
  std::vector<double> angle_from_normal_deg;  // θ_k, [0, 90]
  std::vector<double> azimuth_deg;            // φ_k; empty: the same at every azimuth
  std::vector<double> pulloff_n;              // F_k ≥ 0
  double width_m = 0.02;                      // the measured pad (its area scales the table)
  double length_m = 0.02;
  double friction_mu = 0.0;                   // pressed bonds: shear limit T(90°) + μ|σ|

  template <class A>
  void Serialize(A* a) {
    a->Visit({"angle_from_normal_deg", "deg",
              "measured pull angles, from the pad normal (0 pulls straight off, 90 shears)",
              Range::Closed(0, 90)},
             &angle_from_normal_deg, 0);
    a->Visit({"azimuth_deg", "deg",
              "azimuth of each row's pull in the pad plane, from pad +x towards +y; empty: the "
              "same limit at every azimuth",
              Range::Closed(-360, 360)},
             &azimuth_deg, 0);
    a->Visit({"pulloff_n", "N",
              "measured pull-off force of each row (central pull on the measured pad)",
              Range::NonNegative()},
             &pulloff_n, 0);
    a->Visit({"width_m", "m",
              "width of the measured pad: the table is a traction (force over this area), so "
              "pads of other sizes scale with their area",
              Range::OpenClosed(0, 1)},
             &width_m);
    a->Visit({"length_m", "m", "length of the measured pad", Range::OpenClosed(0, 1)},
             &length_m);
    a->Visit({"friction_mu", "",
              "a pressed bond holds shear up to the 90-degree limit plus this times its "
              "compression (0: the von Mises law's default)",
              Range::NonNegative()},
             &friction_mu);
  }
  // Lengths agree; angle rows unique per azimuth. An empty table passes (law not tabulated);
  // TabulatedLaw refuses it.
  void Validate(const Checker& c) const;
};

// An azimuth wrapped into [0, 2π); two closer than kSameAzimuthRad are one curve.
double WrapAzimuthRad(double azimuth_rad);
inline constexpr double kSameAzimuthRad = 1e-9;

// Throws std::invalid_argument naming adhesion.tabulated.<key>: the declared ranges, the
// lengths, and a non-empty table.
void ValidateTabulatedParams(const TabulatedParams& params);

class TabulatedLaw {
 public:
  explicit TabulatedLaw(const TabulatedParams& params);  // validates; sorts the curves

  const TabulatedParams& params() const { return params_; }
  // T(θ, φ), Pa: the interpolated limit traction (file comment).
  double LimitTractionPa(double angle_rad, double azimuth_rad) const;
  // The table's pull-off for a central pull on a pad of area_m2: T(θ, φ)·area.
  double PulloffCentral(double area_m2, double angle_rad, double azimuth_rad) const;
  // Demand over limit of a bond's stress state; > 1 breaks.
  double Utilisation(double sigma_pa, double tau_x_pa, double tau_y_pa) const;

 private:
  struct Curve {
    double azimuth_rad = 0.0;          // in [0, 2π)
    std::vector<double> angle_rad;     // ascending
    std::vector<double> traction_pa;   // T at those angles
  };
  double CurveAt(const Curve& c, double angle_rad) const;
  void ShareStraightPull();

  TabulatedParams params_;
  std::vector<Curve> curves_;  // by azimuth, ascending
};

// Bond-level breaking under `load` with the tabulated law: the cascade of BondGrid::Update
// (break every bond over its limit against one field, recompute, repeat). Returns what
// Update returns; *peak_utilisation (if not null) the largest utilisation of the bonds left.
BondGrid::UpdateResult TabulatedUpdate(BondGrid* grid, const TabulatedLaw& law,
                                       const PadLoad& load, double* peak_utilisation);

// The quasi-static pull-off of a fully bonded pad under the table (pulloff.h's search on
// TabulatedUpdate); 0 when it holds at no force.
PulloffResult TabulatedPullOff(const PadParams& pad, const TabulatedParams& table,
                               const PullSetup& setup, const PulloffOptions& options = {});

}  // namespace climbsim::adhesion

#endif  // CLIMBSIM_ADHESION_TABULATED_LAW_H_
