// Step never allocates: every global operator new (and, on glibc without sanitizers, every
// malloc, which is what Eigen and C code call) is counted while the networks step.
// Its own executable, because replacing operator new and malloc applies to the whole program.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "cpg/cpg.h"

namespace {
std::atomic<long> g_new_calls{0};
std::atomic<long> g_malloc_calls{0};
void* volatile g_sink = nullptr;
}  // namespace

// GCC sees our replacement delete call free() on memory from operator new and warns; that pair
// is exactly what this file defines (new = malloc, delete = free).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif

// Every replaceable allocation form; the array and nothrow ones do not all route through the
// plain one in libstdc++, so each is counted itself.
void* operator new(std::size_t size) {
  g_new_calls.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return operator new(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  g_new_calls.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(size == 0 ? 1 : size);
}
void* operator new[](std::size_t size, const std::nothrow_t& tag) noexcept {
  return operator new(size, tag);
}
void* operator new(std::size_t size, std::align_val_t align) {
  g_new_calls.fetch_add(1, std::memory_order_relaxed);
  const std::size_t a = static_cast<std::size_t>(align);
  if (void* p = std::aligned_alloc(a, (size + a - 1) / a * a)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size, std::align_val_t align) { return operator new(size, align); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

// malloc itself, on glibc: forward to the allocator glibc exports under __libc_malloc. Not with
// AddressSanitizer, which interposes malloc itself.
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
#define CLIMBSIM_COUNT_MALLOC 1
extern "C" void* __libc_malloc(std::size_t size);
extern "C" void* __libc_calloc(std::size_t count, std::size_t size);
extern "C" void* __libc_realloc(void* p, std::size_t size);
extern "C" void* malloc(std::size_t size) {
  g_malloc_calls.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}
extern "C" void* calloc(std::size_t count, std::size_t size) {
  g_malloc_calls.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(count, size);
}
extern "C" void* realloc(void* p, std::size_t size) {
  g_malloc_calls.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(p, size);
}
#else
#define CLIMBSIM_COUNT_MALLOC 0
#endif

namespace climbsim::cpg {
namespace {

struct Counts {
  long news;
  long mallocs;
};

template <class Body>
Counts Count(Body body) {
  const long news = g_new_calls.load();
  const long mallocs = g_malloc_calls.load();
  body();
  return {g_new_calls.load() - news, g_malloc_calls.load() - mallocs};
}

std::unique_ptr<OscillatorNetwork> Make(bool hopf, int legs, Stepper stepper) {
  const Gait gait = GaitPreset(legs == 4 ? "lateral_sequence" : "wave", legs);
  if (hopf) {
    HopfNetworkParams p = HopfNetworkParamsForGait(gait, 1.0, 2.0);
    p.stepper.type = stepper;
    return std::make_unique<HopfNetwork>(p);
  }
  PhaseNetworkParams p = PhaseNetworkParamsForGait(gait, 1.0, 2.0);
  p.stepper.type = stepper;
  return std::make_unique<PhaseNetwork>(p);
}

TEST(CpgAllocation, CounterSeesAllocations) {
  // The hooks are live: a vector's buffer is one operator new and (glibc) one malloc.
  const Counts counts = Count([] {
    auto* v = new std::vector<double>(16);
    g_sink = v;  // volatile: the allocation cannot be elided
    delete v;
  });
  EXPECT_GE(counts.news, 1);
  if (CLIMBSIM_COUNT_MALLOC) {
    EXPECT_GE(counts.mallocs, 1);
  }
}

TEST(CpgAllocation, StepNeverAllocatesForAnyStepperOrNetwork) {
  for (bool hopf : {false, true}) {
    for (int legs : {4, 6}) {
      for (Stepper stepper : {Stepper::kEuler, Stepper::kRk4, Stepper::kDopri5}) {
        const std::string what = std::string(hopf ? "Hopf" : "Phase") + " legs " +
                                 std::to_string(legs) + " stepper " +
                                 std::to_string(static_cast<int>(stepper));
        std::unique_ptr<OscillatorNetwork> network = Make(hopf, legs, stepper);
        std::vector<double> feedback(legs, 0.0);
        // "Better never": even the first Step, before any warm-up, allocates nothing.
        const Counts first = Count([&] { network->Step(1e-3, feedback); });
        EXPECT_EQ(first.news, 0) << what;
        EXPECT_EQ(first.mallocs, 0) << what;
        // 1000 Steps after that one, with feedback that changes every step (Dopri5 then
        // re-evaluates its derivative) and, every tenth step, none at all.
        const Counts steady = Count([&] {
          for (int k = 0; k < 1000; ++k) {
            for (int i = 0; i < legs; ++i) feedback[i] = 0.1 * ((k + i) % 7) - 0.3;
            if (k % 10 == 0) {
              network->Step(1e-3, {});
            } else {
              network->Step(1e-3, feedback);
            }
            // What the simulator reads after a step.
            for (int i = 0; i < legs; ++i) {
              const LegCommand c =
                  ShapeLeg(LegShape{}, network->phase_rad()[i], network->amplitude()[i]);
              feedback[i] += TegotaeFeedback(0.0, 1.0, c.progress);
            }
          }
        });
        EXPECT_EQ(steady.news, 0) << what;
        EXPECT_EQ(steady.mallocs, 0) << what;
        EXPECT_EQ(network->status(), StepStatus::kOk) << what;
        EXPECT_EQ(network->stats().steps, 1001) << what;
      }
    }
  }
}

}  // namespace
}  // namespace climbsim::cpg
