// The base body and the legs of a generated robot. Servos on the legs: the yaw servo case on
// the body beside the hip, the pitch servo as the coxa, the knee servo on the femur at the
// knee, a tilt servo on the tibia. Servos on the body: a pack of three per leg on the
// platform (a tilt servo on top), cables to the joints, capsule links.
#include <cmath>
#include <string>

#include "robot/compliance.h"
#include "robot/generate.h"
#include "robot/mjcf_dom.h"

namespace climbsim::sim::generate {

namespace {

using tinyxml2::XMLElement;

std::string CaseSize(const ServoModel& s) {
  return MjcfNumbers({s.case_half_m[0], s.case_half_m[1], s.case_half_m[2]});
}

// A servo case as a box geom; mass_kg: the servo's, or more where it also is a link.
void AddCase(XMLElement* body, const std::string& name, const ServoModel& s, const char* rgba,
             double x, double y, double z, double mass_kg = 0) {
  AddElement(body, "geom",
             {{"name", name},
              {"type", "box"},
              {"size", CaseSize(s)},
              {"mass", MjcfNumber(mass_kg > 0 ? mass_kg : s.mass_kg)},
              {"rgba", rgba},
              {"pos", MjcfNumbers({x, y, z})}});
}

// The drawing's 10 um grid, on which a part placed along a segment is written.
double OnGrid(double v) { return std::round(v * 1e5) / 1e5; }

// <leg>_<joint> of class <robot>_<cls> (the joint's own name by default).
XMLElement* AddJoint(const Plan& p, XMLElement* body, const Leg& leg, const std::string& joint,
                     const std::string& axis, const std::string& cls = "") {
  return AddElement(body, "joint",
                    {{"name", leg.name + "_" + joint},
                     {"class", p.prefix + "_" + (cls.empty() ? joint : cls)},
                     {"axis", axis}});
}

void AddBodyServos(const Plan& p, XMLElement* base) {
  const RobotDesign& d = *p.design;
  for (const Leg& leg : p.legs) {
    if (d.servos.placement == "legs") {
      AddCase(base, leg.name + "_yaw_servo", *p.hip_yaw, p.palette.servo, leg.hip_x_m,
              leg.side * (d.body.hip_y_m - d.servos.yaw_case_inset_m), 0);
      continue;
    }
    const double half = d.servos.pack_side_m / 2;
    const double x = leg.hip_x_m == 0 ? 0 : std::copysign(d.servos.pack_x_m, leg.hip_x_m);
    const double y = leg.side * d.servos.pack_y_m, z = d.body.height_m / 2 + half;
    AddElement(base, "geom",
               {{"name", leg.name + "_servos"},
                {"type", "box"},
                {"size", MjcfNumbers({half, half, half})},
                {"mass", MjcfNumber(p.hip_yaw->mass_kg + p.hip_pitch->mass_kg + p.knee->mass_kg)},
                {"rgba", p.palette.servo},
                {"pos", MjcfNumbers({x, y, z})}});
    if (p.tilt)
      AddCase(base, leg.name + "_tilt_servo", *p.tilt, p.palette.servo, x, y,
              z + half + p.tilt->case_half_m[2]);
  }
}

void AddFoot(const Plan& p, const Leg& leg, XMLElement* pad) {
  const RobotDesign& d = *p.design;
  if (p.tilt) AddJoint(p, pad, leg, "ankle_tilt", "0 1 0");
  AddJoint(p, pad, leg, "ankle_pitch", "0 1 0", "ankle");
  AddJoint(p, pad, leg, "ankle_roll", "1 0 0", "ankle");
  AddJoint(p, pad, leg, "ankle_yaw", "0 0 1", "ankle");
  AddElement(pad, "site", {{"name", leg.name + "_ankle"}, {"pos", "0 0 0"}});
  const double post = d.feet.post_m, thick = d.pads.thickness_m;
  AddElement(pad, "geom",
             {{"name", leg.name + "_post"},
              {"class", p.prefix + "_post"},
              {"fromto", MjcfNumbers({0, 0, 0, 0, 0, -(post - thick)})}});
  AddElement(pad, "geom",
             {{"name", leg.name + "_pad"},
              {"class", p.prefix + "_pad"},
              {"pos", MjcfNumbers({0, 0, -(post - thick / 2)})}});
  AddElement(pad, "site",
             {{"name", leg.name + "_pad_face"},
              {"class", p.prefix + "_pad"},
              {"pos", MjcfNumbers({0, 0, -post})}});
}

void AddTibia(const Plan& p, const Leg& leg, XMLElement* femur) {
  const RobotDesign& d = *p.design;
  const LegsDesign& l = d.legs;
  XMLElement* tibia = AddElement(femur, "body",
                                 {{"name", leg.name + "_tibia"},
                                  {"pos", MjcfNumbers({0, leg.side * l.femur_m, l.femur_rise_m})}});
  AddSeriesSpring(d.compliance.knee,
                  AddJoint(p, tibia, leg, "knee", MjcfNumbers({-leg.side, 0, 0})));
  const double ay = -leg.side * l.tibia_inset_m, az = -l.tibia_m;
  AddElement(tibia, "geom",
             {{"name", leg.name + "_tibia"},
              {"class", p.prefix + "_link"},
              {"fromto", MjcfNumbers({0, 0, 0, 0, ay, az})},
              {"size", MjcfNumber(l.tibia_radius_m)},
              {"mass", MjcfNumber(l.tibia_mass_kg)}});
  if (p.tilt && d.servos.placement == "legs") {
    const double at = d.ankles.tilt_servo_at;
    AddCase(tibia, leg.name + "_tilt_servo", *p.tilt, p.palette.servo, 0, OnGrid(at * ay),
            OnGrid(at * az));
  }
  XMLElement* pad =
      AddElement(tibia, "body", {{"name", leg.name + "_pad"}, {"pos", MjcfNumbers({0, ay, az})}});
  if (leg.yaw_rad != 0) pad->SetAttribute("euler", MjcfNumbers({0, 0, -leg.yaw_rad}).c_str());
  AddFoot(p, leg, pad);
}

}  // namespace

XMLElement* AddBase(const Plan& p, XMLElement* worldbody) {
  const BodyDesign& b = p.design->body;
  const LegsDesign& l = p.design->legs;
  const std::string post = MjcfNumber(p.design->feet.post_m);
  AddComment(worldbody,
             {"Base height: the ankle " + MjcfNumber(l.tibia_m - l.femur_rise_m) +
                  " below the hip axes (legs.tibia_m - legs.femur_rise_m),",
              "the pad face " + post + " below the ankle (feet.post_m), and a 0.5 mm gap:",
              MjcfNumber(l.tibia_m) + " - " + MjcfNumber(l.femur_rise_m) + " + " + post +
                  " + 0.0005 = " + MjcfNumber(p.base_z_m) + "."});
  XMLElement* base = AddElement(
      worldbody, "body",
      {{"name", "base"}, {"pos", MjcfNumbers({0, 0, p.base_z_m})}, {"childclass", p.prefix}});
  AddElement(base, "freejoint", {{"name", "root"}});
  AddElement(base, "geom",
             {{"name", "base"},
              {"type", "box"},
              {"size", MjcfNumbers({b.length_m / 2, b.width_m / 2, b.height_m / 2})},
              {"mass", MjcfNumber(b.mass_kg)}});
  AddElement(base, "geom",
             {{"name", "head"},
              {"type", "sphere"},
              {"size", MjcfNumber(b.head_radius_m)},
              {"pos", MjcfNumbers({b.length_m / 2 + b.head_ahead_m, 0, b.head_z_m})},
              {"mass", MjcfNumber(b.head_mass_kg)},
              {"contype", "0"},
              {"conaffinity", "0"},
              {"rgba", p.palette.body}});
  AddBodyServos(p, base);
  AddElement(base, "site", {{"name", "imu"}, {"pos", "0 0 0"}});
  return base;
}

void AddLeg(const Plan& p, const Leg& leg, XMLElement* base) {
  const RobotDesign& d = *p.design;
  const LegsDesign& l = d.legs;
  const char* place = leg.hip_x_m > 0 ? "front" : leg.hip_x_m < 0 ? "hind" : "middle";
  AddComment(base, {"===================== " + leg.name + ": " +
                    (leg.side > 0 ? "left " : "right ") + place + " ====================="});
  XMLElement* coxa =
      AddElement(base, "body",
                 {{"name", leg.name + "_coxa"},
                  {"pos", MjcfNumbers({leg.hip_x_m, leg.side * d.body.hip_y_m, 0})}});
  if (leg.yaw_rad != 0) coxa->SetAttribute("euler", MjcfNumbers({0, 0, leg.yaw_rad}).c_str());
  AddSeriesSpring(d.compliance.hip_yaw,
                  AddJoint(p, coxa, leg, "hip_yaw", MjcfNumbers({0, 0, -leg.side})));
  const bool on_legs = d.servos.placement == "legs";
  if (on_legs) {
    AddCase(coxa, leg.name + "_coxa", *p.hip_pitch, p.palette.servo, 0, leg.side * l.coxa_m / 2, 0,
            l.coxa_mass_kg);
  } else {
    AddElement(coxa, "geom",
               {{"name", leg.name + "_coxa"},
                {"class", p.prefix + "_link"},
                {"fromto", MjcfNumbers({0, 0, 0, 0, leg.side * l.coxa_m, 0})},
                {"size", MjcfNumber(l.coxa_radius_m)},
                {"mass", MjcfNumber(l.coxa_mass_kg)}});
  }
  XMLElement* femur = AddElement(
      coxa, "body",
      {{"name", leg.name + "_femur"}, {"pos", MjcfNumbers({0, leg.side * l.coxa_m, 0})}});
  AddSeriesSpring(d.compliance.hip_pitch,
                  AddJoint(p, femur, leg, "hip_pitch", MjcfNumbers({leg.side, 0, 0})));
  AddElement(femur, "geom",
             {{"name", leg.name + "_femur"},
              {"class", p.prefix + "_link"},
              {"fromto", MjcfNumbers({0, 0, 0, 0, leg.side * l.femur_m, l.femur_rise_m})},
              {"size", MjcfNumber(l.femur_radius_m)},
              {"mass", MjcfNumber(l.femur_mass_kg)}});
  if (on_legs)
    AddCase(femur, leg.name + "_knee_servo", *p.knee, p.palette.servo, 0,
            leg.side * (l.femur_m - p.knee->case_half_m[1]), l.femur_rise_m);
  AddTibia(p, leg, femur);
}

}  // namespace climbsim::sim::generate
