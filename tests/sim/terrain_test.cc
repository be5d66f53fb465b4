// scene.terrain: the rock's statistics against the spectrum's closed forms (RMS exactly, the
// autocorrelation within sampling error), the same bytes for a seed, the heightfield where the
// model expects it, and partial contact seeing it (rays hit it; a pad landing on rock bonds a
// part of its face).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "sim/sim.h"
#include "sim/terrain.h"
#include "tests/common/scenario_error.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::ScenarioErrorOf;
using climbsim::testing::WriteFile;

// The field's autocorrelation at a lag of `lag` grid points, along x and y together, / σ².
double SampledCorrelation(const std::vector<double>& h, int nx, int ny, int lag) {
  double sum = 0.0, sq = 0.0;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const double v = h[j * nx + i];
      sum += v * (h[j * nx + (i + lag) % nx] + h[((j + lag) % ny) * nx + i]);
      sq += 2.0 * v * v;
    }
  }
  return sum / sq;
}

TEST(Terrain, RmsExactAndCorrelationFollowsTheVonKarmanClosedForm) {
  TerrainParams p;  // σ 1 mm, ξ 50 mm, H 0.8, grid 5 mm
  const int n = 256;  // 1.28 m: about 25 correlation lengths a side
  for (int seed : {1, 2, 3}) {
    p.seed = seed;
    const std::vector<double> h = RockField(p, n, n);
    double mean = 0.0, sq = 0.0;
    for (double v : h) mean += v, sq += v * v;
    EXPECT_NEAR(mean / h.size(), 0.0, 1e-12);
    EXPECT_NEAR(std::sqrt(sq / h.size()), p.rms_m, 1e-12);
    // Lags ξ/2, ξ, 2ξ: R(ξ)/σ² = 2^(1−H)/Γ(H)·K_H(1) ≈ 0.52. Over the whole periodic field the
    // autocorrelation is the transform of |c(q)|², the spectrum's own (the same for every
    // seed: fixed amplitudes); it differs from the continuous closed form only by the grid's
    // cut at wavelength 2·grid_m and the period (measured: 0.001, 0.006, 0.011).
    for (int lag : {5, 10, 20}) {
      EXPECT_NEAR(SampledCorrelation(h, n, n, lag), RockCorrelation(p, lag * p.grid_m), 0.015)
          << "seed " << seed << " lag " << lag;
    }
  }
  EXPECT_NEAR(RockCorrelation(p, p.correlation_m),
              std::pow(2.0, 0.2) / std::tgamma(0.8) * std::cyl_bessel_k(0.8, 1.0), 1e-15);
}

TEST(Terrain, SameSeedSameBytesOtherSeedOtherRock) {
  TerrainParams p;
  const std::vector<double> a = RockField(p, 128, 64), b = RockField(p, 128, 64);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0);
  p.seed = 2;
  const std::vector<double> c = RockField(p, 128, 64);
  EXPECT_NE(std::memcmp(a.data(), c.data(), a.size() * sizeof(double)), 0);
}

// examples/gecko_wall.yaml on rock (support_bond_fraction 0.5: bonds on rock are partial).
std::string RockWall(double rms_m, int seed, double duration_s) {
  std::string text = climbsim::testing::ReadFile(climbsim::testing::Source("examples/gecko_wall.yaml"));
  char scene[160];
  std::snprintf(scene, sizeof(scene), "scene:\n  name: wall\n  terrain: {rms_m: %.17g, seed: %d}\n",
                rms_m, seed);
  text.replace(text.find("scene: wall\n"), 12, scene);
  text.replace(text.find("duration_s: 20"), 14, "duration_s: " + std::to_string(duration_s));
  text.replace(text.find("support_bond_fraction: 0.85"), 27, "support_bond_fraction: 0.5");
  return text + "outputs: {trajectory_rate_hz: 0}\n";
}

TEST(Terrain, HeightfieldInTheModelAndTheRobotOnItsMeanPlane) {
  const Scenario s = LoadScenario(WriteFile("rock.yaml", RockWall(0.001, 1, 0.01)));
  const auto model = CompileScenario(s);
  const mjModel* m = model->model();
  const int g = TerrainGeom(m);
  ASSERT_GE(g, 0);
  const int hf = m->geom_dataid[g];
  const TerrainParams& t = *s.scene.terrain;
  EXPECT_EQ(m->hfield_ncol[hf], TerrainColumns(t));  // (1.4 / 0.005) + 1 = 281
  EXPECT_EQ(m->hfield_nrow[hf], TerrainRows(t));
  EXPECT_EQ(TerrainColumns(t), 281);
  // Heights in [0, 1] of the top; the rock's mean (the flattened patches) is the lift.
  const float* d = m->hfield_data + m->hfield_adr[hf];
  const int count = m->hfield_nrow[hf] * m->hfield_ncol[hf];
  double mean = 0.0, lo = 1.0, hi = 0.0;
  for (int k = 0; k < count; ++k) {
    mean += d[k];
    lo = std::min<double>(lo, d[k]);
    hi = std::max<double>(hi, d[k]);
  }
  EXPECT_EQ(lo, 0.0);
  EXPECT_EQ(hi, 1.0);
  const double top = m->hfield_size[4 * hf + 2];
  EXPECT_GT(top, 4 * t.rms_m);  // a Gaussian's range over 80000 points: about 8-10 σ
  EXPECT_LT(top, 12 * t.rms_m);
  // The same robot on the flat wall: the rock lifts it by its lowest point's depth.
  const Scenario flat = LoadScenario(WriteFile("flat.yaml", "robot: gecko\nscene: wall\nduration_s: 1\n"));
  const auto flat_model = CompileScenario(flat);
  EXPECT_EQ(TerrainGeom(flat_model->model()), -1);
  EXPECT_EQ(flat_model->model()->nhfield, 0);
  const int z = model->robot().root_qpos_adr + 2;
  const double lift = m->qpos0[z] - flat_model->model()->qpos0[z];
  EXPECT_GT(lift, 2 * t.rms_m);
  EXPECT_LT(lift, 8 * t.rms_m);
  // mj_ray (what partial contact casts) meets the rock at the flattened patch under a pad,
  // at the lift (the mean plane): the pad's start place. The ray starts between the pad's face
  // (0.5 mm up) and the rock.
  Simulation run(s, *model);
  const mjData* data = run.world().data();
  const int pad = model->robot().legs[0].pad_geom;
  mjtNum from[3] = {data->geom_xpos[3 * pad], data->geom_xpos[3 * pad + 1], lift + 2e-4};
  const mjtNum down[3] = {0, 0, -1};
  int hit = -1;
  const mjtNum x = mj_ray(m, data, from, down, nullptr, 1, -1, &hit);
  EXPECT_EQ(hit, g);
  EXPECT_NEAR(x, 2e-4, 1e-6);
}

TEST(Terrain, PadsLandingOnRockBondPartOfTheirFace) {
  // Landings on 1 mm rock (after the first steps) bond a part of the face, some less than
  // any landing on 10 µm rock, where every landing bonds about the 0.9 a flat one gives.
  // (Seated pads follow the rock's tilt, so what is lost is the asperities shorter than the
  // pad: measured least 0.77.)
  auto attach_fractions = [](double rms_m) {
    const Scenario s = LoadScenario(WriteFile("rock_land.yaml", RockWall(rms_m, 1, 2.5)));
    const auto model = CompileScenario(s);
    Simulation run(s, *model);
    run.Run();
    std::vector<double> f;
    const int g = TerrainGeom(model->model());
    for (const Event& e : run.events().rows()) {
      if (std::string_view(e.kind) == "attach" && e.surface_geom == g) f.push_back(e.bonded_fraction);
    }
    return f;
  };
  const std::vector<double> rock = attach_fractions(0.001), smooth = attach_fractions(1e-5);
  ASSERT_GE(rock.size(), 2u);
  ASSERT_GE(smooth.size(), 2u);
  EXPECT_LT(*std::min_element(rock.begin(), rock.end()), 0.85);
  for (double f : smooth) EXPECT_GT(f, 0.85);
}

TEST(Terrain, RefusedOffThePlaneScenesAndBesideRoughness) {
  EXPECT_EQ(ScenarioErrorOf("t1.yaml",
                            "robot: gecko\nscene:\n  name: floor_to_wall\n  terrain: {rms_m: 0.001}\n"),
            "t1.yaml:4:12: scene.terrain: applies to the plane scenes only (floor, wall, ceiling, "
            "incline)");
  EXPECT_NE(ScenarioErrorOf("t2.yaml", "robot: gecko\nscene:\n  name: wall\n  terrain: {}\n"
                                       "  roughness: {height_m: 0.002}\n")
                .find("scene.terrain: give roughness or terrain, not both"),
            std::string::npos);
  EXPECT_NE(ScenarioErrorOf("t3.yaml", "robot: gecko\nscene:\n  name: wall\n  terrain: "
                                       "{correlation_m: 0.005, grid_m: 0.005}\n")
                .find("scene.terrain.correlation_m: must be at least 2 * grid_m"),
            std::string::npos);
}

}  // namespace
}  // namespace climbsim::sim
