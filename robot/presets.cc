// The six presets: today's robots as designs (mjcf/README.md gives the reasons for each
// number). The gecko is RobotDesign's defaults; the others are the keys that differ.
#include <stdexcept>

#include "robot/design.h"

namespace climbsim::sim {

namespace {

RobotDesign Gecko() {
  RobotDesign d;
  d.preset = "gecko";
  return d;
}

// Active-release feet: a toe tendon lets the pad go, so no peel lever (a short post) and the
// tendon hardware adds to each pad's mass.
RobotDesign WithActiveFeet(RobotDesign d, const char* name, double post_m, double pad_mass_kg) {
  d.preset = name;
  d.feet.post_m = post_m;
  d.feet.release = "active";
  d.pads.mass_kg = pad_mass_kg;
  return d;
}

// A tilt servo per ankle, ahead of the passive ankle.
RobotDesign WithActuatedAnkles(RobotDesign d, const char* name, const char* tilt_servo) {
  d.preset = name;
  d.ankles.actuated = true;
  d.ankles.tilt_servo = tilt_servo;
  return d;
}

RobotDesign GeckoActive() { return WithActiveFeet(Gecko(), "gecko_active", 0.005, 0.003); }
RobotDesign GeckoAnkle() { return WithActuatedAnkles(Gecko(), "gecko_ankle", "hk5320"); }

// The seed's six-legged spider: all 18 servos on the platform, femur 0.08 m rising 30 deg,
// tibia 0.10 m leaning 10 deg inwards, front and hind legs splayed 30 deg.
RobotDesign Spider() {
  RobotDesign d;
  d.preset = "spider";
  d.body = {.length_m = 0.16,
            .width_m = 0.1,
            .height_m = 0.02,
            .mass_kg = 0.0495,
            .hip_x_m = 0.07,
            .hip_y_m = 0.05,
            .head_radius_m = 0.01,
            .head_ahead_m = 0.005,
            .head_z_m = 0.004,
            .head_mass_kg = 0.0005,
            .spine = std::nullopt};
  d.legs.count = 6;
  d.legs.coxa_m = 0.015;
  d.legs.femur_m = 0.06928;
  d.legs.femur_rise_m = 0.04;
  d.legs.tibia_m = 0.098481;
  d.legs.tibia_inset_m = 0.017365;
  d.legs.splay_rad = 0.5236;
  d.legs.coxa_radius_m = 0.004;
  d.legs.femur_radius_m = 0.0035;
  d.legs.tibia_radius_m = 0.003;
  d.legs.coxa_mass_kg = 0.003;
  d.legs.femur_mass_kg = 0.003;
  d.legs.tibia_mass_kg = 0.003;
  d.pads.size_m = 0.035;
  d.pads.thickness_m = 0.003;
  d.pads.mass_kg = 0.006;
  d.pads.ankle_stiffness_nm_per_rad = 0.04;
  d.pads.ankle_damping_nms_per_rad = 0.0005;
  d.feet.post_m = 0.025;
  d.feet.post_radius_m = 0.003;
  d.servos = {.hip_yaw = "hs65hb",
              .hip_pitch = "hs65hb",
              .knee = "hs65hb",
              .placement = "body",
              .yaw_case_inset_m = 0.007,
              .pack_x_m = 0.066,
              .pack_y_m = 0.035,
              .pack_side_m = 0.024};
  return d;
}

RobotDesign SpiderActive() { return WithActiveFeet(Spider(), "spider_active", 0.007, 0.007); }
// The tilt servo sits on the platform with the others (the gecko's hs35hd, cable-driven).
RobotDesign SpiderAnkle() { return WithActuatedAnkles(Spider(), "spider_ankle", "hs35hd"); }

struct Preset {
  const char* name;
  RobotDesign (*make)();
};
constexpr Preset kPresets[] = {
    {"gecko", Gecko},   {"gecko_active", GeckoActive},   {"gecko_ankle", GeckoAnkle},
    {"spider", Spider}, {"spider_active", SpiderActive}, {"spider_ankle", SpiderAnkle}};

}  // namespace

std::vector<std::string> PresetNames() {
  std::vector<std::string> names;
  for (const Preset& p : kPresets) names.emplace_back(p.name);
  return names;
}

RobotDesign PresetDesign(const std::string& name) {
  for (const Preset& p : kPresets)
    if (name == p.name) return p.make();
  std::string all;
  for (const Preset& p : kPresets) all += (all.empty() ? "" : ", ") + std::string(p.name);
  throw std::invalid_argument("robot.preset: unknown preset '" + name + "' (presets: " + all + ")");
}

}  // namespace climbsim::sim
