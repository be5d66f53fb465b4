#include "adhesion/bond_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>

namespace climbsim::adhesion {
namespace {

template <class T>
[[noreturn]] void Reject(const char* key, const char* rule, T value) {
  std::ostringstream message;
  message << "adhesion." << key << " must be " << rule << ", got " << value;
  throw std::invalid_argument(message.str());
}

// Number of bonds that a bonded fraction asks for: round(fraction·n), clamped to [0, n].
int CountFor(double fraction, int n) {
  if (!(fraction > 0.0)) return 0;  // also NaN
  if (fraction >= 1.0) return n;
  return static_cast<int>(std::clamp<long>(std::lround(fraction * n), 0L, static_cast<long>(n)));
}

bool IsFinite(const PadLoad& load) {
  return std::isfinite(load.fn_n) && std::isfinite(load.fx_n) && std::isfinite(load.fy_n) &&
         std::isfinite(load.mx_nm) && std::isfinite(load.my_nm);
}

}  // namespace

void ValidatePadParams(const PadParams& p) {
  if (!(std::isfinite(p.width_m) && p.width_m > 0.0)) {
    Reject("width_m", "> 0 and finite", p.width_m);
  }
  if (!(std::isfinite(p.length_m) && p.length_m > 0.0)) {
    Reject("length_m", "> 0 and finite", p.length_m);
  }
  // The keys: their declared ranges, then the rule min_bonds <= grid_x * grid_y.
  keys::Validate(p, "adhesion");
}

PadLoad PadLoadFromSurfaceWrench(const Eigen::Vector3d& force_on_pad_pad_n,
                                 const Eigen::Vector3d& torque_on_pad_pad_nm) {
  // The bond layer carries the opposite of what the surface exerts.
  return PadLoad{.fn_n = -force_on_pad_pad_n.z(),
                 .fx_n = -force_on_pad_pad_n.x(),
                 .fy_n = -force_on_pad_pad_n.y(),
                 .mx_nm = -torque_on_pad_pad_nm.x(),
                 .my_nm = -torque_on_pad_pad_nm.y()};
}

BondGrid::BondGrid(const PadParams& params) : params_(params) {
  ValidatePadParams(params_);
  const int nx = params_.grid_x;
  const int ny = params_.grid_y;
  const double b = params_.width_m;
  const double h = params_.length_m;
  cell_area_m2_ = b * h / (static_cast<double>(nx) * ny);
  sigma_t_sq_ = params_.sigma_t_pa * params_.sigma_t_pa;
  hinge_nm_ = kHingeMomentTolerance * params_.sigma_t_pa * b * h * std::max(b, h);
  unit_x_m_ = b / (2.0 * nx);
  unit_y_m_ = h / (2.0 * ny);
  // Cell centres, written so that mirror cells have exactly opposite coordinates.
  col_x_m_.resize(nx);
  col_v_.resize(nx);
  for (int ix = 0; ix < nx; ++ix) {
    col_x_m_[ix] = (2 * ix + 1 - nx) * unit_x_m_;
    col_v_[ix] = b * b / 4.0 - col_x_m_[ix] * col_x_m_[ix];
  }
  row_y_m_.resize(ny);
  row_w_.resize(ny);
  for (int iy = 0; iy < ny; ++iy) {
    row_y_m_[iy] = (2 * iy + 1 - ny) * unit_y_m_;
    row_w_[iy] = h * h / 4.0 - row_y_m_[iy] * row_y_m_[iy];
  }

  // Centre-out order in normalised coordinates, ties by index.
  const int n = nx * ny;
  std::vector<double> key(n);
  for (int i = 0; i < n; ++i) {
    const double u = 2.0 * bond_x_m(i) / b;
    const double v = 2.0 * bond_y_m(i) / h;
    key[i] = u * u + v * v;
  }
  centre_out_.resize(n);
  std::iota(centre_out_.begin(), centre_out_.end(), 0);
  std::stable_sort(centre_out_.begin(), centre_out_.end(),
                   [&key](int a, int c) { return key[a] < key[c]; });

  // The moment sums of the full pad, for BondAll.
  for (int i = 0; i < n; ++i) {
    const int64_t kx = 2 * ix_of(i) + 1 - nx;
    const int64_t ky = 2 * iy_of(i) + 1 - ny;
    full_sums_.n += 1, full_sums_.kx += kx, full_sums_.ky += ky;
    full_sums_.kxx += kx * kx, full_sums_.kyy += ky * ky, full_sums_.kxy += kx * ky;
  }
  state_.assign(n, static_cast<uint8_t>(BondState::kUnbonded));
  TouchAll();
  col_count_.assign(nx, 0);
  row_count_.assign(ny, 0);
  col_sigma_.assign(nx, 0.0), col_tau3_.assign(nx, 0.0);
  row_sigma_.assign(ny, 0.0), row_tau3_.assign(ny, 0.0);
  // PeakUtilisation's scratch: per row, and per block of ⌈√N_x⌉ columns.
  row_bound_u2_.assign(ny, 0.0);
  row_order_.assign(ny, 0), row_blocks_.assign(ny, 0);
  while (block_cols_ * block_cols_ < nx) ++block_cols_;
  block_sigma_max_.assign((nx + block_cols_ - 1) / block_cols_, 0.0);
  block_tau3_max_.assign(block_sigma_max_.size(), 0.0);
  broken_log_.resize(n);
}

void BondGrid::SetTouching(std::span<const uint8_t> touching) {
  if (static_cast<int>(touching.size()) != size()) {
    throw std::invalid_argument("BondGrid::SetTouching: " + std::to_string(touching.size()) +
                                " cells for a grid of " + std::to_string(size()));
  }
  touching_count_ = 0;
  for (int i = 0; i < size(); ++i) {
    touching_[i] = touching[i] != 0 ? 1 : 0;
    touching_count_ += touching_[i];
  }
}

void BondGrid::TouchAll() {
  touching_.assign(state_.size(), 1);  // sized once: no allocation after the constructor
  touching_count_ = size();
}

void BondGrid::BondAll() {
  if (touching_count_ < size()) {
    BondFraction(1.0);
    return;
  }
  std::fill(state_.begin(), state_.end(), static_cast<uint8_t>(BondState::kBonded));
  std::fill(col_count_.begin(), col_count_.end(), params_.grid_y);
  std::fill(row_count_.begin(), row_count_.end(), params_.grid_x);
  bonded_count_ = size();
  sums_ = full_sums_;
  set_cached_ = false;
}

void BondGrid::Release() {
  std::fill(state_.begin(), state_.end(), static_cast<uint8_t>(BondState::kUnbonded));
  std::fill(col_count_.begin(), col_count_.end(), 0);
  std::fill(row_count_.begin(), row_count_.end(), 0);
  bonded_count_ = 0;
  sums_ = MomentSums{};
  set_cached_ = false;
  // A released grid carries no stress: a grid bonded again reads the field of no load until
  // the next one is applied, as a new grid does (a reset run's first utilisation was the
  // last run's).
  ClearField();
}

void BondGrid::BondFraction(double fraction) {
  Release();
  const int target = CountFor(fraction, touching_count_);
  for (int k = 0, bonded = 0; bonded < target; ++k) {
    if (!touching_[centre_out_[k]]) continue;
    SetState(centre_out_[k], BondState::kBonded);
    ++bonded;
  }
}

int BondGrid::Grow(double fraction) {
  const int target = CountFor(fraction, touching_count_);
  int added = 0;
  for (int k = 0; k < size() && bonded_count_ < target; ++k) {
    const int i = centre_out_[k];
    if (state(i) == BondState::kUnbonded && touching_[i]) {
      SetState(i, BondState::kBonded);
      ++added;
    }
  }
  return added;
}

void BondGrid::SetBonded(int index, bool bonded) {
  if (index < 0 || index >= size()) {
    throw std::out_of_range("BondGrid::SetBonded: index " + std::to_string(index) +
                            " outside [0, " + std::to_string(size()) + ")");
  }
  SetState(index, bonded ? BondState::kBonded : BondState::kUnbonded);
}

void BondGrid::SetState(int index, BondState new_state) {
  const bool was = bonded(index);
  const bool now = new_state == BondState::kBonded;
  state_[index] = static_cast<uint8_t>(new_state);
  if (was == now) return;
  set_cached_ = false;
  const int ix = ix_of(index);
  const int iy = iy_of(index);
  const int step = now ? 1 : -1;
  col_count_[ix] += step;
  row_count_[iy] += step;
  bonded_count_ += step;
  const int64_t kx = 2 * ix + 1 - params_.grid_x;
  const int64_t ky = 2 * iy + 1 - params_.grid_y;
  sums_.n += step;
  sums_.kx += step * kx;
  sums_.ky += step * ky;
  sums_.kxx += step * kx * kx;
  sums_.kyy += step * ky * ky;
  sums_.kxy += step * kx * ky;
}

void BondGrid::ClearField() {
  std::fill(col_sigma_.begin(), col_sigma_.end(), 0.0);
  std::fill(row_sigma_.begin(), row_sigma_.end(), 0.0);
  std::fill(col_tau3_.begin(), col_tau3_.end(), 0.0);
  std::fill(row_tau3_.begin(), row_tau3_.end(), 0.0);
  tau_x_per_w_ = 0.0;
  tau_y_per_v_ = 0.0;
  col_sigma_max_ = col_tau3_max_ = row_sigma_max_ = row_tau3_max_ = 0.0;
  unsupported_ = false;
}

BondGrid::Bending BondGrid::BendingOfBondedSet() const {
  const int n = bonded_count_;
  const double da = cell_area_m2_;
  Bending b;
  // Centroid, exact in grid units (0 exactly for a set symmetric about the pad centre).
  b.x_c = static_cast<double>(sums_.kx) / n * unit_x_m_;
  b.y_c = static_cast<double>(sums_.ky) / n * unit_y_m_;
  // Centred second moments: n·Σ(k − k̄)² and the like are exact integers (< 2^61 within the
  // grid limits), so whether the set is a line or a point is decided exactly.
  const __int128 cxx =
      static_cast<__int128>(sums_.n) * sums_.kxx - static_cast<__int128>(sums_.kx) * sums_.kx;
  const __int128 cyy =
      static_cast<__int128>(sums_.n) * sums_.kyy - static_cast<__int128>(sums_.ky) * sums_.ky;
  const __int128 cxy =
      static_cast<__int128>(sums_.n) * sums_.kxy - static_cast<__int128>(sums_.kx) * sums_.ky;
  b.is_point = cxx == 0 && cyy == 0;
  b.is_line = !b.is_point && cxx * cyy == cxy * cxy;
  const double scale = da / n;
  b.i_y = static_cast<double>(cxx) * unit_x_m_ * unit_x_m_ * scale;  // Σ(x − x_c)²dA
  b.i_x = static_cast<double>(cyy) * unit_y_m_ * unit_y_m_ * scale;  // Σ(y − y_c)²dA
  b.i_xy = static_cast<double>(cxy) * unit_x_m_ * unit_y_m_ * scale;
  if (b.is_line) {
    double dx = b.i_y, dy = b.i_xy;  // a column of the rank-1 matrix, ∥ d
    if (std::abs(dx) + std::abs(dy) == 0.0) {
      dx = b.i_xy;
      dy = b.i_x;
    }
    const double norm = std::hypot(dx, dy);
    b.line_dx = dx / norm;
    b.line_dy = dy / norm;
  }
  return b;
}

void BondGrid::ComputeField(const PadLoad& load) {
  const int n = bonded_count_;
  if (n == 0) {
    ClearField();
    return;
  }
  const int nx = params_.grid_x;
  const int ny = params_.grid_y;
  const double da = cell_area_m2_;

  if (!set_cached_) {
    set_bend_ = BendingOfBondedSet();
    set_sum_v_ = 0.0;
    for (int ix = 0; ix < nx; ++ix) set_sum_v_ += col_count_[ix] * col_v_[ix];
    set_sum_w_ = 0.0;
    for (int iy = 0; iy < ny; ++iy) set_sum_w_ += row_count_[iy] * row_w_[iy];
    set_cached_ = true;
  }
  const Bending& bend = set_bend_;
  const double x_c = bend.x_c, y_c = bend.y_c;

  unsupported_ = false;
  double g_x = 0.0, g_y = 0.0;  // dσ/dx, dσ/dy
  BendingGradient(bend, load, &g_x, &g_y);
  NormaliseShears(load);

  // The separable parts: σ = col_sigma + row_sigma, 3τ² = col_tau3 + row_tau3.
  const double sigma0 = load.fn_n / (n * da);
  col_sigma_max_ = -std::numeric_limits<double>::infinity();
  col_tau3_max_ = 0.0;
  for (int ix = 0; ix < nx; ++ix) {
    col_sigma_[ix] = sigma0 + g_x * (col_x_m_[ix] - x_c);
    const double tau_y = tau_y_per_v_ * col_v_[ix];
    col_tau3_[ix] = 3.0 * tau_y * tau_y;
    col_sigma_max_ = std::max(col_sigma_max_, col_sigma_[ix]);
    col_tau3_max_ = std::max(col_tau3_max_, col_tau3_[ix]);
  }
  row_sigma_max_ = -std::numeric_limits<double>::infinity();
  row_tau3_max_ = 0.0;
  for (int iy = 0; iy < ny; ++iy) {
    row_sigma_[iy] = g_y * (row_y_m_[iy] - y_c);
    const double tau_x = tau_x_per_w_ * row_w_[iy];
    row_tau3_[iy] = 3.0 * tau_x * tau_x;
    row_sigma_max_ = std::max(row_sigma_max_, row_sigma_[iy]);
    row_tau3_max_ = std::max(row_tau3_max_, row_tau3_[iy]);
  }
}

// The stress gradient (g_x, g_y) that carries the moments about the bonded centroid: the
// solve of [I_y I_xy; I_xy I_x]·(g_x, g_y) = (p, q), p = −M_y^c, q = M_x^c, with a point or a
// line as hinges. Sets unsupported_ when a hinge must carry more than hinge_nm_.
void BondGrid::BendingGradient(const Bending& bend, const PadLoad& load, double* g_x,
                               double* g_y) {
  const double x_c = bend.x_c, y_c = bend.y_c;
  const double i_x = bend.i_x, i_y = bend.i_y, i_xy = bend.i_xy;
  const double p = -(load.my_nm + x_c * load.fn_n);
  const double q = load.mx_nm - y_c * load.fn_n;
  if (bend.is_point) {
    // A single bond: a hinge about every axis.
    if (std::hypot(p, q) > hinge_nm_) unsupported_ = true;
  } else if (bend.is_line) {
    // A line with direction d: the gradient runs along d, the moment about d is unsupported.
    const double dx = bend.line_dx, dy = bend.line_dy;
    const double along = p * dx + q * dy;   // m·d
    const double about = q * dx - p * dy;   // m·d⊥ = M^c·d, the moment about the line
    if (std::abs(about) > hinge_nm_) unsupported_ = true;
    const double lambda = i_x + i_y;        // the one nonzero eigenvalue
    *g_x = along / lambda * dx;
    *g_y = along / lambda * dy;
  } else {
    const double det = i_x * i_y - i_xy * i_xy;
    *g_x = (p * i_x - q * i_xy) / det;
    *g_y = (q * i_y - p * i_xy) / det;
  }
}

// Parabolic shears normalised over the bonded set (tau_x_per_w_, tau_y_per_v_); a shear that
// no row or column can carry sets unsupported_.
void BondGrid::NormaliseShears(const PadLoad& load) {
  const double da = cell_area_m2_;
  const double sum_v = set_sum_v_, sum_w = set_sum_w_;  // ComputeField's, of this set
  tau_x_per_w_ = 0.0;
  if (sum_w > 0.0) {
    tau_x_per_w_ = load.fx_n / (sum_w * da);
  } else if (load.fx_n != 0.0) {
    unsupported_ = true;
  }
  tau_y_per_v_ = 0.0;
  if (sum_v > 0.0) {
    tau_y_per_v_ = load.fy_n / (sum_v * da);
  } else if (load.fy_n != 0.0) {
    unsupported_ = true;
  }
}

int BondGrid::BreakOverThreshold(int round) {
  if (bonded_count_ == 0) return 0;
  const int nx = params_.grid_x;
  const int ny = params_.grid_y;
  const double sigma_t = params_.sigma_t_pa;
  const double mu = params_.mu;
  // The rows' bounds below, all at once: each is at most this one (additions, max and squares
  // of nonnegative numbers are monotone), so below σ_T² no row is scanned.
  const double sigma_all = std::max(col_sigma_max_ + row_sigma_max_, 0.0);
  if (!unsupported_ && sigma_all * sigma_all + (col_tau3_max_ + row_tau3_max_) < sigma_t_sq_) {
    return 0;
  }
  int broken = 0;
  for (int iy = 0; iy < ny; ++iy) {
    if (row_count_[iy] == 0) continue;
    const double row_sigma = row_sigma_[iy];
    const double row_tau3 = row_tau3_[iy];
    // Row bound: every bond's demand σ₊² + 3τ² is at most (max σ)₊² + max 3τ² over the row's
    // columns (floating-point addition is monotone), and every threshold is ≥ σ_T. Below
    // σ_T² nothing in this row can break: skip it.
    if (!unsupported_) {
      const double sigma_bound = std::max(col_sigma_max_ + row_sigma, 0.0);
      if (sigma_bound * sigma_bound + (col_tau3_max_ + row_tau3) < sigma_t_sq_) continue;
    }
    const uint8_t* state = state_.data() + iy * nx;
    for (int ix = 0; ix < nx; ++ix) {
      if (state[ix] != static_cast<uint8_t>(BondState::kBonded)) continue;
      const double sigma = col_sigma_[ix] + row_sigma;
      const double tau3 = col_tau3_[ix] + row_tau3;
      // Rupture in squares (seed eqs. 7–8).
      bool breaks;
      if (sigma >= 0.0) {
        breaks = sigma * sigma + tau3 >= sigma_t_sq_;
      } else {
        const double threshold = sigma_t - mu * sigma;
        breaks = tau3 >= threshold * threshold;
      }
      if (!(breaks || unsupported_)) continue;
      SetState(iy * nx + ix, BondState::kBroken);
      broken_log_[broken_count_++] = BrokenBond{.index = iy * nx + ix, .round = round};
      ++broken;
    }
  }
  return broken;
}


bool BondGrid::Influence(int index, bool uniform_shear, Eigen::Matrix<double, 3, 5>* a) const {
  if (index < 0 || index >= size() || !bonded(index)) return false;
  const int n = bonded_count_;
  const double da = cell_area_m2_;
  // The set's geometry and shear sums as the last field kept them (the same computation).
  const Bending bend = set_cached_ ? set_bend_ : BendingOfBondedSet();
  const double rx = bond_x_m(index) - bend.x_c;
  const double ry = bond_y_m(index) - bend.y_c;
  // σ_i = F_n/A_B + (g_x, g_y)·(rx, ry) with g = S·(p, q), p = −(M_y + x_c F_n),
  // q = M_x − y_c F_n (ComputeField); S is the inverse of [I_y I_xy; I_xy I_x], on a line
  // its pseudo-inverse d·dᵀ/λ, on a point 0.
  double s00 = 0.0, s01 = 0.0, s10 = 0.0, s11 = 0.0;
  if (bend.is_line) {
    const double lambda = bend.i_x + bend.i_y;
    s00 = bend.line_dx * bend.line_dx / lambda;
    s01 = s10 = bend.line_dx * bend.line_dy / lambda;
    s11 = bend.line_dy * bend.line_dy / lambda;
  } else if (!bend.is_point) {
    const double det = bend.i_x * bend.i_y - bend.i_xy * bend.i_xy;
    s00 = bend.i_x / det;
    s01 = s10 = -bend.i_xy / det;
    s11 = bend.i_y / det;
  }
  // dσ/dp and dσ/dq at this bond.
  const double dsigma_dp = rx * s00 + ry * s10;
  const double dsigma_dq = rx * s01 + ry * s11;
  a->setZero();
  (*a)(0, 0) = 1.0 / (n * da) - bend.x_c * dsigma_dp - bend.y_c * dsigma_dq;  // F_n
  (*a)(0, 3) = dsigma_dq;                                                   // M_x
  (*a)(0, 4) = -dsigma_dp;                                                  // M_y
  if (uniform_shear) {
    (*a)(1, 1) = (*a)(2, 2) = 1.0 / (n * da);
  } else {
    double sum_v = set_sum_v_, sum_w = set_sum_w_;
    if (!set_cached_) {
      sum_v = sum_w = 0.0;
      for (int ix = 0; ix < params_.grid_x; ++ix) sum_v += col_count_[ix] * col_v_[ix];
      for (int iy = 0; iy < params_.grid_y; ++iy) sum_w += row_count_[iy] * row_w_[iy];
    }
    if (sum_w > 0.0) (*a)(1, 1) = row_w_[iy_of(index)] / (sum_w * da);
    if (sum_v > 0.0) (*a)(2, 2) = col_v_[ix_of(index)] / (sum_v * da);
  }
  return true;
}

BondGrid::UpdateResult BondGrid::Update(const PadLoad& load_pad) {
  UpdateResult result;
  broken_count_ = 0;
  if (!IsFinite(load_pad)) {
    ClearField();
    result.load_finite = false;
    result.detached = detached();
    return result;
  }
  // Rounds of the cascade until one breaks nothing (at most one per bond, plus one); the
  // field of the last round, over the bonds left, stays for stress() and Summary().
  while (true) {
    ComputeField(load_pad);
    const int broken = BreakOverThreshold(result.rounds + 1);
    if (broken == 0) break;
    ++result.rounds;
    result.broken += broken;
  }
  result.detached = detached();
  return result;
}

StressSummary BondGrid::Evaluate(const PadLoad& load_pad) {
  if (!IsFinite(load_pad)) {
    ClearField();
    return StressSummary{};
  }
  ComputeField(load_pad);
  return Summary();
}

void BondGrid::Break(int index, int round) {
  if (!bonded(index)) return;
  SetState(index, BondState::kBroken);
  if (broken_count_ < size())
    broken_log_[broken_count_++] = BrokenBond{.index = index, .round = round};
}

BondStress BondGrid::stress(int index) const {
  BondStress s;
  if (!bonded(index)) return s;
  const int ix = ix_of(index);
  const int iy = iy_of(index);
  s.sigma_pa = col_sigma_[ix] + row_sigma_[iy];
  s.tau_x_pa = tau_x_per_w_ * row_w_[iy];
  s.tau_y_pa = tau_y_per_v_ * col_v_[ix];
  const double tau3 = 3.0 * (s.tau_x_pa * s.tau_x_pa + s.tau_y_pa * s.tau_y_pa);
  s.von_mises_pa = std::sqrt(s.sigma_pa * s.sigma_pa + tau3);
  if (unsupported_) {
    s.utilisation = std::numeric_limits<double>::infinity();
  } else if (s.sigma_pa >= 0.0) {
    s.utilisation = s.von_mises_pa / params_.sigma_t_pa;
  } else {
    s.utilisation = std::sqrt(tau3) / (params_.sigma_t_pa - params_.mu * s.sigma_pa);
  }
  return s;
}

}  // namespace climbsim::adhesion
