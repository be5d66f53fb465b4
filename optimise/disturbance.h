// The disturbance cases of `climbsim bench robustness` (experiments/robustness.cc) and of the
// objective's robustness term (optimise.objective.robustness): how one case's scenario is
// built and whether its run survived, declared once so that the optimiser's cases are the
// bench's (experiments/experiments.h states the families, the cases and the rule).
#ifndef CLIMBSIM_OPTIMISE_DISTURBANCE_H_
#define CLIMBSIM_OPTIMISE_DISTURBANCE_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "sim/sim.h"

namespace climbsim::optimise {

// A push lasts 10 ms (an impulse, faster than any reflex); the first comes at 4 s, or a third
// of the run when that is earlier.
inline constexpr double kPushDuration = 0.01;
inline constexpr double kDefaultPushTimeS = 4.0;

struct RobustnessOptions {
  double duration_s = 10.0;   // 0: the scenario's
  int seeds = 3;
  int phases = 4;
  // First push, at most a third of the duration (else InputError); default: 4 s, or a
  // third of the duration when that is earlier.
  std::optional<double> push_time_s;
  double tolerance = 0.1;
  int threads = 0;            // 0: all cores
  std::vector<std::string> families;  // empty: all
};

struct RobustnessFamily {
  std::string name, unit, what;
  double lo = 0.0, hi = 0.0;
  bool named_only = false;  // searched only when --families names it (each run costs more)
};
// Every family in table order, ranges resolved for a robot of `robot_mass_kg` (payload's).
std::vector<RobustnessFamily> AllRobustnessFamilies(double robot_mass_kg);

// Seed case k of a scenario: its seed + k for every random draw and, for k ≥ 1, a start moved
// by up to ±5 mm along x and y and turned by up to ±5° (uniform draws from that seed), so the
// cases differ even where nothing else is random. k = 0 leaves the scenario as it is.
void ApplyCaseSeed(sim::Scenario* scenario, int k);

// What every case of a scenario shares: the run's length, the push directions and times.
struct DisturbanceSetup {
  sim::Scenario base;
  RobustnessOptions options;
  double duration_s = 0.0;
  double frequency_hz = 0.0;  // 0: no cpg, no push families
  double push_time_s = 0.0;
  Eigen::Vector3d off{0, 0, 1}, down{-1, 0, 0}, side{0, 1, 0};
  double robot_mass_kg = 0.0;
};
// Compiles the scenario's model once (gravity, travel, mass).
DisturbanceSetup MakeDisturbanceSetup(const sim::Scenario& base, const RobustnessOptions& options);

// Why the scenario cannot take `family`, "" when it can.
std::string CannotTakeFamily(const DisturbanceSetup& setup, const std::string& family);

// Phase j's push time, s: the first push plus j/phases of a gait cycle.
double DisturbancePushTime(const DisturbanceSetup& setup, int phase);

// One case at one magnitude: mode 0 the scenario's reflexes, 1 spindle and GTO off;
// magnitude 0 (or family "") is the undisturbed case. Throws InputError for an unknown family.
sim::Scenario DisturbanceCase(const DisturbanceSetup& setup, const std::string& family,
                              double magnitude, int mode, int seed, int phase);

// The bench's "survived": the run was stable, did not fall, and climbed at least half of
// `baseline_m` (the same case undisturbed) when that is positive. `how` (may be null) says
// why not.
bool SurvivedRun(const sim::RunResult& run, double baseline_m, std::string* how);

}  // namespace climbsim::optimise

#endif  // CLIMBSIM_OPTIMISE_DISTURBANCE_H_
