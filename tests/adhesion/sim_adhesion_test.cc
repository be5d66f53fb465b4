// The adhesion effect in a simulation (sim/adhesion_effect.h): the gecko on the wall, the
// files a run writes, the controller API, ankle force/torque sensors against the weld, and
// the scenario's adhesion keys.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <sstream>

#include "sim/adhesion_effect.h"
#include "sim/sim.h"
#include "tests/common/scenario_error.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::ReadFile;
using climbsim::testing::WriteFile;

Scenario Load(const std::string& name, const std::string& text) {
  return LoadScenario(WriteFile(name, text));
}

std::string ErrorOf(const std::string& name, const std::string& text) {
  return climbsim::testing::ScenarioErrorOf(name, text);
}

const char* kGeckoWall =
    "robot: gecko\nscene: wall\nduration_s: 5\nadhesion:\n  start_attached: true\n";

// A gecko placed on the wall with start_attached and no CPG hangs on its four pads for 5 s:
// no fall, every pad still attached, the base within 5 mm of where it settled. Without the
// adhesion block the same robot slides down and falls (the pad friction alone cannot hold it:
// gravity is along the wall and nothing presses the pads on).
TEST(AdhesionSim, GeckoHoldsOnTheWallWithStartAttachedAndFallsWithout) {
  {
    const Scenario s = Load("wall.yaml", kGeckoWall);
    auto model = CompileScenario(s);
    Simulation sim(s, *model);
    const AdhesionEffect* a = FindAdhesion(sim.effects());
    ASSERT_NE(a, nullptr);
    for (int i = 0; i < a->pad_count(); ++i) EXPECT_TRUE(a->pad(i).attached()) << i;
    const RunResult r = sim.Run();
    EXPECT_TRUE(r.stable) << r.failure;
    EXPECT_FALSE(r.fell);
    EXPECT_LT(std::abs(r.distance_m), 0.005);
    for (int i = 0; i < a->pad_count(); ++i) {
      EXPECT_TRUE(a->pad(i).attached()) << a->pad_name(i);
      EXPECT_EQ(a->pad(i).bonded_fraction(), 1.0);
      EXPECT_EQ(a->pad(i).counts().attach, 1);
    }
    for (const LegSignals& l : sim.legs()) {
      EXPECT_TRUE(l.attached);
      EXPECT_TRUE(l.touching);
      EXPECT_EQ(l.bonded_fraction, 1.0);
    }
  }
  {
    const Scenario s = Load("wall_off.yaml", "robot: gecko\nscene: wall\nduration_s: 5\n");
    auto model = CompileScenario(s);
    Simulation sim(s, *model);
    const RunResult r = sim.Run();
    EXPECT_TRUE(r.fell);
    EXPECT_LT(r.distance_m, -0.1) << "it slides down the wall";
  }
}

// The run directory: events.csv with the columns and the start attachments, a
// bonded-fraction column per pad in trajectory.csv, per-pad counts in summary.json.
TEST(AdhesionSim, RunDirectoryHasEventsColumnsAndCounts) {
  const Scenario s = Load("files.yaml",
                          "robot: gecko\nscene: wall\nduration_s: 0.2\nadhesion:\n"
                          "  start_attached: true\n");
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  sim.Run();
  const std::string dir = climbsim::testing::TempDir() + "/adhesion_run";
  WriteRunDirectory(dir, sim);

  std::istringstream events(ReadFile(dir + "/events.csv"));
  std::string line;
  std::getline(events, line);
  EXPECT_EQ(line, "time_s,pad,event,cause,surface,bonded_fraction,fn_n,fx_n,fy_n,mx_nm,my_nm");
  std::vector<std::string> rows;
  while (std::getline(events, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 8u) << "touchdown and attach for each of 4 pads";
  const std::string touchdown = "0.000000,LF_pad,touchdown,,wall,0.000000,";
  const std::string attach = "0.000000,LF_pad,attach,start_attached,wall,1.000000,";
  EXPECT_EQ(rows[0].substr(0, touchdown.size()), touchdown);
  EXPECT_EQ(rows[1].substr(0, attach.size()), attach);

  std::istringstream traj(ReadFile(dir + "/trajectory.csv"));
  std::getline(traj, line);
  for (const char* pad : {"LF_pad", "RF_pad", "LH_pad", "RH_pad"}) {
    EXPECT_NE(line.find(std::string(pad) + "_bonded_fraction"), std::string::npos) << pad;
  }

  const nlohmann::json j = nlohmann::json::parse(ReadFile(dir + "/summary.json"));
  ASSERT_TRUE(j.contains("adhesion"));
  EXPECT_EQ(j["adhesion"]["model"], "bonds");
  const auto& lf = j["adhesion"]["pads"]["LF_pad"];
  EXPECT_EQ(lf["attach"], 1);
  EXPECT_EQ(lf["touchdown"], 1);
  EXPECT_EQ(lf["attach_rejected"], 0);
  EXPECT_EQ(lf["detach_peel"], 0);
  EXPECT_EQ(lf["detach_overload"], 0);
  EXPECT_EQ(lf["detach_released"], 0);
  EXPECT_EQ(lf["attached_at_end"], true);
  EXPECT_EQ(j["effects"][0], "adhesion") << "first in the pipeline";
}

// The pad load columns of trajectory.csv carry the robot: the gecko hanging still on its four
// welded pads (nothing else touches the wall) pulls them down the wall (pad x = world +x, up)
// with its whole weight, and neither off the wall nor sideways in sum (the pads sit in their
// neutral pose, so pad and world axes agree to within their small settling tilt).
TEST(AdhesionSim, PadLoadColumnsSumToTheRobotsWeight) {
  const Scenario s = Load("load_columns.yaml",
                          "robot: gecko\nscene: wall\nduration_s: 1\nadhesion:\n"
                          "  start_attached: true\n");
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  sim.Run();
  const std::string dir = climbsim::testing::TempDir() + "/adhesion_load_columns";
  WriteRunDirectory(dir, sim);
  std::istringstream traj(ReadFile(dir + "/trajectory.csv"));
  std::string header, line, last;
  std::getline(traj, header);
  while (std::getline(traj, line)) last = line;
  const std::vector<std::string> names = climbsim::testing::SplitCsv(header),
                                 values = climbsim::testing::SplitCsv(last);
  ASSERT_EQ(names.size(), values.size());
  auto column = [&](const std::string& name) {
    for (size_t i = 0; i < names.size(); ++i)
      if (names[i] == name) return std::stod(values[i]);
    ADD_FAILURE() << "no column " << name;
    return 0.0;
  };
  double fn = 0, fx = 0, fy = 0;
  for (const char* pad : {"LF_pad", "RF_pad", "LH_pad", "RH_pad"}) {
    fn += column(std::string(pad) + "_fn_n");
    fx += column(std::string(pad) + "_fx_n");
    fy += column(std::string(pad) + "_fy_n");
    EXPECT_LT(column(std::string(pad) + "_fx_n"), 0.0) << pad << " carries part of the weight";
  }
  const double weight_n = 9.81 * sim.world().robot().mass_kg;
  EXPECT_NEAR(fx, -weight_n, 0.02 * weight_n);
  EXPECT_NEAR(fn, 0.0, 0.02 * weight_n);
  EXPECT_NEAR(fy, 0.0, 0.02 * weight_n);
}

// RequestRelease (the reflexes' way to lift a leg): the pad lets go at once with cause
// released, the leg's signals follow, and the pad does not re-attach while it still rests
// on the wall. The gecko then hangs on three pads.
TEST(AdhesionSim, RequestReleaseDetachesWithCauseReleased) {
  const Scenario s = Load("release.yaml", kGeckoWall);
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  AdhesionEffect* a = FindAdhesion(sim.effects());
  for (int i = 0; i < 200; ++i) sim.Step();
  const int leg = 0, pad = a->pad_of_leg(leg);
  ASSERT_EQ(a->pad_name(pad), "LF_pad");
  EXPECT_EQ(a->leg_of_pad(pad), leg);
  ASSERT_TRUE(a->RequestReleaseLeg(leg));
  EXPECT_FALSE(sim.legs()[leg].attached);
  EXPECT_FALSE(a->RequestRelease(pad)) << "already released";
  const Event& e = sim.events().rows().back();
  EXPECT_STREQ(e.kind, "detach");
  EXPECT_STREQ(e.cause, "released");
  EXPECT_EQ(e.pad, pad);
  for (int i = 0; i < 500; ++i) sim.Step();
  EXPECT_FALSE(a->pad(pad).attached());
  EXPECT_EQ(a->pad(pad).counts().attach, 1);
  EXPECT_FALSE(sim.result().fell);
}

// A force/torque sensor pair at the ankle site (what the tibia exerts on the pad, in the site
// frame) agrees with the weld's wrench: for the welded pad at rest, ankle + weld + the pad's
// weight = 0, forces and moments about the ankle site. The residual is the pad's inertia (it
// sits still in its weld): 1e-5 N against loads of 0.1–0.3 N.
//
// MuJoCo 2.2.2's torque sensors count a weld's couple twice: mj_rnePostConstraint, behind
// force/torque sensors, takes the weld's rotational constraint force without the 1/2 of the
// quaternion residual's Jacobian. Our couple is the one the dynamics apply (it equals Jᵀf to
// 1e-15, and Weld.WrenchBalancesGravityOnAWeldedBlock checks it against statics), so the
// moments balance with the sensor when the weld's couple is counted twice, to 1e-9 N·m.
TEST(AdhesionSim, AnkleForceTorqueSensorsAgreeWithTheWeldWrench) {
  const Scenario s = Load("sensors.yaml", kGeckoWall);
  MjcfAdditions add = EffectAdditions(s);
  for (const char* leg : {"LF", "RF", "LH", "RH"}) {
    add.sensor += std::string("    <force name=\"") + leg + "_f\" site=\"" + leg + "_ankle\"/>\n" +
                  "    <torque name=\"" + leg + "_t\" site=\"" + leg + "_ankle\"/>\n";
  }
  auto model = CompiledModel::Build(s, add);
  Simulation sim(s, *model);
  for (int i = 0; i < 1000; ++i) ASSERT_TRUE(sim.Step());
  const mjModel* m = sim.world().model();
  const mjData* d = sim.world().data();
  const AdhesionEffect* a = FindAdhesion(sim.effects());
  const Eigen::Vector3d g(m->opt.gravity[0], m->opt.gravity[1], m->opt.gravity[2]);
  for (int k = 0; k < 4; ++k) {
    const adhesion::StickyPad& pad = a->pad(k);
    const std::string leg = a->pad_name(k).substr(0, 2);
    const int site = mj_name2id(m, mjOBJ_SITE, (leg + "_ankle").c_str());
    const int eq = mj_name2id(m, mjOBJ_EQUALITY, adhesion::WeldName(a->pad_name(k)).c_str());
    const int body = pad.geometry().body;
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> r_site(d->site_xmat +
                                                                                9 * site);
    const Eigen::Vector3d p_site(d->site_xpos + 3 * site);
    const Eigen::Vector3d f_ankle = r_site * Eigen::Vector3d(d->sensordata + 6 * k);
    const Eigen::Vector3d t_ankle = r_site * Eigen::Vector3d(d->sensordata + 6 * k + 3);
    adhesion::WeldWrench w;
    ASSERT_TRUE(adhesion::ReadWeldWrench(m, d, eq, &w));
    const adhesion::PadFrame face = adhesion::FaceFrame(d, pad.geometry());
    const Eigen::Vector3d weight = m->body_mass[body] * g;
    const Eigen::Vector3d p_com(d->xipos + 3 * body);
    const Eigen::Vector3d force_sum = f_ankle + w.force_n + weight;
    const Eigen::Vector3d moment_sum = t_ankle + 2.0 * w.torque_nm +
                                       (face.pos - p_site).cross(w.force_n) +
                                       (p_com - p_site).cross(weight);
    EXPECT_LT(force_sum.norm(), 1e-5)
        << leg << ": ankle " << f_ankle.transpose() << ", weld " << w.force_n.transpose();
    EXPECT_LT(moment_sum.norm(), 1e-9) << leg;
    EXPECT_GT(w.force_n.norm(), 0.05) << leg << " carries part of the weight";
    // And the pad load the bond grid used is this weld wrench in the pad frame, negated.
    const Eigen::Vector3d f_pad = face.rot.transpose() * w.force_n;
    EXPECT_NEAR(pad.load().fn_n, -f_pad.z(), 1e-12);
    EXPECT_NEAR(pad.load().fx_n, -f_pad.x(), 1e-12);
  }
}

// Switching a weld on in a running robot: the gecko stands on the floor (settled 0.5 s, no
// adhesion conditions), then LF's pad is welded where it is; over 100 steps it moves
// < 1e-4 m and < 1e-3 rad.
TEST(AdhesionSim, WeldSwitchedOnUnderARobotDoesNotMoveThePad) {
  const Scenario s = Load("floor_weld.yaml",
                          "robot: gecko\nscene: floor\nduration_s: 1\nadhesion:\n"
                          "  min_contacts: 5\n");  // never attaches by itself
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  for (int i = 0; i < 500; ++i) sim.Step();
  AdhesionEffect* a = FindAdhesion(sim.effects());
  mjModel* m = sim.world().model();
  mjData* d = sim.world().data();
  auto& pad = const_cast<adhesion::StickyPad&>(a->pad(0));
  bool current = false;
  ASSERT_TRUE(pad.ForceAttach(m, d, d->time, mj_name2id(m, mjOBJ_GEOM, "floor"), 1.0,
                              adhesion::PadCause::kForced, &current, nullptr));
  const adhesion::PadFrame before = adhesion::FaceFrame(d, pad.geometry());
  double worst_m = 0, worst_rad = 0;
  for (int i = 0; i < 100; ++i) {
    sim.Step();
    mj_kinematics(m, d);
    const adhesion::PadFrame now = adhesion::FaceFrame(d, pad.geometry());
    worst_m = std::max(worst_m, (now.pos - before.pos).norm());
    worst_rad = std::max(
        worst_rad, Eigen::AngleAxisd(Eigen::Matrix3d(before.rot.transpose() * now.rot)).angle());
  }
  EXPECT_TRUE(pad.attached());
  EXPECT_LT(worst_m, 1e-4);
  EXPECT_LT(worst_rad, 1e-3);
  std::printf("weld switched on under the standing gecko: pad moved %.3g m, %.3g rad\n", worst_m,
              worst_rad);
}

// The baseline on the same scene: MuJoCo's adhesion actuators (gain σ_T·A = 6.25 N per pad,
// reach 1 mm) hold the gecko on the wall through friction once noslip stops the creep of
// soft friction (mjcf/README.md, docs/mujoco.md).
TEST(AdhesionSim, MujocoActuatorBaselineHoldsTheGeckoOnTheWall) {
  const Scenario s = Load("wall_mujoco.yaml",
                          "robot: gecko\nscene: wall\nduration_s: 2\nphysics:\n"
                          "  noslip_iterations: 10\nadhesion:\n  model: mujoco\n"
                          "  start_attached: true\n");
  auto model = CompileScenario(s);
  EXPECT_EQ(model->model()->nu, 12 + 4) << "one adhesion actuator per pad";
  EXPECT_EQ(model->model()->neq, 0) << "no welds";
  Simulation sim(s, *model);
  const RunResult r = sim.Run();
  EXPECT_FALSE(r.fell);
  EXPECT_LT(std::abs(r.distance_m), 0.005);
  const AdhesionEffect* a = FindAdhesion(sim.effects());
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(a->pad(i).attached()) << i;
}

// An adhesion block adds exactly one inactive weld per pad (none without it), and the
// scenario's weld solref lands on the run's model.
TEST(AdhesionSim, AddsOneInactiveWeldPerPad) {
  const Scenario s = Load("welds.yaml",
                          "robot: spider\nscene: floor\nduration_s: 0.1\nadhesion:\n"
                          "  weld_solref: [0.004, 0.9]\n");
  auto model = CompileScenario(s);
  ASSERT_EQ(model->model()->neq, 6);
  Simulation sim(s, *model);
  const mjModel* m = sim.world().model();
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(m->eq_type[i], mjEQ_WELD);
    EXPECT_FALSE(adhesion::WeldActive(m, sim.world().data(), i));
    EXPECT_EQ(m->eq_solref[2 * i], 0.004);
    EXPECT_EQ(m->eq_solref[2 * i + 1], 0.9);
  }
  const Scenario none = Load("no_welds.yaml", "robot: spider\nscene: floor\nduration_s: 0.1\n");
  EXPECT_EQ(CompileScenario(none)->model()->neq, 0);
}

// Bad adhesion input is rejected before the run with the place and the key.
TEST(AdhesionSim, BadInputNamesThePlace) {
  EXPECT_EQ(ErrorOf("bad_pad.yaml",
                    "robot: gecko\nscene: floor\nduration_s: 1\nadhesion:\n"
                    "  pads: [LF_pad, XX_pad]\n"),
            "bad_pad.yaml:5:9: adhesion.pads: no body named 'XX_pad'");
  EXPECT_EQ(ErrorOf("not_box.yaml",
                    "robot: gecko\nscene: floor\nduration_s: 1\nadhesion:\n"
                    "  pads: [base]\n"),
            "not_box.yaml:5:9: adhesion.pads: pad body 'base' must hold exactly one box geom, "
            "has 5");
  EXPECT_EQ(ErrorOf("bad_surface.yaml",
                    "robot: gecko\nscene: floor\nduration_s: 1\nadhesion:\n"
                    "  surfaces: [ceiling]\n"),
            "bad_surface.yaml:5:13: adhesion.surfaces: no body or geom named 'ceiling'");
  EXPECT_EQ(ErrorOf("sigma.yaml",
                    "robot: gecko\nscene: floor\nduration_s: 1\nadhesion:\n"
                    "  sigma_t_pa: -3\n"),
            "sigma.yaml:5:15: adhesion.sigma_t_pa: must be > 0, got -3");
  EXPECT_EQ(ErrorOf("bonds.yaml",
                    "robot: gecko\nscene: floor\nduration_s: 1\nadhesion:\n"
                    "  grid_x: 2\n  grid_y: 2\n  min_bonds: 5\n"),
            "bonds.yaml:7:14: adhesion.min_bonds: must be <= grid_x * grid_y = 4, got 5");
  EXPECT_EQ(ErrorOf("model.yaml",
                    "robot: gecko\nscene: floor\nduration_s: 1\nadhesion:\n"
                    "  model: velcro\n"),
            "model.yaml:5:10: adhesion.model: must be one of bonds, mujoco, got 'velcro'");
  EXPECT_EQ(ErrorOf("override.yaml",
                    "robot: gecko\nscene: floor\nduration_s: 1\nadhesion:\n"
                    "  pad_overrides:\n    - {pad: L1_pad, mu: 0.5}\n"),
            "override.yaml:6:5: adhesion.pad_overrides: 'L1_pad' is not one of the sticky pads");
}

// pad_overrides change one pad's material.
TEST(AdhesionSim, PadOverridesChangeOnePad) {
  const Scenario s = Load("override_ok.yaml",
                          "robot: gecko\nscene: floor\nduration_s: 0.1\nadhesion:\n"
                          "  pads: [LF_pad, RH_pad]\n  pad_overrides:\n"
                          "    - {pad: RH_pad, sigma_t_pa: 5000, mu: 0.4}\n");
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  const AdhesionEffect* a = FindAdhesion(sim.effects());
  ASSERT_EQ(a->pad_count(), 2);
  EXPECT_EQ(a->pad(0).params().bonds.sigma_t_pa, 10e3);
  EXPECT_EQ(a->pad(1).params().bonds.sigma_t_pa, 5e3);
  EXPECT_EQ(a->pad(1).params().bonds.mu, 0.4);
  EXPECT_EQ(a->pad_of_leg(1), -1) << "RF has no sticky pad";
  // Event rows index the sticky pads by the adhesion effect's numbering.
  ASSERT_GE(sim.events().pad_names().size(), 2u);
  EXPECT_EQ(sim.events().pad_names()[0], "LF_pad");
  EXPECT_EQ(sim.events().pad_names()[1], "RH_pad");
}

}  // namespace
}  // namespace climbsim::sim
