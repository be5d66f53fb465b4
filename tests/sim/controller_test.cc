// The controller interface (sim/controller.h): the built-in CPG runs through it, a user's
// controller sees its command and changes it exactly as documented, a controller that
// replays the built-in's commands reproduces its run bit for bit, and releases act.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "sim/sim.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::WriteFile;

// The gecko on the wall with pads and a CPG, no reflexes (their releases go through the
// adhesion effect, not the command).
constexpr const char* kWall =
    "robot: gecko\nscene: wall\nduration_s: 1.5\nadhesion:\n  start_attached: true\n"
    "cpg:\n  gait: trot\n  frequency_hz: 1.0\n  control_period_s: 0.01\n"
    "outputs:\n  trajectory_rate_hz: 100\n"
    "fall:\n  stop: false\n";  // the trot without reflexes falls; the interface runs on

Scenario Load(const std::string& name, const std::string& text) {
  return LoadScenario(WriteFile(name, text));
}

// Records every command and the start pose it sees (after the built-in in the chain).
class Recorder final : public Controller {
 public:
  const char* name() const override { return "recorder"; }
  void InitialPose(StartPose* pose) override {
    start_q.assign(pose->joint_angle_rad.begin(), pose->joint_angle_rad.end());
    start_base = pose->base_pos_m;
  }
  void Update(const Observation& obs, Command* cmd) override {
    steps.push_back(obs.step);
    targets.insert(targets.end(), cmd->target_rad.begin(), cmd->target_rad.end());
    phases.insert(phases.end(), obs.cpg_phase_rad.begin(), obs.cpg_phase_rad.end());
  }
  std::vector<double> start_q;
  std::array<double, 3> start_base{};
  std::vector<long> steps;
  std::vector<double> targets, phases;
};

// Writes recorded targets back, tick by tick, with the recorded start pose; no CPG.
class Replay final : public Controller {
 public:
  Replay(const Recorder& r, double period_s) : r_(r), period_s_(period_s) {}
  double control_period_s() const override { return period_s_; }
  void InitialPose(StartPose* pose) override {
    std::copy(r_.start_q.begin(), r_.start_q.end(), pose->joint_angle_rad.begin());
    pose->base_pos_m = r_.start_base;
  }
  void Reset() override { tick_ = 0; }
  void Update(const Observation& obs, Command* cmd) override {
    const size_t n = cmd->target_rad.size();
    ASSERT_EQ(obs.step, r_.steps[tick_]);
    for (size_t k = 0; k < n; ++k) cmd->target_rad[k] = r_.targets[tick_ * n + k];
    ++tick_;
  }

 private:
  const Recorder& r_;
  double period_s_;
  size_t tick_ = 0;
};

TEST(Controller, BuiltInCpgIsOneControllerAndAUserSeesItsCommand) {
  const Scenario s = Load("ctl_wall.yaml", kWall);
  auto model = CompileScenario(s);
  Simulation plain(s, *model);
  ASSERT_NE(plain.controller(), nullptr);
  EXPECT_STREQ(plain.controller()->name(), "cpg");
  EXPECT_EQ(plain.controller()->period_steps(), 10);
  plain.Run();

  auto rec = std::make_shared<Recorder>();
  Simulation observed(s, *model, rec);
  EXPECT_STREQ(observed.controller()->name(), "cpg+recorder");
  observed.Run();
  // A controller that changes nothing changes nothing, bit for bit.
  EXPECT_EQ(plain.TrajectoryCsv(), observed.TrajectoryCsv());
  EXPECT_EQ(plain.EventsCsv(), observed.EventsCsv());
  ASSERT_EQ(rec->steps.size(), 150u);  // 1.5 s at 10 ms
  EXPECT_EQ(rec->steps[1], 10);
  // The CPG phases it sees advance at 1 Hz: 2π·0.01 per tick.
  const size_t legs = 4;
  const double d = std::remainder(rec->phases[legs * 2] - rec->phases[legs * 1], 2 * M_PI);
  EXPECT_NEAR(d, 2 * M_PI * 0.01, 1e-3);
}

TEST(Controller, ReplayingTheBuiltInCommandsReproducesItsRunBitForBit) {
  const Scenario s = Load("ctl_wall.yaml", kWall);
  auto model = CompileScenario(s);
  auto rec = std::make_shared<Recorder>();
  Simulation original(s, *model, rec);
  const RunResult a = original.Run();
  ASSERT_TRUE(a.stable);

  // The same scenario without its cpg block: only the replay drives the servos.
  std::string text = kWall;
  text.replace(text.find("cpg:"), text.find("outputs:") - text.find("cpg:"), "");
  const Scenario bare = Load("ctl_wall_bare.yaml", text);
  auto bare_model = CompileScenario(bare);
  Simulation replayed(bare, *bare_model, std::make_shared<Replay>(*rec, 0.01));
  const RunResult b = replayed.Run();
  EXPECT_EQ(original.TrajectoryCsv(), replayed.TrajectoryCsv());
  EXPECT_EQ(original.EventsCsv(), replayed.EventsCsv());
  EXPECT_EQ(a.distance_m, b.distance_m);
  EXPECT_GT(original.events().rows().size(), 0u);
}

// Offsets are added to the targets; the servos get exactly target + offset.
class Offset final : public Controller {
 public:
  void Update(const Observation&, Command* cmd) override {
    for (double& o : cmd->offset_rad) o = 0.05;
    last.assign(cmd->target_rad.begin(), cmd->target_rad.end());
  }
  std::vector<double> last;
};

TEST(Controller, OffsetsActOnTopOfTheCpg) {
  const Scenario s = Load("ctl_wall.yaml", kWall);
  auto model = CompileScenario(s);
  auto off = std::make_shared<Offset>();
  Simulation sim(s, *model, off);
  for (int i = 0; i < 25; ++i) ASSERT_TRUE(sim.Step());
  const RobotInfo& r = sim.world().robot();
  for (size_t i = 0; i < r.legs.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(sim.world().data()->ctrl[r.legs[i].actuator[k]], off->last[3 * i + k] + 0.05);
    }
  }
  EXPECT_EQ(sim.controller()->command().offset_rad[0], 0.05);
}

// A release lets the pad go at that tick: a detach event with cause "released".
class ReleaseLeg0 final : public Controller {
 public:
  void Update(const Observation& obs, Command* cmd) override {
    if (obs.step == 200) {
      EXPECT_TRUE(obs.pads[0].attached);
      EXPECT_GT(obs.pads[0].bonded_fraction, 0.5);
      cmd->release[0] = 1;
    }
  }
};

TEST(Controller, ReleaseLetsThePadGo) {
  const Scenario s =
      Load("ctl_hold.yaml",
           "robot: gecko\nscene: wall\nduration_s: 0.3\nadhesion:\n  start_attached: true\n");
  auto model = CompileScenario(s);
  auto c = std::make_shared<ReleaseLeg0>();
  Simulation sim(s, *model, c);
  sim.Run();
  int released = 0;
  for (const Event& e : sim.events().rows()) {
    if (std::string(e.kind) == "detach" && std::string(e.cause) == "released") {
      EXPECT_EQ(e.pad, 0);
      EXPECT_NEAR(e.time_s, 0.2, 0.0015);
      ++released;
    }
  }
  EXPECT_EQ(released, 1);
}

// A controller's period is a whole multiple of the time step, or 0; any other value (negative,
// NaN, a fraction of a step, one beyond the run's step budget) is refused when the run is
// built, for a C++ controller as for a Python one, instead of being rounded to a step count.
class FixedPeriod final : public Controller {
 public:
  explicit FixedPeriod(double period_s) : period_s_(period_s) {}
  double control_period_s() const override { return period_s_; }
  void Update(const Observation&, Command*) override {}

 private:
  double period_s_;
};

TEST(Controller, APeriodThatIsNotAWholeNumberOfStepsIsRefused) {
  Scenario s = Load("period.yaml", "robot: gecko\nscene: floor\nduration_s: 0.05\n");
  auto model = CompileScenario(s);
  const double dt = model->model()->opt.timestep;
  for (double bad : {-1.0, std::nan(""), 1e300, 1.5 * dt, 0.25 * dt}) {
    EXPECT_THROW(Simulation run(s, *model, std::make_shared<FixedPeriod>(bad)), InputError) << bad;
  }
  for (double good : {0.0, dt, 3 * dt}) {
    EXPECT_NO_THROW(Simulation run(s, *model, std::make_shared<FixedPeriod>(good))) << good;
  }
}

}  // namespace
}  // namespace climbsim::sim
