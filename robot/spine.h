// The spine: an optional yaw joint splitting the body plate into a front half (the body `base`,
// which keeps the free joint, the head and the front legs) and a hind half (body `base_hind`,
// carrying the hind legs), so the trunk bends sideways as a gecko's does in a trot. The design
// keys (SpineDesign, scenario robot.body.spine) and the MJCF it makes of a generated robot
// (AddSpine). The CPG drives it (cpg.spine, sim/cpg_effect.h).
#ifndef CLIMBSIM_ROBOT_SPINE_H_
#define CLIMBSIM_ROBOT_SPINE_H_

#include <tinyxml2.h>

#include <string>

#include "keys/keys.h"

namespace climbsim::sim {

struct SpineDesign {
  std::string servo = "hs35hd";
  double range_rad = 0.5;
  double joint_x_m = 0.0;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"servo", "", "the spine's yaw servo (catalogue name), on the hind half at the joint"},
             &servo);
    a->Visit({"range_rad", "rad",
              "spine yaw travel, +- this; 0.1-1: a gecko's trunk bends about 0.5 rad in a trot, "
              "and past 1 rad the hind hips swing into the front legs",
              Range::Closed(0.1, 1.0)},
             &range_rad);
    a->Visit({"joint_x_m", "m",
              "base x of the yaw axis (0: mid-plate); between the front and hind hips, where the "
              "servo's case fits between the hip servos",
              Range::Closed(-0.1, 0.1)},
             &joint_x_m);
  }
};

// What AddSpine needs of the body: the plate it splits and the robot's class prefix.
struct SpineMount {
  std::string prefix;          // class prefix of the robot ("gecko")
  double length_m = 0.0;       // the plate along x, centred on the base origin
  double width_m = 0.0;
  double height_m = 0.0;
  double mass_kg = 0.0;        // the plate's mass, shared by the halves by their lengths
  double front_hip_x_m = 0.0;  // the hips the joint must lie between
  double hind_hip_x_m = 0.0;
  const char* servo_rgba = "";
};

// Splits the plate geom "base" under `base` into a front half (geom "base") and a hind half
// (geom "base_hind" in a new body base_hind, joined by the hinge spine_yaw about z) and moves
// every body and geom behind the joint (the hind legs, their servo cases, a tail) into
// base_hind. Adds the servo's default class under `defaults`, its case (geom spine_servo) and
// the position servo spine_yaw under `actuator`. Throws std::invalid_argument
// ("robot.body.spine.<key>: ...") for a spine that cannot be built.
void AddSpine(const SpineDesign& spine, const SpineMount& mount, tinyxml2::XMLElement* defaults,
              tinyxml2::XMLElement* base, tinyxml2::XMLElement* actuator);

}  // namespace climbsim::sim

#endif  // CLIMBSIM_ROBOT_SPINE_H_
