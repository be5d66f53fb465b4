// `climbsim pulloff --law frictional` as a user meets it: pulloff.csv with both laws, the
// frictional columns on their closed form (0 where the pull is too steep or reversed, the
// shear limit over sinθ where it holds), the limit curve file and the plot; a bad law exits 2.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "tests/common/test_util.h"

namespace {

using climbsim::testing::CliResult;
using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsim;
using climbsim::testing::SplitCsv;
using climbsim::testing::TempDir;

TEST(PulloffLawCli, FrictionalSweepMatchesItsClosedFormBesideVonMises) {
  const std::string dir = TempDir() + "/pulloff_laws";
  const CliResult r = RunClimbsim("pulloff --law frictional --out " + dir +
                                  " --step-deg 15 --grid 8 --critical-angle-deg 30 --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream csv(ReadFile(dir + "/pulloff.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line,
            "angle_deg,frictional_n,frictional_closed_n,frictional_reversed_n,"
            "frictional_reversed_closed_n,von_mises_n,von_mises_closed_n,capacity_n,"
            "shear_limit_n");
  const double shear_n = 10e3 * 0.025 * 0.025;
  int rows = 0, zero = 0, held = 0;
  while (std::getline(csv, line)) {
    const auto c = SplitCsv(line);
    ASSERT_EQ(c.size(), 9u) << line;
    const double angle = std::stod(c[0]);
    EXPECT_EQ(angle, 15.0 * rows++);
    const double f = std::stod(c[1]), closed = std::stod(c[2]);
    const double reversed = std::stod(c[3]), von_mises = std::stod(c[5]);
    if (angle < 60.0 - 1e-9) {  // steeper than 90° − α*: no hold at any force
      EXPECT_EQ(f, 0.0) << line;
      ++zero;
    } else if (angle <= 90.0) {
      EXPECT_NEAR(f / (shear_n / std::sin(angle * M_PI / 180.0)), 1.0, 1e-5) << line;
      ++held;
    }
    if (closed > 0 && closed < 8.0 * shear_n) {  // below the search cap (--max-force-factor 8)
      EXPECT_NEAR(f / closed, 1.0, 0.01) << line;
    }
    if (angle < 90.0) {
      EXPECT_EQ(reversed, 0.0) << line;  // against the grip: no hold while pulled
    }
    EXPECT_GT(von_mises, 0.0) << line;  // the isotropic law holds at every angle
  }
  EXPECT_EQ(rows, 13);
  EXPECT_EQ(zero, 4);
  EXPECT_EQ(held, 3);
  EXPECT_NE(ReadFile(dir + "/limit.csv").find("# index 0: frictional limit boundary"),
            std::string::npos);
  EXPECT_NE(ReadFile(dir + "/pulloff.gp").find("limit curve"), std::string::npos);
}

TEST(PulloffLawCli, UnknownLawExitsTwo) {
  const CliResult r =
      RunClimbsim("pulloff --law sticky --out " + TempDir() + "/pulloff_bad_law --quiet");
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("--law"), std::string::npos) << r.err;
}

}  // namespace
