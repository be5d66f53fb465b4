// GenerateRobotMjcf: the robot file of a design as a tinyxml2 DOM (the header comment, the
// default classes, the base and legs of generate_legs.cc, the actuators), per the model
// contract of mjcf/README.md.
#include "robot/generate.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "robot/design.h"
#include "robot/mjcf_dom.h"
#include "robot/spine.h"
#include "robot/tail.h"

namespace climbsim::sim {
namespace generate {

namespace {

// The pads' foam (pads.foam_m): soft open-cell polyurethane or silicone foam (30-200 kg/m^3)
// compresses on its stress plateau to about half its thickness before it densifies; under it
// lie the adhesive and its film.
constexpr double kFoamDensity_kg_per_m3 = 100.0;
constexpr double kFoamConformShare = 0.5;
constexpr double kAdhesiveFilm_m = 0.0005;

// How far beyond adhesion.contact_gap_m the face follows relief: the robot file's custom
// numeric climbsim_pad_conform_m (mjcf/README.md).
double PadConformM(const PadsDesign& pads) { return kFoamConformShare * pads.foam_m; }

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

// A servo's joint and actuator class, after a comment naming the part (key: the design's key).
void AddServoClass(tinyxml2::XMLElement* parent, const std::string& name, const std::string& key,
                   const ServoModel& s, const std::vector<double>& range) {
  AddComment(parent, {key + ": " + std::string(s.part) + " at " + MjcfNumber(s.voltage_v) +
                          " V, stall " + MjcfNumber(s.stall_torque_nm) + " N m,",
                      "no-load " + MjcfNumber(s.no_load_speed_rad_s) +
                          " rad/s (mjcf/README.md, \"Servo catalogue\")."});
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

// What the foot post is for: a peel lever, or (an active-release foot) only the ankle's height.
void AddPostComment(tinyxml2::XMLElement* parent, const FeetDesign& feet) {
  const bool peel = feet.release == "peel";
  AddComment(
      parent,
      {std::string("The foot post, ankle to pad (feet.post_m): ") +
           (peel ? "the lever that peels the pad" : "short, a toe tendon releases the pad"),
       std::string("(mjcf/README.md, ") + (peel ? "\"Feet\"" : "\"Active-release feet\"") + ").",
       "Visual only: the pad geom carries the mass."});
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

namespace {

// A pad's footprint in the base frame: centre, half side, angle about z.
struct Footprint {
  double x, y, half, angle;
};

// Where leg's pad lies with its hip yaw at yaw_rad (all other joints 0): the leg's plane turns
// about the hip axis; the pad turns with it (its frame cancels the splay).
Footprint PadAt(const RobotDesign& d, const Leg& leg, double yaw_rad) {
  const double reach = d.legs.coxa_m + d.legs.femur_m - d.legs.tibia_inset_m;
  const double turn = -leg.side * yaw_rad, psi = leg.yaw_rad + turn;
  return {leg.hip_x_m - leg.side * reach * std::sin(psi),
          leg.side * (d.body.hip_y_m + reach * std::cos(psi)), d.pads.size_m / 2, turn};
}

// The gap between two squares (separating-axis test on their edges' normals); < 0: overlap.
double Gap(const Footprint& a, const Footprint& b) {
  double gap = -1e300;
  for (const double axis : {a.angle, a.angle + M_PI / 2, b.angle, b.angle + M_PI / 2}) {
    const double ux = std::cos(axis), uy = std::sin(axis);
    double extent = 0;
    for (const Footprint& f : {a, b})
      extent += f.half * (std::abs(std::cos(f.angle - axis)) + std::abs(std::sin(f.angle - axis)));
    gap = std::max(gap, std::abs((a.x - b.x) * ux + (a.y - b.y) * uy) - extent);
  }
  return gap;
}

// Robot geoms never collide with each other, so pads must not meet: none overlapping in qpos0,
// nor neighbours on a side swung towards each other by the gait's 0.4 rad of hip yaw. (The
// presets keep 5 mm there, the contract's margin; a design may come closer.)
void CheckPads(const Plan& p) {
  const RobotDesign& d = *p.design;
  const std::vector<Leg>& legs = p.legs;
  for (size_t i = 0; i < legs.size(); ++i)
    for (size_t j = i + 1; j < legs.size(); ++j)
      if (Gap(PadAt(d, legs[i], 0), PadAt(d, legs[j], 0)) < 0)
        throw std::invalid_argument("robot.pads.size_m: the pads of " + legs[i].name + " and " +
                                    legs[j].name + " overlap in the neutral pose (pad side " +
                                    MjcfNumber(d.pads.size_m) + " m)");
  // Legs are listed front to back per side: a leg's neighbour is the next one on its side.
  for (size_t i = 0; i < legs.size(); ++i) {
    size_t j = i + 1;
    while (j < legs.size() && legs[j].side != legs[i].side) ++j;
    if (j == legs.size()) continue;
    const double gap = Gap(PadAt(d, legs[i], -kGaitYaw_rad), PadAt(d, legs[j], kGaitYaw_rad));
    if (gap < 0)
      throw std::invalid_argument(
          "robot.body.hip_x_m: the pads of " + legs[i].name + " and " + legs[j].name +
          " overlap by " + MjcfNumber(std::round(-gap * 1e5) / 1e2) +
          " mm at 0.4 rad of hip yaw: move the hips apart, or shorten the legs (legs.coxa_m, "
          "legs.femur_m) or the pads (pads.size_m)");
  }
}

void CheckRange(const std::string& key, const std::vector<double>& range) {
  if (!(range[0] < 0 && 0 < range[1]))
    throw std::invalid_argument("robot." + key + ": [" + MjcfNumbers({range[0], range[1]}) +
                                "] must hold 0, the neutral pose, inside its ends");
}

}  // namespace

double PadMassKg(const PadsDesign& pads) {
  return pads.mass_kg + kFoamDensity_kg_per_m3 * pads.size_m * pads.size_m * pads.foam_m;
}

void CheckGeometry(const Plan& p) {
  const RobotDesign& d = *p.design;
  if (d.pads.foam_m > d.pads.thickness_m - kAdhesiveFilm_m)
    throw std::invalid_argument("robot.pads.foam_m: the foam (" + MjcfNumber(d.pads.foam_m) +
                                " m) must leave the adhesive's 0.5 mm of the pad's thickness (" +
                                MjcfNumber(d.pads.thickness_m) + " m)");
  if (d.feet.post_m <= d.pads.thickness_m)
    throw std::invalid_argument("robot.feet.post_m: the post (" + MjcfNumber(d.feet.post_m) +
                                " m) must be longer than the pad is thick (" +
                                MjcfNumber(d.pads.thickness_m) + " m)");
  const double belly = p.base_z_m - d.body.height_m / 2;
  if (belly < 2 * kPadGap_m)
    throw std::invalid_argument(
        "robot.legs.tibia_m: the body's underside would stand " + MjcfNumber(belly * 1e3) +
        " mm above the surface (1 mm needed): the tibia's drop less the femur's rise plus the "
        "post must exceed half the body's height");
  CheckRange("legs.hip_yaw_range_rad", d.legs.hip_yaw_range_rad);
  CheckRange("legs.hip_pitch_range_rad", d.legs.hip_pitch_range_rad);
  CheckRange("legs.knee_range_rad", d.legs.knee_range_rad);
  CheckPads(p);
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
  AddServoClass(top, p.prefix + "_hip_yaw", "servos.hip_yaw", *p.hip_yaw, d.legs.hip_yaw_range_rad);
  AddServoClass(top, p.prefix + "_hip_pitch", "servos.hip_pitch", *p.hip_pitch,
                d.legs.hip_pitch_range_rad);
  AddServoClass(top, p.prefix + "_knee", "servos.knee", *p.knee, d.legs.knee_range_rad);
  if (p.tilt)
    AddServoClass(top, p.prefix + "_ankle_tilt", "ankles.tilt_servo", *p.tilt,
                  {-d.ankles.range_rad, d.ankles.range_rad});
  const double ankle = d.pads.ankle_range_rad;
  AddComment(top, {"Passive compliant ankle: torsion spring, neutral (springref) at 0."});
  AddElement(AddElement(top, "default", {{"class", p.prefix + "_ankle"}}), "joint",
             {{"stiffness", MjcfNumber(d.pads.ankle_stiffness_nm_per_rad)},
              {"damping", MjcfNumber(d.pads.ankle_damping_nms_per_rad)},
              {"springref", "0"},
              {"range", MjcfNumbers({-ankle, ankle})}});
  AddElement(AddElement(top, "default", {{"class", p.prefix + "_link"}}), "geom",
             {{"type", "capsule"}, {"rgba", p.palette.link}});
  AddPostComment(top, d.feet);
  AddElement(AddElement(top, "default", {{"class", p.prefix + "_post"}}), "geom",
             {{"type", "capsule"},
              {"size", MjcfNumber(d.feet.post_radius_m)},
              {"mass", "0"},
              {"contype", "0"},
              {"conaffinity", "0"},
              {"group", "1"},
              {"rgba", "0.3 0.3 0.32 1"}});
  AddComment(top,
             {"Dry-adhesive pad, polymer on a hard surface. priority 1 makes MuJoCo take friction,",
              "solref and solimp of a pad contact from the pad alone."});
  tinyxml2::XMLElement* pad = AddElement(top, "default", {{"class", p.prefix + "_pad"}});
  const double half = d.pads.size_m / 2;
  const std::vector<double>&f = d.pads.friction, &r = d.pads.solref, &i = d.pads.solimp;
  AddElement(pad, "geom",
             {{"type", "box"},
              {"size", MjcfNumbers({half, half, d.pads.thickness_m / 2})},
              {"mass", MjcfNumber(PadMassKg(d.pads))},
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

namespace {

// The mjcf/README.md section that explains a preset's numbers.
std::string ReadmeSection(const std::string& preset) {
  if (preset.ends_with("_active")) return "Active-release feet";
  if (preset.ends_with("_ankle")) return "Actuated ankles";
  return preset == "spider" ? "Spider" : "Gecko";
}

// The file's header. Its second line names no preset, so a variant's file is its robot's file
// line for line but for the lines that differ (MjcfVariants.ActiveFeetDifferOnlyInTheFeet).
// "  Keys changed from the preset: a 1, b 2," lines of at most 100 columns; "" for a preset.
std::string ChangedKeysText(const RobotDesign& d) {
  std::string text, line = "  Keys changed from the preset:";
  for (const std::string& key : ChangedKeys(d)) {
    if (line.size() + key.size() + 2 > 100) {
      text += line + "\n";
      line = "   ";
    }
    line += " " + key + ",";
  }
  if (line.back() != ',') return text;
  line.back() = '.';
  return text + line + "\n";
}

std::string Header(const RobotDesign& d) {
  return "\n"
         "  Generated by `climbsim model` from a robot design (robot/README.md): change the "
         "design\n"
         "  and generate again rather than edit this file. mjcf/README.md explains the numbers.\n"
         "  The design: the preset " +
         d.preset + " and its keys (mjcf/README.md, \"" + ReadmeSection(d.preset) + "\").\n" +
         ChangedKeysText(d) +
         "  Frames: base x forward, y left, z up. In qpos0 (all joint angles 0) the robot stands "
         "in\n"
         "  its neutral pose with the pad faces 0.5 mm above the plane z = 0.\n"
         "  Sign convention, the same for every leg (axes are mirrored on the right side):\n"
         "    L_hip_yaw   > 0 swings the pad forward (+x of the base)\n"
         "    L_hip_pitch > 0 lifts the pad away from the surface\n"
         "    L_knee      > 0 flexes the knee, which lifts the pad where the tibia leans inwards\n"
         "  Collision bits: robot geoms contype 2 / conaffinity 1, scene geoms contype 1 /\n"
         "  conaffinity 2, so the robot collides with the scene and never with itself.\n"
         "  This file has no <option>: timestep and gravity belong to the scene files.\n";
}

}  // namespace

std::string GenerateRobotMjcf(const RobotDesign& design) {
  const generate::Plan plan = generate::MakePlan(design);
  tinyxml2::XMLDocument doc;
  doc.InsertEndChild(doc.NewComment(Header(design).c_str()));
  tinyxml2::XMLElement* mujoco = doc.NewElement("mujoco");
  doc.InsertEndChild(mujoco);
  mujoco->SetAttribute("model", design.preset.c_str());
  AddElement(mujoco, "compiler", {{"angle", "radian"}, {"autolimits", "true"}});
  tinyxml2::XMLElement* defaults = generate::AddDefaults(plan, mujoco);
  std::string legs;
  for (const generate::Leg& leg : plan.legs) legs += (legs.empty() ? "" : " ") + leg.name;
  tinyxml2::XMLElement* custom = AddElement(mujoco, "custom");
  AddElement(custom, "text", {{"name", "climbsim_legs"}, {"data", legs}});
  if (design.pads.foam_m > 0)
    AddElement(custom, "numeric",
               {{"name", "climbsim_pad_conform_m"},
                {"data", MjcfNumber(generate::PadConformM(design.pads))}});
  tinyxml2::XMLElement* base = generate::AddBase(plan, AddElement(mujoco, "worldbody"));
  for (const generate::Leg& leg : plan.legs) generate::AddLeg(plan, leg, base);
  tinyxml2::XMLElement* actuator = generate::AddActuators(plan, mujoco);
  if (design.tail)
    AddTail(*design.tail, {plan.prefix, -design.body.length_m / 2, 0.0, plan.base_z_m}, defaults,
            base, actuator);
  if (design.body.spine) {  // last: a tail behind the joint moves to the hind half
    const BodyDesign& b = design.body;
    AddSpine(*b.spine,
             {plan.prefix, b.length_m, b.width_m, b.height_m, b.mass_kg, b.hip_x_m, -b.hip_x_m,
              plan.palette.servo},
             defaults, base, actuator);
  }
  return PrintMjcf(doc);
}

}  // namespace climbsim::sim
