// GenerateRobotMjcf: the robot file of a design as a tinyxml2 DOM (the header comment, the
// default classes, the base and legs of generate_legs.cc, the actuators), per the model
// contract of mjcf/README.md.
#include "robot/generate.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "robot/design.h"
#include "robot/mjcf_dom.h"
#include "robot/tail.h"

namespace climbsim::sim {
namespace generate {

namespace {

const ServoModel* Servo(const std::string& key, const std::string& name) {
  const ServoModel* s = FindServo(name);
  if (!s)
    throw std::invalid_argument("robot." + key + ": unknown servo '" + name +
                                "' (catalogue: " + ServoNames() + ")");
  return s;
}

std::vector<Leg> LegsOf(const RobotDesign& d) {
  const double x = d.body.hip_x_m, s = d.legs.splay_rad;
  // Left front legs turn forward (-z), hind legs backward; the right side mirrors.
  if (d.legs.count == 4)
    return {{"LF", x, 1, -s}, {"RF", x, -1, s}, {"LH", -x, 1, s}, {"RH", -x, -1, -s}};
  if (d.legs.count == 6)
    return {{"L1", x, 1, -s}, {"L2", 0, 1, 0},  {"L3", -x, 1, s},
            {"R1", x, -1, s}, {"R2", 0, -1, 0}, {"R3", -x, -1, -s}};
  throw std::invalid_argument("robot.legs.count: must be 4 or 6, not " +
                              std::to_string(d.legs.count));
}

void AddServoClass(tinyxml2::XMLElement* parent, const std::string& name, const ServoModel& s,
                   const std::vector<double>& range) {
  tinyxml2::XMLElement* c = AddElement(parent, "default", {{"class", name}});
  const std::string r = MjcfNumbers({range[0], range[1]});
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

Plan MakePlan(const RobotDesign& d) {
  Plan p{&d, d.preset.substr(0, d.preset.find('_')), {}, nullptr, nullptr, nullptr, nullptr, {},
         0.0};
  p.palette = p.prefix == "spider"
                  ? Palette{"0.3 0.3 0.35 1", "0.6 0.6 0.65 1", "0.12 0.12 0.14 1"}
                  : Palette{"0.45 0.55 0.35 1", "0.55 0.65 0.4 1", "0.15 0.15 0.18 1"};
  p.hip_yaw = Servo("servos.hip_yaw", d.servos.hip_yaw);
  p.hip_pitch = Servo("servos.hip_pitch", d.servos.hip_pitch);
  p.knee = Servo("servos.knee", d.servos.knee);
  if (d.ankles.actuated) p.tilt = Servo("ankles.tilt_servo", d.ankles.tilt_servo);
  p.legs = LegsOf(d);
  // The ankle drops tibia_m below the knee, which rises femur_rise_m above the hips.
  p.base_z_m = d.legs.tibia_m - d.legs.femur_rise_m + d.feet.post_m + kPadGap_m;
  CheckGeometry(p);
  return p;
}

void CheckGeometry(const Plan& p) {
  const RobotDesign& d = *p.design;
  if (d.feet.post_m <= d.pads.thickness_m)
    throw std::invalid_argument("robot.feet.post_m: the post (" + MjcfNumber(d.feet.post_m) +
                                " m) must be longer than the pad is thick (" +
                                MjcfNumber(d.pads.thickness_m) + " m)");
  const double reach = d.legs.coxa_m + d.legs.femur_m - d.legs.tibia_inset_m;
  std::vector<std::pair<double, double>> pads;
  for (const Leg& leg : p.legs)
    pads.emplace_back(leg.hip_x_m - leg.side * reach * std::sin(leg.yaw_rad),
                      leg.side * (d.body.hip_y_m + reach * std::cos(leg.yaw_rad)));
  for (size_t i = 0; i < pads.size(); ++i)
    for (size_t j = i + 1; j < pads.size(); ++j)
      if (std::abs(pads[i].first - pads[j].first) < d.pads.size_m &&
          std::abs(pads[i].second - pads[j].second) < d.pads.size_m)
        throw std::invalid_argument("robot.pads.size_m: the pads of " + p.legs[i].name + " and " +
                                    p.legs[j].name + " overlap in the neutral pose (pad side " +
                                    MjcfNumber(d.pads.size_m) + " m)");
}

tinyxml2::XMLElement* AddDefaults(const Plan& p, tinyxml2::XMLElement* mujoco) {
  const RobotDesign& d = *p.design;
  tinyxml2::XMLElement* top =
      AddElement(AddElement(mujoco, "default"), "default", {{"class", p.prefix}});
  AddElement(top, "geom",
             {{"contype", "2"},
              {"conaffinity", "1"},
              {"condim", "3"},
              {"friction", "0.3 0.005 0.0001"},
              {"rgba", p.palette.body}});
  AddElement(top, "joint", {{"type", "hinge"}, {"limited", "true"}});
  AddElement(top, "site", {{"group", "3"}, {"size", "0.002"}});
  AddServoClass(top, p.prefix + "_hip_yaw", *p.hip_yaw, d.legs.hip_yaw_range_rad);
  AddServoClass(top, p.prefix + "_hip_pitch", *p.hip_pitch, d.legs.hip_pitch_range_rad);
  AddServoClass(top, p.prefix + "_knee", *p.knee, d.legs.knee_range_rad);
  if (p.tilt)
    AddServoClass(top, p.prefix + "_ankle_tilt", *p.tilt,
                  {-d.ankles.range_rad, d.ankles.range_rad});
  const double ankle = d.pads.ankle_range_rad;
  AddElement(AddElement(top, "default", {{"class", p.prefix + "_ankle"}}), "joint",
             {{"stiffness", MjcfNumber(d.pads.ankle_stiffness_nm_per_rad)},
              {"damping", MjcfNumber(d.pads.ankle_damping_nms_per_rad)},
              {"springref", "0"},
              {"range", MjcfNumbers({-ankle, ankle})}});
  AddElement(AddElement(top, "default", {{"class", p.prefix + "_link"}}), "geom",
             {{"type", "capsule"}, {"rgba", p.palette.link}});
  AddElement(AddElement(top, "default", {{"class", p.prefix + "_post"}}), "geom",
             {{"type", "capsule"},
              {"size", MjcfNumber(d.feet.post_radius_m)},
              {"mass", "0"},
              {"contype", "0"},
              {"conaffinity", "0"},
              {"group", "1"},
              {"rgba", "0.3 0.3 0.32 1"}});
  tinyxml2::XMLElement* pad = AddElement(top, "default", {{"class", p.prefix + "_pad"}});
  const double half = d.pads.size_m / 2;
  const std::vector<double>&f = d.pads.friction, &r = d.pads.solref, &i = d.pads.solimp;
  AddElement(pad, "geom",
             {{"type", "box"},
              {"size", MjcfNumbers({half, half, d.pads.thickness_m / 2})},
              {"mass", MjcfNumber(d.pads.mass_kg)},
              {"priority", "1"},
              {"friction", MjcfNumbers({f[0], f[1], f[2]})},
              {"solref", MjcfNumbers({r[0], r[1]})},
              {"solimp", MjcfNumbers({i[0], i[1], i[2]})},
              {"rgba", "0.85 0.45 0.1 1"}});
  AddElement(pad, "site", {{"group", "2"}, {"size", "0.002"}, {"rgba", "1 0 0 1"}});
  return top;
}

tinyxml2::XMLElement* AddActuators(const Plan& p, tinyxml2::XMLElement* mujoco) {
  tinyxml2::XMLElement* actuator = AddElement(mujoco, "actuator");
  std::vector<std::string> joints = {"hip_yaw", "hip_pitch", "knee"};
  if (p.tilt) joints.push_back("ankle_tilt");
  for (const Leg& leg : p.legs)
    for (const std::string& j : joints)
      AddElement(actuator, "position",
                 {{"name", leg.name + "_" + j},
                  {"class", p.prefix + "_" + j},
                  {"joint", leg.name + "_" + j}});
  return actuator;
}

}  // namespace generate

std::string GenerateRobotMjcf(const RobotDesign& design) {
  const generate::Plan plan = generate::MakePlan(design);
  tinyxml2::XMLDocument doc;
  doc.InsertEndChild(doc.NewComment(
      ("\n  climbsim " + design.preset + ": generated by `climbsim model` from the preset " +
       design.preset +
       "\n  (robot/presets.cc) and the design's keys; mjcf/README.md explains "
       "the numbers.\n  Frames: base x forward, y left, z up; in qpos0 the pad faces stand "
       "0.5 mm above z = 0.\n")
          .c_str()));
  tinyxml2::XMLElement* mujoco = doc.NewElement("mujoco");
  doc.InsertEndChild(mujoco);
  mujoco->SetAttribute("model", design.preset.c_str());
  AddElement(mujoco, "compiler", {{"angle", "radian"}, {"autolimits", "true"}});
  tinyxml2::XMLElement* defaults = generate::AddDefaults(plan, mujoco);
  std::string legs;
  for (const generate::Leg& leg : plan.legs) legs += (legs.empty() ? "" : " ") + leg.name;
  AddElement(AddElement(mujoco, "custom"), "text", {{"name", "climbsim_legs"}, {"data", legs}});
  tinyxml2::XMLElement* base = generate::AddBase(plan, AddElement(mujoco, "worldbody"));
  for (const generate::Leg& leg : plan.legs) generate::AddLeg(plan, leg, base);
  tinyxml2::XMLElement* actuator = generate::AddActuators(plan, mujoco);
  if (design.tail)
    AddTail(*design.tail, {plan.prefix, -design.body.length_m / 2, 0.0, plan.base_z_m}, defaults,
            base, actuator);
  tinyxml2::XMLPrinter printer;
  doc.Print(&printer);
  return printer.CStr();
}

}  // namespace climbsim::sim
