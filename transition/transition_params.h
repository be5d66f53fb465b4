// The scenario's transition block: the corner manoeuvre's keys.
#ifndef CLIMBSIM_TRANSITION_TRANSITION_PARAMS_H_
#define CLIMBSIM_TRANSITION_TRANSITION_PARAMS_H_

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "keys/keys.h"

namespace climbsim::sim {

// Surface transitions (sim/transition_effect.h): a planned free gait that takes the robot over a
// sharp 90-degree corner (inner: floor to wall, wall to ceiling; outer: a wall onto its top),
// started when a front pad touches a surface whose normal differs from the one it stands on.
// Needs the cpg and adhesion blocks and a robot with actuated ankles (gecko_ankle,
// spider_ankle).
struct TransitionParams {
  double trigger_angle_deg = 45.0;
  double lost_s = 1.5;
  double body_speed_mps = 0.02;
  double pitch_rate_rad_per_s = 0.2;
  double swing_s = 0.5;
  double lift_m = 0.015;
  double place_speed_mps = 0.06;
  double press_m = 0.001;
  double place_depth_m = 0.004;
  double place_force_n = 0.4;
  double track_s = 0.0;
  double peel_back_m = 0.02;
  std::string peel_toward = "load";
  double peel_lift_m = 0.005;
  double peel_tilt_rad = 0.6;
  double peel_ramp_s = 0.3;
  double peel_max_s = 1.0;
  double margin_rad = 0.05;
  double reach_share = 0.8;
  double crouch_m = 0.02;
  double support_bond_fraction = 0.85;
  int max_place_attempts = 4;
  double unload_gain = 2.0;
  double unload_threshold = 0.8;
  std::string then = "crawl";

  template <class A>
  void Serialize(A* a) {
    a->Visit(
        {"trigger_angle_deg", "deg",
         "a front pad that touches a surface whose normal is more than this from the normal of "
         "the surface the robot stands on starts the manoeuvre",
         Range::OpenClosed(0, 90)},
        &trigger_angle_deg);
    a->Visit({"lost_s", "s",
              "a front foot that has touched nothing for this long has found the surface ended: "
              "the body crouches and the foot probes down past the edge and back until it touches "
              "the surface beyond (an outer corner)",
              Range::Positive()},
             &lost_s);
    a->Visit({"body_speed_mps", "m/s", "body speed along a surface during the manoeuvre",
              Range::Positive()},
             &body_speed_mps);
    a->Visit({"pitch_rate_rad_per_s", "rad/s", "body pitch rate while it turns round the corner",
              Range::Positive()},
             &pitch_rate_rad_per_s);
    a->Visit({"swing_s", "s", "duration of a foot's move from one foothold to the next",
              Range::Positive()},
             &swing_s);
    a->Visit({"lift_m", "m", "clearance of a moving foot above the surfaces it leaves and lands on",
              Range::Closed(0, 0.1)},
             &lift_m);
    a->Visit({"place_speed_mps", "m/s",
              "speed at which a foot is lowered onto its foothold (below the attach limit "
              "adhesion.max_approach_speed_mps)",
              Range::Positive()},
             &place_speed_mps);
    a->Visit(
        {"press_m", "m", "how far a stance foot is aimed into its surface", Range::Closed(0, 0.02)},
        &press_m);
    a->Visit({"place_depth_m", "m",
              "how far a foot being placed is pressed into its surface until its pad attaches",
              Range::Closed(0, 0.03)},
             &place_depth_m);
    a->Visit({"place_force_n", "N",
              "a foot being placed is pressed no further once its pad's contact force reaches this "
              "(a harder press pushes the body off the other pads)",
              Range::Positive()},
             &place_force_n);
    a->Visit({"track_s", "s",
              "time constant of the integral correction that moves the stance legs' targets until "
              "the body, sagging on its compliant servos, is where the plan commands it (updated "
              "every 10 ms); 0: off",
              Range::NonNegative()},
             &track_s);
    a->Visit({"peel_back_m", "m",
              "a foot about to move is drawn this far back along its surface to peel its pad",
              Range::Closed(0, 0.1)},
             &peel_back_m);
    a->Choice({"peel_toward", "",
               "the direction of the peel's pull along the pad's surface, chosen so that its "
               "reaction relieves the other pads. load: along the load they carry (the weight), "
               "else as normals; normals: along the sum of their normals, so that it presses them "
               "into their surfaces, else as back; back: against the body's heading"},
              &peel_toward, {"load", "normals", "back"});
    a->Visit({"peel_lift_m", "m",
              "and this far away from its surface (with peel_back_m: the peel's pull)",
              Range::Closed(0, 0.1)},
             &peel_lift_m);
    a->Visit(
        {"peel_tilt_rad", "rad",
         "while it peels, the ankle tilt is turned this far the way the pull turns the pad (the "
         "servo's torque adds to the pull's moment on the bonds)",
         Range::Closed(0, 2)},
        &peel_tilt_rad);
    a->Visit({"peel_ramp_s", "s", "time to the full peel pull", Range::Positive()}, &peel_ramp_s);
    a->Visit({"peel_max_s", "s", "a peel that has not let go after this long stops the manoeuvre",
              Range::Positive()},
             &peel_max_s);
    a->Visit({"margin_rad", "rad",
              "every joint of a stance leg stays this far inside its range; a leg that would not "
              "steps to a new foothold",
              Range::Closed(0, 0.5)},
             &margin_rad);
    a->Visit({"reach_share", "",
              "inner corner: the front feet step onto the new surface with the front hips this "
              "share of a foot's forward reach (plus the foot post) away from it",
              Range::OpenClosed(0, 1)},
             &reach_share);
    a->Visit({"crouch_m", "m",
              "outer corner: the body rides this much closer to the surfaces while it turns over "
              "the edge",
              Range::Closed(0, 0.05)},
             &crouch_m);
    a->Visit({"support_bond_fraction", "",
              "a foot moves only while every other pad is attached with at least this bonded "
              "fraction of the share of its face that touches the surface, or all that its torn "
              "bonds leave",
              Range::Closed(0, 1)},
             &support_bond_fraction);
    a->Visit({"max_place_attempts", "",
              "a foot that does not attach is lifted and placed again up to this many times; then "
              "the manoeuvre stops",
              Range::Closed(1, 100)},
             &max_place_attempts);
    a->Visit({"unload_gain", "",
              "a stance leg whose pad is at utilisation U above unload_threshold has its servos' "
              "kp lowered by the factor max(0.2, 1 - unload_gain (U - unload_threshold)) (the GTO "
              "unload law of reflex.gto), so the other pads take the load; 0: off",
              Range::NonNegative()},
             &unload_gain);
    a->Visit({"unload_threshold", "", "utilisation from which a stance leg yields",
              Range::Closed(0, 10)},
             &unload_threshold);
    a->Choice({"then", "",
               "once every foot is on the new surface: gait, the feet are stepped to where the "
               "CPG's gait has them and the CPG and reflexes go on (and the next corner is "
               "watched for); crawl, the manoeuvre's free gait walks on along the new surface"},
              &then, {"gait", "crawl"});
  }
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_TRANSITION_TRANSITION_PARAMS_H_
