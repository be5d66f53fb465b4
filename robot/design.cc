#include "robot/design.h"

#include <stdexcept>

namespace climbsim::sim {

// SCAFFOLD: replaced by the generator's engineer.
std::vector<std::string> PresetNames() {
  return {"gecko", "gecko_active", "gecko_ankle", "spider", "spider_active", "spider_ankle"};
}
RobotDesign PresetDesign(const std::string& name) {
  RobotDesign d;
  d.preset = name;
  return d;
}
std::string GenerateRobotMjcf(const RobotDesign&) {
  throw std::logic_error("robot designs: not built yet");
}

}  // namespace climbsim::sim
