// A controller of one's own, built against an installed climbsim: a bang-bang trot for the
// gecko on the floor, no CPG. The legs go in two diagonal pairs (LF+RH, RF+LH); a cycle of
// period_s has six equal parts, and in each the servo targets jump to fixed values:
//   1 pair A lifts     2 A swings forward, B pushes back     3 A lands
//   4 pair B lifts     5 B swings forward, A pushes back     6 B lands
// Joint order per leg: hip_yaw (> 0 swings the pad forward), hip_pitch (> 0 lifts), knee.
//
//   bang_bang_gecko [duration_s] [run_dir]
// prints the distance walked; writes a run folder when run_dir is given.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "sim/sim.h"

namespace {

using climbsim::sim::Command;
using climbsim::sim::Controller;
using climbsim::sim::Observation;

class BangBangTrot final : public Controller {
 public:
  BangBangTrot(double period_s, double yaw_rad, double lift_rad)
      : period_s_(period_s), yaw_(yaw_rad), lift_(lift_rad) {}
  const char* name() const override { return "bang_bang_trot"; }
  double control_period_s() const override { return 0.01; }  // 100 Hz

  void Update(const Observation& obs, Command* cmd) override {
    const double u = std::fmod(obs.time_s / period_s_, 1.0);
    const int part = static_cast<int>(u * 6.0);  // 0..5
    for (int leg = 0; leg < obs.legs; ++leg) {
      const bool pair_a = leg == 0 || leg == 3;      // LF, RH (leg order LF RF LH RH)
      const int p = pair_a ? part : (part + 3) % 6;  // pair B runs half a cycle later
      // This leg's part: 0 lift, 1 swing forward, 2 land, 3 wait, 4 push back, 5 wait.
      const double yaw = p >= 1 && p <= 3 ? yaw_ : -yaw_;
      const double pitch = p <= 1 ? lift_ : 0.0;
      cmd->target_rad[3 * leg + 0] = yaw;
      cmd->target_rad[3 * leg + 1] = pitch;
      cmd->target_rad[3 * leg + 2] = 0.5 * pitch;
    }
  }

 private:
  double period_s_, yaw_, lift_;
};

}  // namespace

int main(int argc, char** argv) {
  const double duration_s = argc > 1 ? std::atof(argv[1]) : 5.0;
  try {
    // A scenario without a cpg block: the controller alone drives the servos.
    const std::string yaml =
        "robot: gecko\nscene: floor\nduration_s: " + std::to_string(duration_s) + "\n";
    const climbsim::sim::Scenario s =
        climbsim::sim::ParseScenario(YAML::Load(yaml), "bang_bang_gecko.yaml");
    auto model = climbsim::sim::CompileScenario(s);
    auto controller = std::make_shared<BangBangTrot>(0.6, 0.3, 0.4);
    climbsim::sim::Simulation sim(s, *model, controller);
    const climbsim::sim::RunResult r = sim.Run();
    std::printf("mjcf_dir %s\n", climbsim::sim::MjcfDir().c_str());
    std::printf("controller %s\n", sim.Summary()["effects"].dump().c_str());
    std::printf("stable %d\n", r.stable ? 1 : 0);
    std::printf("distance_m %.6f\n", r.distance_m);
    std::printf("heading_deg %.3f\n", r.heading_deg);
    if (argc > 2) climbsim::sim::WriteRunDirectory(argv[2], sim);
    return r.stable ? 0 : 1;
  } catch (const climbsim::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
}
