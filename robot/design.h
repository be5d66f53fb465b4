// A robot described by parameters (scenario key `robot`): a preset (today's gecko and spider
// and their variants) changed by a few keys, from which the MJCF robot file is generated as a
// DOM (generate.cc), per the model contract of mjcf/README.md. The six files in mjcf/ are the
// presets' generated text.
#ifndef CLIMBSIM_ROBOT_DESIGN_H_
#define CLIMBSIM_ROBOT_DESIGN_H_

#include <optional>
#include <string>
#include <vector>

#include "keys/keys.h"
#include "robot/compliance.h"
#include "robot/spine.h"
#include "robot/tail.h"

namespace climbsim::sim {

// The body: a plate carrying frame, battery and electronics, with a head sphere in front (visual
// weight only). Ranges: a hobby-servo climber between a 10 cm gecko and a 40 cm hexapod.
struct BodyDesign {
  double length_m = 0.1;
  double width_m = 0.07;
  double height_m = 0.01;
  double mass_kg = 0.024;
  double hip_x_m = 0.045;
  double hip_y_m = 0.05;
  double head_radius_m = 0.012;
  double head_ahead_m = 0.008;
  double head_z_m = 0.002;
  double head_mass_kg = 0.0005;
  std::optional<SpineDesign> spine;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"length_m", "m", "plate length along x; 0.04-0.4: a micro-servo robot's frame",
              Range::Closed(0.04, 0.4)},
             &length_m);
    a->Visit({"width_m", "m", "plate width along y", Range::Closed(0.02, 0.3)}, &width_m);
    a->Visit({"height_m", "m", "plate thickness; 2-40 mm: a printed or milled frame",
              Range::Closed(0.002, 0.04)},
             &height_m);
    a->Visit({"mass_kg", "kg",
              "frame, battery and electronics; a 1S LiPo and a board weigh "
              ">= 5 g",
              Range::Closed(0.005, 1.0)},
             &mass_kg);
    a->Visit({"hip_x_m", "m",
              "front and hind hips ahead of / behind the centre (middle hips "
              "of six legs at 0)",
              Range::Closed(0.0, 0.2)},
             &hip_x_m);
    a->Visit({"hip_y_m", "m", "hip-yaw axes beside the centre line", Range::Closed(0.01, 0.15)},
             &hip_y_m);
    a->Visit({"head_radius_m", "m", "the head sphere (camera, sensors); up to a 3 cm dome",
              Range::OpenClosed(0.0, 0.03)},
             &head_radius_m);
    a->Visit({"head_ahead_m", "m", "head centre ahead of the plate's front edge",
              Range::Closed(0.0, 0.05)},
             &head_ahead_m);
    a->Visit({"head_z_m", "m", "head centre above the plate centre", Range::Closed(-0.02, 0.05)},
             &head_z_m);
    a->Visit({"head_mass_kg", "kg", "the head", Range::Closed(0.0, 0.05)}, &head_mass_kg);
    a->Visit({"spine", "", "a yaw joint splitting the plate (robot/spine.h); absent: rigid"},
             &spine);
  }
};

// The legs, drawn as a drawing does: Cartesian segments in the leg's plane (so the numbers are
// the drawing's rounded ones); lengths and angles follow from them (mjcf/README.md).
struct LegsDesign {
  int count = 4;
  double coxa_m = 0.01;
  double femur_m = 0.06;
  double femur_rise_m = 0.0;
  double tibia_m = 0.03759;
  double tibia_inset_m = 0.01368;
  double splay_rad = 0.0;
  double coxa_radius_m = 0.004;
  double femur_radius_m = 0.003;
  double tibia_radius_m = 0.0025;
  double coxa_mass_kg = 0.005;
  double femur_mass_kg = 0.0015;
  double tibia_mass_kg = 0.0015;
  std::vector<double> hip_yaw_range_rad = {-0.5, 0.5};
  std::vector<double> hip_pitch_range_rad = {-0.5, 1.0};
  std::vector<double> knee_range_rad = {-0.6, 1.2};

  template <class A>
  void Serialize(A* a) {
    a->Visit({"count", "", "4 (LF RF LH RH) or 6 (L1 L2 L3 R1 R2 R3)", Range::Closed(4, 6)},
             &count);
    a->Visit({"coxa_m", "m", "hip-yaw axis to hip-pitch axis, outward; a servo horn is >= 5 mm",
              Range::Closed(0.005, 0.05)},
             &coxa_m);
    a->Visit({"femur_m", "m", "hip-pitch axis to knee, outward reach", Range::Closed(0.02, 0.2)},
             &femur_m);
    a->Visit({"femur_rise_m", "m", "knee above the hip-pitch axis", Range::Closed(-0.05, 0.1)},
             &femur_rise_m);
    a->Visit({"tibia_m", "m", "ankle below the knee (the drop)", Range::Closed(0.01, 0.2)},
             &tibia_m);
    a->Visit({"tibia_inset_m", "m", "ankle inboard of the knee", Range::Closed(-0.05, 0.05)},
             &tibia_inset_m);
    a->Visit({"splay_rad", "rad", "front and hind coxa frames turned about z (hind backward)",
              Range::Closed(0.0, 1.0)},
             &splay_rad);
    a->Visit(
        {"coxa_radius_m", "m", "coxa capsule (servos on the body)", Range::Closed(0.001, 0.01)},
        &coxa_radius_m);
    a->Visit({"femur_radius_m", "m", "femur capsule", Range::Closed(0.001, 0.01)}, &femur_radius_m);
    a->Visit({"tibia_radius_m", "m", "tibia capsule", Range::Closed(0.001, 0.01)}, &tibia_radius_m);
    a->Visit({"coxa_mass_kg", "kg", "coxa link (with the hip-pitch servo on the legs)",
              Range::Closed(0.0005, 0.05)},
             &coxa_mass_kg);
    a->Visit({"femur_mass_kg", "kg", "femur link", Range::Closed(0.0005, 0.05)}, &femur_mass_kg);
    a->Visit({"tibia_mass_kg", "kg", "tibia link", Range::Closed(0.0005, 0.05)}, &tibia_mass_kg);
    a->Visit({"hip_yaw_range_rad", "rad", "hip-yaw travel [lo, hi]; hobby servos turn +-1.5"},
             &hip_yaw_range_rad, 2);
    a->Visit({"hip_pitch_range_rad", "rad", "hip-pitch travel [lo, hi]"}, &hip_pitch_range_rad, 2);
    a->Visit({"knee_range_rad", "rad", "knee travel [lo, hi]"}, &knee_range_rad, 2);
  }
};

// The dry-adhesive pads and the passive two-axis ankle spring that carries them.
struct PadsDesign {
  double size_m = 0.025;
  double thickness_m = 0.002;
  double mass_kg = 0.0025;
  // A soft foam layer in the backing (part of thickness_m) lets the face follow the surface's
  // relief: on a bump a rigid backing lifts the face off everything but the bump's top.
  double foam_m = 0.0;
  std::vector<double> friction = {1.0, 0.005, 0.0001};
  std::vector<double> solref = {0.015, 1.0};
  std::vector<double> solimp = {0.9, 0.95, 0.001};
  double ankle_stiffness_nm_per_rad = 0.02;
  double ankle_damping_nms_per_rad = 0.0002;
  double ankle_range_rad = 0.5;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"size_m", "m", "square pad side; cast polymer pads are 10-60 mm",
              Range::Closed(0.01, 0.06)},
             &size_m);
    a->Visit({"thickness_m", "m", "pad with its backing", Range::Closed(0.0005, 0.01)},
             &thickness_m);
    a->Visit({"mass_kg", "kg", "pad, backing and ankle parts", Range::Closed(0.0005, 0.05)},
             &mass_kg);
    a->Visit({"foam_m", "m",
              "soft foam in the backing (part of thickness_m, which must exceed it by the "
              "adhesive's 0.5 mm): the face follows relief up to half of it beyond "
              "adhesion.contact_gap_m, and a landing without adhesion.min_contacts at the end "
              "of the attach window is judged by the share of the face that reaches the "
              "surface; adds its own mass (100 kg/m^3); 0: a rigid backing",
              Range::Closed(0.0, 0.008)},
             &foam_m);
    a->Visit({"friction", "", "MuJoCo friction of a pad contact: slide, spin, roll"}, &friction, 3);
    a->Visit({"solref", "", "MuJoCo solref of a pad contact"}, &solref, 2);
    a->Visit({"solimp", "", "MuJoCo solimp of a pad contact"}, &solimp, 3);
    a->Visit({"ankle_stiffness_nm_per_rad", "N·m/rad", "ankle torsion spring",
              Range::Closed(0.001, 1.0)},
             &ankle_stiffness_nm_per_rad);
    a->Visit({"ankle_damping_nms_per_rad", "N·m·s/rad", "ankle damping", Range::Closed(0.0, 0.1)},
             &ankle_damping_nms_per_rad);
    a->Visit({"ankle_range_rad", "rad", "ankle stops, +- this", Range::Closed(0.05, 1.5)},
             &ankle_range_rad);
  }
};

// The foot: a post from the ankle down to the pad face.
struct FeetDesign {
  double post_m = 0.017;
  double post_radius_m = 0.002;
  std::string release = "peel";

  template <class A>
  void Serialize(A* a) {
    a->Visit({"post_m", "m", "ankle centre to pad face; the peel lever (mjcf/README.md, Feet)",
              Range::Closed(0.002, 0.06)},
             &post_m);
    a->Visit({"post_radius_m", "m", "the post (visual)", Range::Closed(0.0005, 0.01)},
             &post_radius_m);
    a->Choice({"release", "", "peel: the leg tears the pad off; active: a toe tendon lets go"},
              &release, {"peel", "active"});
  }
};

// A fourth servo per leg tilting the foot about its y axis, ahead of the passive ankle.
struct AnklesDesign {
  bool actuated = false;
  std::string tilt_servo = "hk5320";
  double range_rad = 1.7;
  double tilt_servo_at = 0.7;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"actuated", "", "a tilt servo per ankle"}, &actuated);
    a->Visit({"tilt_servo", "", "the tilt servo (catalogue name)"}, &tilt_servo);
    a->Visit({"range_rad", "rad", "tilt travel, +- this; hobby servos turn +-1.7 at most",
              Range::Closed(0.1, 1.7)},
             &range_rad);
    a->Visit({"tilt_servo_at", "",
              "servos on the legs: the tilt case this far down the tibia "
              "(on the 10 um grid)",
              Range::Closed(0.0, 1.0)},
             &tilt_servo_at);
  }
};

// The leg servos and where they sit: on the legs (each at its joint) or on the body in packs of
// three per leg, driving the joints through cables (only the rotor inertia at the joint).
struct ServosDesign {
  std::string hip_yaw = "hs35hd";
  std::string hip_pitch = "hs35hd";
  std::string knee = "hs35hd";
  std::string placement = "legs";
  double yaw_case_inset_m = 0.007;
  double pack_x_m = 0.066;
  double pack_y_m = 0.035;
  double pack_side_m = 0.024;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"hip_yaw", "", "hip-yaw servo (catalogue name)"}, &hip_yaw);
    a->Visit({"hip_pitch", "", "hip-pitch servo (catalogue name)"}, &hip_pitch);
    a->Visit({"knee", "", "knee servo (catalogue name)"}, &knee);
    a->Choice({"placement", "", "legs: each servo at its joint; body: packs on the platform"},
              &placement, {"legs", "body"});
    a->Visit({"yaw_case_inset_m", "m", "legs: yaw servo case inboard of the hip axis",
              Range::Closed(0.0, 0.05)},
             &yaw_case_inset_m);
    a->Visit({"pack_x_m", "m", "body: front and hind packs' |x|", Range::Closed(0.0, 0.2)},
             &pack_x_m);
    a->Visit({"pack_y_m", "m", "body: packs beside the centre line", Range::Closed(0.0, 0.15)},
             &pack_y_m);
    a->Visit(
        {"pack_side_m", "m", "body: a pack of three servos as a cube", Range::Closed(0.01, 0.06)},
        &pack_side_m);
  }
};

struct RobotDesign {
  std::string preset = "gecko";
  BodyDesign body;
  LegsDesign legs;
  PadsDesign pads;
  FeetDesign feet;
  AnklesDesign ankles;
  ServosDesign servos;
  std::optional<TailDesign> tail;
  ComplianceDesign compliance;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"preset", "",
              "the design the other keys change: gecko, gecko_active, gecko_ankle, "
              "spider, spider_active, spider_ankle"},
             &preset);
    a->Visit({"body", "", "the body plate and head"}, &body);
    a->Visit({"legs", "", "leg segments, link masses and joint ranges"}, &legs);
    a->Visit({"pads", "", "adhesive pads and the passive ankle"}, &pads);
    a->Visit({"feet", "", "foot post and pad release"}, &feet);
    a->Visit({"ankles", "", "actuated ankle tilt"}, &ankles);
    a->Visit({"servos", "", "leg servos and their placement"}, &servos);
    a->Visit({"tail", "", "a tail behind the body; absent: none"}, &tail);
    a->Visit({"compliance", "", "series springs between servos and links"}, &compliance);
  }
};

// gecko, gecko_active, gecko_ankle, spider, spider_active, spider_ankle.
std::vector<std::string> PresetNames();
// The preset of this name; throws std::invalid_argument naming the presets for another.
RobotDesign PresetDesign(const std::string& name);
// The keys where a design differs from its preset, in declaration order, each as
// "legs.femur_m 0.072" (a list element "legs.knee_range_rad[1] 1.1"; an absent part "tail none").
std::vector<std::string> ChangedKeys(const RobotDesign& design);
// The robot file of a design: a complete <mujoco> document (what mjcf/<preset>.xml holds for
// a preset). Throws std::invalid_argument (key path and reason) for a design it cannot build.
std::string GenerateRobotMjcf(const RobotDesign& design);

}  // namespace climbsim::sim

#endif  // CLIMBSIM_ROBOT_DESIGN_H_
