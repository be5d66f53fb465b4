// Series-elastic legs: a spring between a servo's output and its link (a torsion spring in
// the horn), as design keys (ComplianceDesign, scenario robot.compliance) and the MJCF that
// adds it: a passive hinge right after the servo's hinge, on the same axis, so the servo's
// joint angle stays what its potentiometer reads and the link turns by servo + spring.
#ifndef CLIMBSIM_ROBOT_COMPLIANCE_H_
#define CLIMBSIM_ROBOT_COMPLIANCE_H_

#include <tinyxml2.h>

#include <string>

#include "keys/keys.h"

namespace climbsim::sim {

// One joint's series spring; stiffness 0: no spring (the servo drives its link rigidly).
struct SeriesSpring {
  double stiffness_nm_per_rad = 0.0;
  double damping_nms_per_rad = 0.0;
  double travel_rad = 0.2;
  double preload_nm = 0.0;

  template <class A>
  void Serialize(A* a) {
    // A steel wire torsion spring that fits a micro servo's horn (coil under 15 mm): from about
    // 0.05 N·m/rad (0.5 mm wire, many turns) to a few N·m/rad; above the servo's own loop
    // (kp 1.5 N·m/rad on the gecko) it adds little, so 10 is the top.
    a->Visit({"stiffness_nm_per_rad", "N·m/rad",
              "spring between servo horn and link; 0: rigid (no spring joint)",
              Range::Closed(0.0, 10.0)},
             &stiffness_nm_per_rad);
    // A coil's own loss is tiny; an elastomer sleeve or a viscous damper adds some. Up to the
    // servo's back-EMF damping class (0.0075 N·m·s/rad) and a little beyond.
    a->Visit({"damping_nms_per_rad", "N·m·s/rad", "the spring's damping (coil loss, a sleeve)",
              Range::Closed(0.0, 0.05)},
             &damping_nms_per_rad);
    // The horn's stops: a torsion spring's arms travel at most about 60° in a horn.
    a->Visit({"travel_rad", "rad", "the spring's stops, ± this about the servo's angle",
              Range::OpenClosed(0.0, 1.0)},
             &travel_rad);
    // A torsion spring whose arms are preloaded against a pin in the horn (as a break-away horn
    // in an RC servo): rigid until the torque through it passes the preload, compliant beyond,
    // one way only: positive gives for a positive torque (hip yaw: the pad forward, the way a
    // push down the wall loads every stance leg), negative for a negative one (hip pitch: the
    // pad pulled towards the wall, the way a pitch off the wall loads the front legs). Above
    // the weight's torque per stance leg, below the servo's stall torque (above it the spring
    // never moves); 1 N·m is more than any catalogue servo holds.
    a->Visit({"preload_nm", "N·m",
              "torque the spring's arms are preloaded with against their stop; 0: a symmetric "
              "spring (± travel_rad); else rigid below its size, then travel_rad its way",
              Range::Closed(-1.0, 1.0)},
             &preload_nm);
  }
};

struct ComplianceDesign {
  SeriesSpring hip_yaw;
  SeriesSpring hip_pitch;
  SeriesSpring knee;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"hip_yaw", "", "series spring of every hip-yaw servo"}, &hip_yaw);
    a->Visit({"hip_pitch", "", "series spring of every hip-pitch servo"}, &hip_pitch);
    a->Visit({"knee", "", "series spring of every knee servo"}, &knee);
  }
};

// The spring joint's name for a servo joint: "LF_hip_yaw" -> "LF_hip_yaw_spring".
std::string SpringJointName(const std::string& servo_joint);

// Inserts the spring hinge "<servo joint name>_spring" right after `servo_joint` (a <joint>
// element with name and axis) when spring.stiffness_nm_per_rad > 0; nothing otherwise. The
// spring joint has no class of its own beyond the body's childclass and sets every attribute
// that matters (stiffness, damping, springref, range, armature 0), so a servo class's damping
// and armature stay on the servo joint. Preloaded (preload_nm p != 0): range [0, travel] (p > 0)
// or [-travel, 0] (p < 0) and springref -p/k, so the spring presses the joint onto its stop at
// 0 with |p| and leaves it only when a torque of p's sign passes |p|; a stiff stop
// (solreflimit) keeps it there. Throws std::invalid_argument when the element has no name or axis.
void AddSeriesSpring(const SeriesSpring& spring, tinyxml2::XMLElement* servo_joint);

// AddSeriesSpring on every leg's hip_yaw, hip_pitch and knee joint of a robot document (legs
// from the custom text "climbsim_legs"). Throws std::invalid_argument naming a missing joint.
void AddSeriesSprings(const ComplianceDesign& design, tinyxml2::XMLDocument* robot);

}  // namespace climbsim::sim

#endif  // CLIMBSIM_ROBOT_COMPLIANCE_H_
