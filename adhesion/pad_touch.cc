#include "adhesion/pad_touch.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace climbsim::adhesion {

TouchProbe::TouchProbe(const mjModel* m, const PadGeometry& pad, int grid_x, int grid_y)
    : pad_(pad),
      grid_x_(grid_x),
      grid_y_(grid_y),
      back_m_(std::max(2.0 * m->geom_size[3 * pad.geom + 2], kRayBackM)),
      half_diagonal_m_(0.5 * std::hypot(pad.width_m, pad.length_m)),
      own_root_(m->body_rootid[pad.body]),
      gaps_(static_cast<size_t>(grid_x) * grid_y, kNoSurface),
      candidates_(m->ngeom, -1) {}

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

int TouchProbe::Measure(const mjModel* m, const mjData* d, const std::vector<uint8_t>& sticks_to,
                        double contact_gap_m, double standoff_m, double pressed_m,
                        std::span<uint8_t> touching) {
  const PadFrame f = FaceFrame(d, pad_);
  return MeasureFrom(m, d, sticks_to, f.pos, f.rot, contact_gap_m, standoff_m, pressed_m,
                     touching);
}

int TouchProbe::MeasureSeated(const mjModel* m, const mjData* d,
                              const std::vector<uint8_t>& sticks_to, double contact_gap_m,
                              double standoff_m, double pressed_m, const Eigen::Vector3d& point,
                              const Eigen::Vector3d& normal, std::span<uint8_t> touching) {
  const PadFrame f = FaceFrame(d, pad_);
  // The shortest turn of the pad normal onto the surface's, about the contact point.
  const Eigen::Matrix3d turn =
      Eigen::Quaterniond::FromTwoVectors(f.rot.col(2), normal).toRotationMatrix();
  return MeasureFrom(m, d, sticks_to, point + turn * (f.pos - point), turn * f.rot,
                     contact_gap_m, standoff_m, pressed_m, touching);
}

int TouchProbe::MeasureFrom(const mjModel* m, const mjData* d,
                            const std::vector<uint8_t>& sticks_to, const Eigen::Vector3d& origin,
                            const Eigen::Matrix3d& axes, double contact_gap_m, double standoff_m,
                            double pressed_m, std::span<uint8_t> touching) {
  const PadFrame f{origin, axes};
  const Eigen::Vector3d n = f.rot.col(2);
  // The rays start back_m_ behind the face and reach the farthest gap that can still touch.
  const double reach_m = back_m_ + standoff_m + pressed_m + back_m_ + contact_gap_m;
  const int candidates = Candidates(m, d, sticks_to, f.pos, reach_m);
  const mjtNum vec[3] = {-n.x(), -n.y(), -n.z()};
  double nearest = kNoSurface;
  for (int iy = 0; iy < grid_y_; ++iy) {
    const double y = ((iy + 0.5) / grid_y_ - 0.5) * pad_.length_m;
    for (int ix = 0; ix < grid_x_; ++ix) {
      const double x = ((ix + 0.5) / grid_x_ - 0.5) * pad_.width_m;
      const Eigen::Vector3d start = f.pos + x * f.rot.col(0) + y * f.rot.col(1) + back_m_ * n;
      const mjtNum pnt[3] = {start.x(), start.y(), start.z()};
      const double hit = NearestHit(m, d, candidates, pnt, vec);
      const double gap = hit < 0 ? kNoSurface : hit - back_m_;
      gaps_[iy * grid_x_ + ix] = gap;
      nearest = std::min(nearest, gap);
    }
  }
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

}  // namespace climbsim::adhesion
