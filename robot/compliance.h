// Series-elastic legs: a spring between a servo's output and its link (a torsion spring in
// the horn), as design keys (ComplianceDesign, scenario robot.compliance) and the MJCF that
// adds it: a passive hinge right after the servo's hinge, on the same axis, so the servo's
// joint angle stays what its potentiometer reads and the link turns by servo + spring.
// SCAFFOLD: the compliance engineer owns this file and compliance.cc and may change it.
#ifndef CLIMBSIM_ROBOT_COMPLIANCE_H_
#define CLIMBSIM_ROBOT_COMPLIANCE_H_

#include <tinyxml2.h>

#include "keys/keys.h"

namespace climbsim::sim {

// One joint's series spring; stiffness 0: no spring (the servo drives its link rigidly).
struct SeriesSpring {
  double stiffness_nm_per_rad = 0.0;
  double damping_nms_per_rad = 0.0;
  double travel_rad = 0.3;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"stiffness_nm_per_rad", "N·m/rad", "spring between servo horn and link; 0: rigid",
              Range::NonNegative()},
             &stiffness_nm_per_rad);
    a->Visit({"damping_nms_per_rad", "N·m·s/rad", "the spring's damping", Range::NonNegative()},
             &damping_nms_per_rad);
    a->Visit({"travel_rad", "rad", "the spring's stops, ± this", Range::OpenClosed(0, 1.0)},
             &travel_rad);
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

// Inserts the spring hinge "<servo joint name>_spring" right after `servo_joint` (a <joint>
// element with name and axis) when spring.stiffness_nm_per_rad > 0; nothing otherwise.
void AddSeriesSpring(const SeriesSpring& spring, tinyxml2::XMLElement* servo_joint);

}  // namespace climbsim::sim

#endif  // CLIMBSIM_ROBOT_COMPLIANCE_H_
