// The servo catalogue: real hobby parts a design picks by name, so a stronger joint is always
// a heavier one (mjcf/README.md, "Servo catalogue", gives the sources and the rules). A
// position servo is modelled as: force limit = stall torque, joint damping = stall torque /
// no-load speed (a saturated servo runs at its no-load speed: back-EMF), kp = stall torque 3°
// from target (a hobby servo's proportional band), armature = rotor inertia × gear ratio².
#ifndef CLIMBSIM_ROBOT_SERVOS_H_
#define CLIMBSIM_ROBOT_SERVOS_H_

#include <array>
#include <span>
#include <string>
#include <string_view>

namespace climbsim::sim {

struct ServoModel {
  std::string_view name;         // catalogue key: "hs35hd"
  std::string_view part;         // "Hitec HS-35HD"
  double voltage_v;              // the data sheet's figures are at this supply
  double mass_kg;
  double stall_torque_nm;
  double no_load_speed_rad_s;
  double gear_ratio;             // motor turns per output turn (estimate where not published)
  // Continuous rating: hobby data sheets give stall torque only; a servo holding more than half
  // of it draws most of its stall current and overheats within minutes, so half is the rating.
  double rated_torque_nm;
  double kp_nm_per_rad;          // stall torque at 3° (0.052 rad) from target, 2 significant digits
  double damping_nms_per_rad;    // stall torque / no-load speed
  double armature_kgm2;          // reflected rotor inertia
  std::array<double, 3> case_half_m;  // the case as a box (half sizes: x, y, z when mounted)
};

// Every servo of the catalogue, lightest first.
std::span<const ServoModel> ServoCatalogue();
// The catalogue's servo of this name; nullptr when none.
const ServoModel* FindServo(std::string_view name);
// "hk5320, hs40, ..." for messages and key docs.
std::string ServoNames();

}  // namespace climbsim::sim

#endif  // CLIMBSIM_ROBOT_SERVOS_H_
