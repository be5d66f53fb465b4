// The tail: a rod behind the body on a pitch servo at the base (yaw optional), whose tip
// touches the surface. The design keys (TailDesign, scenario robot.tail) and the MJCF it adds
// to a generated robot (AddTail). The tail reflex that presses it lives in reflex/tail_reflex.h.
//
// Geometry: the pitch axis lies across the body (base y) at the body's rear edge; the rod runs
// backwards from it, drooping by the angle that puts the tip's lowest point `rest_gap_m` above
// the surface in qpos0 (the servo's neutral angle, computed: the designer gives the length).
// tail_pitch > 0 turns the tip into the surface. Collision bits as every robot geom
// (contype 2, conaffinity 1): the tail touches the scene, never the robot.
#ifndef CLIMBSIM_ROBOT_TAIL_H_
#define CLIMBSIM_ROBOT_TAIL_H_

#include <tinyxml2.h>

#include <string>

#include "keys/keys.h"

namespace climbsim::sim {

struct TailDesign {
  double length_m = 0.15;
  int segments = 1;
  double segment_stiffness_nm_per_rad = 0.05;
  double mass_kg = 0.0008;
  double rod_radius_m = 0.001;
  std::string servo = "hs35hd";
  bool yaw = false;
  std::string tip = "skid";
  double tip_radius_m = 0.003;
  double tip_mass_kg = 0.0003;
  double rest_gap_m = 0.0;
  double pad_size_m = 0.02;
  double slide_stiffness_n_per_m = 20.0;
  double slide_travel_m = 0.015;
  double range_up_rad = 0.6;
  double range_down_rad = 0.6;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"length_m", "m",
              "from the pitch servo's axis to the tip's centre; at least the base's height "
              "above the surface (the tip must reach it: gecko 0.055 m, spider 0.084 m), up to 0.3 "
              "m: a longer rod of a sub-gram weight bends like a whip",
              Range::Closed(0.06, 0.3)},
             &length_m);
    a->Visit({"segments", "",
              "rigid segments of equal length, joined by passive torsion springs (a rod of "
              "several pieces); 1: one rigid rod",
              Range::Closed(1, 4)},
             &segments);
    a->Visit(
        {"segment_stiffness_nm_per_rad", "N·m/rad",
         "segments > 1: each joint's torsion spring (a music-wire spring of 0.01 to 1 N·m/rad)",
         Range::Closed(0.005, 1.0)},
        &segment_stiffness_nm_per_rad);
    a->Visit(
        {"mass_kg", "kg", "the rod (a capsule of this mass; carbon tube of 2 mm: 0.5 g per 0.1 m)",
         Range::Closed(0.0002, 0.05)},
        &mass_kg);
    a->Visit({"rod_radius_m", "m", "the rod's radius (carbon tube 1 to 4 mm across)",
              Range::Closed(0.0005, 0.005)},
             &rod_radius_m);
    a->Visit({"servo", "", "the base pitch servo (and yaw servo), catalogue name"}, &servo);
    a->Visit({"yaw", "", "a second servo (the same model) turns the tail sideways"}, &yaw);
    a->Choice({"tip", "",
               "skid: a PTFE ball (friction 0.1) that slides up the wall behind the robot; pad: "
               "an elastomer foot (friction 1.0, not adhesive) that holds where it presses; "
               "adhesive: a square dry-adhesive pad on a two-hinge ankle (body tail_pad), "
               "bonded by the adhesion model as the feet are and engaged only while the tail "
               "reflex presses (a gecko's tail pad, Stickybot's and RiSE's tails)"},
              &tip, {"skid", "pad", "adhesive"});
    a->Visit({"tip_radius_m", "m",
              "the tip's ball radius (a 3 to 16 mm PTFE bead); adhesive: the ankle's centre "
              "to the pad's face",
              Range::Closed(0.0015, 0.008)},
             &tip_radius_m);
    a->Visit({"tip_mass_kg", "kg", "the tip's mass (adhesive: the pad with its backing)",
              Range::Closed(0.0, 0.01)},
             &tip_mass_kg);
    a->Visit({"pad_size_m", "m",
              "adhesive: the square pad's side (cast polymer pads are 10 to 60 mm; the feet's "
              "is 25 mm); a wider pad holds more twist, a heavier tail swings further",
              Range::Closed(0.01, 0.04)},
             &pad_size_m);
    a->Visit({"slide_stiffness_n_per_m", "N/m",
              "adhesive: the pad rides on a sleeve that slides along the body's axis on a soft "
              "spring (a linear guide): the pad holds the tail sideways and into the surface, "
              "while the climb it interrupts (the stance legs still stroke) pulls the sleeve, "
              "not the bond; a rigid tip fought the hind pads along the wall and tore with them",
              Range::Closed(1.0, 1000.0)},
             &slide_stiffness_n_per_m);
    a->Visit({"slide_travel_m", "m", "adhesive: the sleeve's travel each way (a 10-40 mm guide)",
              Range::Closed(0.002, 0.04)},
             &slide_travel_m);
    a->Visit({"rest_gap_m", "m",
              "the tip's lowest point above the surface in qpos0 (0: touching): a gap drags "
              "nothing, a tail on the surface catches a pitch at once",
              Range::Closed(0.0, 0.02)},
             &rest_gap_m);
    a->Visit({"range_up_rad", "rad",
              "the pitch servo's travel lifting the tip off the surface from its neutral angle "
              "(a hobby servo turns ±1.05 rad)",
              Range::Closed(0.05, 1.05)},
             &range_up_rad);
    a->Visit({"range_down_rad", "rad",
              "the pitch servo's travel turning the tip into the surface from its neutral "
              "angle: the reflex's press command stays inside it",
              Range::Closed(0.05, 1.05)},
             &range_down_rad);
  }
};

// Where the generator mounts the tail: the body's rear end in the base frame, and how high
// the base origin stands above the surface (the plane z = 0) in qpos0.
struct TailMount {
  std::string prefix;          // class and name prefix of the robot ("gecko")
  double rear_x_m = 0.0;       // base x of the mount (the body's rear edge)
  double mount_z_m = 0.0;      // base z of the pitch axis
  double base_height_m = 0.0;  // base origin above the surface in qpos0
};

// The rod's droop below the base's x axis in qpos0 (the servo's neutral angle), rad: the tip's
// lowest point at rest_gap_m above the surface. Throws std::invalid_argument (robot.tail.*)
// when the tail is too short to reach the surface.
double TailNeutralDroopRad(const TailDesign& tail, const TailMount& mount);
// The mass the tail adds: its servo(s), rod and tip, kg.
double TailMassKg(const TailDesign& tail);

// Adds the tail's bodies, joints and geoms under `base` (the base body element), its default
// classes under `defaults` (the robot's top default class) and its servos under `actuator`.
// Names: tail_pitch (joint and servo), tail_yaw when yaw, tail_tip (geom and site),
// tail_seg<k> (joints between segments); an adhesive tip is the body tail_pad (ankle hinges
// tail_ankle_pitch, tail_ankle_roll) whose one box is the geom tail_tip. Throws std::invalid_argument (robot.tail.<key>).
void AddTail(const TailDesign& tail, const TailMount& mount, tinyxml2::XMLElement* defaults,
             tinyxml2::XMLElement* base, tinyxml2::XMLElement* actuator);

// A robot file (the text of mjcf/<preset>.xml) with the tail added: the mount read from the
// file (base body's height, the "base" box's rear edge, the top default class's name).
std::string AddTailToRobotFile(const TailDesign& tail, const std::string& robot_xml);

}  // namespace climbsim::sim

#endif  // CLIMBSIM_ROBOT_TAIL_H_
