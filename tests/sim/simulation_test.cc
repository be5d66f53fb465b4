// The step loop: a scenario without effects is bare MuJoCo bit for bit; stepping never
// allocates; the same scenario gives the same files; numerical trouble stops the run with
// the step, the time and MuJoCo's warning.
#include <gtest/gtest.h>

#include <cstring>

#include "sim/sim.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::ReadFile;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

Scenario Load(const std::string& name, const std::string& text) {
  return LoadScenario(WriteFile(name, text));
}

TEST(Simulation, NoEffectsIsBareMujocoBitForBit) {
  for (const char* robot : {"gecko", "spider"}) {
    const Scenario s = Load(std::string("bare_") + robot + ".yaml",
                            std::string("robot: ") + robot +
                                "\nscene: floor\nduration_s: 0.5\noutputs:\n"
                                "  trajectory_rate_hz: 0\n");
    auto model = CompileScenario(s);
    Simulation sim(s, *model);
    EXPECT_TRUE(sim.effects().empty());

    // The same model: the run's own copy, with the scenario's options applied.
    mjModel* m = mj_copyModel(nullptr, sim.world().model());
    mjData* d = mj_makeData(m);
    mj_resetData(m, d);
    for (long i = 0; i < sim.steps_total(); ++i) mj_step(m, d);
    const RunResult r = sim.Run();
    ASSERT_TRUE(r.stable) << r.failure;
    EXPECT_EQ(r.steps, 500);
    EXPECT_EQ(0, std::memcmp(d->qpos, sim.world().data()->qpos, sizeof(mjtNum) * m->nq))
        << robot;
    EXPECT_EQ(0, std::memcmp(d->qvel, sim.world().data()->qvel, sizeof(mjtNum) * m->nv))
        << robot;
    mj_deleteData(d);
    mj_deleteModel(m);
  }
}

TEST(Simulation, RecordingDoesNotChangeThePhysics) {
  const std::string base = "robot: gecko\nscene: floor\nduration_s: 0.3\n";
  const Scenario quiet = Load("rec0.yaml", base + "outputs:\n  trajectory_rate_hz: 0\n");
  const Scenario recorded = Load("rec1.yaml", base + "outputs:\n  trajectory_rate_hz: 1000\n");
  auto m0 = CompileScenario(quiet);
  auto m1 = CompileScenario(recorded);
  Simulation a(quiet, *m0), b(recorded, *m1);
  a.Run();
  b.Run();
  const mjModel* m = a.world().model();
  EXPECT_EQ(0, std::memcmp(a.world().data()->qpos, b.world().data()->qpos,
                           sizeof(mjtNum) * m->nq));
  // One row at t = 0 and one per step: 1 + 300 rows plus the header.
  const std::string csv = b.TrajectoryCsv();
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 302);
}

TEST(Simulation, SameScenarioGivesIdenticalFiles) {
  const std::string path = WriteFile("twice.yaml",
                                     "robot: gecko\nscene: floor\nduration_s: 1\n"
                                     "cpg:\n  gait: trot\n");
  std::string files[2][4];
  for (int run = 0; run < 2; ++run) {
    const Scenario s = LoadScenario(path);
    auto model = CompileScenario(s);
    Simulation sim(s, *model);
    sim.Run();
    const std::string dir = TempDir() + "/twice_" + std::to_string(run);
    WriteRunDirectory(dir, sim);
    files[run][0] = ReadFile(dir + "/trajectory.csv");
    files[run][1] = ReadFile(dir + "/events.csv");
    files[run][2] = ReadFile(dir + "/scenario.yaml");
    // Wall time differs between runs by nature; everything else in the summary must not.
    auto summary = nlohmann::json::parse(ReadFile(dir + "/summary.json"));
    summary.erase("wall_time_s");
    summary.erase("realtime_factor");
    files[run][3] = summary.dump();
  }
  EXPECT_GT(files[0][0].size(), 1000u);
  for (int f = 0; f < 4; ++f) EXPECT_EQ(files[0][f], files[1][f]) << "file " << f;
}

TEST(Simulation, NoTemporaryFilesAreLeftBehind) {
  const Scenario s = Load("atomic.yaml", "robot: gecko\nscene: floor\nduration_s: 0.05\n");
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  sim.Run();
  const std::string dir = TempDir() + "/atomic_run";
  WriteRunDirectory(dir, sim);
  int files = 0;
  for (const auto& f : std::filesystem::directory_iterator(dir)) {
    EXPECT_EQ(f.path().string().find(".tmp"), std::string::npos) << f.path();
    ++files;
  }
  // scenario.yaml, model.xml, trajectory.csv, events.csv, summary.json and the run-folder
  // marker .climbsim-run
  EXPECT_EQ(files, 6);
}

// A joint with an absurd explicit spring at a large step diverges: MuJoCo flags the bad
// acceleration; the run must stop there and say where.
TEST(Simulation, UnstableRunStopsWithStepTimeAndCause) {
  WriteFile("models/unstable.xml", climbsim::testing::kUnstableRobotMjcf);
  const Scenario s = Load("unstable.yaml",
                          "robot: models/unstable.xml\nscene: floor\nduration_s: 1\n"
                          "physics:\n  integrator: euler\n  timestep_s: 0.01\n");
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  const RunResult r = sim.Run();
  EXPECT_FALSE(r.stable);
  EXPECT_LT(r.steps, 100);  // stopped early
  const std::string expected_start = "step " + std::to_string(r.steps) + ", t = ";
  EXPECT_EQ(r.failure.rfind(expected_start, 0), 0u) << r.failure;
  EXPECT_NE(r.failure.find("mjWARN_BAD"), std::string::npos) << r.failure;
}

// A push of impulse J on a free robot with nothing to touch and no gravity changes its
// momentum by exactly J: the centre of mass then moves at J/m (internal servo forces cannot
// move it). Over 0.2 s after the push, to 1e-5 relative: Euler's implicit joint damping and
// the servos' internal motion leave a few 1e-6 of drift (measured 2.4e-6).
TEST(Simulation, PushChangesMomentumByItsImpulse) {
  WriteFile("scenes/space.xml",
            "<mujoco><option gravity=\"0 0 0\" timestep=\"0.001\"/><worldbody/></mujoco>\n");
  const Scenario s = Load("push.yaml",
                          "robot: gecko\nscene: scenes/space.xml\nduration_s: 0.4\n"
                          "physics:\n  integrator: euler\n"
                          "perturbations:\n  - {time_s: 0.1, impulse_ns: [0.002, -0.001, 0.0005],"
                          " duration_s: 0.005}\n");
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  ASSERT_EQ(sim.effects().front()->name(), std::string("perturbation"));
  const mjModel* m = sim.world().model();
  const int base = sim.world().robot().base_body;
  const double mass = m->body_subtreemass[base];
  std::array<double, 3> com_at_0_2{};
  for (int i = 0; i < 400; ++i) {
    ASSERT_TRUE(sim.Step());
    if (i == 199) {
      for (int k = 0; k < 3; ++k) com_at_0_2[k] = sim.world().data()->subtree_com[3 * base + k];
    }
  }
  const double impulse[3] = {0.002, -0.001, 0.0005};
  for (int k = 0; k < 3; ++k) {
    // subtree_com is computed at the start of a step: positions one step behind qpos, for
    // both samples alike, so the 0.2 s difference is exact.
    const double moved = sim.world().data()->subtree_com[3 * base + k] - com_at_0_2[k];
    const double expected = impulse[k] / mass * 0.2;
    EXPECT_NEAR(moved, expected, 1e-5 * std::abs(expected)) << k;
  }
}

}  // namespace
}  // namespace climbsim::sim
