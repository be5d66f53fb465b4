// Update never allocates (STYLE.md §7): global operator new is replaced by a counting one for
// this test executable, and the count over 1000 updates after construction must be 0.
// Eigen is used only with fixed-size types here, which never touch the heap.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "reflex/reflex.h"

namespace {
std::atomic<long> g_allocations{0};
std::atomic<bool> g_counting{false};

void* CountedAlloc(std::size_t size) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t size) { return CountedAlloc(size); }
void* operator new[](std::size_t size) { return CountedAlloc(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace climbsim::reflex {
namespace {

// Counts allocations between construction and destruction of a scope.
class AllocationCounter {
 public:
  AllocationCounter() {
    g_allocations = 0;
    g_counting = true;
  }
  ~AllocationCounter() { g_counting = false; }
  long count() const { return g_allocations.load(); }
};

TEST(ReflexNoAlloc, CounterSeesAllocations) {
  AllocationCounter counter;
  auto* p = new int(3);
  delete p;
  EXPECT_EQ(counter.count(), 1);
}

// A script that drives every reflex: touchdown and preload, a failed swing and a search,
// peeling, bond loss and re-grip, loads, stretches.
TEST(ReflexNoAlloc, LegReflexUpdateNeverAllocates) {
  LegReflex leg(LegReflexParams{}, 0.002);
  DelayLine line(7);
  SpindleReflex spindle(SpindleParams{}, 0.002);
  GtoReflex gto(GtoParams{}, 0.002);
  LegSensing s;
  long allocations = 0;
  uint32_t fired = 0;
  int events = 0;
  {
    AllocationCounter counter;
    for (int k = 0; k < 1000; ++k) {
      const int phase = k % 200;
      s.stance = phase < 120;
      s.phase_progress = s.stance ? phase / 120.0 : (phase - 120) / 80.0;
      const bool failed_step = (k / 200) % 2 == 1;
      // Normal steps touch down at phase 3 and stay on into the swing (peel); failed steps
      // touch down only at phase 61 (search).
      s.touching = failed_step ? (phase > 60 && phase < 124) : (phase > 2 && phase < 124);
      s.attached = s.touching && phase > 10;
      s.bonded_fraction = s.attached ? 0.5 : 0.0;
      s.normal_load_n = s.attached && phase < 90 ? 0.4 : 0.0;
      s.preload_n = s.touching ? 0.3 : 0.0;
      s.bonds_lost = phase == 50 || phase == 125;
      s.partner_attached = phase % 97 != 0;
      s.stretch_rad = Eigen::Vector3d(0.1, -0.2, 0.3) * std::sin(0.05 * k);
      s.stretch_velocity_rad_per_s = Eigen::Vector3d(1.0, -2.0, 3.0) * std::cos(0.05 * k);
      const LegReflexOutput out = leg.Update(s);
      fired |= out.fired;
      events += out.events.size();
      line.Update(k);
      spindle.Update(0.1 * k, 0.0);
      gto.Update(0.01 * k);
    }
    allocations = counter.count();
  }
  EXPECT_EQ(allocations, 0);
  EXPECT_EQ(fired, (1u << 7) - 1) << "every reflex should have acted in the script";
  EXPECT_GT(events, 10);
}

// Load sharing over six legs, legs letting go and landing, above and below its threshold.
TEST(ReflexNoAlloc, LoadSharingUpdateNeverAllocates) {
  LoadSharingParams p;
  p.gain_per_s = 50.0;
  LoadSharing sharing(p, 0.001);
  std::array<SharingLeg, 6> legs;
  long allocations = 0;
  double total = 0.0;
  {
    AllocationCounter counter;
    for (int k = 0; k < 1000; ++k) {
      for (int i = 0; i < 6; ++i) {
        legs[i].active = (k / 50 + i) % 6 != 0;
        legs[i].position_m = Eigen::Vector3d(0.1 * (i % 3 - 1), i < 3 ? 0.1 : -0.1, 0.0);
        legs[i].utilisation = 0.5 + 0.4 * std::sin(0.01 * k + i);
        legs[i].gradient_per_n = Eigen::Vector3d(1.0, 0.3 * i, 0.5 * std::cos(0.02 * k));
      }
      total += sharing.Update(legs.data(), 6)[0].norm();
    }
    allocations = counter.count();
  }
  EXPECT_EQ(allocations, 0);
  EXPECT_GT(total, 0.0);  // it acted
}

}  // namespace
}  // namespace climbsim::reflex
