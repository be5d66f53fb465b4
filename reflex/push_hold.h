// The spindles' push hold for the robot: LegReflex bounds one leg's push, PushHold the pushes of
// all legs together (reflex.spindle.max_hold_s, leg_params.h).
#ifndef CLIMBSIM_REFLEX_PUSH_HOLD_H_
#define CLIMBSIM_REFLEX_PUSH_HOLD_H_

#include <vector>

namespace climbsim::reflex {

// The spindle's push hold for the robot (reflex.spindle.max_hold_s). Each leg's push
// (LegReflexOutput::pushed) asks every leg to stay in stance, and LegReflex bounds one leg's
// push by max_hold_s. Pushes of one leg after another that hold the gait longer than that in a
// row are the robot's posture after a slide, not a push: the legs pushed then, and those pushed
// before the pushes pass, hold nothing until they leave stance or their pad lets go.
// max_hold_s = 0: every push holds, as long as it lasts.
class PushHold {
 public:
  PushHold(int legs, double max_hold_s, double dt_s);
  // Leg i this period: pushed (LegReflexOutput::pushed), and planted (in stance with its pad
  // attached). Then Update: whether the pushes hold the gait.
  void SetLeg(int i, bool pushed, bool planted);
  bool Update();
  void Reset();

 private:
  std::vector<char> pushed_;
  std::vector<char> posture_;  // per leg: its stretch is posture until it steps or lets go
  int run_ = 0;                // control periods in a row some leg was pushed
  int max_periods_ = 0;        // max_hold_s in control periods; 0: no limit
};

}  // namespace climbsim::reflex

#endif  // CLIMBSIM_REFLEX_PUSH_HOLD_H_
