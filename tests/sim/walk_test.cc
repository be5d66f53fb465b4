// The foundation's acceptance test: on the floor, the gecko (trot) and the spider (tripod),
// driven by the bundled examples, walk forward at least two body lengths in 10 s without
// falling, heading within 20° of forward. Body lengths are those of mjcf/README.md.
#include <gtest/gtest.h>

#include "sim/sim.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

struct Case {
  const char* example;
  double body_length_m;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.example; }

class Walk : public ::testing::TestWithParam<Case> {};

TEST_P(Walk, TwoBodyLengthsInTenSecondsHeadingForward) {
  const Case c = GetParam();
  Scenario s = LoadScenario(climbsim::testing::Source(c.example));
  s.duration_s = 10.0;
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  const RunResult r = sim.Run();
  ASSERT_TRUE(r.stable) << r.failure;
  EXPECT_FALSE(r.fell);
  EXPECT_GE(r.distance_m, 2.0 * c.body_length_m) << c.example;
  EXPECT_LE(std::abs(r.heading_deg), 20.0) << c.example;
}

INSTANTIATE_TEST_SUITE_P(Floor, Walk,
                         ::testing::Values(Case{"examples/gecko_floor.yaml", 0.10},
                                           Case{"examples/spider_floor.yaml", 0.16}),
                         [](const auto& info) {
                           return std::string(info.index == 0 ? "Gecko" : "Spider");
                         });

}  // namespace
}  // namespace climbsim::sim
