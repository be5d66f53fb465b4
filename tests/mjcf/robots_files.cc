// mjcf_tests runs the model contract on the files in mjcf/, with the figures mjcf/README.md
// documents for each robot.
#include <cmath>

#include "mjcf_test_util.h"
#include "robots_under_test.h"

namespace climbsim::mjcf_test {

const std::string* RobotText(const std::string&) { return nullptr; }

namespace {

const RobotSpec kGecko{"gecko", {"LF", "RF", "LH", "RH"}, 0.080, 0.150, 0.025, 0.002, 0.001, 0.005,
                       0.078,   (M_PI / 3) / 0.10};
const RobotSpec kSpider{"spider", {"L1", "L2", "L3", "R1", "R2", "R3"},
                        0.300,    0.420,
                        0.035,    0.003,
                        0.003,    0.015,
                        0.176,    (M_PI / 3) / 0.14};
// The same robots with active-release feet: the same contract.
RobotSpec Variant(RobotSpec spec, const std::string& name) {
  spec.robot = name;
  return spec;
}
// The options (README, "Actuated ankles"): gecko + 4 x 1.7 g ultra-micro servos (109.3 g),
// spider + 6 x 4.5 g sub-micro servos (381.2 g).
RobotSpec WithTilt(RobotSpec spec, const std::string& robot, double mass_min_kg, double mass_max_kg,
                   double stall_nm, double t60_s) {
  spec.robot = robot;
  spec.mass_min_kg = mass_min_kg;
  spec.mass_max_kg = mass_max_kg;
  spec.tilt_stall_torque_nm = stall_nm;
  spec.tilt_no_load_speed_rad_s = (M_PI / 3) / t60_s;
  return spec;
}

const std::vector<std::string> kGeckoTrot = {"LF", "RH"};
const std::vector<std::string> kSpiderTripod = {"L1", "R2", "L3"};

}  // namespace

std::vector<RobotSpec> ContractRobots() {
  return {kGecko,
          kSpider,
          Variant(kGecko, "gecko_active"),
          Variant(kSpider, "spider_active"),
          WithTilt(kGecko, "gecko_ankle", 0.108, 0.111, 0.0078, 0.06),
          WithTilt(kSpider, "spider_ankle", 0.378, 0.385, 0.078, 0.10)};
}

std::vector<std::string> StandingRobots() { return AllRobotNames(); }

std::vector<std::string> InclineRobots() { return AllRobotNames(); }

std::vector<HoldCase> HoldCases() {
  return {{"gecko", "wall", kGeckoTrot, 0.5},        {"gecko", "ceiling", kGeckoTrot, 0.5},
          {"gecko", "incline", kGeckoTrot, 0.5},     {"spider", "wall", kSpiderTripod, 0.6},
          {"spider", "ceiling", kSpiderTripod, 0.5}, {"spider", "incline", kSpiderTripod, 0.5}};
}

}  // namespace climbsim::mjcf_test
