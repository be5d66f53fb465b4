// Gait presets (docs/control.md's table) and the phase network running them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "cpg/cpg.h"
#include "tests/cpg/test_util.h"

namespace climbsim::cpg {
namespace {

using testing::kTwoPi;
using testing::WrapPi;

const std::vector<std::string> kQuadrupedLegs = {"LF", "RF", "LH", "RH"};
const std::vector<std::string> kHexapodLegs = {"L1", "L2", "L3", "R1", "R2", "R3"};

TEST(CpgGait, PresetsMatchTheTable) {
  auto offsets = [](std::string_view name, int legs) {
    return GaitPreset(name, legs).offsets_cycles;
  };
  // Exact: the table's fractions, written the same way.
  EXPECT_EQ(offsets("trot", 4), (std::vector<double>{0.0, 0.5, 0.5, 0.0}));
  EXPECT_EQ(offsets("lateral_sequence", 4), (std::vector<double>{0.25, 0.75, 0.0, 0.5}));
  EXPECT_EQ(offsets("tripod", 6), (std::vector<double>{0.0, 0.5, 0.0, 0.5, 0.0, 0.5}));
  EXPECT_EQ(offsets("tetrapod", 6),
            (std::vector<double>{2.0 / 3, 1.0 / 3, 0.0, 1.0 / 3, 0.0, 2.0 / 3}));
  EXPECT_EQ(offsets("wave", 6),
            (std::vector<double>{2.0 / 6, 1.0 / 6, 0.0, 5.0 / 6, 4.0 / 6, 3.0 / 6}));
  EXPECT_EQ(GaitPreset("trot", 4).duty_factor, 0.5);
  EXPECT_EQ(GaitPreset("lateral_sequence", 4).duty_factor, 0.75);
  EXPECT_EQ(GaitPreset("tripod", 6).duty_factor, 0.5);
  EXPECT_EQ(GaitPreset("tetrapod", 6).duty_factor, 2.0 / 3);
  EXPECT_EQ(GaitPreset("wave", 6).duty_factor, 5.0 / 6);
  EXPECT_EQ(GaitPresetNames(4), (std::vector<std::string>{"trot", "lateral_sequence"}));
  EXPECT_EQ(GaitPresetNames(6), (std::vector<std::string>{"tripod", "tetrapod", "wave"}));
  EXPECT_TRUE(GaitPresetNames(5).empty());
}

TEST(CpgGait, UnknownNameOrWrongLegCountThrowsAndListsTheNames) {
  try {
    GaitPreset("gallop", 4);
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'gallop'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("trot, lateral_sequence"), std::string::npos) << e.what();
  }
  EXPECT_THROW(GaitPreset("trot", 6), std::invalid_argument);
  EXPECT_THROW(GaitPreset("tripod", 4), std::invalid_argument);
  EXPECT_THROW(GaitPreset("wave", 8), std::invalid_argument);
}

TEST(CpgGait, PhaseBiasIsTwoPiTimesOffsetDifference) {
  const std::vector<double> offsets = {0.1, 0.35, 0.8};
  const Eigen::MatrixXd bias = PhaseBiasFromOffsets(offsets);
  ASSERT_EQ(bias.rows(), 3);
  ASSERT_EQ(bias.cols(), 3);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      EXPECT_DOUBLE_EQ(bias(i, j), kTwoPi * (offsets[i] - offsets[j]));
    }
  }
  EXPECT_THROW(PhaseBiasFromOffsets({0.0, std::nan("")}), std::invalid_argument);
}

// The order in which legs start swing over one cycle, as groups of legs starting together
// (within two steps), beginning with the group that contains leg `first`.
std::vector<std::vector<std::string>> SwingOrder(const std::vector<std::vector<double>>& onsets,
                                                 const std::vector<std::string>& names, int first,
                                                 double tie_s) {
  const double t_first = onsets[first][onsets[first].size() - 2];
  std::vector<std::pair<double, std::string>> events;
  for (size_t i = 0; i < onsets.size(); ++i) {
    for (double t : onsets[i]) {
      if (t >= t_first - tie_s && t < t_first + (onsets[first].back() - t_first) - tie_s) {
        events.emplace_back(t, names[i]);
      }
    }
  }
  std::sort(events.begin(), events.end());
  std::vector<std::vector<std::string>> groups;
  double group_start = -1e9;
  for (const auto& [t, name] : events) {
    if (t - group_start > tie_s) {
      groups.push_back({});
      group_start = t;
    }
    groups.back().push_back(name);
  }
  for (auto& group : groups) std::sort(group.begin(), group.end());
  return groups;
}

struct PresetCase {
  std::string name;
  std::vector<std::string> legs;
  int first;  // a leg with offset 0
  std::vector<std::vector<std::string>> swing_order;
};

TEST(CpgGait, PhaseNetworkLocksToEveryPresetFromRandomStarts) {
  const std::vector<PresetCase> cases = {
      // Diagonal pairs together.
      {"trot", kQuadrupedLegs, 0, {{"LF", "RH"}, {"LH", "RF"}}},
      {"lateral_sequence", kQuadrupedLegs, 2, {{"LH"}, {"LF"}, {"RH"}, {"RF"}}},
      {"tripod", kHexapodLegs, 0, {{"L1", "L3", "R2"}, {"L2", "R1", "R3"}}},
      {"tetrapod", kHexapodLegs, 2, {{"L3", "R2"}, {"L2", "R1"}, {"L1", "R3"}}},
      // Back to front on each side, left then right.
      {"wave", kHexapodLegs, 2, {{"L3"}, {"L2"}, {"L1"}, {"R3"}, {"R2"}, {"R1"}}},
  };
  for (const PresetCase& c : cases) {
    const int n = static_cast<int>(c.legs.size());
    const Gait gait = GaitPreset(c.name, n);
    for (unsigned seed = 0; seed < 20; ++seed) {
      PhaseNetwork network(PhaseNetworkParamsForGait(gait, 1.0, 2.0));
      std::mt19937 rng(seed);
      network.Reset(testing::RandomPhases(rng, n), testing::RandomAmplitudes(rng, n, 0.0, 2.0));
      const double dt_s = 1e-3;
      testing::RunFor(network, 20.0, dt_s);
      // Locked: θ_j − θ_i = 2π(offset_i − offset_j). The complete graph contracts phase errors
      // at rate n·w·R ≥ 8/s; after 20 s only starts within ~1e-6 rad of an unstable
      // equilibrium could still be away, and none of these seeds is.
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          const double expected = kTwoPi * (gait.offsets_cycles[i] - gait.offsets_cycles[j]);
          const double actual = network.phase_rad()[j] - network.phase_rad()[i];
          EXPECT_NEAR(WrapPi(actual - expected), 0.0, 1e-6)
              << c.name << " seed " << seed << " legs " << i << "," << j;
        }
      }
      const auto onsets = testing::SwingOnsetTimes(network, 2.5, dt_s);
      EXPECT_EQ(SwingOrder(onsets, c.legs, c.first, 2 * dt_s), c.swing_order)
          << c.name << " seed " << seed;
    }
  }
}

TEST(CpgGait, HopfFrequenciesGiveTheDutyFactor) {
  for (double duty : {0.5, 2.0 / 3, 0.75, 5.0 / 6}) {
    const HopfFrequencies f = HopfFrequenciesForGait(0.8, duty);
    // Stance lasts 1/(2 f_stance) = D/f and swing 1/(2 f_swing) = (1−D)/f.
    EXPECT_NEAR(1.0 / (2.0 * f.stance_frequency_hz), duty / 0.8, 1e-15);
    EXPECT_NEAR(1.0 / (2.0 * f.swing_frequency_hz), (1.0 - duty) / 0.8, 1e-15);
  }
  EXPECT_THROW(HopfFrequenciesForGait(0.0, 0.5), std::invalid_argument);
  EXPECT_THROW(HopfFrequenciesForGait(1.0, 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace climbsim::cpg
