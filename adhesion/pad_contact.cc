#include "adhesion/pad_contact.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace climbsim::adhesion {
namespace {

// Linear velocity (world) of the point p fixed to `body`.
Eigen::Vector3d PointVelocity(const mjModel* m, const mjData* d, int body,
                              const Eigen::Vector3d& p) {
  mjtNum v[6];  // [ω, v] at the body frame's origin, world orientation
  mj_objectVelocity(m, d, mjOBJ_XBODY, body, v, 0);
  const Eigen::Vector3d w(v[0], v[1], v[2]);
  const Eigen::Vector3d origin(d->xpos[3 * body], d->xpos[3 * body + 1], d->xpos[3 * body + 2]);
  return Eigen::Vector3d(v[3], v[4], v[5]) + w.cross(p - origin);
}

// The body's box geoms: how many, and the last one.
int CountBoxes(const mjModel* m, int body, int* last_box) {
  int boxes = 0;
  for (int g = m->body_geomadr[body]; g >= 0 && g < m->body_geomadr[body] + m->body_geomnum[body];
       ++g) {
    if (m->geom_type[g] != mjGEOM_BOX) continue;
    ++boxes;
    *last_box = g;
  }
  return boxes;
}

}  // namespace

std::string PadGeometryProblem(const mjModel* m, int body) {
  int geom = -1;
  const int boxes = CountBoxes(m, body, &geom);
  if (boxes == 1) return "";
  const char* name = mj_id2name(m, mjOBJ_BODY, body);
  const std::string body_name = name != nullptr ? name : "#" + std::to_string(body);
  return "pad body '" + body_name + "' must hold exactly one box geom, has " +
         std::to_string(boxes);
}

PadGeometry ReadPadGeometry(const mjModel* m, int body) {
  PadGeometry pad;
  pad.body = body;
  if (CountBoxes(m, body, &pad.geom) != 1) {
    throw std::invalid_argument(PadGeometryProblem(m, body));
  }
  const mjtNum* size = m->geom_size + 3 * pad.geom;
  pad.width_m = 2.0 * size[0];
  pad.length_m = 2.0 * size[1];
  const mjtNum* q = m->geom_quat + 4 * pad.geom;
  pad.face_rot_body = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
  const Eigen::Vector3d centre(m->geom_pos[3 * pad.geom], m->geom_pos[3 * pad.geom + 1],
                               m->geom_pos[3 * pad.geom + 2]);
  // The −z face of the box: half its thickness below the geom centre, along the geom's z.
  pad.face_pos_body = centre - size[2] * pad.face_rot_body.col(2);
  return pad;
}

PadFrame FaceFrame(const mjData* d, const PadGeometry& pad) {
  // xmat is row-major: map it as the transpose of a column-major matrix.
  const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> r(d->xmat + 9 * pad.body);
  const Eigen::Map<const Eigen::Vector3d> x(d->xpos + 3 * pad.body);
  PadFrame f;
  f.pos = x + r * pad.face_pos_body;
  f.rot = r * pad.face_rot_body;
  return f;
}

void SensePadContacts(const mjModel* m, const mjData* d, const PadGeometry& pad,
                      const std::vector<uint8_t>& sticks_to, ContactSense* out) {
  *out = ContactSense{};
  int strongest = -1;
  double strongest_n = -1.0;
  bool pad_is_geom2 = false;
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    int other;
    if (c.geom1 == pad.geom) {
      other = c.geom2;
    } else if (c.geom2 == pad.geom) {
      other = c.geom1;
    } else {
      continue;
    }
    if (!sticks_to[other]) continue;
    if (c.exclude == 1) {
      if (out->contacts_in_gap++ == 0 && strongest < 0) out->surface_geom = other;
      continue;
    }
    if (c.exclude != 0) continue;
    ++out->contacts;
    out->depth_m = std::max(out->depth_m, -c.dist);
    mjtNum f[6];
    mj_contactForce(m, d, i, f);
    out->preload_n += f[0];
    if (f[0] > strongest_n) {
      strongest_n = f[0];
      strongest = i;
      pad_is_geom2 = c.geom2 == pad.geom;
    }
  }
  if (strongest < 0) return;

  const mjContact& c = d->contact[strongest];
  const int surface = pad_is_geom2 ? c.geom1 : c.geom2;
  out->surface_geom = surface;
  // The contact normal runs from geom1 to geom2: from the surface into the pad when the pad is
  // geom2.
  Eigen::Vector3d n(c.frame[0], c.frame[1], c.frame[2]);
  if (!pad_is_geom2) n = -n;
  out->surface_normal = n;
  const Eigen::Vector3d p(c.pos[0], c.pos[1], c.pos[2]);
  out->contact_pos = p;
  const Eigen::Vector3d v_rel =
      PointVelocity(m, d, pad.body, p) - PointVelocity(m, d, m->geom_bodyid[surface], p);
  out->approach_speed_mps = -v_rel.dot(n);
  const PadFrame frame = FaceFrame(d, pad);
  out->angle_rad = std::acos(std::clamp(frame.rot.col(2).dot(n), -1.0, 1.0));
}

}  // namespace climbsim::adhesion
