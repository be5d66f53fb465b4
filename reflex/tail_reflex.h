// The tail reflex (scenario reflex.tail; absent: off): a tail on a pitch servo (robot/tail.h)
// rests on the surface behind the robot and is pressed into it when the body is about to
// pitch off: when a front pad lets go outside its own release, or when the body pitches away
// from the surface beyond a threshold. Geckos do this when a front foot slips (Jusufi A et
// al. (2008) PNAS 105:4215); Stickybot and RiSE carry a tail for it. The press holds for a
// while after the last trigger, then eases back to rest.
//
// Why a tail helps (docs/climbing.md, "Tail"): on a wall the weight acts h off the surface
// and pitches the head away with m·g·h; the front pads' pull holds that moment. Without a front
// pad nothing does, and the hind pads are torn off within 0.1-0.15 s. A tail tip pressed with
// force F at d behind the hind pads holds F·d of it (the hind pads then pull F).
//
// The command is an angle: the servo's force limit (its stall torque) caps the press, as a
// real hobby servo's. Pure controller code (no MuJoCo), as the rest of the module.
#ifndef CLIMBSIM_REFLEX_TAIL_REFLEX_H_
#define CLIMBSIM_REFLEX_TAIL_REFLEX_H_

#include <string>
#include <string_view>

#include "keys/keys.h"
#include "reflex/laws.h"

namespace climbsim::reflex {

struct TailReflexParams {
  double rest_rad = 0.0;
  double press_rad = 0.3;
  bool on_front_pad_loss = true;
  double pitch_threshold_rad = 0.08;
  double delay_s = 0.01;
  double hold_s = 0.6;
  double ease_s = 0.2;
  double yaw_rad = 0.0;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"rest_rad", "rad",
              "the tail servo's command at rest, from the tail's neutral angle (tip on the "
              "surface); > 0 presses lightly, < 0 lifts the tip clear (a hobby servo turns "
              "±1.05 rad; the tail's joint range bounds it)",
              Range::Closed(-1.05, 1.05)},
             &rest_rad);
    a->Visit({"press_rad", "rad",
              "the press command, from the neutral angle into the surface: past ~3° (the "
              "servo's proportional band) the servo pushes at its stall torque",
              Range::Closed(0.0, 1.05)},
             &press_rad);
    a->Visit({"on_front_pad_loss", "",
              "press when a front pad lets go in stance, outside its peel (a pad failure)"},
             &on_front_pad_loss);
    a->Visit({"pitch_threshold_rad", "rad",
              "press while the body's nose turns away from the surface by more than this from "
              "its starting attitude (an IMU's pitch; the gecko's gait alone turns it < 0.01 rad)",
              Range::OpenClosed(0.0, 1.0)},
             &pitch_threshold_rad);
    a->Visit({"delay_s", "s",
              "sensing and command latency (the pad's contact sensing or the IMU, and the servo's "
              "PWM frame: 10-20 ms on a hobby servo)",
              Range::Closed(0.0, 0.1)},
             &delay_s);
    a->Visit({"hold_s", "s", "the press holds this long after the last trigger",
              Range::OpenClosed(0.0, 10.0)},
             &hold_s);
    a->Visit({"ease_s", "s", "then the command ramps back to rest over this long",
              Range::Closed(0.0, 10.0)},
             &ease_s);
    a->Visit({"yaw_rad", "rad",
              "a pad-loss press also swings the tail this far towards the lost pad's side "
              "(robot.tail.yaw: the tip widens the support on the side that has no pad; "
              "geckos right themselves so); 0: no swing. The yaw joint's range is ±0.5 rad",
              Range::Closed(0.0, 0.5)},
             &yaw_rad);
  }
};

// One control tick's input: what the robot's sensors tell the tail.
struct TailSensing {
  bool front_pad_lost = false;  // a front pad let go in stance, outside its release, this tick
  int lost_side = 0;            // the lost pad's side: +1 left (+y), -1 right
  double pitch_rad = 0.0;       // the body's nose away from the surface (+), from its start
};

enum class TailEventType { kNone, kPress, kRelease };
enum class TailTrigger { kNone, kFrontPadLoss, kPitch };

struct TailOutput {
  double command_rad = 0.0;      // the tail servo's target, from its neutral angle
  double yaw_command_rad = 0.0;  // the tip's swing towards +y (left), from straight back
  TailEventType event = TailEventType::kNone;
  TailTrigger trigger = TailTrigger::kNone;  // of a kPress
};

std::string_view TailEventName(TailEventType type);     // "tail_press", "tail_release"
std::string_view TailTriggerName(TailTrigger trigger);  // "front_pad_lost", "pitch", ""

class TailReflex {
 public:
  // Throws std::invalid_argument ("tail.<key> ...") for params outside their ranges or a delay
  // or duration that does not fit the control period dt_s.
  TailReflex(const TailReflexParams& params, double dt_s);
  // One control tick; never allocates.
  TailOutput Update(const TailSensing& in);
  void Reset();
  bool pressing() const { return hold_left_ > 0; }
  const TailReflexParams& params() const { return params_; }

 private:
  TailReflexParams params_;
  DelayLine pad_lost_;  // the lost pad's side (±1) on the tick a front pad was lost, delayed
  DelayLine pitch_;     // the pitch, delayed
  int hold_samples_ = 0;
  int ease_samples_ = 0;
  int hold_left_ = 0;  // ticks of press left (> 0: pressing)
  int ease_left_ = 0;  // ticks of the ramp back left
  int side_ = 0;       // the side the tail swings to (the last pad loss's), 0 after a rest
};

// The tail block's checks that need the control period (delay_s, hold_s, ease_s), through
// checker.Fail(prefix + "<key>", ...).
void CheckTailControlPeriod(const TailReflexParams& params, double dt_s, const Checker& checker,
                            std::string_view prefix);

}  // namespace climbsim::reflex

#endif  // CLIMBSIM_REFLEX_TAIL_REFLEX_H_
