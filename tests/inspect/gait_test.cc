// The gait diagram's data (stances in `inspect --json`) of a real trot with sticking pads:
// the diagonal legs attach together, the two diagonals half a stride apart.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <vector>

#include "tests/inspect/inspect_test_util.h"

namespace {

using climbsim::testing::RunClimbsim;
using climbsim::testing::SharedRun;
using climbsim::testing::Source;
using nlohmann::json;

// Stance onsets per leg from the JSON; stances that began at t = 0 (placed attached) are not
// steps and are left out.
std::map<std::string, std::vector<double>> Onsets(const json& report) {
  std::map<std::string, std::vector<double>> onsets;
  for (const json& leg : report["legs"]) {
    for (const json& s : leg["stances"]) {
      const double t = s["start_s"];
      if (!s["open_start"].get<bool>() && t > 0) onsets[leg["leg"]].push_back(t);
    }
  }
  return onsets;
}

// Distance from t to the nearest onset of another leg, in strides.
double Nearest(double t, const std::vector<double>& other, double stride_s) {
  double best = INFINITY;
  for (double u : other) best = std::min(best, std::abs(u - t));
  return best / stride_s;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

TEST(InspectGait, GeckoTrotAttachesDiagonalLegsTogether) {
  const std::string dir = SharedRun("gecko_trot", Source("tests/inspect/gecko_trot.yaml"));
  const auto r = RunClimbsim("inspect " + dir + " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto onsets = Onsets(json::parse(r.out));
  for (const char* leg : {"LF", "RF", "LH", "RH"}) {
    ASSERT_TRUE(onsets.count(leg)) << leg;
    ASSERT_GE(onsets.at(leg).size(), 3u) << leg << ": too few steps to judge a gait";
  }
  // The stride: median time between a leg's onsets. (Holds for support stretch it beyond the
  // CPG's 1/0.8 Hz, so it is measured, not assumed.)
  std::vector<double> gaps;
  for (const auto& [leg, t] : onsets) {
    for (size_t i = 1; i < t.size(); ++i) gaps.push_back(t[i] - t[i - 1]);
  }
  const double stride_s = Median(gaps);
  ASSERT_GT(stride_s, 0.5);

  // Diagonal partners attach within a tenth of a stride of each other...
  const std::vector<std::pair<const char*, const char*>> diagonal = {
      {"LF", "RH"}, {"RH", "LF"}, {"RF", "LH"}, {"LH", "RF"}};
  for (const auto& [a, b] : diagonal) {
    std::vector<double> lag;
    for (double t : onsets.at(a)) lag.push_back(Nearest(t, onsets.at(b), stride_s));
    EXPECT_LT(Median(lag), 0.1) << a << " with " << b;
  }
  // ...and about half a stride from the other diagonal (left-right and fore-hind pairs).
  const std::vector<std::pair<const char*, const char*>> others = {
      {"LF", "RF"}, {"LF", "LH"}, {"RF", "RH"}, {"LH", "RH"}};
  for (const auto& [a, b] : others) {
    std::vector<double> lag;
    for (double t : onsets.at(a)) lag.push_back(Nearest(t, onsets.at(b), stride_s));
    EXPECT_NEAR(Median(lag), 0.5, 0.15) << a << " with " << b;
  }
}

}  // namespace
