// The robot as a model holds it: the contract of mjcf/README.md (legs, joints, servos, pads)
// resolved to MuJoCo ids once, so the step never looks up a name, and the servos' stiffness.
// ReadRobot reads it (sim/world.cc composes the model and calls it). The leg chains
// (leg_chain.h) and the legs' inverse kinematics (leg_ik.h) build on it.
#ifndef CLIMBSIM_ROBOT_ROBOT_H_
#define CLIMBSIM_ROBOT_ROBOT_H_

#include <mujoco/mujoco.h>

#include <array>
#include <string>
#include <vector>

namespace climbsim::sim {

// One leg of the robot contract: ids resolved once so the step never looks up a name.
struct LegInfo {
  std::string name;                    // "LF"
  std::array<int, 3> joint{};          // hip_yaw, hip_pitch, knee
  std::array<int, 3> qpos_adr{};
  std::array<int, 3> dof_adr{};
  std::array<int, 3> actuator{};       // position servos, same names as the joints
  int pad_body = -1;                   // "LF_pad"
  int pad_geom = -1;
  int ankle_site = -1;                 // "LF_ankle"
  int pad_face_site = -1;              // "LF_pad_face"
  // Optional (the robots with actuated ankles, mjcf/README.md): the ankle tilt servo "LF_ankle_tilt"
  // that turns the pad about its y axis; −1 when the robot has none.
  int tilt_joint = -1;
  int tilt_qpos_adr = -1;
  int tilt_actuator = -1;
};

// The optional tail (robot/tail.h): its servos, the tip; every id −1 when the robot has none
// (tail_pitch missing). Not a leg: the CPG and the leg reflexes never drive its servos.
struct TailInfo {
  int pitch_joint = -1;                // "tail_pitch"; > 0 turns the tip into the surface
  int pitch_qpos_adr = -1;
  int pitch_dof_adr = -1;
  int pitch_actuator = -1;
  int yaw_joint = -1;                  // "tail_yaw", optional
  int yaw_actuator = -1;
  int tip_geom = -1;                   // "tail_tip"
  int tip_site = -1;
  int pad_body = -1;                   // "tail_pad": an adhesive tip (a sticky pad), optional
  bool present() const { return pitch_joint >= 0; }
};

struct RobotInfo {
  int base_body = -1;
  int root_qpos_adr = -1;
  int root_dof_adr = -1;
  std::vector<LegInfo> legs;           // order of the custom text "climbsim_legs"
  TailInfo tail;
  // Optional (a designed robot with robot.body.spine): the hinge "spine_yaw" between base and
  // base_hind and its servo; -1 when the body is rigid.
  int spine_joint = -1;
  int spine_qpos_adr = -1;
  int spine_actuator = -1;
  double mass_kg = 0.0;
};

// The robot contract of a compiled model (mjcf/README.md): the base with its free joint
// "root", and for each leg of the custom text "climbsim_legs" its joints, servos, pad and
// sites, and the tail when it has a joint "tail_pitch". Throws std::invalid_argument naming
// the first item the model lacks.
RobotInfo ReadRobot(const mjModel* model);

// A position servo's stiffness (force = gain·ctrl + bias1·q + bias2·q̇ with gain = kp and
// bias1 = −kp): read, and set at run time (the run's own model copy; both terms together).
inline double ServoKp(const mjModel* m, int actuator) { return m->actuator_gainprm[actuator * mjNGAIN]; }
inline void SetServoKp(mjModel* m, int actuator, double kp) {
  m->actuator_gainprm[actuator * mjNGAIN] = kp;
  m->actuator_biasprm[actuator * mjNBIAS + 1] = -kp;
}

}  // namespace climbsim::sim

#endif  // CLIMBSIM_ROBOT_ROBOT_H_
