#include "robot/compliance.h"

#include <sstream>
#include <stdexcept>
#include <vector>

#include "robot/mjcf_dom.h"

namespace climbsim::sim {

std::string SpringJointName(const std::string& servo_joint) { return servo_joint + "_spring"; }

void AddSeriesSpring(const SeriesSpring& spring, tinyxml2::XMLElement* servo_joint) {
  if (spring.stiffness_nm_per_rad <= 0) return;
  const char* name = servo_joint->Attribute("name");
  const char* axis = servo_joint->Attribute("axis");
  if (!name || !axis) {
    throw std::invalid_argument("robot.compliance: a servo joint needs a name and an axis");
  }
  const char* pos = servo_joint->Attribute("pos");
  const double k = spring.stiffness_nm_per_rad;
  const double p = spring.preload_nm;
  const bool preloaded = p != 0;
  tinyxml2::XMLElement* joint = InsertElementAfter(
      servo_joint, "joint",
      {{"name", SpringJointName(name)},
       {"type", "hinge"},
       {"axis", axis},
       {"pos", pos ? pos : "0 0 0"},
       {"stiffness", MjcfNumber(spring.stiffness_nm_per_rad)},
       {"damping", MjcfNumber(spring.damping_nms_per_rad)},
       {"springref", preloaded ? MjcfNumber(-p / k) : "0"},
       {"armature", "0"},
       {"limited", "true"},
       {"range",
        MjcfNumbers({p > 0 ? 0.0 : -spring.travel_rad, p < 0 ? 0.0 : spring.travel_rad})}});
  if (preloaded) {
    // MuJoCo's default stop (solref 0.02 s) lets the preload press the light spring joint
    // 0.06 rad into it: the leg would sit that far off. The stiffest stop the solver takes
    // (time constant 2 timesteps at 1 ms; shorter is clamped to that) and a harder impedance.
    joint->SetAttribute("solreflimit", "0.002 1");
    joint->SetAttribute("solimplimit", "0.95 0.99 0.001");
  }
}

namespace {

std::vector<std::string> LegNames(tinyxml2::XMLDocument* robot) {
  tinyxml2::XMLElement* root = robot->RootElement();
  tinyxml2::XMLElement* text = root ? FindNamed(root, "text", "climbsim_legs") : nullptr;
  const char* data = text ? text->Attribute("data") : nullptr;
  if (!data) throw std::invalid_argument("robot.compliance: the robot has no climbsim_legs text");
  std::istringstream in(data);
  std::vector<std::string> names;
  for (std::string n; in >> n;) names.push_back(n);
  return names;
}

}  // namespace

void AddSeriesSprings(const ComplianceDesign& design, tinyxml2::XMLDocument* robot) {
  const std::pair<const char*, const SeriesSpring*> joints[] = {
      {"_hip_yaw", &design.hip_yaw}, {"_hip_pitch", &design.hip_pitch}, {"_knee", &design.knee}};
  for (const std::string& leg : LegNames(robot)) {
    for (const auto& [suffix, spring] : joints) {
      if (spring->stiffness_nm_per_rad <= 0) continue;
      tinyxml2::XMLElement* j = FindNamed(robot->RootElement(), "joint", leg + suffix);
      if (!j) {
        throw std::invalid_argument("robot.compliance: the robot has no joint " + leg + suffix);
      }
      AddSeriesSpring(*spring, j);
    }
  }
}

}  // namespace climbsim::sim
