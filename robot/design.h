// A robot described by parameters (scenario key `robot`): a preset (today's gecko and spider
// and their variants) changed by a few keys, from which the MJCF robot file is generated as a
// DOM (generate.cc), per the model contract of mjcf/README.md. The six files in mjcf/ are the
// presets' generated text.
// SCAFFOLD: the generator's engineer owns this file and fills the parts (body, legs, pads,
// feet, ankles, servos); tail.h and compliance.h belong to their own engineers.
#ifndef CLIMBSIM_ROBOT_DESIGN_H_
#define CLIMBSIM_ROBOT_DESIGN_H_

#include <optional>
#include <string>
#include <vector>

#include "keys/keys.h"
#include "robot/compliance.h"
#include "robot/tail.h"

namespace climbsim::sim {

struct RobotDesign {
  std::string preset = "gecko";
  // ... body, legs, pads, feet, ankles, servos: the generator's engineer adds them ...
  std::optional<TailDesign> tail;
  ComplianceDesign compliance;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"preset", "", "the design the other keys change: gecko, gecko_active, gecko_ankle, "
                            "spider, spider_active, spider_ankle"},
             &preset);
    a->Visit({"tail", "", "a tail behind the body; absent: none"}, &tail);
    a->Visit({"compliance", "", "series springs between servos and links"}, &compliance);
  }
};

// gecko, gecko_active, gecko_ankle, spider, spider_active, spider_ankle.
std::vector<std::string> PresetNames();
// The preset of this name; throws std::invalid_argument naming the presets for another.
RobotDesign PresetDesign(const std::string& name);
// The robot file of a design: a complete <mujoco> document (what mjcf/<preset>.xml holds for
// a preset). Throws std::invalid_argument (key path and reason) for a design it cannot build.
std::string GenerateRobotMjcf(const RobotDesign& design);

}  // namespace climbsim::sim

#endif  // CLIMBSIM_ROBOT_DESIGN_H_
