// A sticky pad as MuJoCo sees it: its box geom, its contact-face frame, and what its contacts
// with the surfaces say each step (count, preload, approach speed and angle).
//
// PAD FRAME (bond_grid.h). A pad body holds exactly one box geom (mjcf/README.md); its −z face
// is the contact face. The pad frame has its origin at that face's centroid and the geom's
// axes: x across the width b = 2·size[0], y along the length h = 2·size[1], n = z from the
// surface into the pad. For the robots of mjcf/ this is the site L_pad_face (a test checks).
//
// CONTACTS. MuJoCo's contacts of the last mj_step (d->contact, computed from the state at the
// start of that step) between the pad geom and a surface geom, with exclude == 0 (contacts in
// a geom's gap are listed but carry no force; they are counted apart, for MuJoCo's adhesion
// actuator). mj_contactForce() gives each contact's force in its frame; frame row 0 is the
// normal from geom1 to geom2 and the force is geom1's on geom2, so f[0] ≥ 0 is the
// compression. The sensed quantities, all from that same state:
//
//   contacts           contacts with exclude == 0
//   preload_n          Σ f[0] over them (N, ≥ 0: compression)
//   depth_m            the deepest of them, −dist (m, ≥ 0): how far the soft contact lets the
//                      pad sink in
//   surface_normal     unit normal from the surface into the pad (the contact normal,
//                      oriented), of the contact with the largest normal force (or the first)
//   contact_pos        that contact's point (world)
//   approach_speed_mps −(v_pad − v_surface)·surface_normal at that contact's point: > 0 when
//                      the pad moves towards the surface
//   angle_rad          angle between the pad normal n and surface_normal, 0 when flat
//
// None of these functions allocates; ids are resolved by the caller.
#ifndef CLIMBSIM_ADHESION_PAD_CONTACT_H_
#define CLIMBSIM_ADHESION_PAD_CONTACT_H_

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace climbsim::adhesion {

// The pad's box and its face frame in the pad body's frame. Fixed by the model.
struct PadGeometry {
  int body = -1;
  int geom = -1;
  double width_m = 0.0;                                         // b = 2·size[0]
  double length_m = 0.0;                                        // h = 2·size[1]
  Eigen::Vector3d face_pos_body = Eigen::Vector3d::Zero();      // face centroid, body frame
  Eigen::Matrix3d face_rot_body = Eigen::Matrix3d::Identity();  // face axes, body frame
};

// Reads the geometry of pad body `body`. Throws std::invalid_argument when the body does not
// hold exactly one box geom.
PadGeometry ReadPadGeometry(const mjModel* m, int body);
// What ReadPadGeometry would throw for `body`, or "" when it is a pad: a caller that reports
// errors its own way (at a scenario key) checks first instead of catching.
std::string PadGeometryProblem(const mjModel* m, int body);

// The pad frame in the world, from the current xpos/xmat of the pad body.
struct PadFrame {
  Eigen::Vector3d pos = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rot = Eigen::Matrix3d::Identity();  // columns: x, y, n in the world
};
PadFrame FaceFrame(const mjData* d, const PadGeometry& pad);

struct ContactSense {
  int contacts = 0;         // with a surface geom, exclude == 0
  int contacts_in_gap = 0;  // with a surface geom, exclude == 1 (no force; adhesion actuator)
  double preload_n = 0.0;
  double depth_m = 0.0;   // deepest penetration of those contacts (−dist, ≥ 0)
  int surface_geom = -1;  // geom of the strongest contact (or the first in the gap)
  Eigen::Vector3d surface_normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d contact_pos = Eigen::Vector3d::Zero();  // that contact's point, world
  double approach_speed_mps = 0.0;
  double angle_rad = 0.0;
};

// Scans d->contact for contacts of the pad geom with geoms g where sticks_to[g] != 0.
// (`sticks_to` has one entry per geom of the model.)
void SensePadContacts(const mjModel* m, const mjData* d, const PadGeometry& pad,
                      const std::vector<uint8_t>& sticks_to, ContactSense* out);

}  // namespace climbsim::adhesion

#endif  // CLIMBSIM_ADHESION_PAD_CONTACT_H_
