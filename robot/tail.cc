#include "robot/tail.h"

#include <cmath>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "robot/mjcf_dom.h"
#include "robot/servos.h"

namespace climbsim::sim {
namespace {

// The tip's friction: a PTFE bead slides (0.1, PTFE on painted wood or glass), an elastomer
// foot holds (1.0, as the pads' polymer). Torsional and rolling as the robot's other geoms.
const char* TipFriction(const std::string& tip) {
  return tip == "pad" ? "1.0 0.005 0.0001" : "0.1 0.005 0.0001";
}

const ServoModel& NeedServo(const TailDesign& tail) {
  const ServoModel* s = FindServo(tail.servo);
  if (s == nullptr) {
    throw std::invalid_argument("robot.tail.servo: no servo '" + tail.servo +
                                "' in the catalogue (" + ServoNames() + ")");
  }
  return *s;
}

// The tail's default classes: its geoms (robot collision bits) and its servos (the catalogue
// model, servos.h: kp, force limit = stall torque, damping, armature).
void AddTailDefaults(const ServoModel& servo, const std::string& prefix,
                     tinyxml2::XMLElement* defaults) {
  tinyxml2::XMLElement* geom_class = AddElement(defaults, "default", {{"class", prefix + "_tail"}});
  AddElement(
      geom_class, "geom",
      {{"contype", "2"}, {"conaffinity", "1"}, {"condim", "3"}, {"rgba", "0.35 0.3 0.25 1"}});
  tinyxml2::XMLElement* servo_class =
      AddElement(defaults, "default", {{"class", prefix + "_tail_servo"}});
  AddElement(servo_class, "joint",
             {{"damping", MjcfNumber(servo.damping_nms_per_rad)},
              {"armature", MjcfNumber(servo.armature_kgm2)}});
  AddElement(servo_class, "position",
             {{"kp", MjcfNumber(servo.kp_nm_per_rad)},
              {"forcelimited", "true"},
              {"forcerange", MjcfNumbers({-servo.stall_torque_nm, servo.stall_torque_nm})}});
  AddElement(
      servo_class, "geom",
      {{"type", "box"},
       {"size", MjcfNumbers({servo.case_half_m[0], servo.case_half_m[1], servo.case_half_m[2]})},
       {"mass", MjcfNumber(servo.mass_kg)},
       {"rgba", "0.15 0.15 0.18 1"}});
}

// A servo: its case (a box of the catalogue's mass, centred on the axis) in `body`, and its
// position actuator over `range` (joint limits = control range).
void AddServo(const std::string& prefix, const std::string& name, double lo, double hi,
              tinyxml2::XMLElement* case_body, double case_x_m, double case_z_m,
              tinyxml2::XMLElement* actuator) {
  AddElement(case_body, "geom",
             {{"name", name + "_servo"},
              {"class", prefix + "_tail_servo"},
              {"pos", MjcfNumbers({case_x_m, 0, case_z_m})}});
  AddElement(actuator, "position",
             {{"name", name},
              {"class", prefix + "_tail_servo"},
              {"joint", name},
              {"ctrlrange", MjcfNumbers({lo, hi})}});
}

// An adhesive tip: the body tail_pad at the rod's end (x, z), on a sleeve that slides along
// x (tail_slide, TailDesign::slide_stiffness_n_per_m) and pitch and roll hinges with
// the feet's ankle springs (so its face lies flat on the surface whatever the rod's angle),
// its face tip_radius_m below the ankle (where a ball tip's lowest point would be, so the
// droop and rest_gap_m keep their meaning) and parallel to the base's xy plane in qpos0. Its
// one box is the geom tail_tip: the adhesion model's pad (sim/adhesion_effect.h). Friction
// 1.0 as the feet's pads.
void AddAdhesiveTip(const TailDesign& tail, const std::string& prefix, double x_m, double z_m,
                    tinyxml2::XMLElement* body) {
  constexpr double kThickness_m = 0.002;
  tinyxml2::XMLElement* pad =
      AddElement(body, "body", {{"name", "tail_pad"}, {"pos", MjcfNumbers({x_m, 0, z_m})}});
  // The sleeve: a slide along the body's axis (x) with its spring and a light damper.
  AddElement(pad, "joint",
             {{"name", "tail_slide"},
              {"type", "slide"},
              {"axis", "1 0 0"},
              {"stiffness", MjcfNumber(tail.slide_stiffness_n_per_m)},
              {"damping", MjcfNumber(tail.slide_stiffness_n_per_m * 0.01)},
              {"springref", "0"},
              {"range", MjcfNumbers({-tail.slide_travel_m, tail.slide_travel_m})}});
  for (const char* axis : {"pitch", "roll"}) {
    AddElement(pad, "joint",
               {{"name", std::string("tail_ankle_") + axis},
                {"axis", std::strcmp(axis, "pitch") == 0 ? "0 1 0" : "1 0 0"},
                {"stiffness", "0.02"},
                {"damping", "0.0002"},
                {"springref", "0"},
                {"range", "-0.5 0.5"}});
  }
  AddElement(pad, "site", {{"name", "tail_tip"}, {"pos", "0 0 0"}});
  const double half = tail.pad_size_m / 2;
  AddElement(pad, "geom",
             {{"name", "tail_tip"},
              {"class", prefix + "_tail"},
              {"type", "box"},
              {"pos", MjcfNumbers({0, 0, -tail.tip_radius_m + kThickness_m / 2})},
              {"size", MjcfNumbers({half, half, kThickness_m / 2})},
              {"mass", MjcfNumber(tail.tip_mass_kg)},
              {"priority", "1"},
              {"friction", "1 0.005 0.0001"},
              {"solref", "0.015 1"},
              {"solimp", "0.9 0.95 0.001"}});
}

// The rod's segments from the pitch body outwards (each a body with a spring hinge after the
// first), then the tip's ball and site at the last segment's end.
void AddRod(const TailDesign& tail, const std::string& prefix, double droop_rad,
            tinyxml2::XMLElement* body) {
  const double seg = tail.length_m / tail.segments;
  const double dx = -seg * std::cos(droop_rad), dz = -seg * std::sin(droop_rad);
  for (int k = 1; k <= tail.segments; ++k) {
    if (k > 1) {
      const std::string name = "tail_seg" + std::to_string(k);
      body = AddElement(body, "body", {{"name", name}, {"pos", MjcfNumbers({dx, 0, dz})}});
      // A music-wire torsion spring; its damping a hundredth of its stiffness (a 10 ms decay).
      AddElement(body, "joint",
                 {{"name", name},
                  {"axis", "0 -1 0"},
                  {"stiffness", MjcfNumber(tail.segment_stiffness_nm_per_rad)},
                  {"damping", MjcfNumber(tail.segment_stiffness_nm_per_rad * 0.01)},
                  {"springref", "0"},
                  {"range", "-0.5 0.5"}});
    }
    AddElement(body, "geom",
               {{"name", "tail_rod" + std::to_string(k)},
                {"class", prefix + "_tail"},
                {"type", "capsule"},
                {"fromto", MjcfNumbers({0, 0, 0, dx, 0, dz})},
                {"size", MjcfNumber(tail.rod_radius_m)},
                {"mass", MjcfNumber(tail.mass_kg / tail.segments)}});
  }
  if (tail.tip == "adhesive") {
    AddAdhesiveTip(tail, prefix, dx, dz, body);
    return;
  }
  AddElement(body, "geom",
             {{"name", "tail_tip"},
              {"class", prefix + "_tail"},
              {"type", "sphere"},
              {"pos", MjcfNumbers({dx, 0, dz})},
              {"size", MjcfNumber(tail.tip_radius_m)},
              {"mass", MjcfNumber(tail.tip_mass_kg)},
              {"priority", "1"},
              {"friction", TipFriction(tail.tip)}});
  AddElement(body, "site", {{"name", "tail_tip"}, {"pos", MjcfNumbers({dx, 0, dz})}});
}

double Number(const char* text, int index, const std::string& what) {
  std::istringstream in(text != nullptr ? text : "");
  double v = 0.0;
  for (int i = 0; i <= index; ++i) {
    if (!(in >> v)) throw std::invalid_argument("robot file: cannot read " + what);
  }
  return v;
}

}  // namespace

double TailNeutralDroopRad(const TailDesign& tail, const TailMount& mount) {
  const double drop_m = mount.base_height_m + mount.mount_z_m - tail.tip_radius_m - tail.rest_gap_m;
  if (drop_m <= 0.0) {
    throw std::invalid_argument("robot.tail.rest_gap_m: the tip would stand above the pitch axis");
  }
  if (drop_m >= tail.length_m) {
    throw std::invalid_argument("robot.tail.length_m: " + MjcfNumber(tail.length_m) +
                                " m cannot reach the surface " + MjcfNumber(drop_m) +
                                " m below the pitch axis; make it longer");
  }
  return std::asin(drop_m / tail.length_m);
}

double TailMassKg(const TailDesign& tail) {
  return NeedServo(tail).mass_kg * (tail.yaw ? 2 : 1) + tail.mass_kg + tail.tip_mass_kg;
}

void AddTail(const TailDesign& tail, const TailMount& mount, tinyxml2::XMLElement* defaults,
             tinyxml2::XMLElement* base, tinyxml2::XMLElement* actuator) {
  const ServoModel& servo = NeedServo(tail);
  const double droop = TailNeutralDroopRad(tail, mount);
  AddTailDefaults(servo, mount.prefix, defaults);
  const double hx = servo.case_half_m[0];
  double axis_x = mount.rear_x_m - hx;  // the pitch axis at the centre of its servo's case
  tinyxml2::XMLElement* carrier = base;
  if (tail.yaw) {
    // The yaw servo on the body, the pitch servo on its horn one case further back.
    AddServo(mount.prefix, "tail_yaw", -0.5, 0.5, base, axis_x, mount.mount_z_m, actuator);
    carrier = AddElement(
        base, "body", {{"name", "tail_yaw"}, {"pos", MjcfNumbers({axis_x, 0, mount.mount_z_m})}});
    AddElement(carrier, "joint",
               {{"name", "tail_yaw"},
                {"class", mount.prefix + "_tail_servo"},
                {"axis", "0 0 1"},
                {"range", "-0.5 0.5"}});
    axis_x = -2 * hx;
  }
  const double axis_z = tail.yaw ? 0.0 : mount.mount_z_m;
  AddServo(mount.prefix, "tail_pitch", -tail.range_up_rad, tail.range_down_rad, carrier, axis_x,
           axis_z, actuator);
  tinyxml2::XMLElement* pitch =
      AddElement(carrier, "body", {{"name", "tail"}, {"pos", MjcfNumbers({axis_x, 0, axis_z})}});
  AddElement(pitch, "joint",
             {{"name", "tail_pitch"},
              {"class", mount.prefix + "_tail_servo"},
              {"axis", "0 -1 0"},
              {"range", MjcfNumbers({-tail.range_up_rad, tail.range_down_rad})}});
  AddRod(tail, mount.prefix, droop, pitch);
}

std::string AddTailToRobotFile(const TailDesign& tail, const std::string& robot_xml) {
  tinyxml2::XMLDocument doc;
  if (doc.Parse(robot_xml.c_str()) != tinyxml2::XML_SUCCESS) {
    throw std::invalid_argument(std::string("robot file: ") + doc.ErrorStr());
  }
  tinyxml2::XMLElement* root = doc.FirstChildElement("mujoco");
  tinyxml2::XMLElement* base = root ? FindNamed(root, "body", "base") : nullptr;
  tinyxml2::XMLElement* plate = base ? FindNamed(base, "geom", "base") : nullptr;
  tinyxml2::XMLElement* actuator = root ? root->FirstChildElement("actuator") : nullptr;
  if (plate == nullptr || actuator == nullptr || base->Attribute("childclass") == nullptr) {
    throw std::invalid_argument(
        "robot file: needs a body 'base' with a childclass, its geom 'base' and <actuator>");
  }
  TailMount mount;
  mount.prefix = base->Attribute("childclass");
  mount.rear_x_m = -Number(plate->Attribute("size"), 0, "the base geom's size");
  mount.base_height_m = Number(base->Attribute("pos"), 2, "the base body's pos");
  tinyxml2::XMLElement* defaults = nullptr;
  for (tinyxml2::XMLElement* d = root->FirstChildElement("default"); d && !defaults;
       d = d->NextSiblingElement("default")) {
    for (tinyxml2::XMLElement* c = d->FirstChildElement("default"); c;
         c = c->NextSiblingElement("default")) {
      if (const char* n = c->Attribute("class"); n && mount.prefix == n) defaults = c;
    }
  }
  if (defaults == nullptr) {
    throw std::invalid_argument("robot file: no default class '" + mount.prefix + "'");
  }
  AddTail(tail, mount, defaults, base, actuator);
  tinyxml2::XMLPrinter printer;
  doc.Print(&printer);
  return printer.CStr();
}

}  // namespace climbsim::sim
