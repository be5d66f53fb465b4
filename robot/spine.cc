#include "robot/spine.h"

#include <cstring>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "robot/mjcf_dom.h"
#include "robot/servos.h"

namespace climbsim::sim {

namespace {

using tinyxml2::XMLElement;
using tinyxml2::XMLNode;

const ServoModel& CheckSpine(const SpineDesign& spine, const SpineMount& mount) {
  const ServoModel* s = FindServo(spine.servo);
  if (!s)
    throw std::invalid_argument("robot.body.spine.servo: unknown servo '" + spine.servo +
                                "' (catalogue: " + ServoNames() + ")");
  const double x = spine.joint_x_m;
  if (!(mount.hind_hip_x_m < x && x < mount.front_hip_x_m))
    throw std::invalid_argument("robot.body.spine.joint_x_m: " + MjcfNumber(x) +
                                " m must lie between the hind hips (" +
                                MjcfNumber(mount.hind_hip_x_m) + " m) and the front hips (" +
                                MjcfNumber(mount.front_hip_x_m) + " m)");
  return *s;
}

// An element's pos attribute as x, y, z (0 0 0 when it has none).
std::vector<double> PosOf(const XMLElement* e) {
  std::vector<double> p = {0, 0, 0};
  if (const char* text = e->Attribute("pos")) {
    std::istringstream in(text);
    in >> p[0] >> p[1] >> p[2];
  }
  return p;
}

// A body or placed geom of the base behind the joint (not the plate, which is split).
bool BehindJoint(const XMLNode* node, double joint_x_m) {
  const XMLElement* e = node ? node->ToElement() : nullptr;
  if (!e || !e->Attribute("pos")) return false;
  if (std::strcmp(e->Name(), "body") != 0 && std::strcmp(e->Name(), "geom") != 0) return false;
  return PosOf(e)[0] < joint_x_m;
}

// Moves what lies behind the joint into hind, its positions now from the joint; a comment
// moves with the element it names (the next one).
void MoveBehind(XMLElement* base, XMLElement* hind, double joint_x_m) {
  XMLNode* node = base->FirstChild();
  while (node) {
    XMLNode* next = node->NextSibling();
    const bool move = node != hind && (node->ToComment() ? BehindJoint(next, joint_x_m)
                                                         : BehindJoint(node, joint_x_m));
    if (move) {
      if (XMLElement* e = node->ToElement()) {
        const std::vector<double> p = PosOf(e);
        e->SetAttribute("pos", MjcfNumbers({p[0] - joint_x_m, p[1], p[2]}).c_str());
      }
      hind->InsertEndChild(node);
    }
    node = next;
  }
}

void AddServoClass(const std::string& prefix, const ServoModel& s, double range_rad,
                   XMLElement* defaults) {
  AddComment(defaults, {"body.spine.servo: " + std::string(s.part) + " at " +
                            MjcfNumber(s.voltage_v) + " V, stall " +
                            MjcfNumber(s.stall_torque_nm) + " N m (the spine's yaw)."});
  XMLElement* c = AddElement(defaults, "default", {{"class", prefix + "_spine_yaw"}});
  const std::string r = MjcfNumbers({-range_rad, range_rad});
  AddElement(c, "joint",
             {{"damping", MjcfNumber(s.damping_nms_per_rad)},
              {"armature", MjcfNumber(s.armature_kgm2)},
              {"range", r}});
  AddElement(c, "position",
             {{"kp", MjcfNumber(s.kp_nm_per_rad)},
              {"forcelimited", "true"},
              {"forcerange", MjcfNumbers({-s.stall_torque_nm, s.stall_torque_nm})},
              {"ctrlrange", r}});
}

}  // namespace

void AddSpine(const SpineDesign& spine, const SpineMount& mount, XMLElement* defaults,
              XMLElement* base, XMLElement* actuator) {
  const ServoModel& servo = CheckSpine(spine, mount);
  const double x = spine.joint_x_m, half_l = mount.length_m / 2;
  const double front_m = half_l - x, hind_m = half_l + x;
  AddServoClass(mount.prefix, servo, spine.range_rad, defaults);
  XMLElement* plate = FindNamed(base, "geom", "base");
  if (!plate) throw std::logic_error("AddSpine: the base has no plate geom 'base'");
  // Each half's mass by its share of the plate's length.
  plate->SetAttribute("size",
                      MjcfNumbers({front_m / 2, mount.width_m / 2, mount.height_m / 2}).c_str());
  plate->SetAttribute("pos", MjcfNumbers({x + front_m / 2, 0, 0}).c_str());
  plate->SetAttribute("mass", MjcfNumber(mount.mass_kg * front_m / mount.length_m).c_str());
  AddComment(base, {"The hind half of the plate on the spine's yaw joint (body.spine): the hind",
                    "legs hang from it; spine_yaw > 0 turns it counter-clockwise seen from +z."});
  XMLElement* hind =
      AddElement(base, "body", {{"name", "base_hind"}, {"pos", MjcfNumbers({x, 0, 0})}});
  MoveBehind(base, hind, x);
  XMLElement* joint = AddElement(hind, "joint",
                                 {{"name", "spine_yaw"},
                                  {"class", mount.prefix + "_spine_yaw"},
                                  {"axis", "0 0 1"}});
  hind->InsertFirstChild(joint);
  XMLElement* case_geom = InsertElementAfter(
      joint, "geom",
      {{"name", "spine_servo"},
       {"type", "box"},
       {"size", MjcfNumbers({servo.case_half_m[0], servo.case_half_m[1], servo.case_half_m[2]})},
       {"mass", MjcfNumber(servo.mass_kg)},
       {"rgba", mount.servo_rgba},
       {"pos", MjcfNumbers({0, 0, mount.height_m / 2 + servo.case_half_m[2]})}});
  InsertElementAfter(case_geom, "geom",
                     {{"name", "base_hind"},
                      {"type", "box"},
                      {"size", MjcfNumbers({hind_m / 2, mount.width_m / 2, mount.height_m / 2})},
                      {"pos", MjcfNumbers({-hind_m / 2, 0, 0})},
                      {"mass", MjcfNumber(mount.mass_kg * hind_m / mount.length_m)}});
  AddElement(actuator, "position",
             {{"name", "spine_yaw"},
              {"class", mount.prefix + "_spine_yaw"},
              {"joint", "spine_yaw"}});
}

}  // namespace climbsim::sim
