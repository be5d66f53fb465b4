// A user's controller in the step loop: nothing is allocated (every operator new and malloc
// of the program is counted) while a C++ controller drives the gecko, alone or on top of the
// built-in CPG.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/sim.h"
#include "tests/common/alloc_counter.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

class Sine final : public Controller {
 public:
  double control_period_s() const override { return 0.005; }
  void Update(const Observation& obs, Command* cmd) override {
    for (int leg = 0; leg < obs.legs; ++leg) {
      cmd->offset_rad[3 * leg + 1] = 0.1 * std::sin(2 * M_PI * obs.time_s + leg);
      cmd->release[leg] = obs.pads[leg].utilisation > 2.0;
    }
    ++ticks;
  }
  long ticks = 0;
};

void ExpectNoAllocation(const std::string& name, const std::string& text) {
  // Steps after a fall must not allocate either: the run goes on through it.
  const Scenario s =
      LoadScenario(climbsim::testing::WriteFile(name, text + "fall: {stop: false}\n"));
  auto model = CompileScenario(s);
  auto c = std::make_shared<Sine>();
  Simulation sim(s, *model, c);
  ASSERT_TRUE(sim.Step());
  bool ok = true;
  const auto counts = climbsim::testing::CountAllocations([&] {
    for (int i = 0; i < 1000; ++i) ok &= sim.Step();
  });
  EXPECT_TRUE(ok);
  EXPECT_GT(c->ticks, 100);
  EXPECT_EQ(counts.news, 0) << name;
  EXPECT_EQ(counts.mallocs, 0) << name;
}

TEST(ControllerAllocation, UserControllerAloneAllocatesNothing) {
  ExpectNoAllocation("alloc_user.yaml",
                     "robot: gecko\nscene: wall\nduration_s: 2\nadhesion:\n"
                     "  start_attached: true\noutputs:\n  trajectory_rate_hz: 100\n");
}

TEST(ControllerAllocation, UserControllerOnTheCpgAndReflexesAllocatesNothing) {
  ExpectNoAllocation("alloc_user_cpg.yaml",
                     "robot: gecko\nscene: wall\nduration_s: 2\nadhesion:\n"
                     "  start_attached: true\ncpg:\n  gait: trot\nreflex: {}\n");
}

}  // namespace
}  // namespace climbsim::sim
