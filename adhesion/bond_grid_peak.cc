// BondGrid's peaks (bond_grid.h): the full summary scan, the peak utilisation by row bounds
// (with the last step's peak bond as a floor) and the peak σ from the field's row and column
// parts. Split from bond_grid.cc by topic: these read the field, they never change the grid.
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "adhesion/bond_grid.h"

namespace climbsim::adhesion {
namespace {
// A row's bound on u² when every bond of it is pressed (σ ≤ s_max < 0): each threshold is
// at least σ_T − μ·s_max (rounding is monotone); else the tension bound as given.
double PressedRowBound(double s_max, double tau3_max, double sigma_t, double mu, double bound) {
  if (!(s_max < 0.0)) return bound;
  const double threshold = sigma_t - mu * s_max;
  return tau3_max / (threshold * threshold);
}

// u² of a bond: (σ² + 3τ²)/σ_T² in tension, 3τ²/(σ_T + μ|σ|)² in compression (the scans').
double BondU2(double sigma, double tau3, double sigma_t, double mu, double sigma_t_sq) {
  if (sigma >= 0.0) return (sigma * sigma + tau3) / sigma_t_sq;
  const double threshold = sigma_t - mu * sigma;
  return tau3 / (threshold * threshold);
}

// Whether no bond with σ ≤ s_max and 3τ² ≤ t_max can reach u² ≥ floor_u2, decided without a
// division: a bond's u² is at most fl(num/den) (rounding is monotone), num/den the bound of
// PeakUtilisationByRowBound (tension) or PressedRowBound (σ ≤ s_max < 0), and
// num < fl(fl(floor·den)·(1 − 2⁻⁵⁰)) keeps fl(num/den) below the floor despite the roundings.
bool BelowFloor(double s_max, double t_max, double sigma_t, double mu, double sigma_t_sq,
                double floor_u2) {
  constexpr double kShrink = 1.0 - 0x1p-50;
  if (s_max < 0.0) {
    const double threshold = sigma_t - mu * s_max;
    return t_max < floor_u2 * (threshold * threshold) * kShrink;
  }
  return s_max * s_max + t_max < floor_u2 * sigma_t_sq * kShrink;
}
}  // namespace

StressSummary BondGrid::Summary() const {
  StressSummary summary;
  if (bonded_count_ == 0) return summary;
  const int nx = params_.grid_x;
  const int ny = params_.grid_y;
  const double sigma_t = params_.sigma_t_pa;
  const double mu = params_.mu;
  double max_sigma = -std::numeric_limits<double>::infinity();
  double max_vm_sq = 0.0;
  double max_tension_sq = 0.0;      // largest σ² + 3τ² among bonds in tension
  double max_compression_u2 = 0.0;  // largest 3τ²/(σ_T + μ|σ|)² among bonds in compression
  int over = 0;
  for (int iy = 0; iy < ny; ++iy) {
    if (row_count_[iy] == 0) continue;
    const uint8_t* state = state_.data() + iy * nx;
    for (int ix = 0; ix < nx; ++ix) {
      if (state[ix] != static_cast<uint8_t>(BondState::kBonded)) continue;
      const double sigma = col_sigma_[ix] + row_sigma_[iy];
      const double tau3 = col_tau3_[ix] + row_tau3_[iy];
      const double vm_sq = sigma * sigma + tau3;
      max_sigma = std::max(max_sigma, sigma);
      max_vm_sq = std::max(max_vm_sq, vm_sq);
      if (sigma >= 0.0) {
        max_tension_sq = std::max(max_tension_sq, vm_sq);
        over += vm_sq >= sigma_t_sq_ ? 1 : 0;
      } else {
        const double threshold = sigma_t - mu * sigma;
        const double threshold_sq = threshold * threshold;
        max_compression_u2 = std::max(max_compression_u2, tau3 / threshold_sq);
        over += tau3 >= threshold_sq ? 1 : 0;
      }
    }
  }
  summary.peak_sigma_pa = max_sigma;
  summary.peak_von_mises_pa = std::sqrt(max_vm_sq);
  summary.peak_utilisation =
      unsupported_ ? std::numeric_limits<double>::infinity()
                   : std::sqrt(std::max(max_tension_sq / sigma_t_sq_, max_compression_u2));
  summary.over_threshold = unsupported_ ? bonded_count_ : over;
  summary.load_unsupported = unsupported_;
  return summary;
}

double BondGrid::PeakUtilisation() const { return PeakUtilisation(nullptr); }

double BondGrid::PeakUtilisationByRowBound(int* peak_bond) const {
  if (peak_bond != nullptr) *peak_bond = -1;
  if (bonded_count_ == 0) return 0.0;
  if (unsupported_) return std::numeric_limits<double>::infinity();
  const int nx = params_.grid_x, ny = params_.grid_y;
  const double sigma_t = params_.sigma_t_pa, mu = params_.mu;
  // u² of a bond: (σ² + 3τ²)/σ_T² in tension, 3τ²/(σ_T + μ|σ|)² in compression, both at most
  // the row's bound/σ_T² (σ ≤ max σ; σ_T + μ|σ| ≥ σ_T; rounding is monotone). Rows in order of
  // (bound descending, index ascending), each pick the largest key below the last (a row
  // without bonds: −1, never picked), until the peak found beats every row left.
  double* row_bound = row_bound_u2_.data();
  for (int iy = 0; iy < ny; ++iy) {
    const double sigma_bound = std::max(col_sigma_max_ + row_sigma_[iy], 0.0);
    const double bound = sigma_bound * sigma_bound + (col_tau3_max_ + row_tau3_[iy]);
    row_bound[iy] = row_count_[iy] == 0 ? -1.0 : bound / sigma_t_sq_;
  }
  double peak_u2 = 0.0, skip_d = -1.0;  // d ≥ 0: the first bond is never skipped
  double last_bound = std::numeric_limits<double>::infinity();
  int last_row = -1;
  for (int pick = 0; pick < ny; ++pick) {
    int row = -1;
    double bound = -1.0;
    for (int iy = 0; iy < ny; ++iy) {
      const double b = row_bound[iy];
      const bool after_last = b < last_bound || (b == last_bound && iy > last_row);
      if (after_last && b > bound) {
        bound = b;
        row = iy;
      }
    }
    if (row < 0 || bound < peak_u2) break;
    last_bound = bound;
    last_row = row;
    // Pressed rows have a tighter bound: skipped (not reordered: ties keep the first bond).
    if (PressedRowBound(col_sigma_max_ + row_sigma_[row], col_tau3_max_ + row_tau3_[row], sigma_t,
                        mu, bound) < peak_u2) {
      continue;
    }
    const uint8_t* state = state_.data() + row * nx;
    for (int ix = 0; ix < nx; ++ix) {
      if (state[ix] != static_cast<uint8_t>(BondState::kBonded)) continue;
      const double sigma = col_sigma_[ix] + row_sigma_[row];
      const double tau3 = col_tau3_[ix] + row_tau3_[row];
      // u² ≤ d/σ_T² (in compression too) and skip_d/σ_T² ≤ peak_u2: d ≤ skip_d cannot win.
      const double d = sigma * sigma + tau3;
      if (d <= skip_d) continue;
      const double threshold = sigma_t - mu * sigma;  // σ < 0
      const double u2 = sigma >= 0.0 ? d / sigma_t_sq_ : tau3 / (threshold * threshold);
      if (u2 > peak_u2 || (peak_bond != nullptr && *peak_bond < 0)) {
        peak_u2 = std::max(peak_u2, u2);
        if (peak_bond != nullptr) *peak_bond = row * nx + ix;
      }
      if (sigma >= 0.0) skip_d = std::max(skip_d, d);  // d/σ_T² = u2 ≤ peak_u2 now
    }
  }
  return std::sqrt(peak_u2);
}

double BondGrid::PeakUtilisation(int* peak_bond, int hint) const {
  if (peak_bond != nullptr) *peak_bond = -1;
  if (bonded_count_ == 0) return 0.0;
  if (unsupported_) return std::numeric_limits<double>::infinity();
  const int nx = params_.grid_x, ny = params_.grid_y;
  // Each column block's largest σ and 3τ²; `nan` turns NaN if any part is not finite (x·0),
  // and such a field takes the row scan.
  double nan = 0.0;
  const int blocks = static_cast<int>(block_sigma_max_.size());
  for (int k = 0; k < blocks; ++k) {
    double s = -std::numeric_limits<double>::infinity(), t = 0.0;
    for (int ix = k * block_cols_; ix < std::min(nx, (k + 1) * block_cols_); ++ix) {
      s = std::max(s, col_sigma_[ix]);
      t = std::max(t, col_tau3_[ix]);
      nan += col_sigma_[ix] * 0.0 + col_tau3_[ix] * 0.0;
    }
    block_sigma_max_[k] = s, block_tau3_max_[k] = t;
  }
  for (int iy = 0; iy < ny; ++iy) nan += row_sigma_[iy] * 0.0 + row_tau3_[iy] * 0.0;
  if (nan != 0.0) return PeakUtilisationByRowBound(peak_bond);
  // The floor: the hint's u², a bonded bond's, so at most the peak. A row or block whose bound
  // stays below it holds neither the peak nor a bond that ties it: left out.
  double floor_u2 = 0.0;
  if (hint >= 0 && hint < size() && bonded(hint)) {
    floor_u2 = BondU2(col_sigma_[ix_of(hint)] + row_sigma_[iy_of(hint)],
                      col_tau3_[ix_of(hint)] + row_tau3_[iy_of(hint)], params_.sigma_t_pa,
                      params_.mu, sigma_t_sq_);
  }
  // The rows left, in the row scan's order (its bound descending, then index), each with the
  // mask of its blocks that reach the floor.
  int rows = 0;
  for (int iy = 0; iy < ny; ++iy) {
    if (row_count_[iy] == 0) continue;
    const double sigma_bound = std::max(col_sigma_max_ + row_sigma_[iy], 0.0);
    const double bound = sigma_bound * sigma_bound + (col_tau3_max_ + row_tau3_[iy]);
    if (BelowFloor(sigma_bound, col_tau3_max_ + row_tau3_[iy], 0.0, 0.0, sigma_t_sq_, floor_u2)) {
      continue;
    }
    row_blocks_[iy] = BlocksOverFloor(iy, floor_u2);
    if (row_blocks_[iy] == 0) continue;
    row_bound_u2_[iy] = bound / sigma_t_sq_;
    int k = rows++;
    for (; k > 0 && row_bound_u2_[row_order_[k - 1]] < row_bound_u2_[iy]; --k) {
      row_order_[k] = row_order_[k - 1];
    }
    row_order_[k] = iy;
  }
  return ScanRows(rows, floor_u2, peak_bond);
}

// The mask of row iy's blocks whose bound reaches floor_u2 (bit k: block k).
uint32_t BondGrid::BlocksOverFloor(int iy, double floor_u2) const {
  uint32_t mask = 0;
  const int blocks = static_cast<int>(block_sigma_max_.size());
  for (int k = 0; k < blocks; ++k) {
    if (!BelowFloor(block_sigma_max_[k] + row_sigma_[iy], block_tau3_max_[k] + row_tau3_[iy],
                    params_.sigma_t_pa, params_.mu, sigma_t_sq_, floor_u2)) {
      mask |= 1u << k;
    }
  }
  return mask;
}

// PeakUtilisationByRowBound's scan over the rows row_order_[0, rows) and their blocks
// (row_blocks_), blocks below the peak found skipped too: the bonds it skips cannot carry the
// peak, nor an earlier bond of the same u².
double BondGrid::ScanRows(int rows, double floor_u2, int* peak_bond) const {
  const int nx = params_.grid_x;
  const double sigma_t = params_.sigma_t_pa, mu = params_.mu;
  double peak_u2 = 0.0, skip_d = -1.0;
  for (int r = 0; r < rows; ++r) {
    const int row = row_order_[r];
    if (row_bound_u2_[row] < peak_u2) break;
    const double row_sigma = row_sigma_[row], row_tau3 = row_tau3_[row];
    const uint8_t* state = state_.data() + row * nx;
    for (uint32_t mask = row_blocks_[row]; mask != 0; mask &= mask - 1) {
      const int k = std::countr_zero(mask);
      if (peak_u2 > floor_u2 && BelowFloor(block_sigma_max_[k] + row_sigma,
                                           block_tau3_max_[k] + row_tau3, sigma_t, mu,
                                           sigma_t_sq_, peak_u2)) {
        continue;
      }
      for (int ix = k * block_cols_; ix < std::min(nx, (k + 1) * block_cols_); ++ix) {
        if (state[ix] != static_cast<uint8_t>(BondState::kBonded)) continue;
        const double sigma = col_sigma_[ix] + row_sigma;
        const double tau3 = col_tau3_[ix] + row_tau3;
        const double d = sigma * sigma + tau3;
        if (d <= skip_d) continue;
        const double u2 = BondU2(sigma, tau3, sigma_t, mu, sigma_t_sq_);
        if (u2 > peak_u2 || (peak_bond != nullptr && *peak_bond < 0)) {
          peak_u2 = std::max(peak_u2, u2);
          if (peak_bond != nullptr) *peak_bond = row * nx + ix;
        }
        if (sigma >= 0.0) skip_d = std::max(skip_d, d);
      }
    }
  }
  return std::sqrt(peak_u2);
}

bool BondGrid::SigmaFinite() const {
  for (double s : col_sigma_) {
    if (!std::isfinite(s)) return false;
  }
  for (double s : row_sigma_) {
    if (!std::isfinite(s)) return false;
  }
  return true;
}

double BondGrid::PeakSigma() const {
  const int nx = params_.grid_x;
  double best = -std::numeric_limits<double>::infinity();
  for (int iy = 0; iy < params_.grid_y; ++iy) {
    if (row_count_[iy] == 0) continue;
    // Every σ of the row is at most this, and a full row reaches it (rounding is monotone).
    const double bound = col_sigma_max_ + row_sigma_[iy];
    if (row_count_[iy] == nx) {
      best = std::max(best, bound);
      continue;
    }
    if (bound <= best) continue;
    const uint8_t* state = state_.data() + iy * nx;
    for (int ix = 0; ix < nx; ++ix) {
      if (state[ix] == static_cast<uint8_t>(BondState::kBonded)) {
        best = std::max(best, col_sigma_[ix] + row_sigma_[iy]);
      }
    }
  }
  return best;
}

int BondGrid::PeakSigmaBond() const {
  const int nx = params_.grid_x;
  const int ny = params_.grid_y;
  if (SigmaFinite()) {
    // The scan below keeps the first bond, in index order, of the largest σ: find that σ from
    // the field's parts, then the first bond that has it, skipping rows that cannot.
    const double peak = PeakSigma();
    for (int iy = 0; iy < ny; ++iy) {
      if (row_count_[iy] == 0 || col_sigma_max_ + row_sigma_[iy] < peak) continue;
      const uint8_t* state = state_.data() + iy * nx;
      for (int ix = 0; ix < nx; ++ix) {
        const bool bonded_here = state[ix] == static_cast<uint8_t>(BondState::kBonded);
        if (bonded_here && col_sigma_[ix] + row_sigma_[iy] == peak) return iy * nx + ix;
      }
    }
    return -1;  // none bonded
  }
  int best = -1;
  double best_sigma = -std::numeric_limits<double>::infinity();
  for (int iy = 0; iy < ny; ++iy) {
    // No bond of this row beats the best found: every σ here is at most the column maximum
    // plus the row's part.
    if (row_count_[iy] == 0 || col_sigma_max_ + row_sigma_[iy] <= best_sigma) continue;
    const uint8_t* state = state_.data() + iy * nx;
    for (int ix = 0; ix < nx; ++ix) {
      if (state[ix] != static_cast<uint8_t>(BondState::kBonded)) continue;
      const double sigma = col_sigma_[ix] + row_sigma_[iy];
      if (sigma > best_sigma) {
        best_sigma = sigma;
        best = iy * nx + ix;
      }
    }
  }
  return best;
}

}  // namespace climbsim::adhesion
