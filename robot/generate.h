// The generator's parts (internal to climbsim::robot): what GenerateRobotMjcf resolves once
// from a design (servos, legs, colours) and the functions that add the body, the legs and the
// actuators to the DOM.
#ifndef CLIMBSIM_ROBOT_GENERATE_H_
#define CLIMBSIM_ROBOT_GENERATE_H_

#include <tinyxml2.h>

#include <string>
#include <vector>

#include "robot/design.h"
#include "robot/servos.h"

namespace climbsim::sim::generate {

// Pad faces stand this far above the plane z = 0 in qpos0 (mjcf/README.md, "Frames").
inline constexpr double kPadGap_m = 0.0005;
// Neighbouring pads swung towards each other by this much hip yaw (the gait's largest swing,
// mjcf/README.md) must not meet.
inline constexpr double kGaitYaw_rad = 0.4;

struct Leg {
  std::string name;  // "LF", "L1"
  double hip_x_m;    // base x of the hip-yaw axis
  double side;       // +1 left, -1 right
  double yaw_rad;    // coxa frame turned about z (splay); 0: none
};

// The robot's colours (rgba text); the gecko's and the spider's families differ.
struct Palette {
  const char* body;
  const char* link;
  const char* servo;
};

struct Plan {
  const RobotDesign* design;
  std::string prefix;  // class prefix: the preset's robot ("gecko", "spider")
  Palette palette;
  const ServoModel* hip_yaw;
  const ServoModel* hip_pitch;
  const ServoModel* knee;
  const ServoModel* tilt;  // nullptr without actuated ankles
  std::vector<Leg> legs;
  double base_z_m;  // base origin above the plane in qpos0
};

// Resolves servos and legs; throws std::invalid_argument ("robot.<key>: ...") for a design
// that cannot be built.
Plan MakePlan(const RobotDesign& design);
// Refuses what cannot be built: pads that overlap in qpos0 or meet at the gait's hip yaw, a
// post no longer than the pad is thick, a body plate at or below the pads, a joint range
// without 0 inside it.
void CheckGeometry(const Plan& plan);
// A pad's mass with its foam (pads.foam_m, 100 kg/m^3).
double PadMassKg(const PadsDesign& pads);

// <default>: the robot's classes; returns the robot's top class.
tinyxml2::XMLElement* AddDefaults(const Plan& plan, tinyxml2::XMLElement* mujoco);
// The base body (plate, head, servos on the body) and every leg under worldbody.
tinyxml2::XMLElement* AddBase(const Plan& plan, tinyxml2::XMLElement* worldbody);
void AddLeg(const Plan& plan, const Leg& leg, tinyxml2::XMLElement* base);
// <actuator>: one position servo per actuated joint, leg by leg; returns it.
tinyxml2::XMLElement* AddActuators(const Plan& plan, tinyxml2::XMLElement* mujoco);

}  // namespace climbsim::sim::generate

#endif  // CLIMBSIM_ROBOT_GENERATE_H_
