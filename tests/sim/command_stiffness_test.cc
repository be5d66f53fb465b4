// Command::kp_scale (sim/controller.h): a controller sets a servo's stiffness as a fraction
// of its own kp, clamped to [0, 1], and the built-in reflexes' stance compliance writes the
// same field, where a later controller of the chain reads and may undo it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include "sim/sim.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::WriteFile;

// The gecko standing on the floor, its servos holding the neutral pose (no CPG).
constexpr const char* kStand =
    "robot: gecko\nscene: floor\nduration_s: 1.0\noutputs:\n  trajectory_rate_hz: 0\n";

// Holds the start pose and scales three joints: LF hip_pitch to 0.25, LF knee asks 3 (more
// than the servo has: clamped to 1), RF hip_pitch asks -1 (clamped to 0).
class Soft final : public Controller {
 public:
  explicit Soft(double scale) : scale_(scale) {}
  double control_period_s() const override { return 0.01; }
  void Update(const Observation& obs, Command* cmd) override {
    if (hold_.empty()) hold_.assign(obs.joint_angle_rad.begin(), obs.joint_angle_rad.end());
    std::copy(hold_.begin(), hold_.end(), cmd->target_rad.begin());
    cmd->kp_scale[1] = scale_;
    cmd->kp_scale[2] = 3.0;
    cmd->kp_scale[4] = -1.0;
    sag_rad = std::abs(obs.joint_angle_rad[1] - hold_[1]);
  }
  double sag_rad = 0.0;

 private:
  double scale_;
  std::vector<double> hold_;
};

TEST(CommandStiffness, AUserScalesAServosKpWithinZeroAndOne) {
  const Scenario s = LoadScenario(WriteFile("kp_stand.yaml", kStand));
  auto model = CompileScenario(s);
  double sag[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    auto soft = std::make_shared<Soft>(k == 0 ? 1.0 : 0.25);
    Simulation sim(s, *model, soft);
    const mjModel* m = sim.world().model();
    const auto& leg = sim.world().robot().legs;
    const double kp_pitch = ServoKp(m, leg[0].actuator[1]);
    const double kp_knee = ServoKp(m, leg[0].actuator[2]), kp_yaw = ServoKp(m, leg[1].actuator[0]);
    ASSERT_TRUE(sim.Run().stable);
    sag[k] = soft->sag_rad;
    const double want = k == 0 ? kp_pitch : 0.25 * kp_pitch;
    EXPECT_EQ(m->actuator_gainprm[leg[0].actuator[1] * mjNGAIN], want);
    EXPECT_EQ(m->actuator_biasprm[leg[0].actuator[1] * mjNBIAS + 1], -want);
    EXPECT_EQ(ServoKp(m, leg[0].actuator[2]), kp_knee);
    EXPECT_EQ(ServoKp(m, leg[1].actuator[1]), 0.0);
    EXPECT_EQ(ServoKp(m, leg[1].actuator[0]), kp_yaw);
  }
  // A quarter of the stiffness under the same load: the joint gives way about four times as
  // far (at least twice, whatever else the posture does).
  EXPECT_GT(sag[1], 2.0 * sag[0]) << sag[0] << " " << sag[1];
}

class NanScale final : public Controller {
 public:
  void Update(const Observation&, Command* cmd) override { cmd->kp_scale[0] = std::nan(""); }
};

TEST(CommandStiffness, NanIsRefused) {
  const Scenario s = LoadScenario(WriteFile("kp_stand.yaml", kStand));
  auto model = CompileScenario(s);
  Simulation sim(s, *model, std::make_shared<NanScale>());
  EXPECT_THROW(sim.Run(), std::invalid_argument);
}

// The gecko on the wall with stance compliance: attached stance legs at half stiffness (the
// GTO's unloading, which would lower it further, off).
constexpr const char* kCompliant =
    "robot: gecko\nscene: wall\nduration_s: 0.6\nadhesion:\n  start_attached: true\n"
    "cpg:\n  gait: trot\n  frequency_hz: 1.0\n  control_period_s: 0.01\n"
    "reflex:\n  compliance: {enabled: true, stance_kp_fraction: 0.5, ramp_s: 0}\n"
    "  gto: {enabled: false}\n"
    "outputs:\n  trajectory_rate_hz: 0\nfall:\n  stop: false\n";

// After the built-in controller: records the stiffness it commanded and, with `stiff`,
// writes every servo back to full stiffness; checks the model holds what the last tick
// commanded.
class AfterReflexes final : public Controller {
 public:
  explicit AfterReflexes(bool stiff) : stiff_(stiff) {}
  void Update(const Observation&, Command* cmd) override {
    if (model != nullptr && !last_.empty()) {
      for (size_t j = 0; j < last_.size(); ++j) {
        EXPECT_EQ(ServoKp(model, actuator[j]), own_kp[j] * last_[j]) << j;
      }
    }
    for (double f : cmd->kp_scale) least = std::min(least, f);
    if (stiff_) std::fill(cmd->kp_scale.begin(), cmd->kp_scale.end(), 1.0);
    last_.assign(cmd->kp_scale.begin(), cmd->kp_scale.end());
  }
  const mjModel* model = nullptr;
  std::vector<int> actuator;
  std::vector<double> own_kp;
  double least = 1.0;

 private:
  bool stiff_;
  std::vector<double> last_;
};

TEST(CommandStiffness, TheReflexesComplianceGoesThroughTheCommandAndCanBeUndone) {
  const Scenario s = LoadScenario(WriteFile("kp_compliant.yaml", kCompliant));
  auto model = CompileScenario(s);
  for (const bool stiff : {false, true}) {
    auto after = std::make_shared<AfterReflexes>(stiff);
    Simulation sim(s, *model, after);
    after->model = sim.world().model();
    for (const LegInfo& leg : sim.world().robot().legs) {
      for (int k = 0; k < 3; ++k) {
        after->actuator.push_back(leg.actuator[k]);
        after->own_kp.push_back(ServoKp(after->model, leg.actuator[k]));
      }
    }
    ASSERT_TRUE(sim.Run().stable);
    // The built-in's command carries the stance stiffness, exactly the fraction asked for.
    EXPECT_EQ(after->least, 0.5) << stiff;
  }
}

}  // namespace
}  // namespace climbsim::sim
