// The robots the model contract tests (contract_test.cc, dynamics_test.cc) run on, defined once
// per test executable: mjcf_tests runs them on the files in mjcf/ (robots_files.cc),
// design_tests on generated models of designs that differ from the presets (design_robots.cc).
#ifndef CLIMBSIM_TESTS_MJCF_ROBOTS_UNDER_TEST_H_
#define CLIMBSIM_TESTS_MJCF_ROBOTS_UNDER_TEST_H_

#include <ostream>
#include <string>
#include <vector>

namespace climbsim::mjcf_test {

// The documented figures of a robot (mjcf/README.md).
struct RobotSpec {
  std::string robot;
  std::vector<std::string> legs;
  double mass_min_kg, mass_max_kg;     // total mass range
  double pad_side_m, pad_thickness_m;  // pad box, full sizes
  double pad_mass_min_kg, pad_mass_max_kg;
  double stall_torque_nm;      // servo stall torque = forcerange
  double no_load_speed_rad_s;  // servo no-load speed (60 deg per t_60)
  // The ankle option's tilt servo (0: the robot has none).
  double tilt_stall_torque_nm = 0;
  double tilt_no_load_speed_rad_s = 0;
  // Servos outside the legs (a spine's spine_yaw): their count.
  int body_actuators = 0;
};
// Names the case in test listings (gtest would print the struct's bytes).
inline void PrintTo(const RobotSpec& spec, std::ostream* os) { *os << spec.robot; }

struct HoldCase {
  std::string robot;
  std::string scene;
  std::vector<std::string> stance;  // legs welded to the surface (the gait's stance set)
  double max_torque_ratio;          // max |servo torque| / stall torque allowed
};
inline void PrintTo(const HoldCase& c, std::ostream* os) { *os << c.robot << " on " << c.scene; }

// MjcfContract's robots and figures.
std::vector<RobotSpec> ContractRobots();
// MjcfStanding, MjcfStatics: robots standing on the floor.
std::vector<std::string> StandingRobots();
// MjcfFriction: robots whose pads hold them on the 30 deg incline within its creep bound.
std::vector<std::string> InclineRobots();
// MjcfHold: robots hanging on their stance legs.
std::vector<HoldCase> HoldCases();

}  // namespace climbsim::mjcf_test

#endif  // CLIMBSIM_TESTS_MJCF_ROBOTS_UNDER_TEST_H_
