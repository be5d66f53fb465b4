// scene.terrain: the rock's statistics against the spectrum's closed forms (RMS exactly, the
// autocorrelation within sampling error), the same bytes for a seed, the heightfield where the
// model expects it, partial contact seeing it (rays hit it; a pad landing on rock bonds a
// part of its face), and the terrain's box collider (a flat heightfield gives the plane's
// contacts and climbs as the plane; a rock peak under a face pushes along the face's normal).
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
  EXPECT_GT(lift - kTerrainPlaneClearM, 2 * t.rms_m);
  EXPECT_LT(lift - kTerrainPlaneClearM, 8 * t.rms_m);
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

// A 25 mm pad (a 2 mm thick box) over a 0.2 m square surface: a plane, or a flat heightfield
// on a 12.5 mm grid (17 × 17 points, top 1 mm) named `field` (TerrainBoxContacts takes the one
// named as the terrain, MuJoCo the others). The pad's face centre at (x, y, face_z), tilted
// tilt_deg about y; `peak_m` raises the field's centre point. Returns the contacts.
std::vector<mjContact> PadContacts(const std::string& field, double x, double y, double face_z,
                                   double tilt_deg, double peak_m = 0.0) {
  const double tilt = tilt_deg * M_PI / 180.0;
  // The box centre 1 mm (its half thickness) above the face centre, along the pad's normal.
  const double cx = x + 1e-3 * std::sin(tilt), cz = face_z + 1e-3 * std::cos(tilt);
  char xml[1024];
  std::snprintf(
      xml, sizeof(xml),
      "<mujoco><size nconmax=\"200\" njmax=\"800\"/><asset><hfield name=\"h\" nrow=\"17\" "
      "ncol=\"17\" size=\"0.1 0.1 0.001 0.01\"/></asset><worldbody>%s<body pos=\"%.17g %.17g "
      "%.17g\" euler=\"0 %.17g 0\"><freejoint/><geom type=\"box\" size=\"0.0125 0.0125 0.001\" "
      "contype=\"2\" conaffinity=\"1\"/></body></worldbody></mujoco>",
      field == "plane" ? "<geom type=\"plane\" size=\"1 1 0.1\" contype=\"1\" conaffinity=\"2\"/>"
                       : ("<geom name=\"" + field +
                          "\" type=\"hfield\" hfield=\"h\" contype=\"1\" conaffinity=\"2\"/>")
                             .c_str(),
      cx, y, cz, tilt_deg);
  char error[1000] = "";
  mjModel* m = mj_loadXML(climbsim::testing::WriteFile("pad_field.xml", xml).c_str(), nullptr,
                          error, sizeof(error));
  EXPECT_NE(m, nullptr) << error;
  if (m == nullptr) return {};
  if (m->nhfield > 0) m->hfield_data[8 * 17 + 8] = static_cast<float>(peak_m / 1e-3);
  mjData* d = mj_makeData(m);
  mj_forward(m, d);
  std::vector<mjContact> contacts(d->contact, d->contact + d->ncon);
  mj_deleteData(d);
  mj_deleteModel(m);
  return contacts;
}

TEST(TerrainContacts, APadOnAFlatHeightfieldGetsThePlanesContacts) {
  // Pressed 0.2 and 0.5 mm in, flat and tilted 3°, off the grid's lines: the terrain's collider
  // writes the plane's contacts (its corners below the surface), to rounding.
  for (double depth_m : {2e-4, 5e-4}) {
    for (double tilt_deg : {0.0, 3.0}) {
      const std::vector<mjContact> plane = PadContacts("plane", 0.003, 0.002, -depth_m, tilt_deg);
      const std::vector<mjContact> rock =
          PadContacts("climbsim_terrain", 0.003, 0.002, -depth_m, tilt_deg);
      ASSERT_EQ(rock.size(), plane.size()) << depth_m << " " << tilt_deg;
      ASSERT_GE(rock.size(), 2u);
      for (const mjContact& c : rock) {
        EXPECT_NEAR(c.frame[2], 1.0, 1e-12);
        const auto same = std::find_if(plane.begin(), plane.end(), [&](const mjContact& p) {
          return std::abs(p.dist - c.dist) < 1e-12 &&
                 std::hypot(p.pos[0] - c.pos[0], p.pos[1] - c.pos[1]) < 1e-12;
        });
        EXPECT_NE(same, plane.end()) << "contact at " << c.pos[0] << " " << c.pos[1];
      }
    }
  }
  // What it replaces: MuJoCo 2.2.2's prism-by-prism collider tilts some normals sideways on the
  // same flat field (a pad leaving the rock snagged on them).
  const std::vector<mjContact> mujoco = PadContacts("other_field", 0.003, 0.002, -5e-4, 0.0);
  EXPECT_GT(mujoco.size(), 4u);
  EXPECT_TRUE(std::any_of(mujoco.begin(), mujoco.end(),
                          [](const mjContact& c) { return c.frame[2] < 0.99; }));
}

TEST(TerrainContacts, ARockPeakUnderTheFacePushesAlongTheFaceNormalAtItsDepth) {
  // The field's centre point raised 1 mm (its neighbours 12.5 mm away at 0); the face tilted
  // 1° with its centre 0.7 mm up, over the peak: its corners clear the flat rock (0.7 mm ∓
  // 12.5 mm·sin 1°, > 0.48 mm), and the peak stands 0.3 mm·cos 1° into the box along the
  // face's normal: one contact there, along that normal.
  const double tilt = M_PI / 180.0;
  const std::vector<mjContact> c = PadContacts("climbsim_terrain", 0.0, 0.0, 7e-4, 1.0, 1e-3);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].dist, -3e-4 * std::cos(tilt), 1e-12);
  EXPECT_NEAR(c[0].frame[0], std::sin(tilt), 1e-12);
  EXPECT_NEAR(c[0].frame[1], 0.0, 1e-12);
  EXPECT_NEAR(c[0].frame[2], std::cos(tilt), 1e-12);
  // At the midpoint of the penetration: the peak less half the depth along the normal.
  EXPECT_NEAR(c[0].pos[0], 0.5 * c[0].dist * std::sin(tilt), 1e-12);
  EXPECT_NEAR(c[0].pos[2], 1e-3 + 0.5 * c[0].dist * std::cos(tilt), 1e-12);
}

TEST(Terrain, AFlatHeightfieldClimbsAsThePlane) {
  // gecko_wall.yaml for 4 s on the plane and on a heightfield of 1 nm RMS (flat to the float
  // heights): the same landings and bonds, and the climb within 1 % (the start 2 mm higher,
  // kTerrainPlaneClearM, is the only difference; before the terrain's collider a flat field
  // halved the climb).
  std::string text =
      climbsim::testing::ReadFile(climbsim::testing::Source("examples/gecko_wall.yaml"));
  text.replace(text.find("duration_s: 20"), 14, "duration_s: 4");
  std::string rock = text;
  rock.replace(rock.find("scene: wall\n"), 12,
               "scene:\n  name: wall\n  terrain: {rms_m: 1.0e-9, grid_m: 0.0125}\n");
  auto run = [](const std::string& name, const std::string& yaml) {
    const Scenario s = LoadScenario(climbsim::testing::WriteFile(name, yaml));
    const auto model = CompileScenario(s);
    Simulation sim(s, *model);
    const RunResult r = sim.Run();
    std::vector<double> attach;
    for (const Event& e : sim.events().rows()) {
      if (std::string_view(e.kind) == "attach") attach.push_back(e.bonded_fraction);
    }
    return std::make_pair(r, attach);
  };
  const auto [plane, plane_attach] = run("flat_plane.yaml", text);
  const auto [field, field_attach] = run("flat_field.yaml", rock);
  EXPECT_FALSE(field.fell);
  EXPECT_GT(plane.distance_m, 0.05);
  EXPECT_NEAR(field.distance_m, plane.distance_m, 0.01 * plane.distance_m);
  ASSERT_EQ(field_attach.size(), plane_attach.size());
  for (size_t i = 0; i < field_attach.size(); ++i) EXPECT_EQ(field_attach[i], plane_attach[i]);
}

// The rock examples, 20 s on rock seeds 1-3: no fall, no stall, and most of the flat wall's
// climb (0.352 m gecko, 0.467 m spider; measured 0.317-0.350 and 0.385-0.456 m). Before the
// terrain's collider and the examples' search and attach-window keys the gecko stalled on every
// seed by 11.3 s and the spider fell on two (docs/climbing.md, "Rough rock").
void ExpectClimbsSeeds1To3(const std::string& example, double least_m) {
  for (int seed : {1, 2, 3}) {
    std::string text = climbsim::testing::ReadFile(climbsim::testing::Source(example));
    text.replace(text.find("seed: 1,"), 8, "seed: " + std::to_string(seed) + ",");
    const Scenario s =
        LoadScenario(WriteFile("rock_example.yaml", text + "outputs: {trajectory_rate_hz: 0}\n"));
    ASSERT_EQ(s.scene.terrain->seed, seed);
    const auto model = CompileScenario(s);
    Simulation run(s, *model);
    const RunResult r = run.Run();
    const nlohmann::json summary = run.Summary();
    EXPECT_FALSE(r.fell) << example << " seed " << seed << " fell at " << r.fall_time_s;
    EXPECT_FALSE(summary["stalled"].get<bool>())
        << example << " seed " << seed << " stalled at " << summary["stall_time_s"];
    EXPECT_GT(r.distance_m, least_m) << example << " seed " << seed;
  }
}

TEST(Terrain, GeckoRockWallClimbsRockSeeds1To3) {
  ExpectClimbsSeeds1To3("examples/gecko_rock_wall.yaml", 0.25);
}

TEST(Terrain, SpiderRockWallClimbsRockSeeds1To3) {
  ExpectClimbsSeeds1To3("examples/spider_rock_wall.yaml", 0.3);
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
