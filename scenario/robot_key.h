// The scenario's `robot` key has two shapes: a name (a preset of robot/design.h, or a path to
// an MJCF robot file) or a map describing a design, a preset changed by a few keys:
//   robot: gecko
//   robot: {preset: gecko, legs: {femur_m: 0.072}, tail: {length_m: 0.1}}
// RobotKey is the one Visit of both shapes; the archives of archive.h read, write and list it
// (robot_key.cc). Internal to scenario/.
#ifndef CLIMBSIM_SCENARIO_ROBOT_KEY_H_
#define CLIMBSIM_SCENARIO_ROBOT_KEY_H_

#include <optional>
#include <string>

#include "robot/design.h"

namespace climbsim::sim {

// What a name names: a path holds a '/' or ends in .xml; anything else is a preset.
bool IsRobotPath(const std::string& name);

// Points at Scenario::robot (the name; a design's preset) and Scenario::robot_design (set
// when the file gives a map).
struct RobotKey {
  std::string* name;
  std::optional<RobotDesign>* design;
};

// The preset whose keys `climbsim keys` lists as the design keys' defaults.
inline constexpr const char* kDocumentedPreset = "gecko";

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SCENARIO_ROBOT_KEY_H_
