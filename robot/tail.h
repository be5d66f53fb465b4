// The tail: a rod behind the body on a pitch servo at the base (yaw optional), whose tip
// touches the surface. The design keys (TailDesign, scenario robot.tail) and the MJCF it adds
// to a generated robot (AddTail). The tail reflex that presses it lives in reflex/.
// SCAFFOLD: the tail's engineer owns this file and tail.cc and may change everything here.
#ifndef CLIMBSIM_ROBOT_TAIL_H_
#define CLIMBSIM_ROBOT_TAIL_H_

#include <tinyxml2.h>

#include <string>

#include "keys/keys.h"

namespace climbsim::sim {

struct TailDesign {
  double length_m = 0.08;
  int segments = 1;
  double mass_kg = 0.003;
  std::string servo = "hs35hd";
  bool yaw = false;
  std::string tip = "skid";

  template <class A>
  void Serialize(A* a) {
    a->Visit({"length_m", "m", "from the base servo's axis to the tip", Range::Closed(0.02, 0.3)},
             &length_m);
    a->Visit({"segments", "", "rigid segments, joined by passive springs", Range::Closed(1, 4)},
             &segments);
    a->Visit({"mass_kg", "kg", "rod and tip, without the servo", Range::Closed(0.0005, 0.05)},
             &mass_kg);
    a->Visit({"servo", "", "the base pitch servo (catalogue name)"}, &servo);
    a->Visit({"yaw", "", "a second base servo turns the tail sideways"}, &yaw);
    a->Choice({"tip", "", "skid: a low-friction ball; pad: a small sticky pad"}, &tip,
              {"skid", "pad"});
  }
};

// Where the generator mounts the tail: the body's rear end in the base frame, and how high
// the base origin stands above the surface in qpos0 (so the tip can be placed on it).
struct TailMount {
  std::string prefix;       // class and name prefix of the robot ("gecko")
  double rear_x_m = 0.0;    // base x of the mount (the body's rear edge)
  double mount_z_m = 0.0;   // base z of the pitch axis
  double base_height_m = 0.0;  // base origin above the surface (the plane z = 0) in qpos0
};

// Adds the tail's bodies, joints and geoms under `base` (the base body element), its default
// classes under `defaults` (the robot's top default class) and its servos under `actuator`.
// Names: tail_pitch (joint and servo), tail_yaw when yaw, tail_tip (geom), tail_tip (site).
void AddTail(const TailDesign& tail, const TailMount& mount, tinyxml2::XMLElement* defaults,
             tinyxml2::XMLElement* base, tinyxml2::XMLElement* actuator);

}  // namespace climbsim::sim

#endif  // CLIMBSIM_ROBOT_TAIL_H_
