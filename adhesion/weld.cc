#include "adhesion/weld.h"

namespace climbsim::adhesion {

bool WeldActive(const mjModel* m, const mjData* /*d*/, int eq) { return m->eq_active[eq] != 0; }

void SetWeldActive(mjModel* m, mjData* /*d*/, int eq, bool active) {
  m->eq_active[eq] = active ? 1 : 0;
}

void SetWeldFromCurrentPoses(mjModel* m, const mjData* d, int eq, int body2,
                             const Eigen::Vector3d& point_body1) {
  const int body1 = m->eq_obj1id[eq];
  m->eq_obj2id[eq] = body2;
  mjtNum* data = m->eq_data + eq * mjNEQDATA;

  // The weld point in the world, then in body2's frame: anchor = R2ᵀ·(p − x2).
  mjtNum p[3], rel[3];
  mju_rotVecMat(p, point_body1.data(), d->xmat + 9 * body1);
  mju_addTo3(p, d->xpos + 3 * body1);
  mju_sub3(rel, p, d->xpos + 3 * body2);
  mju_rotVecMatT(data, rel, d->xmat + 9 * body2);
  mju_copy3(data + 3, point_body1.data());

  // Relative orientation q1⁻¹·q2.
  mjtNum q1_inv[4];
  mju_negQuat(q1_inv, d->xquat + 4 * body1);
  mju_mulQuat(data + 6, q1_inv, d->xquat + 4 * body2);
}

bool ReadWeldWrench(const mjModel* m, const mjData* d, int eq, WeldWrench* out) {
  *out = WeldWrench{};
  // Equality rows come first in the efc arrays; stop at the first other row.
  for (int r = 0; r < d->nefc && d->efc_type[r] == mjCNSTR_EQUALITY; ++r) {
    if (d->efc_id[r] != eq) continue;
    const mjtNum* f = d->efc_force + r;
    out->force_n = Eigen::Vector3d(f[0], f[1], f[2]);
    const double torquescale = m->eq_data[eq * mjNEQDATA + 10];
    mjtNum t[3];
    mju_rotVecMat(t, f + 3, d->xmat + 9 * m->eq_obj2id[eq]);
    out->torque_nm = 0.5 * torquescale * Eigen::Vector3d(t[0], t[1], t[2]);
    return true;
  }
  return false;
}

std::string WeldName(const std::string& pad_body) { return "climbsim_bond_" + pad_body; }

std::string AdhesionActuatorName(const std::string& pad_body) {
  return "climbsim_adhesion_" + pad_body;
}

}  // namespace climbsim::adhesion
