#include "robot/compliance.h"

#include <stdexcept>

namespace climbsim::sim {

// SCAFFOLD: replaced by the compliance engineer.
void AddSeriesSpring(const SeriesSpring& spring, tinyxml2::XMLElement*) {
  if (spring.stiffness_nm_per_rad > 0) throw std::logic_error("robot.compliance: not built yet");
}

}  // namespace climbsim::sim
