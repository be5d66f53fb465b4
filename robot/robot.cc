#include "robot/robot.h"

#include <sstream>
#include <stdexcept>
#include <utility>

namespace climbsim::sim {
namespace {

int Id(const mjModel* m, mjtObj type, const std::string& name) {
  return mj_name2id(m, type, name.c_str());
}

// The custom text "climbsim_legs": leg names separated by spaces.
std::vector<std::string> LegNames(const mjModel* m) {
  const int id = Id(m, mjOBJ_TEXT, "climbsim_legs");
  if (id < 0) return {};
  std::istringstream in(std::string(m->text_data + m->text_adr[id]));
  std::vector<std::string> names;
  for (std::string n; in >> n;) names.push_back(n);
  return names;
}

// The id of a contract item the robot must have.
int Need(const mjModel* m, mjtObj type, const std::string& name) {
  const int id = Id(m, type, name);
  if (id < 0) {
    throw std::invalid_argument("the robot model lacks '" + name +
                                "' (see mjcf/README.md, contract)");
  }
  return id;
}

LegInfo ReadLeg(const mjModel* m, const std::string& leg) {
  const char* joint_suffix[3] = {"_hip_yaw", "_hip_pitch", "_knee"};
  LegInfo l;
  l.name = leg;
  for (int k = 0; k < 3; ++k) {
    l.joint[k] = Need(m, mjOBJ_JOINT, leg + joint_suffix[k]);
    l.qpos_adr[k] = m->jnt_qposadr[l.joint[k]];
    l.dof_adr[k] = m->jnt_dofadr[l.joint[k]];
    l.actuator[k] = Need(m, mjOBJ_ACTUATOR, leg + joint_suffix[k]);
  }
  l.pad_body = Need(m, mjOBJ_BODY, leg + "_pad");
  l.pad_geom = Need(m, mjOBJ_GEOM, leg + "_pad");
  l.ankle_site = Need(m, mjOBJ_SITE, leg + "_ankle");
  l.pad_face_site = Need(m, mjOBJ_SITE, leg + "_pad_face");
  l.tilt_joint = Id(m, mjOBJ_JOINT, leg + "_ankle_tilt");
  if (l.tilt_joint >= 0) {
    l.tilt_qpos_adr = m->jnt_qposadr[l.tilt_joint];
    l.tilt_actuator = Need(m, mjOBJ_ACTUATOR, leg + "_ankle_tilt");
  }
  return l;
}

// The tail's ids: none without a joint "tail_pitch"; with it, its servo and tip are required.
TailInfo ReadTail(const mjModel* m) {
  TailInfo t;
  t.pitch_joint = Id(m, mjOBJ_JOINT, "tail_pitch");
  if (t.pitch_joint < 0) return t;
  t.pitch_qpos_adr = m->jnt_qposadr[t.pitch_joint];
  t.pitch_dof_adr = m->jnt_dofadr[t.pitch_joint];
  t.pitch_actuator = Need(m, mjOBJ_ACTUATOR, "tail_pitch");
  t.tip_geom = Need(m, mjOBJ_GEOM, "tail_tip");
  t.tip_site = Need(m, mjOBJ_SITE, "tail_tip");
  t.pad_body = Id(m, mjOBJ_BODY, "tail_pad");
  t.yaw_joint = Id(m, mjOBJ_JOINT, "tail_yaw");
  if (t.yaw_joint >= 0) t.yaw_actuator = Need(m, mjOBJ_ACTUATOR, "tail_yaw");
  return t;
}

}  // namespace

RobotInfo ReadRobot(const mjModel* m) {
  RobotInfo r;
  r.base_body = Need(m, mjOBJ_BODY, "base");
  const int root = Need(m, mjOBJ_JOINT, "root");
  if (m->jnt_type[root] != mjJNT_FREE) {
    throw std::invalid_argument("the robot's joint 'root' must be a free joint");
  }
  r.root_qpos_adr = m->jnt_qposadr[root];
  r.root_dof_adr = m->jnt_dofadr[root];
  r.mass_kg = m->body_subtreemass[r.base_body];
  for (const std::string& leg : LegNames(m)) r.legs.push_back(ReadLeg(m, leg));
  r.tail = ReadTail(m);
  r.spine_joint = Id(m, mjOBJ_JOINT, "spine_yaw");
  if (r.spine_joint >= 0) {
    r.spine_qpos_adr = m->jnt_qposadr[r.spine_joint];
    r.spine_actuator = Need(m, mjOBJ_ACTUATOR, "spine_yaw");
  }
  return r;
}

}  // namespace climbsim::sim
