// Buildability: can the robot's servos hold it? Before a run, the robot hangs in the scenario's
// scene and gravity (payload included) from each stance set of its gait, its stance pads
// welded where they stand and its swing legs lifted; once settled, each servo's holding torque
// (|actuator force|) is compared with its rating, half its force limit (the stall torque: a
// hobby servo holding more than half of it overheats within minutes, robot/servos.h).
// Works for any robot that meets the model contract (mjcf/README.md), a user's MJCF included.
#ifndef CLIMBSIM_SIM_SERVO_MARGIN_H_
#define CLIMBSIM_SIM_SERVO_MARGIN_H_

#include <mujoco/mujoco.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scenario/scenario.h"

namespace climbsim::sim {

// How long each stance set settles before the torques are read, and how far a swing leg's hip
// pitch lifts it (as the gait's swing does; clamped to the servo's range).
inline constexpr double kServoMarginSettleS = 2.0;
inline constexpr double kServoMarginLiftRad = 0.4;

struct ServoHold {
  std::string name;            // the actuator ("LF_hip_yaw")
  double holding_torque_nm = 0.0;  // the largest over the stance sets
  double rated_torque_nm = 0.0;    // half the force limit
  std::string stance;          // the set in which it is largest ("LF RH")
  double load_fraction() const { return holding_torque_nm / rated_torque_nm; }
};

struct ServoMargins {
  double mass_kg = 0.0;        // the robot with its payload
  std::vector<std::vector<std::string>> stance_sets;
  std::vector<ServoHold> servos;  // force-limited actuators on joints, model order
  // The servos over their rating ("LF_hip_yaw 112 %"), empty when all hold.
  std::vector<std::string> Overloaded() const;
  const ServoHold* Worst() const;
  nlohmann::json ToJson() const;
};

// The stance sets of a gait: the distinct sets of legs in stance over one cycle (leg i in stance
// when its phase, lagging offsets[i] cycles, is in the last `duty` of the cycle), each as leg
// indices in increasing order, then all legs; sets of fewer than two legs are left out.
std::vector<std::vector<int>> GaitStanceSets(const std::vector<double>& offsets_cycles,
                                             double duty);

// Welds the pads of `stance` legs where they are, lifts the other legs' hip pitch, steps
// `steps` with every other control at 0, and returns |actuator_force| of each actuator.
// `welds[leg]` is the id of an inactive weld of that leg's pad to the world.
std::vector<double> SettledActuatorForces(mjModel* m, mjData* d, const std::vector<int>& welds,
                                          const std::vector<int>& stance_legs,
                                          const std::vector<int>& lift_actuators, int steps);

// The margins of a scenario's robot in its scene (before its run; effects left out). Throws
// InputError at the robot key when the model cannot be built.
ServoMargins MeasureServoMargins(const Scenario& scenario);

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_SERVO_MARGIN_H_
