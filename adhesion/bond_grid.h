// The bond grid of one dry-adhesive pad: bond stresses, rupture and progressive detachment
// (docs/design.md section 3, seed section 2.2.2). Pure math: no MuJoCo, testable alone.
//
// PAD FRAME. Origin at the centroid of the pad's contact face. n is the pad normal, from
// the surface into the pad; x spans the width b, y the length h; (x, y, n) is right-handed
// (n = x × y). Bond i sits at the centre of cell (ix, iy) of an N_x × N_y grid:
//
//     x_i = (ix + 1/2)·b/N_x − b/2,   y_i = (iy + 1/2)·h/N_y − h/2,   dA = b·h/(N_x·N_y),
//     index i = iy·N_x + ix  (x runs fastest).
//
// THE LOAD (PadLoad) AND ITS SIGNS. The load is the wrench that the rest of the robot puts
// on the pad and that the bond layer must carry; for a pad held still, it is MINUS the
// wrench that the surface exerts on the pad (PadLoadFromSurfaceWrench() does the negation).
// All five numbers are components in the pad frame, the moments taken about the pad
// centroid (the origin):
//
//     fn_n  = F·n   > 0 pulls the pad off the surface, < 0 presses it on;
//     fx_n, fy_n    shear along x, y;
//     mx_nm = M·x,  my_nm = M·y   with M = Σ r × F about the pad centroid.
//
// A pull F_n applied at (0, y0) gives M_x = +y0·F_n and tensions the +y edge first; a pull
// at (x0, 0) gives M_y = −x0·F_n and tensions the +x edge first (tests pin both). With
// these signs docs/design.md's  σ = F_n/A + M_x·y/I_x − M_y·x/I_y  holds. If instead one took
// the surface's own torque (−M) while flipping only F_n, both moment terms would change
// sign: the formula holds for this one convention only.
//
// NORMAL STRESS (Pa, tension positive) over the bonded set B, bonds as points of area dA,
// linear in position (the pad is rigid, the bond layer a bed of equal springs):
//
//     A_B = |B|·dA,   (x_c, y_c) = mean of the bonded positions,
//     I_x = Σ_B (y_i − y_c)²·dA,   I_y = Σ_B (x_i − x_c)²·dA,
//     I_xy = Σ_B (x_i − x_c)(y_i − y_c)·dA,
//     M_x^c = M_x − y_c·F_n,   M_y^c = M_y + x_c·F_n      (the moments moved to (x_c, y_c)),
//     σ_i = F_n/A_B + g_x·(x_i − x_c) + g_y·(y_i − y_c),   with
//     [ I_y  I_xy ] [g_x]   [ −M_y^c ]
//     [ I_xy  I_x ] [g_y] = [  M_x^c ].
//
//   When I_xy = 0 (a full pad, or any set symmetric about an axis through its centroid
//   parallel to x or y) this is exactly docs/design.md's
//     σ_i = F_n/A_B + M_x^c·(y_i − y_c)/I_x − M_y^c·(x_i − x_c)/I_y;
//   for other sets (a corner peeled off, a random patch) docs/design.md's formula is not in
//   equilibrium and the 2×2 solve (unsymmetric bending) is what makes it so. Either way the
//   bonded points carry the load exactly: Σ σ_i dA = F_n, Σ σ_i y_i dA = M_x,
//   −Σ σ_i x_i dA = M_y. Moving the moments to the bonded centroid is also left implicit in
//   docs/design.md; it changes nothing for a full pad (x_c = y_c = 0) and makes a central pull on
//   a partly bonded pad load the bonds nearest the pull line hardest.
//   For a full pad, I_x = b·h³/12·(1 − 1/N_y²) and I_y = h·b³/12·(1 − 1/N_x²): the point
//   sums miss the continuous area moments by the midpoint-rule term dA·dy²/12 per bond, so
//   the full-pad σ equals F_n/(bh) + M_x·y/(bh³/12) − M_y·x/(hb³/12) only as the grid
//   refines (the moment terms are 1/(N² − 1) too large: 0.1 % at 32 cells, 1.6 % at 8).
//
// SHEAR (Pa), parabolic across the direction of each shear force, normalised over B:
//
//     τ_x,i = F_x·w_i / Σ_B w_j·dA,   w_i = h²/4 − y_i²,
//     τ_y,i = F_y·v_i / Σ_B v_j·dA,   v_i = b²/4 − x_i².
//
//   Σ_B τ_x dA = F_x and Σ_B τ_y dA = F_y for every pad shape and bonded set; a full pad
//   peaks at 3F/(2bh) as the grid refines. (Seed eqs. 3–4 divide by h·b³/12 where b·h³/12
//   belongs and vice versa; they agree with this only for square pads.)
//
// RUPTURE (seed eqs. 6–8). σ_vM = sqrt(σ² + 3τ_x² + 3τ_y²). A bonded bond breaks when
//
//     σ ≥ 0 (tension):      σ² + 3τ_x² + 3τ_y² ≥ σ_T²
//     σ < 0 (compression):  3τ_x² + 3τ_y² ≥ (σ_T + μ·|σ|)²
//
//   (squares of the docs/design.md conditions; all terms are ≥ 0, so they are equivalent). The
//   UTILISATION of a bond is demand over threshold, sqrt(σ² + 3τ²)/σ_T in tension and
//   sqrt(3τ²)/(σ_T + μ|σ|) in compression: a bond breaks at utilisation ≥ 1.
//
// DEGENERATE BONDED SETS. Bonds all on one line (a single row or column, a diagonal, the
// last row left by a peel: det = I_x·I_y − I_xy² = 0, detected exactly on integer sums)
// form a hinge: they carry the moment that bends the line (gradient along it) but have no
// lever against the moment about the line itself, M^c·d (d the line's direction). Rule: if
// |M^c·d| > kHingeMomentTolerance·σ_T·b·h·max(b, h), the load is unsupported and every bond
// of the set breaks in that round (the pad would rotate about the line and peel);
// otherwise that component is dropped. A single bond is a hinge about every axis: any
// |M^c| above the tolerance breaks it. An empty set carries nothing and breaks nothing.
// Σ_B w = 0 (or Σ_B v = 0) cannot happen with cell centres (every w_i, v_i > 0); it is
// guarded anyway: a nonzero F_x (F_y) on such a set is unsupported too.
//
// PROGRESSIVE DETACHMENT (Update). Round k: compute the stress field over the current B,
// break every bond at or over its threshold (all against the same field), and repeat
// while a round breaks something. Bonds broken in one update are logged in order (round,
// then index) in a buffer sized at construction. The pad is detached when fewer than
// min_bonds remain; the grid only reports it (releasing the weld and the remaining bonds
// is the caller's choice, e.g. Release()).
//
// ALLOCATION. The constructor sizes everything; nothing else allocates (tests count it).
// Threads: one BondGrid per pad per rollout; const members but PeakUtilisation may run together.
#ifndef CLIMBSIM_ADHESION_BOND_GRID_H_
#define CLIMBSIM_ADHESION_BOND_GRID_H_

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "keys/keys.h"

namespace climbsim::adhesion {

// A moment about a hinge line counts as zero when it is below this fraction of
// σ_T·b·h·max(b, h): far below anything a real load produces, far above the rounding of a
// moment moved to a centroid that is zero in exact arithmetic.
inline constexpr double kHingeMomentTolerance = 1e-9;

// Largest grid side that the constructor accepts (so at most 2^20 bonds: the exact integer
// moment sums of the bonded set then stay below 2^61 and their products below 2^127).
inline constexpr int kMaxGridSide = 1024;

// Pad geometry and bond strength. Validated once (ValidatePadParams), never changed.
struct PadParams {
  double width_m = 0.0;     // b, along pad x (> 0; no default: must be given)
  double length_m = 0.0;    // h, along pad y (> 0; no default: must be given)
  int grid_x = 16;          // N_x bonds across the width (1 .. kMaxGridSide = 1024)
  int grid_y = 16;          // N_y bonds along the length (1 .. kMaxGridSide)
  double sigma_t_pa = 10e3; // σ_T, rupture threshold (> 0); 10 kPa: the seed's authors'
                            // estimate for their dry adhesive
  double mu = 0.0;          // μ ≥ 0, gain of compression on the shear threshold
  int min_bonds = 1;        // detached when fewer bonds than this remain (1 .. N_x·N_y)

  // The scenario keys adhesion.sigma_t_pa .. min_bonds (width_m and length_m are not keys:
  // they come from each pad's box geom). keys::Validate checks them, then Validate.
  template <class A>
  void Serialize(A* a) {
    a->Visit({"sigma_t_pa", "Pa",
              "sigma_T, bond rupture threshold (10 kPa: the seed authors' estimate for their dry "
              "adhesive)",
              Range::Positive()},
             &sigma_t_pa);
    a->Visit({"mu", "",
              "gain of compression on the shear threshold: a compressed bond breaks when sqrt(3) "
              "times its shear reaches sigma_T + mu times its compression",
              Range::NonNegative()},
             &mu);
    a->Visit({"grid_x", "", "bonds across the pad width (accuracy against time)",
              Range::Closed(1, kMaxGridSide)},
             &grid_x);
    a->Visit({"grid_y", "", "bonds along the pad length", Range::Closed(1, kMaxGridSide)},
             &grid_y);
    a->Visit({"min_bonds", "", "the pad detaches when fewer bonds than this remain",
              Range::Closed(1, 1.0 * kMaxGridSide * kMaxGridSide)},
             &min_bonds);
  }
  void Validate(const Checker& c) const {
    if (static_cast<long>(min_bonds) > static_cast<long>(grid_x) * grid_y) {
      c.Fail("min_bonds", "must be <= grid_x * grid_y = " + std::to_string(grid_x * grid_y) +
                              ", got " + std::to_string(min_bonds));
    }
  }
};

// Throws std::invalid_argument naming the key and the value: width_m and length_m must be
// > 0 and finite; the keys are checked against their declaration (keys::Validate, e.g.
// "adhesion.sigma_t_pa must be > 0, got -3"; min_bonds <= grid_x·grid_y).
void ValidatePadParams(const PadParams& params);

// The load the bond layer carries: pad frame, moments about the pad centroid (signs: above).
struct PadLoad {
  double fn_n = 0.0;   // normal force, > 0 pulls off
  double fx_n = 0.0;   // shear along x
  double fy_n = 0.0;   // shear along y
  double mx_nm = 0.0;  // moment about x
  double my_nm = 0.0;  // moment about y
};

// The load from the wrench that the surface exerts on the pad (force, and torque about the
// pad centroid, both in pad-frame components): the negation of both. The twist about n is
// not part of the model and is dropped.
PadLoad PadLoadFromSurfaceWrench(const Eigen::Vector3d& force_on_pad_pad_n,
                                 const Eigen::Vector3d& torque_on_pad_pad_nm);

// Per-bond state. Broken stays broken until BondAll, BondFraction or Release; Grow never re-bonds.
enum class BondState : uint8_t { kUnbonded = 0, kBonded = 1, kBroken = 2 };

// Stresses of one bond in the last evaluated field; all zero for a bond not bonded.
struct BondStress {
  double sigma_pa = 0.0;      // σ, tension positive
  double tau_x_pa = 0.0;      // τ_x
  double tau_y_pa = 0.0;      // τ_y
  double von_mises_pa = 0.0;  // sqrt(σ² + 3τ_x² + 3τ_y²)
  double utilisation = 0.0;   // demand/threshold, ≥ 1 breaks; +inf if load_unsupported
};

// The stress field over the bonded set, summarised.
struct StressSummary {
  double peak_sigma_pa = 0.0;      // largest σ over B (0 when B is empty)
  double peak_von_mises_pa = 0.0;  // largest σ_vM over B
  double peak_utilisation = 0.0;   // largest utilisation over B; +inf if load_unsupported
  int over_threshold = 0;          // bonds of B at or over their threshold
  bool load_unsupported = false;   // a moment about a hinge line (or shear on zero weight)
};

// One bond broken during the last Update, in order of breaking.
struct BrokenBond {
  int index = 0;  // bond index, iy·N_x + ix
  int round = 0;  // 1 for the first round of the cascade
};

class BondGrid {
 public:
  // Validates params (throws std::invalid_argument), sizes every buffer; all bonds unbonded.
  explicit BondGrid(const PadParams& params);

  // --- Attachment state (no allocation) ---
  // PARTIAL CONTACT (pad_touch.h): only the cells that touch the surface can bond. T is the
  // touching set, all N cells after construction and until SetTouching changes it (Release
  // keeps it). With T the whole pad, everything below is as without it, bit for bit.
  // `touching` has one entry per bond (index iy·N_x + ix), nonzero where the cell touches.
  // Call it before the attachment's BondAll or BondFraction; bonds already bonded stay.
  void SetTouching(std::span<const uint8_t> touching);
  void TouchAll();
  bool touching(int index) const { return touching_[index] != 0; }
  int touching_count() const { return touching_count_; }

  // Every touching bond bonded (a fresh, full attachment).
  void BondAll();
  // A fresh attachment with round(fraction·|T|) bonds bonded, chosen centre-out among the
  // touching cells: bonds in order of (2x/b)² + (2y/h)² (the patch keeps the pad's aspect),
  // ties by index. All others unbonded (not broken). fraction clamped to [0, 1]; NaN is 0.
  void BondFraction(double fraction);
  // Grows the bonded set, centre-out, until round(fraction·|T|) bonds are bonded, skipping
  // bonds broken since the last attachment and cells that do not touch; returns how many.
  int Grow(double fraction);
  // Sets one bond bonded or unbonded (tests, custom patterns). Throws std::out_of_range.
  void SetBonded(int index, bool bonded);
  void Release();  // every bond unbonded: the pad released

  // --- Loading (no allocation) ---
  struct UpdateResult {
    int broken = 0;           // bonds broken in this update
    int rounds = 0;           // cascade rounds that broke at least one bond
    bool detached = false;    // fewer than min_bonds bonded after the cascade
    bool load_finite = true;  // false: a NaN/inf load component; nothing was evaluated
  };
  // Stresses, rupture and the cascade to a fixed point under load_pad. Logs the broken
  // bonds (last_broken()) and keeps the field over the bonds left for stress() and
  // Summary(). A round costs O(N_x + N_y) plus a scan of the rows whose bound
  // (max σ)₊² + max 3τ² reaches σ_T² (bond_grid.cc): a pad that holds comfortably is not
  // scanned bond by bond.
  UpdateResult Update(const PadLoad& load_pad);
  // The stress field over the current bonded set under load_pad, breaking nothing; returns
  // Summary(). A non-finite load gives an empty summary and an all-zero field.
  StressSummary Evaluate(const PadLoad& load_pad);
  // Peaks of the current field (last Update, after its cascade, or Evaluate) over the
  // bonded set: one scan of the bonds.
  StressSummary Summary() const;
  // Summary().peak_utilisation, the same number bit for bit, without scanning every bond:
  // rows are scanned in order of their bound (max σ)₊² + max 3τ² (the one BreakOverThreshold
  // skips by) until no row left can beat the peak found. Once per step per pad (the reflexes'
  // utilisation signal); a pad far from its limit costs a row or two instead of N_x·N_y bonds.
  double PeakUtilisation() const;
  // The same, and the index of a bond that carries it (the first in row-bound order; −1 when
  // none is bonded or the load is unsupported). `hint`, e.g. the last step's peak bond: rows
  // and blocks of ⌈√N_x⌉ columns whose bound cannot reach its utilisation are not scanned;
  // number and bond are PeakUtilisationByRowBound's whatever the hint (tests pin it).
  double PeakUtilisation(int* peak_bond, int hint = -1) const;
  double PeakUtilisationByRowBound(int* peak_bond) const;  // the reference; non-finite fields
  // Index of a bonded bond with the largest σ in the current field (the frictional law's most
  // loaded bond: its utilisation grows with σ at a uniform shear); −1 when none is bonded.
  int PeakSigmaBond() const;

  // INFLUENCE of the load on one bond over the current bonded set: the 3×5 matrix A with
  //   (σ_i, τ_x,i, τ_y,i)ᵀ = A·(F_n, F_x, F_y, M_x, M_y)ᵀ
  // for the field the first round of Update would compute (the field is linear in the load:
  // the σ rows follow the 2×2 bending solve of the file comment, the τ rows the parabolic
  // profile, or with `uniform_shear` the frictional law's τ = F/A_B on every bond). Used for
  // the gradient of a pad's utilisation (sticky_pad.h). Pure: the stored field is untouched.
  // Returns false (A unchanged) for a bond not bonded; on a hinge (line or point set) the
  // moment about the hinge has no lever and its column is zero.
  bool Influence(int index, bool uniform_shear, Eigen::Matrix<double, 3, 5>* a) const;

  // --- Queries ---
  const PadParams& params() const { return params_; }
  int size() const { return static_cast<int>(state_.size()); }
  int grid_x() const { return params_.grid_x; }
  int grid_y() const { return params_.grid_y; }
  int index(int ix, int iy) const { return iy * params_.grid_x + ix; }
  int ix_of(int index) const { return index % params_.grid_x; }
  int iy_of(int index) const { return index / params_.grid_x; }
  double bond_x_m(int index) const { return col_x_m_[ix_of(index)]; }
  double bond_y_m(int index) const { return row_y_m_[iy_of(index)]; }
  double cell_area_m2() const { return cell_area_m2_; }
  double pad_area_m2() const { return params_.width_m * params_.length_m; }

  BondState state(int index) const { return static_cast<BondState>(state_[index]); }
  bool bonded(int index) const { return state(index) == BondState::kBonded; }
  int bonded_count() const { return bonded_count_; }
  double bonded_fraction() const { return static_cast<double>(bonded_count_) / size(); }
  double bonded_area_m2() const { return bonded_count_ * cell_area_m2_; }
  bool detached() const { return bonded_count_ < params_.min_bonds; }

  // Stresses of one bond in the field of the last Update (after its cascade) or Evaluate.
  BondStress stress(int index) const;
  // The bonds broken by the last Update, in order. Valid until the next Update.
  std::span<const BrokenBond> last_broken() const {
    return {broken_log_.data(), static_cast<size_t>(broken_count_)};
  }

  // --- Another rupture law's cascade (frictional_law.h: FrictionalUpdate) ---
  // Empties the log of broken bonds (the start of an update).
  void ClearBrokenLog() { broken_count_ = 0; }
  // Breaks bond `index` if bonded (kBroken, as Update does) and logs it with `round`.
  void Break(int index, int round);
  // The field of Evaluate under a finite load_pad, without its summary's scan of every bond;
  // returns whether the load is unsupported (Summary().load_unsupported).
  bool Field(const PadLoad& load_pad) {
    ComputeField(load_pad);
    return unsupported_;
  }
  // Whether every part of the σ field is finite; the largest σ over the bonds (−inf: none),
  // a full row's from its parts alone (the max over columns plus the row's part).
  bool SigmaFinite() const;
  double PeakSigma() const;
  // σ of one bond in the current field (Evaluate, Update); 0 for a bond not bonded.
  double sigma_pa(int index) const {
    return bonded(index) ? col_sigma_[ix_of(index)] + row_sigma_[iy_of(index)] : 0.0;
  }

 private:
  // Exact sums over the bonded set in grid units: a bond at column ix and row iy sits at
  // x = kx·b/(2N_x), y = ky·h/(2N_y) with the integers kx = 2·ix + 1 − N_x, ky = 2·iy + 1 − N_y.
  struct MomentSums { int64_t n = 0, kx = 0, ky = 0, kxx = 0, kyy = 0, kxy = 0; };

  // The linear-plus-parabolic field of one round, separable into per-row and per-column
  // parts: σ_i = col_sigma_[ix] + row_sigma_[iy], 3τ² = col_tau3_[ix] + row_tau3_[iy].
  void ComputeField(const PadLoad& load);
  // The bonded set's geometry for the bending solve: centroid, centred second moments, and
  // whether it is a point or a line (decided exactly on the integer sums); n > 0.
  struct Bending {
    double x_c = 0.0, y_c = 0.0, i_x = 0.0, i_y = 0.0, i_xy = 0.0;
    bool is_point = false, is_line = false;
    double line_dx = 0.0, line_dy = 0.0;  // a line's unit direction
  };
  Bending BendingOfBondedSet() const;
  void BendingGradient(const Bending& bend, const PadLoad& load, double* g_x, double* g_y);
  void NormaliseShears(const PadLoad& load);
  void ClearField();
  // Breaks (and logs, with round) every bonded bond over its threshold in the current
  // field; returns how many.
  int BreakOverThreshold(int round);
  // PeakUtilisation's: a mask of row iy's blocks that reach floor_u2; the scan of rows kept.
  uint32_t BlocksOverFloor(int iy, double floor_u2) const;
  double ScanRows(int rows, double floor_u2, int* peak_bond) const;
  void SetState(int index, BondState new_state);

  PadParams params_;
  double cell_area_m2_ = 0.0;
  double sigma_t_sq_ = 0.0;
  double hinge_nm_ = 0.0;  // kHingeMomentTolerance·σ_T·b·h·max(b, h)
  double unit_x_m_ = 0.0;  // b/(2N_x)
  double unit_y_m_ = 0.0;  // h/(2N_y)

  // Geometry, fixed at construction.
  std::vector<double> col_x_m_;  // x of column ix
  std::vector<double> row_y_m_;  // y of row iy
  std::vector<double> col_v_;    // v = b²/4 − x²
  std::vector<double> row_w_;    // w = h²/4 − y²
  std::vector<int> centre_out_;  // bond indices, centre-out
  MomentSums full_sums_;         // of the full pad

  // State.
  std::vector<uint8_t> state_;  // BondState per bond
  std::vector<uint8_t> touching_;  // 1: the cell touches the surface and may bond
  int touching_count_ = 0;
  std::vector<int> col_count_;  // bonded bonds per column
  std::vector<int> row_count_;  // bonded bonds per row
  int bonded_count_ = 0;
  MomentSums sums_;
  // Of the bonded set, kept until it changes (SetState, BondAll, Release): ComputeField's
  // bending geometry and shear sums Σ count·v, Σ count·w.
  bool set_cached_ = false;
  Bending set_bend_;
  double set_sum_v_ = 0.0, set_sum_w_ = 0.0;

  // The current field.
  std::vector<double> col_sigma_;
  std::vector<double> row_sigma_;
  std::vector<double> col_tau3_;
  std::vector<double> row_tau3_;
  double tau_x_per_w_ = 0.0, tau_y_per_v_ = 0.0;  // τ_x = tau_x_per_w_·w, τ_y = tau_y_per_v_·v
  double col_sigma_max_ = 0.0;  // max over columns of col_sigma_
  double col_tau3_max_ = 0.0;   // max over columns of col_tau3_
  double row_sigma_max_ = 0.0, row_tau3_max_ = 0.0;  // max over rows of row_sigma_, row_tau3_
  bool unsupported_ = false;
  // PeakUtilisation's scratch: row bounds, candidate rows, each column block's max σ, max 3τ².
  mutable std::vector<double> row_bound_u2_, block_sigma_max_, block_tau3_max_;
  mutable std::vector<uint32_t> row_order_, row_blocks_;
  int block_cols_ = 1;  // ⌈√N_x⌉ (so at most 32 blocks)

  // The log of the last Update.
  std::vector<BrokenBond> broken_log_;
  int broken_count_ = 0;
};

}  // namespace climbsim::adhesion

#endif  // CLIMBSIM_ADHESION_BOND_GRID_H_
