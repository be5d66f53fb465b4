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
  // Half: a foot set down on an edge with most of its face in the air is placed again (the
  // search reflex, a corner manoeuvre's probe) rather than held by a sliver; on a flat surface
  // every cell touches and nothing changes.
  double min_contact_share = 0.5;

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
    a->Visit({"min_contact_share", "",
              "partial contact: attach condition 5, the share of the pad face that must touch "
              "the surface for a landing pad to attach (within attach_window_s)",
              Range::Closed(0, 1)},
             &min_contact_share);
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
  // SEATED. The same for a pad pressed onto the surface through its centre (a landing, a
  // start pose): it comes to rest on the gaps' REST PLANE (RestPlane below) instead of where
  // its tilt left it, and cell i touches when gap_i − p_i ≤ pressed + contact_gap_m. A pad that
  // lands tilted on two corners of a flat surface is seated flat by its compliance (the weld
  // would freeze the tilt): every cell touches. What decides is the surface's shape: a step, a
  // hollow, a bump's edge, the kink of a fillet's facets. Where the centre lies beyond every
  // cell that sees a surface (the pad would tip off an edge), the cells are judged as they
  // stand (Measure with `standoff_m`).
  int MeasureSeated(const mjModel* m, const mjData* d, const std::vector<uint8_t>& sticks_to,
                    double contact_gap_m, double standoff_m, double pressed_m,
                    std::span<uint8_t> touching);

  // The gaps of the last Measure (m; kNoSurface: no surface within the ray's reach).
  double gap_m(int cell) const { return gaps_[cell]; }
  int size() const { return static_cast<int>(gaps_.size()); }

 private:
  // The surface geoms whose bounding sphere the rays may reach; how many.
  int Candidates(const mjModel* m, const mjData* d, const std::vector<uint8_t>& sticks_to,
                 const Eigen::Vector3d& face_pos, double reach_m);
  // Fills gaps_ from the face's current pose, the rays starting back_m behind the face;
  // returns the nearest gap.
  double MeasureGaps(const mjModel* m, const mjData* d, const std::vector<uint8_t>& sticks_to,
                     double back_m, double reach_m);
  // Distance along the ray (pnt, unit vec) to the nearest candidate; −1 for none.
  double NearestHit(const mjModel* m, const mjData* d, int candidates, const mjtNum pnt[3],
                    const mjtNum vec[3]) const;

  PadGeometry pad_;
  int grid_x_, grid_y_;
  double back_m_;           // the rays start this far behind the face
  double half_diagonal_m_;  // of the face
  int own_root_;  // the pad's tree (body_rootid): the robot, never a surface
  std::vector<double> gaps_;
  std::vector<double> cell_x_m_, cell_y_m_;  // the cells' points in the pad frame
  std::vector<int> candidates_;
};

// THE REST PLANE of a rigid pad pressed through its centre onto a surface whose gaps under the
// cells (x_i, y_i) are g_i (kNoSurface where none): the plane p(x, y) = a + b·x + c·y below
// every gap (p_i ≤ g_i) that is highest under the centre (0, 0) — the facet of the gaps' lower
// convex hull beneath the centre, on which the pad rests. A linear program in (a, b, c), solved
// through its dual (the centre as a convex combination Σλ_i(x_i, y_i) = 0, Σλ_i = 1, λ ≥ 0, of
// least Σλ_i g_i) by the simplex method with Bland's rule: exact, a few pivots over the cells,
// no allocation. Writes {a, b, c}; false when the centre lies beyond the cells that see a
// surface (or the grid has fewer than 2×2 cells).
bool RestPlane(std::span<const double> x_m, std::span<const double> y_m,
               std::span<const double> gap_m, int grid_x, int grid_y, double plane[3]);

// Whether a support pad has built its bond, as a gait or a manoeuvre that waits for it asks
// (cpg.support_bond_fraction, transition.support_bond_fraction): it has bonded `fraction` of
// what it touches, or all it still can (StickyPad::bondable_fraction: torn bonds do not grow
// back, so a wait past that would never end). The arguments are the pad's fractions.
inline bool SupportBuilt(double bonded, double touched, double bondable, double fraction) {
  return bonded >= fraction * touched || bonded >= bondable;
}

}  // namespace climbsim::adhesion

#endif  // CLIMBSIM_ADHESION_PAD_TOUCH_H_
