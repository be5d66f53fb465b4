// The adhesion effect allocates nothing in the step loop: every operator new and malloc of
// the program is counted (tests/common/alloc_counter) while scenarios with adhesion step
// through attaches, bond losses and detaches.
#include <gtest/gtest.h>

#include "sim/adhesion_effect.h"
#include "sim/sim.h"
#include "tests/common/alloc_counter.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

void ExpectNoAllocation(const std::string& name, const std::string& text, int steps) {
  const Scenario s = LoadScenario(climbsim::testing::WriteFile(name, text));
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  ASSERT_TRUE(sim.Step());
  AdhesionEffect* a = FindAdhesion(sim.effects());
  ASSERT_NE(a, nullptr);
  bool ok = true;
  const auto counts = climbsim::testing::CountAllocations([&] {
    for (int i = 0; i < steps; ++i) ok &= sim.Step();
    a->RequestRelease(0);  // the controller API too
    for (int i = 0; i < 50; ++i) ok &= sim.Step();
  });
  EXPECT_TRUE(ok);
  EXPECT_EQ(counts.news, 0) << name;
  EXPECT_EQ(counts.mallocs, 0) << name;
  long attaches = 0, detaches = 0, losses = 0;
  for (int i = 0; i < a->pad_count(); ++i) {
    const auto& c = a->pad(i).counts();
    attaches += c.attach;
    detaches += c.detach_peel + c.detach_overload + c.detach_released + c.detach_contact_lost;
    losses += c.bonds_lost;
  }
  ::testing::Test::RecordProperty("attaches", std::to_string(attaches));
  EXPECT_GT(attaches, 0) << name;
  EXPECT_GT(detaches, 0) << name;
  if (text.find("mujoco") == std::string::npos) {
    EXPECT_GT(losses, 0) << name;
  }
}

// The gecko trotting on the floor with the bond model: touchdowns, rejections, attaches,
// bonds lost, detaches (the swing legs tear their pads off), all in 2000 steps.
TEST(AdhesionAllocation, BondModelStepLoopAllocatesNothing) {
  ExpectNoAllocation("alloc_bonds.yaml",
                     "robot: gecko\nscene: floor\nduration_s: 3\nadhesion:\n  grid_x: 32\n"
                     "  grid_y: 32\ncpg:\n  gait: trot\noutputs:\n  trajectory_rate_hz: 200\n",
                     2000);
}

// The same with MuJoCo's adhesion actuator.
TEST(AdhesionAllocation, MujocoModelStepLoopAllocatesNothing) {
  ExpectNoAllocation("alloc_mujoco.yaml",
                     "robot: spider\nscene: wall\nduration_s: 3\nadhesion:\n  model: mujoco\n"
                     "  start_attached: true\ncpg:\n  gait: tripod\n",
                     1500);
}

}  // namespace
}  // namespace climbsim::sim
