// The tail reflex in a run (reflex.tail): the ReflexEffect's channel that senses for the tail
// (front pads lost in stance outside their peel, the body's pitch off the surface), runs
// reflex::TailReflex at the control period and writes the tail servo's ctrl, with a
// tail_press / tail_release row in events.csv (pad "tail", cause the trigger). An adhesive
// tip grips only while pressed: the press engages its pad, the press's end lets it go (detach
// "released"), so the tail never drags a bond up the wall behind the climb. The tail's
// servo is not a leg's: nothing else writes its ctrl (mj_resetData leaves 0, the neutral
// angle: a robot with a tail and no tail reflex holds it there).
#ifndef CLIMBSIM_SIM_TAIL_DRIVER_H_
#define CLIMBSIM_SIM_TAIL_DRIVER_H_

#include <Eigen/Core>
#include <vector>

#include "reflex/leg_reflex.h"
#include "reflex/tail_reflex.h"
#include "sim/adhesion_effect.h"
#include "sim/effect.h"
#include "sim/world.h"

namespace climbsim::sim {

class TailDriver {
 public:
  // The robot has a tail (world.robot().tail.present()); `event_pad` is the tail's index in
  // the EventLog's pad names. Front legs: those whose hip stands foremost on the body.
  // An adhesive tip (robot.tail.tip: adhesive) is `adhesion`'s pad tail_pad: engaged only
  // while the reflex presses, released when the press ends (nullptr or no such pad: none).
  TailDriver(const reflex::TailReflexParams& params, const World& world, double dt_s,
             int event_pad, AdhesionEffect* adhesion = nullptr);
  // The tail at rest; the surface's normal is the base's z axis as the run starts (the robot
  // starts on its surface).
  void Reset(World& world);
  // One control tick, after the legs' reflexes (`legs`: their state, to tell a peel from a
  // failure). Never allocates.
  void Update(World& world, RunContext& ctx, const std::vector<reflex::LegReflex>& legs);
  long presses() const { return presses_; }
  double max_pitch_rad() const { return max_pitch_rad_; }

 private:
  reflex::TailReflex reflex_;
  int actuator_;
  int yaw_actuator_;                // -1: no yaw servo
  int event_pad_;
  AdhesionEffect* adhesion_;        // with tail_pad_ >= 0
  int tail_pad_ = -1;               // the adhesive tip's index among the sticky pads, or -1
  std::vector<int> front_;          // front legs' indices
  std::vector<int> front_side_;     // per front leg: +1 left (+y on the body), -1 right
  std::vector<bool> was_attached_;  // per front leg, at the last tick
  Eigen::Vector3d normal_ = Eigen::Vector3d::UnitZ();
  long presses_ = 0;
  double max_pitch_rad_ = 0.0;

  double PitchRad(const World& world) const;
  void DriveTailPad(bool pressing);
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_TAIL_DRIVER_H_
