#include "adhesion/pad_touch.h"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>

namespace climbsim::adhesion {

TouchProbe::TouchProbe(const mjModel* m, const PadGeometry& pad, int grid_x, int grid_y)
    : pad_(pad),
      grid_x_(grid_x),
      grid_y_(grid_y),
      back_m_(std::max(2.0 * m->geom_size[3 * pad.geom + 2], kRayBackM)),
      half_diagonal_m_(0.5 * std::hypot(pad.width_m, pad.length_m)),
      own_root_(m->body_rootid[pad.body]),
      gaps_(static_cast<size_t>(grid_x) * grid_y, kNoSurface),
      cell_x_m_(gaps_.size()),
      cell_y_m_(gaps_.size()),
      candidates_(m->ngeom, -1) {
  for (int iy = 0; iy < grid_y; ++iy) {
    for (int ix = 0; ix < grid_x; ++ix) {
      cell_x_m_[iy * grid_x + ix] = ((ix + 0.5) / grid_x - 0.5) * pad.width_m;
      cell_y_m_[iy * grid_x + ix] = ((iy + 0.5) / grid_y - 0.5) * pad.length_m;
    }
  }
}

int TouchProbe::Candidates(const mjModel* m, const mjData* d,
                           const std::vector<uint8_t>& sticks_to, const Eigen::Vector3d& face_pos,
                           double reach_m) {
  int n = 0;
  for (int g = 0; g < m->ngeom; ++g) {
    if (!sticks_to[g]) continue;
    // The robot's own geoms (the pad's kinematic tree) are never the surface under it.
    if (own_root_ != 0 && m->body_rootid[m->geom_bodyid[g]] == own_root_) continue;
    const double rbound = m->geom_rbound[g];
    // rbound 0: a plane (unbounded); otherwise skip a geom no ray of the pad can reach.
    if (rbound > 0 && std::isfinite(reach_m)) {
      const Eigen::Map<const Eigen::Vector3d> centre(d->geom_xpos + 3 * g);
      if ((centre - face_pos).norm() > rbound + half_diagonal_m_ + reach_m) continue;
    }
    candidates_[n++] = g;
  }
  return n;
}

double TouchProbe::NearestHit(const mjModel* m, const mjData* d, int candidates,
                              const mjtNum pnt[3], const mjtNum vec[3]) const {
  double best = -1.0;
  for (int k = 0; k < candidates; ++k) {
    const int g = candidates_[k];
    double x;
    switch (m->geom_type[g]) {
      case mjGEOM_MESH:
        x = mj_rayMesh(m, d, g, pnt, vec);
        break;
      case mjGEOM_HFIELD:
        x = mj_rayHfield(m, d, g, pnt, vec);
        break;
      default:
        x = mju_rayGeom(d->geom_xpos + 3 * g, d->geom_xmat + 9 * g, m->geom_size + 3 * g, pnt,
                        vec, m->geom_type[g]);
        break;
    }
    if (x >= 0 && (best < 0 || x < best)) best = x;
  }
  return best;
}

double TouchProbe::MeasureGaps(const mjModel* m, const mjData* d,
                               const std::vector<uint8_t>& sticks_to, double back_m,
                               double reach_m) {
  const PadFrame f = FaceFrame(d, pad_);
  const Eigen::Vector3d n = f.rot.col(2);
  const int candidates = Candidates(m, d, sticks_to, f.pos, reach_m);
  const mjtNum vec[3] = {-n.x(), -n.y(), -n.z()};
  double nearest = kNoSurface;
  for (int i = 0; i < size(); ++i) {
    const Eigen::Vector3d start =
        f.pos + cell_x_m_[i] * f.rot.col(0) + cell_y_m_[i] * f.rot.col(1) + back_m * n;
    const mjtNum pnt[3] = {start.x(), start.y(), start.z()};
    const double hit = NearestHit(m, d, candidates, pnt, vec);
    gaps_[i] = hit < 0 ? kNoSurface : hit - back_m;
    nearest = std::min(nearest, gaps_[i]);
  }
  return nearest;
}

int TouchProbe::Measure(const mjModel* m, const mjData* d, const std::vector<uint8_t>& sticks_to,
                        double contact_gap_m, double standoff_m, double pressed_m,
                        std::span<uint8_t> touching) {
  // The rays start back_m_ behind the face and reach the farthest gap that can still touch.
  const double reach_m = back_m_ + standoff_m + pressed_m + back_m_ + contact_gap_m;
  const double nearest = MeasureGaps(m, d, sticks_to, back_m_, reach_m);
  // Pressed in: by the contacts' depth, or by the deepest cell's (a start pose in the surface).
  const double pressed = std::max(pressed_m, nearest < 0 ? -nearest : 0.0);
  const double limit = standoff_m + pressed + contact_gap_m;
  int count = 0;
  for (int i = 0; i < size(); ++i) {
    touching[i] = gaps_[i] < kNoSurface && gaps_[i] <= limit ? 1 : 0;
    count += touching[i];
  }
  return count;
}

int TouchProbe::MeasureSeated(const mjModel* m, const mjData* d,
                              const std::vector<uint8_t>& sticks_to, double contact_gap_m,
                              double standoff_m, double pressed_m, std::span<uint8_t> touching) {
  // A tilt lifts the far edge, or buries the near one (a start pose set into the surface), by
  // up to the face's diagonal: the rays start and reach that much farther.
  const double tilt_m = 2.0 * half_diagonal_m_;
  const double back_m = back_m_ + tilt_m;
  const double reach_m = back_m + standoff_m + pressed_m + back_m + contact_gap_m;
  MeasureGaps(m, d, sticks_to, back_m, reach_m);
  double plane[3];
  if (!RestPlane(cell_x_m_, cell_y_m_, gaps_, grid_x_, grid_y_, plane)) {
    return Measure(m, d, sticks_to, contact_gap_m, standoff_m, pressed_m, touching);
  }
  const double limit = pressed_m + contact_gap_m;
  int count = 0;
  for (int i = 0; i < size(); ++i) {
    const double rest = plane[0] + plane[1] * cell_x_m_[i] + plane[2] * cell_y_m_[i];
    touching[i] = gaps_[i] < kNoSurface && gaps_[i] - rest <= limit ? 1 : 0;
    count += touching[i];
  }
  return count;
}

namespace {

// Far above any real gap: a cell without a surface joins the program as a point so high that
// the optimum uses it only when the centre lies beyond every other cell.
constexpr double kNoSurfaceGapM = 1.0;

double GapOrFar(std::span<const double> gap_m, int i) {
  return gap_m[i] < TouchProbe::kNoSurface ? gap_m[i] : kNoSurfaceGapM;
}

}  // namespace

bool RestPlane(std::span<const double> x_m, std::span<const double> y_m,
               std::span<const double> gap_m, int grid_x, int grid_y, double plane[3]) {
  if (grid_x < 2 || grid_y < 2) return false;
  const int n = static_cast<int>(gap_m.size());
  // A first basis whose triangle holds the centre: two corners of one edge and a cell of the
  // opposite edge's middle (the grid is centred on the face).
  int basis[3] = {0, grid_x - 1, (grid_y - 1) * grid_x + grid_x / 2};
  const auto column = [&](int i) { return Eigen::Vector3d(1.0, x_m[i], y_m[i]); };
  Eigen::Matrix3d cols;
  for (int k = 0; k < 3; ++k) cols.col(k) = column(basis[k]);
  Eigen::Vector3d lambda = cols.fullPivLu().solve(Eigen::Vector3d(1, 0, 0));
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int pivots = 0; pivots <= 4 * n; ++pivots) {
    const Eigen::Vector3d g_basis(GapOrFar(gap_m, basis[0]), GapOrFar(gap_m, basis[1]),
                                  GapOrFar(gap_m, basis[2]));
    p = cols.transpose().fullPivLu().solve(g_basis);  // the plane through the basis' gaps
    int enter = -1;  // Bland: the first cell below the plane
    for (int i = 0; i < n && enter < 0; ++i) {
      if (GapOrFar(gap_m, i) - column(i).dot(p) < -1e-12) enter = i;
    }
    if (enter < 0) break;
    const Eigen::Vector3d dir = cols.fullPivLu().solve(column(enter));
    int leave = -1;
    double ratio = 0.0;
    for (int k = 0; k < 3; ++k) {
      if (dir[k] <= 1e-12) continue;
      const double r = lambda[k] / dir[k];
      if (leave < 0 || r < ratio || (r == ratio && basis[k] < basis[leave])) leave = k, ratio = r;
    }
    if (leave < 0) return false;  // cannot happen: the program is bounded
    lambda -= ratio * dir;
    lambda[leave] = ratio;
    basis[leave] = enter;
    cols.col(leave) = column(enter);
  }
  for (int k = 0; k < 3; ++k) {
    if (lambda[k] > 1e-12 && !(gap_m[basis[k]] < TouchProbe::kNoSurface)) return false;
  }
  plane[0] = p[0], plane[1] = p[1], plane[2] = p[2];
  return true;
}

}  // namespace climbsim::adhesion
