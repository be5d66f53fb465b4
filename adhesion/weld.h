// Weld equalities used as adhesive bonds (MuJoCo 2.2.2; facts in docs/mujoco.md).
//
// A pad is held by one weld equality, body1 = the pad body, body2 = the body it touched
// (the world for a static surface). The weld is compiled inactive and switched at run time:
//
//   eq_data (11 numbers) = [anchor in body2's frame (3), the same point in body1's frame (3),
//                           relative orientation q1⁻¹·q2 (4), torquescale (1)];
//   residual             = (x1 + R1·d[3:6]) − (x2 + R2·d[0:3]),  vec(q2⁻¹·q1·d[6:10]).
//
// SWITCHING ON WITHOUT A JUMP. After mj_step, xpos/xquat still describe the state before
// the integration, so the caller runs mj_kinematics first; SetWeldFromCurrentPoses then
// writes the anchor, the point and the orientation from the current poses (residual 0) and
// points eq_obj2id at the touched body. Only then is the weld switched on.
//
// THE WRENCH. The weld's constraint rows are the equality rows with efc_id == eq (6 for a
// weld; MuJoCo puts equality rows first). Their force, filled by mj_step for that step, is
//
//   force on body1 (world)               = efc_force[r .. r+2],
//   torque on body1 (world, about point) = 0.5 · torquescale · R2 · efc_force[r+3 .. r+5],
//
// acting at the weld point (measured against statics and Jᵀf to 1e-6). With the point put at
// the pad's contact-face centroid, this is the surface's wrench on the pad about that
// centroid, which is what PadLoadFromSurfaceWrench() wants (after rotating it into the pad
// frame).
//
// MODEL-LEVEL STATE. MuJoCo 2.2.2 keeps eq_active, eq_data and eq_obj2id in mjModel, so each
// run needs its own model copy; MuJoCo 3.x moves eq_active to mjData. WeldActive() and
// SetWeldActive() are the only two places that touch eq_active: change them when upgrading.
// None of these functions allocates.
#ifndef CLIMBSIM_ADHESION_WELD_H_
#define CLIMBSIM_ADHESION_WELD_H_

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <string>

namespace climbsim::adhesion {

// Is weld `eq` switched on? (`d` is unused in 2.2.2; it is there for MuJoCo 3.)
bool WeldActive(const mjModel* m, const mjData* d, int eq);
// Switches weld `eq` on or off (takes effect at the next mj_step).
void SetWeldActive(mjModel* m, mjData* d, int eq, bool active);

// Points weld `eq` at `body2` and writes its anchor, the matching point of body1
// (`point_body1`, in body1's frame) and its relative orientation from the current xpos,
// xquat and xmat, so that the residual is zero. Does not switch the weld on.
void SetWeldFromCurrentPoses(mjModel* m, const mjData* d, int eq, int body2,
                             const Eigen::Vector3d& point_body1);

// The wrench of weld `eq` on its body1, world frame, torque about the weld point.
struct WeldWrench {
  Eigen::Vector3d force_n = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque_nm = Eigen::Vector3d::Zero();
};
// Reads the weld's rows of the last mj_step. False (and a zero wrench) when the weld has no
// rows, i.e. it was off in that step.
bool ReadWeldWrench(const mjModel* m, const mjData* d, int eq, WeldWrench* out);

// The MJCF name of the weld (and of the baseline actuator) that holds pad body `pad_body`.
std::string WeldName(const std::string& pad_body);
std::string AdhesionActuatorName(const std::string& pad_body);

}  // namespace climbsim::adhesion

#endif  // CLIMBSIM_ADHESION_WELD_H_
