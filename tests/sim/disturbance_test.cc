// The disturbance keys of `climbsim bench robustness`, each shown by its effect: payload_kg
// adds exactly its mass (centre of mass kept); adhesion.pad_failure_probability 1 fails every
// attachment within the window (event bonds_lost, detach cause failure), 0 none;
// scene.weak_patches scales σ_T exactly (a weak patch at fraction f and σ_T/f is the plain
// surface at σ_T, event for event); scene.roughness adds bumps of the given height, none under
// the starting feet, and pads attach on their tops.
#include <gtest/gtest.h>

#include <cmath>
#include <string_view>

#include "sim/adhesion_effect.h"
#include "sim/sim.h"
#include "tests/common/scenario_error.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

Scenario Load(const std::string& name, const std::string& text) {
  return LoadScenario(WriteFile(name, text));
}

std::string ErrorOf(const std::string& name, const std::string& text) {
  return climbsim::testing::ScenarioErrorOf(name, text);
}

// The gecko on the wall as in examples/gecko_wall.yaml, short.
std::string GeckoWall(double duration_s, const std::string& extra_adhesion = "",
                      const std::string& scene = "wall") {
  return "robot: gecko\nscene: " + scene + "\nduration_s: " + std::to_string(duration_s) +
         "\noutputs: {trajectory_rate_hz: 0}\n"
         "adhesion:\n  start_attached: true\n  initial_fraction: 0.9\n  buildup_time_s: 0.05\n"
         "  mu: 1.0\n" +
         extra_adhesion +
         "cpg:\n  gait: lateral_sequence\n  frequency_hz: 0.6\n  start_amplitude: 1\n"
         "  stride_m: 0.03\n  lift_m: 0.012\n  press_m: 0.002\n  lift_share: 0.25\n"
         "  wait_for_support: true\n  support_bond_fraction: 0.85\n"
         "reflex:\n  spindle: {enabled: false}\n  gto: {enabled: false}\n"
         "  preload: {hip_pitch_press_rad: 0.05, knee_press_rad: 0.03, force_limit_n: 0.6}\n";
}

int CountDetach(const Simulation& sim, std::string_view cause) {
  int n = 0;
  for (const Event& e : sim.events().rows()) {
    n += std::string_view(e.kind) == "detach" && std::string_view(e.cause) == cause;
  }
  return n;
}

TEST(Disturbance, PayloadAddsExactlyItsMassAtTheBaseCentreOfMass) {
  const Scenario plain = Load("payload0.yaml", "robot: gecko\nscene: floor\nduration_s: 0.1\n");
  const Scenario loaded =
      Load("payload1.yaml", "robot: gecko\nscene: floor\nduration_s: 0.1\npayload_kg: 0.25\n");
  auto model = CompileScenario(plain);
  World a(*model, plain), b(*model, loaded);
  const int base = model->robot().base_body;
  EXPECT_NEAR(mj_getTotalmass(b.model()) - mj_getTotalmass(a.model()), 0.25, 1e-12);
  // mj_setConst brought the subtree masses along (the robot's root body holds it all).
  EXPECT_NEAR(b.model()->body_subtreemass[base] - a.model()->body_subtreemass[base], 0.25, 1e-12);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(b.model()->body_ipos[3 * base + i], a.model()->body_ipos[3 * base + i]);
    // Inertia scaled with the mass: same radii of gyration.
    EXPECT_NEAR(b.model()->body_inertia[3 * base + i] / a.model()->body_inertia[3 * base + i],
                b.model()->body_mass[base] / a.model()->body_mass[base], 1e-12);
  }
  // No payload: the model copy is untouched.
  EXPECT_EQ(a.model()->body_mass[base], model->model()->body_mass[base]);
  EXPECT_EQ(a.model()->body_invweight0[2 * base], model->model()->body_invweight0[2 * base]);
  // The robot standing on the floor then pushes the floor down by the extra weight too.
  auto weight_on_floor = [&](const Scenario& s) {
    Simulation sim(s, *model);
    sim.Run();
    const mjModel* m = sim.world().model();
    const mjData* d = sim.world().data();
    double fz = 0.0;
    for (int c = 0; c < d->ncon; ++c) {
      double f[6];
      mj_contactForce(m, d, c, f);
      fz += std::abs(f[0]);  // normal along the frame's first axis
    }
    return fz;
  };
  const Scenario plain_long = Load("payload2.yaml", "robot: gecko\nscene: floor\nduration_s: 1\n");
  const Scenario loaded_long =
      Load("payload3.yaml", "robot: gecko\nscene: floor\nduration_s: 1\npayload_kg: 0.25\n");
  EXPECT_NEAR(weight_on_floor(loaded_long) - weight_on_floor(plain_long), 0.25 * 9.81, 0.02 * 9.81);
}

TEST(Disturbance, PadFailureProbabilityOneFailsEveryAttachmentAndZeroNone) {
  const double window = 0.2;
  const Scenario always = Load(
      "fail1.yaml", GeckoWall(1.0, "  pad_failure_probability: 1\n  pad_failure_window_s: 0.2\n"));
  auto model = CompileScenario(always);
  Simulation sim(always, *model);
  sim.Run();
  // Every attachment is followed, within the window, by bonds_lost then detach "failure" of
  // that pad, unless it let go otherwise first.
  const auto& rows = sim.events().rows();
  int attaches = 0;
  for (size_t i = 0; i < rows.size(); ++i) {
    if (std::string_view(rows[i].kind) != "attach") continue;
    ++attaches;
    const double t_attach = rows[i].time_s;
    bool ended = false;
    for (size_t j = i + 1; j < rows.size() && !ended; ++j) {
      if (rows[j].pad != rows[i].pad || std::string_view(rows[j].kind) != "detach") continue;
      ended = true;
      if (std::string_view(rows[j].cause) == "failure") {
        EXPECT_LT(rows[j].time_s, t_attach + window + 1e-9);
        ASSERT_GT(j, 0u);
        EXPECT_STREQ(rows[j - 1].kind, "bonds_lost");
        EXPECT_EQ(rows[j - 1].pad, rows[i].pad);
      } else {
        EXPECT_LT(rows[j].time_s, t_attach + window);
      }
    }
    if (!ended) {
      EXPECT_GT(t_attach + window, 1.0 - 1e-9) << "attach at " << t_attach;
    }
  }
  EXPECT_GE(attaches, 4);
  EXPECT_GE(CountDetach(sim, "failure"), 4);  // the four start attachments at least

  const Scenario never = Load("fail0.yaml", GeckoWall(1.0, "  pad_failure_probability: 0\n"));
  Simulation calm(never, *model);
  calm.Run();
  EXPECT_EQ(CountDetach(calm, "failure"), 0);
  EXPECT_FALSE(calm.result().fell);

  // The draws are the seed's: the same run twice gives the same events.
  const Scenario half =
      Load("fail_half.yaml", GeckoWall(1.0, "  pad_failure_probability: 0.5\n") + "seed: 7\n");
  Simulation h1(half, *model), h2(half, *model);
  h1.Run();
  h2.Run();
  EXPECT_EQ(h1.EventsCsv(), h2.EventsCsv());
}

TEST(Disturbance, WeakPatchScalesSigmaTExactly) {
  // Hanging from the ceiling, no gait: at σ_T = S the pads give way. A surface that is all
  // weak patch at fraction 1/4 under σ_T = 4 S is the same surface: the same detaches at the
  // same times. Without the patches, 4 S holds.
  auto hang = [](double sigma, const std::string& scene) {
    return "robot: gecko\nscene: " + scene +
           "\nduration_s: 1\noutputs: {trajectory_rate_hz: 0}\n"
           "adhesion:\n  start_attached: true\n  sigma_t_pa: " +
           std::to_string(sigma) + "\n";
  };
  const std::string weak_all =
      "{name: ceiling, weak_patches: {fraction: 0.25, size_m: 0.05, coverage: 1}}";
  const double s = 800.0;
  const Scenario plain = Load("hang_plain.yaml", hang(s, "ceiling"));
  const Scenario weak = Load("hang_weak.yaml", hang(4 * s, weak_all));
  const Scenario strong = Load("hang_strong.yaml", hang(4 * s, "ceiling"));
  auto model = CompileScenario(plain);
  Simulation a(plain, *model), b(weak, *model), c(strong, *model);
  a.Run();
  b.Run();
  c.Run();
  const int detach_a = CountDetach(a, "overload") + CountDetach(a, "peel");
  ASSERT_GT(detach_a, 0) << "sigma_T = " << s << " must let go for this test to mean anything";
  EXPECT_EQ(CountDetach(b, "overload") + CountDetach(b, "peel"), detach_a);
  std::vector<double> ta, tb;
  for (const Event& e : a.events().rows()) {
    if (std::string_view(e.kind) == "detach") ta.push_back(e.time_s);
  }
  for (const Event& e : b.events().rows()) {
    if (std::string_view(e.kind) == "detach") tb.push_back(e.time_s);
  }
  ASSERT_EQ(ta.size(), tb.size());
  for (size_t i = 0; i < ta.size(); ++i) EXPECT_NEAR(ta[i], tb[i], 2e-3);
  EXPECT_EQ(CountDetach(c, "overload") + CountDetach(c, "peel"), 0);
  // Each pad's scale is the patch's.
  const AdhesionEffect* ad = FindAdhesion(b.effects());
  ASSERT_NE(ad, nullptr);
  Simulation fresh(weak, *model);
  const AdhesionEffect* f = FindAdhesion(fresh.effects());
  for (int i = 0; i < f->pad_count(); ++i) EXPECT_EQ(f->pad(i).strength_scale(), 0.25);
  (void)ad;
}

TEST(Disturbance, WeakPatchLayoutIsTheSeedsAndCoversTheShareAsked) {
  WeakPatchParams p;
  p.fraction = 0.3;
  p.size_m = 0.05;
  p.coverage = 0.3;
  int weak = 0, n = 0;
  for (int i = -50; i < 50; ++i) {
    for (int j = -50; j < 50; ++j) {
      const double x = (i + 0.5) * p.size_m, y = (j + 0.5) * p.size_m;
      const double k = PatchStrength(p, 3, x, y);
      EXPECT_TRUE(k == 1.0 || k == 0.3);
      // Constant over the cell.
      EXPECT_EQ(k, PatchStrength(p, 3, x + 0.02, y - 0.02));
      weak += k < 1.0;
      ++n;
    }
  }
  EXPECT_NEAR(static_cast<double>(weak) / n, 0.3, 0.02);  // 10 000 cells: σ = 0.005
}

TEST(Disturbance, RoughnessAddsBumpsOfTheHeightGivenAndPadsAttachOnTheirTops) {
  const std::string scene =
      "{name: wall, roughness: {height_m: 0.003, spacing_m: 0.03, size_m: 0.028}}";
  const Scenario s = Load("rough.yaml", GeckoWall(6.0, "", scene));
  auto model = CompileScenario(s);
  double top = 0.0;
  const int bumps = BumpCount(model->model(), &top);
  EXPECT_GT(bumps, 100);
  EXPECT_NEAR(top, 0.003, 1e-15);
  // Each bump reaches far below the surface: a pad sunk into a soft contact deeper than half a
  // thin slab would be pushed through it, into the surface, by the box-box contact.
  const mjModel* bm = model->model();
  for (int g = 0; g < bm->ngeom; ++g) {
    const char* name = mj_id2name(bm, mjOBJ_GEOM, g);
    if (name == nullptr || !std::string_view(name).starts_with("bump_")) continue;
    EXPECT_LE(bm->geom_pos[3 * g + 2] - bm->geom_size[3 * g + 2], -0.01) << name;
  }
  // The plain wall has none.
  const Scenario flat = Load("flat.yaml", GeckoWall(1.0));
  EXPECT_EQ(BumpCount(CompileScenario(flat)->model()), 0);

  Simulation sim(s, *model);
  sim.Run();
  // Every pad starts attached (no bump under the starting feet) ...
  int start = 0, on_bump = 0;
  const mjModel* m = sim.world().model();
  for (const Event& e : sim.events().rows()) {
    if (std::string_view(e.kind) != "attach") continue;
    start += std::string_view(e.cause) == "start_attached";
    const char* name = e.surface_geom >= 0 ? mj_id2name(m, mjOBJ_GEOM, e.surface_geom) : nullptr;
    on_bump += name != nullptr && std::string_view(name).starts_with("bump_");
  }
  EXPECT_EQ(start, 4);
  // ... and a foot that steps onto a bump sticks to its top.
  EXPECT_GT(on_bump, 0);
}

TEST(Disturbance, KeysAreCheckedWithTheirPlace) {
  EXPECT_EQ(ErrorOf("rough_bad.yaml",
                    "robot: gecko\nscene:\n  name: wall\n  roughness: {height_m: 0.002, "
                    "spacing_m: 0.01, size_m: 0.02}\nduration_s: 1\n"),
            "rough_bad.yaml:4:57: scene.roughness.size_m: must be <= spacing_m");
  EXPECT_EQ(ErrorOf("rough_scene.yaml",
                    "robot: gecko\nscene:\n  name: floor_to_wall\n  roughness: {height_m: 0.002}\n"
                    "duration_s: 1\n"),
            "rough_scene.yaml:4:14: scene.roughness: applies to the plane scenes only (floor, "
            "wall, ceiling, incline)");
  EXPECT_EQ(ErrorOf("fail_bad.yaml",
                    "robot: gecko\nscene: wall\nduration_s: 1\nadhesion:\n"
                    "  pad_failure_probability: 1.5\n"),
            "fail_bad.yaml:5:28: adhesion.pad_failure_probability: must be in [0, 1], got 1.5");
  EXPECT_EQ(
      ErrorOf("payload_bad.yaml", "robot: gecko\nscene: wall\nduration_s: 1\npayload_kg: -1\n"),
      "payload_bad.yaml:4:13: payload_kg: must be in [0, 1000], got -1");
}

}  // namespace
}  // namespace climbsim::sim
