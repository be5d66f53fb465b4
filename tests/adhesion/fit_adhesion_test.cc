// The tabulated law on the bond grid and climbsim fit-adhesion's fit: the table reproduced by
// a central pull, peel with a lever, no break by a push; each law's parameters recovered from
// data it generated (5 % noise, several angles and azimuths) with 95 % intervals that cover
// the truth; the designer's table: tabulated within 2 %, the others "cannot represent"; the
// CSV's errors at file:line:column.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "common/common.h"
#include "experiments/fit_adhesion.h"
#include "tests/common/test_util.h"

namespace climbsim::optimise {
namespace {

using adhesion::PadParams;
using adhesion::PullSetup;
using adhesion::TabulatedParams;
constexpr double kDeg = M_PI / 180.0;

// The designer's 20 x 20 mm pad.
TabulatedParams Designer() {
  TabulatedParams t;
  t.angle_from_normal_deg = {0, 30, 60, 90};
  t.pulloff_n = {2.1, 2.4, 3.3, 1.2};
  return t;
}

PadParams Pad(int grid) {
  return PadParams{.width_m = 0.02, .length_m = 0.02, .grid_x = grid, .grid_y = grid};
}

TEST(TabulatedLaw, CentralPullDetachesAtTheTableOnAnyGridAndInterpolates) {
  const TabulatedParams t = Designer();
  for (int grid : {4, 16}) {
    for (size_t k = 0; k < 4; ++k) {
      const auto r = adhesion::TabulatedPullOff(
          Pad(grid), t, PullSetup{.angle_rad = t.angle_from_normal_deg[k] * kDeg});
      EXPECT_NEAR(r.force_n / t.pulloff_n[k], 1.0, 1e-5) << grid << " " << k;
      EXPECT_EQ(r.rounds, 1);  // all at once: every bond carries the same traction
    }
  }
  // Halfway between 30 and 60 deg: the mean; a 10 x 20 mm pad: half the force.
  EXPECT_NEAR(adhesion::TabulatedPullOff(Pad(8), t, {.angle_rad = 45 * kDeg}).force_n, 2.85,
              2.85e-5);
  PadParams half = Pad(8);
  half.width_m = 0.01;
  EXPECT_NEAR(adhesion::TabulatedPullOff(half, t, {.angle_rad = 60 * kDeg}).force_n, 1.65, 1.65e-5);
}

TEST(TabulatedLaw, AzimuthInterpolatesPeriodicallyBetweenCurves) {
  TabulatedParams t;
  t.angle_from_normal_deg = {0, 90, 0, 90};
  t.azimuth_deg = {0, 0, 90, 90};
  t.pulloff_n = {2.0, 1.0, 2.0, 3.0};
  const adhesion::TabulatedLaw law(t);
  const double area = 4e-4;
  EXPECT_NEAR(law.PulloffCentral(area, 90 * kDeg, 0.0), 1.0, 1e-12);
  EXPECT_NEAR(law.PulloffCentral(area, 90 * kDeg, 45 * kDeg), 2.0, 1e-12);
  EXPECT_NEAR(law.PulloffCentral(area, 90 * kDeg, 180 * kDeg), 7.0 / 3.0, 1e-12);  // 90 → 360: 3 → 1
  EXPECT_NEAR(law.PulloffCentral(area, 90 * kDeg, -45 * kDeg), 4.0 / 3.0, 1e-12);
  const auto r = adhesion::TabulatedPullOff(Pad(8), t, {.angle_rad = 90 * kDeg,
                                                        .azimuth_rad = 45 * kDeg});
  EXPECT_NEAR(r.force_n, 2.0, 2e-5);
}

TEST(TabulatedLaw, ALeverPeelsFromTheTrailingEdgeAndAPushAloneBreaksNothing) {
  const TabulatedParams t = Designer();
  const auto central = adhesion::TabulatedPullOff(Pad(16), t, {.angle_rad = 60 * kDeg});
  const auto lever =
      adhesion::TabulatedPullOff(Pad(16), t, {.angle_rad = 60 * kDeg, .arm_m = 0.01});
  EXPECT_LT(lever.force_n, 0.8 * central.force_n);
  EXPECT_GT(lever.rounds, 3);
  ASSERT_FALSE(lever.sequence.empty());
  EXPECT_LT(lever.sequence.front().x_m, 0.0);  // trailing edge (−x) first
  adhesion::BondGrid grid(Pad(8));
  grid.BondAll();
  const adhesion::TabulatedLaw law(t);
  const auto push = adhesion::TabulatedUpdate(&grid, law, {.fn_n = -100.0}, nullptr);
  EXPECT_EQ(push.broken, 0);
}

// Rows at the given angles and azimuths, `repeats` each, forces from the law's own
// prediction times (1 + 5 % noise).
PulloffData Generate(const AdhesionFit& truth, const std::vector<double>& angles,
                     const std::vector<double>& azimuths, int repeats, int grid, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.05);
  PulloffData d;
  d.file = "generated";
  d.has_azimuth = azimuths.size() > 1;
  d.has_repeat = repeats > 1;
  for (double az : azimuths) {
    for (double a : angles) {
      for (int k = 0; k < repeats; ++k) {
        PulloffMeasurement m{.angle_from_normal_deg = a, .azimuth_deg = az, .force_n = 0,
                             .width_m = 0.02, .length_m = 0.02, .arm_m = 0, .preload_n = 0,
                             .repeat = k, .line = static_cast<int>(d.rows.size()) + 2};
        m.force_n = PredictPulloff(truth, m, grid) * (1.0 + noise(rng));
        d.rows.push_back(m);
      }
    }
  }
  return d;
}

void ExpectRecovered(const AdhesionFit& fit, const std::string& key, double truth) {
  for (const FittedParameter& p : fit.parameters) {
    if (p.key != key) continue;
    EXPECT_NEAR(p.value / truth, 1.0, 0.05) << key;
    EXPECT_LE(p.low95, truth) << key << " " << p.value << " +- " << p.uncertainty;
    EXPECT_GE(p.high95, truth) << key << " " << p.value << " +- " << p.uncertainty;
    return;
  }
  ADD_FAILURE() << "no parameter " << key;
}

TEST(FitAdhesion, VonMisesRecoversSigmaTWithinFivePercent) {
  const std::vector<double> angles{0, 10, 20, 30, 40, 50, 60, 70, 80, 90};
  for (double sigma_t : {4e3, 12e3, 40e3}) {
    AdhesionFit truth;
    truth.law = "von_mises";
    truth.von_mises.sigma_t_pa = sigma_t;
    const PulloffData d = Generate(truth, angles, {0, 45}, 1, 8, 7);
    const AdhesionFit fit = FitAdhesion(d, {.law = "von_mises", .grid = 8});
    ExpectRecovered(fit, "sigma_t_pa", sigma_t);
    EXPECT_TRUE(fit.represents) << fit.verdict;
  }
}

TEST(FitAdhesion, FrictionalRecoversShearLimitAndCriticalAngle) {
  std::vector<double> angles;
  for (double a = 1; a < 90; a += 4) angles.push_back(a);  // 22 angles, none on a threshold
  const std::pair<double, double> sets[] = {{5e3, 30}, {12e3, 40}, {8e3, 25}};
  for (const auto& [tau, alpha] : sets) {
    AdhesionFit truth;
    truth.law = "frictional";
    truth.frictional.grip_x = 1.0;
    truth.frictional.shear_limit_pa = tau;
    truth.frictional.critical_angle_deg = alpha;
    const PulloffData d = Generate(truth, angles, {0, 40}, 1, 8, 11);
    const AdhesionFit fit = FitAdhesion(d, {.law = "frictional", .grid = 8});
    ExpectRecovered(fit, "frictional.shear_limit_pa", tau);
    ExpectRecovered(fit, "frictional.critical_angle_deg", alpha);
    EXPECT_TRUE(fit.represents) << fit.verdict;
  }
}

TEST(FitAdhesion, TabulatedRecoversEveryNodeFromRepeats) {
  for (double scale : {0.5, 1.0, 3.0}) {
    AdhesionFit truth;
    truth.law = "tabulated";
    truth.tabulated.angle_from_normal_deg = {0, 30, 60, 90, 0, 30, 60, 90};
    truth.tabulated.azimuth_deg = {0, 0, 0, 0, 90, 90, 90, 90};
    truth.tabulated.pulloff_n = {2.1, 2.4, 3.3, 1.2, 2.1, 1.9, 2.0, 0.8};  // one straight pull
    for (double& f : truth.tabulated.pulloff_n) f *= scale;
    const PulloffData d = Generate(truth, {0, 30, 60, 90}, {0, 90}, 8, 8, 5);
    const AdhesionFit fit = FitAdhesion(d, {.law = "tabulated", .grid = 8});
    ASSERT_EQ(fit.parameters.size(), 7u);  // the straight pulls are one node
    EXPECT_TRUE(fit.spread_from_repeats);
    for (size_t k = 0; k < 7; ++k) {
      const double a = fit.tabulated.angle_from_normal_deg[k];
      const double az = fit.tabulated.azimuth_deg[k];
      for (size_t j = 0; j < 8; ++j) {
        if (truth.tabulated.angle_from_normal_deg[j] == a && truth.tabulated.azimuth_deg[j] == az) {
          const FittedParameter& p = fit.parameters[k];
          EXPECT_NEAR(p.value / truth.tabulated.pulloff_n[j], 1.0, 0.05) << a << " " << az;
          EXPECT_LE(p.low95, truth.tabulated.pulloff_n[j]);
          EXPECT_GE(p.high95, truth.tabulated.pulloff_n[j]);
        }
      }
    }
  }
}

TEST(FitAdhesion, DesignersTableOnlyTheTabulatedLawRepresents) {
  const PulloffData d =
      ReadPulloffCsv(std::string(CLIMBSIM_SOURCE_DIR) + "/examples/pad_pulloff.csv");
  ASSERT_EQ(d.rows.size(), 4u);
  const AdhesionFit tab = FitAdhesion(d, {.law = "tabulated"});
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(tab.predicted_n[k] / d.rows[k].force_n, 1.0, 0.02) << k;
  }
  EXPECT_TRUE(tab.represents) << tab.verdict;
  for (const char* law : {"von_mises", "frictional"}) {
    const AdhesionFit f = FitAdhesion(d, {.law = law});
    EXPECT_FALSE(f.represents) << f.verdict;
    EXPECT_NE(f.verdict.find("this law cannot represent your data"), std::string::npos);
    EXPECT_GT(f.rms_n, 0.5);  // 1.11 N von Mises, 1.35 N frictional
  }
}

TEST(FitAdhesion, CsvErrorsNameFileLineAndColumn) {
  const auto error = [](const std::string& text) -> InputError {
    const std::string path = climbsim::testing::WriteFile("fit.csv", text);
    try {
      ReadPulloffCsv(path);
    } catch (const InputError& e) {
      return e;
    }
    ADD_FAILURE() << "accepted: " << text;
    return InputError("", 0, 0, "", "");
  };
  InputError e = error("# a comment\nforce_n, angle\n1,2\n");
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.column(), 10);
  EXPECT_EQ(e.key(), "angle");
  EXPECT_NE(std::string(e.what()).find("angle_from_normal_deg"), std::string::npos);
  e = error("angle_from_normal_deg,force_n,pad_width_m\n0,2,0.02\n30,x,0.02\n");
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.column(), 4);
  EXPECT_EQ(e.key(), "force_n");
  e = error("angle_from_normal_deg,force_n,pad_width_m\n200,2,0.02\n");
  EXPECT_EQ(e.key(), "angle_from_normal_deg");
  e = error("angle_from_normal_deg,force_n\n10,2\n");  // no pad size anywhere
  EXPECT_EQ(e.key(), "pad_width_m");
  EXPECT_NO_THROW(ReadPulloffCsv(climbsim::testing::WriteFile(
      "fit_ok.csv", "angle_from_normal_deg,force_n,pad_width_m\n100,2,0.02\n")));
  try {
    CheckFitData(ReadPulloffCsv(climbsim::testing::WriteFile(
                     "fit_push.csv", "angle_from_normal_deg,force_n,pad_width_m\n100,2,0.02\n")),
                 "tabulated");
    ADD_FAILURE() << "tabulated took a push";
  } catch (const InputError& push) {
    EXPECT_EQ(push.line(), 2);
  }
}

}  // namespace
}  // namespace climbsim::optimise
