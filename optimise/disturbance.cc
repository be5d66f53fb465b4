// The disturbance cases shared by bench robustness and the objective's robustness term
// (optimise/disturbance.h).
#include "optimise/disturbance.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdio>

#include "common/common.h"
#include "sim/surface.h"

namespace climbsim::optimise {
namespace {

constexpr double kJitterOffsetM = 0.005;
constexpr double kJitterYawDeg = 5.0;
constexpr uint64_t kStreamJitter = 101;

bool PlaneScene(const sim::Scenario& s) {
  const std::string& n = s.scene.name;
  return n == "floor" || n == "wall" || n == "ceiling" || n == "incline";
}

}  // namespace

std::vector<RobustnessFamily> AllRobustnessFamilies(double mass_kg) {
  return {
      {"push_off", "N s", "10 ms push off the surface", 0.005, 1.0},
      {"push_down", "N s", "10 ms push down the slope", 0.005, 1.0},
      {"push_side", "N s", "10 ms push across the slope", 0.005, 1.0},
      {"payload", "kg", "payload on the base", 0.02 * mass_kg, 4.0 * mass_kg},
      {"pad_failure", "", "probability that an attachment fails", 0.01, 1.0},
      {"weak_patch", "", "sigma_T lost on weak patches (1 - fraction)", 0.02, 0.99},
      {"roughness", "m", "bump height", 0.0005, 0.03},
      // scene.terrain's RMS height; case seed k draws rock seed k + 1. Named only: a rock run
      // costs about twice a flat one, and "all" stays what it was.
      {"terrain", "m", "RMS height of rough rock", 0.0001, 0.005, true},
  };
}

void ApplyCaseSeed(sim::Scenario* s, int k) {
  s->seed += k;
  if (k <= 0) return;
  const auto sd = static_cast<uint64_t>(s->seed);
  s->initial.offset_m[0] += kJitterOffsetM * (2 * sim::UnitDraw(sd, kStreamJitter, 0, 0) - 1);
  s->initial.offset_m[1] += kJitterOffsetM * (2 * sim::UnitDraw(sd, kStreamJitter, 1, 0) - 1);
  s->initial.yaw_deg = std::clamp(
      s->initial.yaw_deg + kJitterYawDeg * (2 * sim::UnitDraw(sd, kStreamJitter, 2, 0) - 1),
      -180.0, 180.0);
}

DisturbanceSetup MakeDisturbanceSetup(const sim::Scenario& base, const RobustnessOptions& options) {
  DisturbanceSetup u;
  u.base = base;
  u.options = options;
  u.duration_s = options.duration_s > 0 ? options.duration_s : base.duration_s;
  u.frequency_hz = base.cpg ? base.cpg->frequency_hz : 0.0;
  u.push_time_s = options.push_time_s.value_or(std::min(kDefaultPushTimeS, u.duration_s / 3.0));
  // Directions on the contract's surface, the plane z = 0 with normal +z: off it; down the
  // slope (gravity along the surface; on a level surface, against the travel); across.
  const std::unique_ptr<sim::CompiledModel> model =
      sim::CompiledModel::Build(base, sim::MjcfAdditions{});
  sim::World world(*model, base);
  u.robot_mass_kg = model->robot().mass_kg;
  const Eigen::Vector3d z(0, 0, 1);
  Eigen::Vector3d g = world.gravity();
  Eigen::Vector3d along = g - g.dot(z) * z;
  if (along.norm() < 1e-6 * std::max(1.0, g.norm())) {
    along = -(model->scene().travel - model->scene().travel.dot(z) * z);
  }
  if (along.norm() > 0) u.down = along.normalized();
  u.side = z.cross(u.down).normalized();
  return u;
}

// Why the scenario cannot take a family, "" when it can.
std::string CannotTakeFamily(const DisturbanceSetup& u, const std::string& family) {
  if (family.rfind("push_", 0) == 0 && u.frequency_hz <= 0) {
    return "it has no cpg (the pushes are timed by its gait)";
  }
  const bool adhesion_family = family == "pad_failure" || family == "weak_patch";
  if (adhesion_family && !u.base.adhesion) return "it has no adhesion";
  if (family == "weak_patch" && u.base.adhesion->model != "bonds") {
    return "its adhesion.model is '" + u.base.adhesion->model + "', not bonds";
  }
  const bool surface_family =
      family == "weak_patch" || family == "roughness" || family == "terrain";
  if (surface_family && !PlaneScene(u.base)) {
    return "its scene '" + u.base.scene.name + "' is not a plane (floor, wall, ceiling, incline)";
  }
  // The search sets these keys itself: the scenario's own would be silently replaced.
  if (family == "roughness" && u.base.scene.roughness) {
    return "it sets scene.roughness itself (the search replaces it: remove it)";
  }
  if (family == "terrain" && u.base.scene.terrain) {
    return "it sets scene.terrain itself (the search replaces it: remove it)";
  }
  if ((family == "terrain" && u.base.scene.roughness) ||
      (family == "roughness" && u.base.scene.terrain)) {
    return "it sets scene.roughness or scene.terrain (bumps and rock do not combine)";
  }
  if (family == "weak_patch" && u.base.scene.weak_patches) {
    return "it sets scene.weak_patches itself (the search replaces it: remove it)";
  }
  if (family == "pad_failure" && u.base.adhesion->pad_failure_probability > 0) {
    return "it sets adhesion.pad_failure_probability itself (the search replaces it: remove it)";
  }
  return "";
}

double DisturbancePushTime(const DisturbanceSetup& u, int phase) {
  return u.push_time_s + phase / (u.options.phases * u.frequency_hz);
}

sim::Scenario DisturbanceCase(const DisturbanceSetup& u, const std::string& family,
                              double magnitude, int mode, int seed, int phase) {
  sim::Scenario s = u.base;
  s.duration_s = u.duration_s;
  s.fall.stop = true;
  s.outputs.trajectory_rate_hz = 0.0;
  ApplyCaseSeed(&s, seed);
  if (mode == 1 && s.reflex) {
    s.reflex->spindle.enabled = false;
    s.reflex->gto.enabled = false;
  }
  if (family.empty() || magnitude <= 0) return s;
  if (family.rfind("push_", 0) == 0) {
    const Eigen::Vector3d dir = family == "push_off"    ? u.off
                                : family == "push_down" ? u.down
                                                        : u.side;
    sim::PushParams p;
    p.time_s = DisturbancePushTime(u, phase);
    p.body = "base";
    p.impulse_ns = {magnitude * dir.x(), magnitude * dir.y(), magnitude * dir.z()};
    p.duration_s = kPushDuration;
    s.perturbations.push_back(p);
  } else if (family == "payload") {
    s.payload_kg += magnitude;
  } else if (family == "pad_failure") {
    s.adhesion->pad_failure_probability = std::min(1.0, magnitude);
  } else if (family == "weak_patch") {
    sim::WeakPatchParams w;
    w.fraction = std::max(1e-6, 1.0 - magnitude);
    w.size_m = 0.05;
    w.coverage = 0.3;
    s.scene.weak_patches = w;
  } else if (family == "roughness") {
    sim::RoughnessParams r;
    r.height_m = magnitude;
    s.scene.roughness = r;
  } else if (family == "terrain") {
    sim::TerrainParams t;
    t.rms_m = magnitude;
    t.seed = seed + 1;
    s.scene.terrain = t;
  } else {
    throw InputError("climbsim bench robustness", 0, 0, "--families",
                     "unknown family '" + family + "'");
  }
  return s;
}

bool SurvivedRun(const sim::RunResult& r, double baseline_m, std::string* how) {
  char buf[160];
  if (!r.stable) {
    if (how) *how = "unstable: " + r.failure;
    return false;
  }
  if (r.fell) {
    std::snprintf(buf, sizeof(buf), "fell at %.2f s", r.fall_time_s);
    if (how) *how = buf;
    return false;
  }
  if (baseline_m > 0 && r.distance_m < 0.5 * baseline_m) {
    std::snprintf(buf, sizeof(buf), "climbed %.3f m of %.3f m", r.distance_m, baseline_m);
    if (how) *how = buf;
    return false;
  }
  return true;
}

}  // namespace climbsim::optimise
