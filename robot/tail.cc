#include "robot/tail.h"

#include <stdexcept>

namespace climbsim::sim {

// SCAFFOLD: replaced by the tail's engineer.
void AddTail(const TailDesign&, const TailMount&, tinyxml2::XMLElement*, tinyxml2::XMLElement*,
             tinyxml2::XMLElement*) {
  throw std::logic_error("robot.tail: not built yet");
}

}  // namespace climbsim::sim
