// Helpers of the hard-case tests (issue 7 item 3): finiteness, MuJoCo's warning counters and
// the residual of a weld as MuJoCo itself computes it.
#ifndef CLIMBSIM_TESTS_HARD_HARD_UTIL_H_
#define CLIMBSIM_TESTS_HARD_HARD_UTIL_H_

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <cmath>
#include <string>

namespace climbsim::testing {

// Every number of the state (qpos, qvel, qacc, act) is finite.
inline bool StateFinite(const mjModel* m, const mjData* d) {
  for (int i = 0; i < m->nq; ++i) {
    if (!std::isfinite(d->qpos[i])) return false;
  }
  for (int i = 0; i < m->nv; ++i) {
    if (!std::isfinite(d->qvel[i]) || !std::isfinite(d->qacc[i])) return false;
  }
  for (int i = 0; i < m->na; ++i) {
    if (!std::isfinite(d->act[i])) return false;
  }
  return true;
}

// Every MuJoCo warning raised since mj_resetData, any kind; "" when there was none.
inline std::string WarningsRaised(const mjData* d) {
  std::string out;
  for (int w = 0; w < mjNWARNING; ++w) {
    if (d->warning[w].number > 0) {
      out += "warning " + std::to_string(w) + " raised " + std::to_string(d->warning[w].number) +
             " times (last info " + std::to_string(d->warning[w].lastinfo) + "); ";
    }
  }
  return out;
}

// The position residual of weld `eq` in the last mj_step, as MuJoCo computed it for the
// constraint (efc_pos of the weld's first three rows: pad point minus its target, world frame,
// at the state the step started from). Negative when the weld had no rows (off in that step).
inline double WeldPositionResidualM(const mjModel* m, const mjData* d, int eq) {
  for (int r = 0; r < d->nefc; ++r) {
    if (d->efc_type[r] == mjCNSTR_EQUALITY && d->efc_id[r] == eq) {
      return Eigen::Vector3d(d->efc_pos[r], d->efc_pos[r + 1], d->efc_pos[r + 2]).norm();
    }
  }
  (void)m;
  return -1.0;
}

// Linear speed of a free body's root joint (its qvel[0..2], world frame).
inline double RootSpeedMps(const mjData* d, int root_dof_adr) {
  return Eigen::Vector3d(d->qvel[root_dof_adr], d->qvel[root_dof_adr + 1],
                         d->qvel[root_dof_adr + 2])
      .norm();
}

}  // namespace climbsim::testing

#endif  // CLIMBSIM_TESTS_HARD_HARD_UTIL_H_
