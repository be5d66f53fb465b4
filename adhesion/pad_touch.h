// PARTIAL CONTACT: which cells of a pad's bond grid touch the surface when it attaches. Only
// those cells may bond (BondGrid::SetTouching); cells over a hollow or beyond an edge stay
// unbonded for the whole attachment, so the pad's capacity, peel and utilisation follow the
// bonds that exist.
//
// THE GAP OF A CELL. From the cell's point on the pad face, p_i = o + x_i·x̂ + y_i·ŷ (pad frame
// of bond_grid.h, o the face centroid), a ray runs along −n (from the pad towards the surface)
// against the surface geoms (sticks_to: MuJoCo's own geometry, mju_rayGeom / mj_rayMesh /
// mj_rayHfield), leaving out the geoms of the pad's own kinematic tree (the robot: by default
// every geom but the pads' is a surface, the robot's links included). The ray starts at
// p_i + t·n, t = max(pad thickness, kRayBackM), so that a cell pressed into the surface's soft
// contact (or a bump standing into the pad) still sees it:
//
//   gap_i = (distance along the ray to the nearest surface) − t   (m; < 0: pressed in;
//                                                                 +inf: no surface below)
//
// THE TOUCHED SET. A pad that attached by its contacts is pressed into MuJoCo's soft contact by
// δ, its contacts' deepest penetration (ContactSense::depth_m) or its deepest cell's −gap_i:
// that is the contact's compliance, and a rigid pad rocks on it, its far side rising by up to
// δ (on a plane, with three corners pressed in, the fourth is out by at most the depth of one
// of them). A pad that starts attached (start_attached) may stand off by s = start_gap_m (the
// robots start 0.5 mm from the surface); s = 0 otherwise. Cell i touches when
//
//   gap_i ≤ s + δ + contact_gap_m.
//
// contact_gap_m is what the adhesive's fibres and backing bridge: a flat pad on a flat surface
// touches everywhere (bit for bit the bonds without partial contact), a pad across a 2 mm step
// or over a hollow does not. Geoms whose bounding sphere is farther from the pad than the ray's reach are not
// tried, so a rough wall of hundreds of bumps costs a few of them per attach.
//
// COST. Only at attach: one ray per cell and candidate geom (a 16² pad on a flat wall: 256
// rays, a few µs), never in the step otherwise. Nothing allocates after construction.
#ifndef CLIMBSIM_ADHESION_PAD_TOUCH_H_
#define CLIMBSIM_ADHESION_PAD_TOUCH_H_

#include <mujoco/mujoco.h>

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "adhesion/pad_contact.h"
#include "keys/keys.h"

namespace climbsim::adhesion {

// The scenario keys adhesion.partial_contact and adhesion.contact_gap_m.
struct PartialContactParams {
  bool partial_contact = true;
  // 0.5 mm: about the length of a dry adhesive's fibres plus the compliance of its backing
  // (mushroom-tipped and wedge microstructures of 0.1–0.2 mm on a soft backing; gecko setae
  // and lamellae together about 0.1–1 mm): farther than this a cell does not reach the surface.
  double contact_gap_m = 0.5e-3;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"partial_contact", "",
              "model bonds: at attach, only the cells of the bond grid whose point on the pad face "
              "lies within contact_gap_m of a surface may bond (cells over a hollow or beyond an "
              "edge stay unbonded); false: every cell, as if the whole face touched"},
             &partial_contact);
    a->Visit({"contact_gap_m", "m",
              "partial contact: how far from the surface a cell of the pad face still bonds (the "
              "adhesive's fibre length and backing compliance, about 0.5 mm)",
              Range::Closed(0, 0.01)},
             &contact_gap_m);
  }
};

// One pad's probe: the cell points and the buffers, sized once.
class TouchProbe {
 public:
  static constexpr double kNoSurface = std::numeric_limits<double>::infinity();
  // How far behind the face the rays start at least (m): deeper than the soft contact lets a
  // pad sink (≤ 2 mm measured on the robots, start poses included).
  static constexpr double kRayBackM = 0.005;

  TouchProbe(const mjModel* m, const PadGeometry& pad, int grid_x, int grid_y);

  // Measures every cell's gap from the current geom poses (xpos/xmat must be current) against
  // the geoms g with sticks_to[g] != 0, and writes touching[i] = 1 for the cells that touch,
  // 0 for the others (size grid_x·grid_y, index iy·grid_x + ix). `standoff_m` ≥ 0 is s and
  // `pressed_m` ≥ 0 the contacts' depth (see the file comment; δ is the larger of it and the
  // deepest cell's). Returns how many cells touch.
  int Measure(const mjModel* m, const mjData* d, const std::vector<uint8_t>& sticks_to,
              double contact_gap_m, double standoff_m, double pressed_m,
              std::span<uint8_t> touching);
  // SEATED. The same for a pad that landed by its contacts: its face first turned, about the
  // contact point `point` (world), until its normal is the surface's `normal` (unit, from the
  // surface into the pad), the rays along −normal. A pad that lands tilted on two corners of a
  // flat surface is seated flat on it by its compliance (the weld would freeze the tilt), so
  // what decides the touch is the surface's shape: a step, a hollow, a bump's edge. A pad that
  // starts attached is seated the same way on the contact its widened margin found, standing
  // off by `standoff_m` (start_gap_m; 0 for a landing).
  int MeasureSeated(const mjModel* m, const mjData* d, const std::vector<uint8_t>& sticks_to,
                    double contact_gap_m, double standoff_m, double pressed_m,
                    const Eigen::Vector3d& point,
                    const Eigen::Vector3d& normal, std::span<uint8_t> touching);

  // The gaps of the last Measure (m; kNoSurface: no surface within the ray's reach).
  double gap_m(int cell) const { return gaps_[cell]; }
  int size() const { return static_cast<int>(gaps_.size()); }

 private:
  // The surface geoms whose bounding sphere the rays may reach; how many.
  int Candidates(const mjModel* m, const mjData* d, const std::vector<uint8_t>& sticks_to,
                 const Eigen::Vector3d& face_pos, double reach_m);
  // The cells' gaps from the face (origin, axes x, y, n) and the touching set.
  int MeasureFrom(const mjModel* m, const mjData* d, const std::vector<uint8_t>& sticks_to,
                  const Eigen::Vector3d& origin, const Eigen::Matrix3d& axes,
                  double contact_gap_m, double standoff_m, double pressed_m,
                  std::span<uint8_t> touching);
  // Distance along the ray (pnt, unit vec) to the nearest candidate; −1 for none.
  double NearestHit(const mjModel* m, const mjData* d, int candidates, const mjtNum pnt[3],
                    const mjtNum vec[3]) const;

  PadGeometry pad_;
  int grid_x_, grid_y_;
  double back_m_;           // the rays start this far behind the face
  double half_diagonal_m_;  // of the face
  int own_root_;  // the pad's tree (body_rootid): the robot, never a surface
  std::vector<double> gaps_;
  std::vector<int> candidates_;
};

}  // namespace climbsim::adhesion

#endif  // CLIMBSIM_ADHESION_PAD_TOUCH_H_
