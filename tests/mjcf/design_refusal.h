// The refusal a robot design gets from the MJCF generator (shared by the tests that check a
// bad design is named by its key). In mjcf_test, not climbsim::testing: a unity build puts
// these files with ones whose `testing::` means GoogleTest's.
#ifndef CLIMBSIM_TESTS_MJCF_DESIGN_REFUSAL_H_
#define CLIMBSIM_TESTS_MJCF_DESIGN_REFUSAL_H_

#include <stdexcept>
#include <string>

#include "robot/design.h"

namespace climbsim::mjcf_test {

// GenerateRobotMjcf's invalid_argument message for `d`, or "" when the design is accepted.
inline std::string Refusal(const sim::RobotDesign& d) {
  try {
    sim::GenerateRobotMjcf(d);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace climbsim::mjcf_test

#endif  // CLIMBSIM_TESTS_MJCF_DESIGN_REFUSAL_H_
