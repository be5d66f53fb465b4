// Nothing allocates in the step: every operator new and malloc of this executable is counted
// (tests/common/alloc_counter). The loop does what the simulation does every step
// (Update, queries) plus the attachment changes, with cascades and degenerate sets.
#include <gtest/gtest.h>

#include "adhesion/bond_grid.h"
#include "tests/common/alloc_counter.h"

namespace climbsim::adhesion {
namespace {

TEST(PadAllocation, CounterSeesAllocations) {
  // Through a volatile pointer the compiler may not elide the allocation.
  int* volatile p = nullptr;
  const auto counts = climbsim::testing::CountAllocations([&] { p = new int(3); });
  delete p;
  EXPECT_EQ(counts.news, 1);
}

TEST(PadAllocation, UpdateNeverAllocatesAfterConstruction) {
  PadParams small;
  small.width_m = 0.02;
  small.length_m = 0.01;
  small.grid_x = 1;
  small.grid_y = 1;
  PadParams big = small;
  big.grid_x = 32;
  big.grid_y = 32;
  big.mu = 0.5;
  big.min_bonds = 10;
  BondGrid one(small);
  BondGrid grid(big);
  const double capacity = big.sigma_t_pa * 0.02 * 0.01;

  long broken = 0;
  double sink = 0.0;
  const auto counts = climbsim::testing::CountAllocations([&] {
  for (int k = 0; k < 1000; ++k) {
    switch (k % 4) {
      case 0: grid.BondAll(); break;
      case 1: grid.BondFraction(0.1 + 0.0009 * k); break;
      case 2: grid.Grow(0.95); break;
      default: break;  // keep what is left
    }
    one.BondAll();
    // From holding loads to cascades, pulling and pushing, with moments.
    const double f = capacity * (0.05 + 0.001 * k);
    const double angle = 0.003 * k;
    const PadLoad load{.fn_n = f * std::cos(angle),
                       .fx_n = f * std::sin(angle),
                       .fy_n = 0.1 * f,
                       .mx_nm = 1e-3 * f * std::sin(0.1 * k),
                       .my_nm = 0.004 * f * std::sin(angle)};
    const BondGrid::UpdateResult r = grid.Update(load);
    broken += r.broken + one.Update(load).broken;
    sink += grid.Evaluate(load).peak_utilisation + grid.stress(k % grid.size()).von_mises_pa;
    for (const BrokenBond& b : grid.last_broken()) sink += b.round;
    sink += PadLoadFromSurfaceWrench(Eigen::Vector3d(f, 0, -f), Eigen::Vector3d(0, f, 0)).fn_n;
  }
  });
  EXPECT_EQ(counts.total(), 0);
  EXPECT_GT(broken, 1000);  // the loop did break bonds, in cascades
  EXPECT_TRUE(std::isfinite(sink) || std::isinf(sink));
}

}  // namespace
}  // namespace climbsim::adhesion
