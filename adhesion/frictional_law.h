// The directional pad law, "frictional adhesion" (Autumn et al. 2006, J. Exp. Biol.
// 209:3569–3579; the limit surface as Santos et al. 2007/2008 use it for Stickybot's pads),
// beside the isotropic von Mises law of bond_grid.h, on the same bond grid. Pure math: no
// MuJoCo. adhesion/README.md has the equations with the sources and the comparison.
//
// FRAMES AND SIGNS: the pad frame and the load of bond_grid.h (F_n > 0 pulls the pad off;
// (F_x, F_y) is the shear that the robot puts on the pad). d = (d_x, d_y), a unit vector in
// the pad's x-y plane, is the GRIPPING DIRECTION: the shear that engages the adhesive (for a
// climber, pointing down the wall: the legs drag the feet down under the body's weight).
//
//   F_t = F_x·d_x + F_y·d_y    shear along the gripping direction (< 0: reversed)
//   F_s = sqrt(F_x² + F_y²)    shear magnitude (lateral shear counts here, never for adhesion)
//   C   = max(−F_n, 0)         compression
//
// THE PAD-LEVEL LIMIT SURFACE (α* the critical angle, F_t,max = τ_max·A the shear limit,
// μ the friction coefficient; all three parameters). The pad holds while
//
//   pulled  (F_n > 0):   F_t > 0,  F_n ≤ F_t·tan α*,  F_s ≤ F_t,max
//   pressed (F_n ≤ 0):   F_t ≥ −μ·C,                   F_s ≤ F_t,max + μ·C
//
// so: no adhesion without shear in the gripping direction (F_t ≤ 0 and pulled lets go at any
// F_n > 0), the adhesion is at most tan α* times that shear, and the pad releases when the
// shear is taken off (unloading). Pressed, the reversed side is Coulomb friction and the
// gripping side the shear limit plus friction.
//
// DISCRETISATION ON THE BOND GRID (FrictionalUpdate; the moments scaled by moment_share
// first). Each bond i of the bonded set B obeys
// the same law in stresses: σ_i from bond_grid.h's linear field (the bonds as a bed of equal
// springs under a rigid pad: F_n/A_B plus the moments' gradient), and one shear vector for
// every bond, τ = (F_x, F_y)/A_B (a rigid in-plane displacement of the backing strains every
// stalk alike: the fibrillar adhesive has no shear lag), with τ_t = τ·d, τ_s = |τ|,
// c_i = max(−σ_i, 0). Bond i breaks when
//
//   σ_i > 0:   τ_t ≤ 0,  or σ_i > τ_t·tan α*,  or τ_s > τ_max
//   σ_i ≤ 0:   τ_t < −μ·c_i,  or τ_s > τ_max + μ·c_i
//
// and the cascade of bond_grid.h runs on it (break all over threshold against one field,
// recompute over the bonds left, repeat). Without a moment (a pull through the centroid of
// a fully bonded pad) every bond has the same σ = F_n/A and τ = F/A, so the per-bond law IS
// the pad-level law (all inequalities are homogeneous in the area) and the pad lets go all
// at once: the pad-level law is exact for a central pull. With a moment (a lever, a leg's
// torque) the tensioned edge reaches σ_i > τ_t tan α* first and the pad peels bond by bond.
//
// UTILISATION of a bond (demand over threshold, > 1 breaks; capped at kFrictionalCap, the
// cap meaning "no hold": pulled without gripping shear):
//   σ_i > 0:  max(σ_i/(τ_t tan α*), τ_s/τ_max)       (kFrictionalCap if τ_t ≤ 0)
//   σ_i ≤ 0:  max(τ_s/(τ_max + μc_i), −τ_t/(μc_i))    (the second 0 when τ_t ≥ 0)
//
// Nothing here allocates; FrictionalUpdate costs one BondGrid::Evaluate plus a scan of the
// bonds per cascade round.
#ifndef CLIMBSIM_ADHESION_FRICTIONAL_LAW_H_
#define CLIMBSIM_ADHESION_FRICTIONAL_LAW_H_

#include <algorithm>
#include <cmath>
#include <vector>

#include "adhesion/bond_grid.h"
#include "adhesion/pulloff.h"
#include "keys/keys.h"

namespace climbsim::adhesion {

// Which law decides when bonds break.
enum class PadLaw { kVonMises, kFrictional, kTabulated };  // kTabulated: tabulated_law.h

// Utilisation reported for a bond (or pad) that cannot hold at all (pulled, no gripping
// shear): far above 1, finite so that it plots and averages.
inline constexpr double kFrictionalCap = 1e3;

// The law's parameters. Defaults: α* = 30° (Autumn et al. 2006: a critical angle near 25°
// for isolated setal arrays and live toes; 25–30° is the range quoted for geckos), τ_max = 10 kPa
// (the von Mises law's σ_T, so the two compare on the same pad; Stickybot's directional polymer
// gives a few kPa, gecko toes about 100 kPa), μ = 1 (MuJoCo's default geom friction).
struct FrictionalParams {
  double critical_angle_deg = 30.0;  // α*, in (0, 90)
  double shear_limit_pa = 10e3;      // τ_max > 0; F_t,max = τ_max·A
  double friction_mu = 1.0;          // μ ≥ 0, Coulomb friction when pressed
  double grip_x = -1.0;              // gripping direction d in the pad frame; normalised by
  double grip_y = 0.0;               // FrictionalLaw, must not be zero. Default −x: down the
                                     // wall for the bundled robots, whose pad x runs along
                                     // the base's heading (they climb +x)
  // Share of the load's moments (M_x, M_y) that the bonds carry, in [0, 1]. 1: a rigid pad
  // on a rigid ankle, the moments peel it bond by bond; 0: a compliant toe or a passive ankle
  // (gecko toes, Stickybot's toes) passes no moment to the adhesive: the pad-level law.
  double moment_share = 1.0;

  // The scenario keys adhesion.frictional.*; Validate holds the one rule across them.
  template <class A>
  void Serialize(A* a) {
    a->Visit({"critical_angle_deg", "deg",
              "alpha*: a pulled pad holds while F_n <= F_t tan(alpha*) (Autumn et al. 2006: about "
              "25-30 deg for geckos)",
              Range{0.0, 90.0, true, true}},
             &critical_angle_deg);
    a->Visit({"shear_limit_pa", "Pa",
              "tau_max: the shear limit F_t,max = tau_max times the pad area (also per bond)",
              Range::Positive()},
             &shear_limit_pa);
    a->Visit({"friction_mu", "",
              "Coulomb friction of a pressed pad: reversed shear up to mu C, gripping shear up to "
              "F_t,max + mu C (C the compression)",
              Range::NonNegative()},
             &friction_mu);
    a->Visit({"grip_x", "",
              "gripping direction d in the pad frame, x component (x across the pad width, along "
              "the heading for the bundled robots); normalised; default -1: down the wall for a "
              "robot climbing +x",
              Range::Any()},
             &grip_x);
    a->Visit({"grip_y", "",
              "gripping direction d in the pad frame, y component (y along the pad length); a "
              "climber's d points down the wall",
              Range::Any()},
             &grip_y);
    a->Visit({"moment_share", "",
              "share of the pad's moments the bonds carry: 1 a rigid pad on a rigid ankle (moments "
              "peel it bond by bond); 0 a compliant toe or passive ankle (the pad-level law)",
              Range::Closed(0, 1)},
             &moment_share);
  }
  void Validate(const Checker& c) const {
    if (!(std::hypot(grip_x, grip_y) > 1e-9))
      c.Fail("grip_x", "the gripping direction (grip_x, grip_y) must not be zero");
  }
};

// Throws std::invalid_argument naming the key (adhesion.frictional.<key>) and the value: the
// keys' declared ranges and the non-zero gripping direction (keys::Validate).
void ValidateFrictionalParams(const FrictionalParams& params);

// The pad-level law with its parameters prepared (tan α*, unit d).
class FrictionalLaw {
 public:
  explicit FrictionalLaw(const FrictionalParams& params);  // validates

  const FrictionalParams& params() const { return params_; }
  double tan_critical() const { return tan_critical_; }
  double grip_x() const { return dx_; }
  double grip_y() const { return dy_; }
  double GripShear(double fx, double fy) const { return fx * dx_ + fy * dy_; }  // F_t

  // The least gripping shear F_t with which the pad holds the normal load fn_n (+ pulls off),
  // the pad-level law's edge: pulled, F_n/tan α*; pressed, −credit·μ·|F_n| (reversed shear
  // that friction carries, of which only the share `credit` in [0, 1] is spent: a press can
  // vanish at the next landing or release). Stance controllers aim above it.
  double LeastGripShear(double fn_n, double credit) const {
    return fn_n > 0.0 ? fn_n / tan_critical_ : credit * params_.friction_mu * fn_n;
  }

  // Utilisation of a stress state (σ tension +, shear (τ_x, τ_y)), per the file comment;
  // > 1 breaks. Also the pad-level law with forces over the pad area. Never falls as σ grows
  // at a fixed shear, rounding included (FrictionalUpdate's shortcut relies on it).
  double Utilisation(double sigma_pa, double tau_x_pa, double tau_y_pa) const;
  bool Holds(double sigma_pa, double tau_x_pa, double tau_y_pa) const {
    return Utilisation(sigma_pa, tau_x_pa, tau_y_pa) <= 1.0;
  }
  // The pad-level law on a load (pad of area A): holds per the limit surface. Moments are
  // not part of the pad-level law (FrictionalUpdate carries them).
  bool PadHolds(const PadLoad& load, double area_m2) const;

  // Closed-form pull-off force of a central pull (no lever) on a pad of area A, direction
  // (θ from the normal, φ in-plane from +x), on the limit surface above: 0 when the pad
  // cannot hold at any force (too steep for α*, or reversed shear beyond friction), +inf
  // when it holds at every force (inside the friction cone).
  //   θ < 90°:  0 if cosθ > sinθ·cos(φ − φ_d)·tan α*, else τ_max·A / sinθ
  //   θ ≥ 90°:  0 if sinθ·cos(φ − φ_d) < −μ|cosθ|, else τ_max·A / (sinθ − μ|cosθ|)
  //             (+inf when that denominator is ≤ 0)
  double PulloffClosedForm(double area_m2, double angle_rad, double azimuth_rad) const;

 private:
  FrictionalParams params_;
  double tan_critical_ = 0.0;
  double dx_ = -1.0, dy_ = 0.0;
};

// The cascade both per-bond shear laws (frictional, tabulated) break bonds with: σ_i over the
// bonds left from BondGrid's field (its shears unused), one shear for every bond; each bond
// whose `utilisation(σ_i, τ_x, τ_y)` passes 1 breaks, and the field is recomputed until none
// does. Allocates nothing. *peak_utilisation (if not null): the largest over the bonds left.
// `monotone_in_sigma`: the law's utilisation never falls as σ grows at a fixed shear (the
// frictional law): a round then first tries the largest σ alone (BondGrid::PeakSigma, from the
// field's row and column parts); if it holds, every bond holds and its utilisation is the
// peak, the numbers of the scan bit for bit. Only a round that breaks bonds scans them all.
inline bool PadLoadFinite(const PadLoad& l) {
  return std::isfinite(l.fn_n) && std::isfinite(l.fx_n) && std::isfinite(l.fy_n) &&
         std::isfinite(l.mx_nm) && std::isfinite(l.my_nm);
}
// A bond breaks at utilisation > 1 + kShearLawRoundoff: on the limit itself the bond and
// pad-level evaluations differ only by rounding, and the laws say "holds while ≤".
inline constexpr double kShearLawRoundoff = 1e-12;
template <class Utilisation>
BondGrid::UpdateResult ShearFieldCascade(BondGrid* grid, const PadLoad& load,
                                         const Utilisation& utilisation,
                                         double* peak_utilisation, bool monotone_in_sigma) {
  BondGrid::UpdateResult result;
  grid->ClearBrokenLog();
  if (peak_utilisation != nullptr) *peak_utilisation = 0.0;
  if (!PadLoadFinite(load)) {
    grid->Evaluate(load);  // clears the field
    result.load_finite = false;
    result.detached = grid->detached();
    return result;
  }
  const int n = grid->size();
  while (grid->bonded_count() > 0) {
    const bool unsupported = grid->Field(load);
    const double area = grid->bonded_area_m2();
    const double tau_x = load.fx_n / area, tau_y = load.fy_n / area;
    if (monotone_in_sigma && !unsupported && grid->SigmaFinite()) {
      const double u = utilisation(grid->PeakSigma(), tau_x, tau_y);
      if (!(u > 1.0 + kShearLawRoundoff)) {
        if (peak_utilisation != nullptr) *peak_utilisation = std::max(0.0, u);
        break;
      }
    }
    const int round = result.rounds + 1;
    int broken = 0;
    double peak = 0.0;
    for (int i = 0; i < n; ++i) {
      if (!grid->bonded(i)) continue;
      const double u = unsupported ? kFrictionalCap : utilisation(grid->sigma_pa(i), tau_x, tau_y);
      if (u > 1.0 + kShearLawRoundoff) {
        grid->Break(i, round);
        ++broken;
      } else {
        peak = std::max(peak, u);
      }
    }
    if (broken == 0) {
      if (peak_utilisation != nullptr) *peak_utilisation = peak;
      break;
    }
    ++result.rounds;
    result.broken += broken;
  }
  result.detached = grid->detached();
  return result;
}

// Throws std::invalid_argument for a pull setup or search options pulloff.h does not take.
void CheckPullSetup(const PullSetup& setup, const PulloffOptions& options);

// Bond-level breaking under `load` with the frictional law, the cascade of BondGrid::Update
// (file comment). Broken bonds become kBroken and are logged (grid->last_broken()). Returns
// what Update returns; *peak_utilisation (if not null) gets the largest bond utilisation over
// the bonds left (0 if none), capped at kFrictionalCap.
BondGrid::UpdateResult FrictionalUpdate(BondGrid* grid, const FrictionalLaw& law,
                                        const PadLoad& load, double* peak_utilisation);

// The quasi-static pull-off of a fully bonded pad under the frictional law: the search of
// pulloff.h (bracket, bisect) on FrictionalUpdate. capacity = τ_max·A; force_n 0 when the
// pad holds at no force, +inf when it holds at max_force_factor·capacity.
PulloffResult FrictionalPullOff(const PadParams& pad, const FrictionalParams& law,
                                const PullSetup& setup, const PulloffOptions& options = {});

// The pad-level limit surface in the (F_t, F_n) plane (no lateral shear), as the vertices of
// its boundary down to the compression `max_compression_n`: the friction ray F_t = −μC from
// (−μC_max, −C_max) to the origin, the adhesion line F_n = F_t tan α* to (F_t,max,
// F_t,max tan α*), the shear limit down to (F_t,max, 0) and on to (F_t,max + μC_max, −C_max).
struct LimitVertex {
  double ft_n = 0.0;  // + along d
  double fn_n = 0.0;  // + pulls off
};
std::vector<LimitVertex> FrictionalLimitBoundary(const FrictionalLaw& law, double area_m2,
                                                 double max_compression_n);

// The von Mises law's closed-form pull-off of a central pull on a fine grid (pulloff.h):
// σ_T·A/sqrt(cos²θ + 6.75 sin²θ) for θ ≤ 90°, σ_T·A/(2.598 sinθ − μ|cosθ|) beyond (+inf
// when that is ≤ 0), for the comparison plots.
// The GRADIENT of a pad's utilisation with respect to the load its grid carries,
// ∂U/∂(F_n, F_x, F_y, M_x, M_y) (per N, per N·m; pad frame), for the grid's current bonded set
// and field: U is the largest bond utilisation, so the gradient is that of the bond carrying
// it (the von Mises law's PeakUtilisation bond; for the frictional law the bond of largest σ,
// whose utilisation grows with σ at the uniform shear), through the bond's influence
// (BondGrid::Influence, linear in the load) and the law's derivative at the bond's stress:
// analytic for von Mises (σ_vM/σ_T in tension, √(3τ²)/(σ_T + μ|σ|) in compression), central
// differences of FrictionalLaw::Utilisation for the frictional law (piecewise smooth).
// `frictional` null: the von Mises law with the grid's σ_T and μ. `load` must be the load of
// the grid's last Update or Evaluate. False (grad unchanged) when no bond is bonded or the
// load is unsupported. Never allocates.
// `peak_bond` ≥ 0: the von Mises peak's bond, already found (BondGrid::PeakUtilisation of the
// same field), so that it is not searched again.
bool PadUtilisationGradient(const BondGrid& grid, const FrictionalLaw* frictional,
                            const PadLoad& load, Eigen::Matrix<double, 5, 1>* grad,
                            int peak_bond = -1);

double VonMisesPulloffClosedForm(double capacity_n, double angle_rad, double mu);

}  // namespace climbsim::adhesion

#endif  // CLIMBSIM_ADHESION_FRICTIONAL_LAW_H_
