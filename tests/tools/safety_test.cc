// Nothing a user has is lost or misreported (issue 13): the climbsim executable as a user, or
// an attacker, meets it. Output folders that are not climbsim's are refused before anything
// runs; a fall and a stall are reported as such; hostile input gets a clear error (exit 2)
// with its place.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "sim/sim.h"
#include "tests/common/test_util.h"

namespace {

namespace fs = std::filesystem;
using climbsim::testing::CliResult;
using climbsim::testing::Has;
using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsim;
using climbsim::testing::RunClimbsimArgs;
using climbsim::testing::Source;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

// events.csv's header (inspect/inspect.h).
const std::string kEventsHeader =
    "time_s,pad,event,cause,surface,bonded_fraction,fn_n,fx_n,fy_n,mx_nm,my_nm\n";

// A short floor walk: runs in well under a second.
const char* kWalk = "robot: gecko\nscene: floor\nduration_s: 0.2\ncpg:\n  gait: trot\n";

std::string Walk(const std::string& name, const std::string& extra = "") {
  return WriteFile(name, std::string(kWalk) + extra);
}

// A run folder made by `climbsim simulate` (exit code checked).
std::string SimulatedRun(const std::string& name, const std::string& extra = "") {
  const std::string dir = TempDir() + "/" + name;
  const CliResult r =
      RunClimbsim("simulate " + Walk(name + ".yaml", extra) + " --out " + dir + " --quiet");
  EXPECT_EQ(r.code, 0) << r.err;
  return dir;
}

nlohmann::json Summary(const std::string& dir) {
  return nlohmann::json::parse(ReadFile(dir + "/summary.json"));
}

// ---- Output folders --------------------------------------------------------------------------

TEST(OutputFolder, TheScenariosOwnFolderIsRefusedAndTheScenarioKept) {
  const std::string folder = TempDir() + "/own_folder";
  const std::string text = std::string("# my notes\n") + kWalk;
  const std::string scenario = WriteFile(folder + "/scenario.yaml", text);
  for (const char* force : {"", " --force"}) {
    const CliResult r = RunClimbsim("simulate " + scenario + " --out " + folder + force);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_TRUE(Has(r.err, "holds the input")) << r.err;
  }
  EXPECT_EQ(ReadFile(scenario), text) << "the user's scenario (and its comments) must survive";
}

TEST(OutputFolder, AnEarlierRunIsRefusedWithoutForceAndReplacedWholeWithIt) {
  const std::string dir = SimulatedRun("earlier_run");
  ASSERT_TRUE(fs::exists(dir + "/trajectory.csv"));
  const std::string before = ReadFile(dir + "/summary.json");
  const std::string no_traj = Walk("no_traj.yaml", "outputs: {trajectory_rate_hz: 0}\n");
  CliResult r = RunClimbsim("simulate " + no_traj + " --out " + dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "holds a previous climbsim run")) << r.err;
  EXPECT_EQ(ReadFile(dir + "/summary.json"), before);
  r = RunClimbsim("simulate " + no_traj + " --out " + dir + " --force --quiet");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/trajectory.csv")) << "the old run's trajectory must not mix in";
  EXPECT_TRUE(fs::exists(dir + "/.climbsim-run"));
}

TEST(OutputFolder, AFolderOfTheUsersIsRefusedEvenWithForce) {
  const std::string dir = TempDir() + "/users_folder";
  WriteFile(dir + "/notes.txt", "mine\n");
  const CliResult r = RunClimbsim("simulate " + Walk("users.yaml") + " --out " + dir + " --force");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "holds files climbsim did not make")) << r.err;
  EXPECT_EQ(ReadFile(dir + "/notes.txt"), "mine\n");
  EXPECT_FALSE(fs::exists(dir + "/summary.json"));
}

TEST(OutputFolder, OptimiseRefusesASimulateRun) {
  const std::string dir = SimulatedRun("opt_over_sim");
  const std::string before = ReadFile(dir + "/summary.json");
  const std::string scenario =
      Walk("opt_over_sim_opt.yaml",
           "optimise:\n  parameters:\n    - {key: cpg.frequency_hz, start: 1, min: 0.5, max: 2}\n"
           "  max_evaluations: 2\n");
  const CliResult r = RunClimbsim("optimise " + scenario + " --out " + dir + " --quiet");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "holds a previous climbsim run (made by climbsim simulate)")) << r.err;
  EXPECT_EQ(ReadFile(dir + "/summary.json"), before);
}

// A file, a folder that cannot be written, an empty name, `/` and `.`: refused before the run
// (no summary printed, nothing written), exit 2.
TEST(OutputFolder, ImpossibleOutputsAreRefusedBeforeTheRun) {
  const std::string file = WriteFile("out_is_a_file", "x\n");
  const std::string scenario = Walk("impossible.yaml");
  const std::pair<std::string, std::string> cases[] = {
      {file, "is a file, not a folder"},   {file + "/run", "is a file, not a folder"},
      {"/proc/climbsim_out", "cannot be"}, {"''", "must not be empty"},
      {"/", "is the root folder"},         {".", "is the current folder"},
  };
  for (const auto& [out, message] : cases) {
    const CliResult r = RunClimbsim("simulate " + scenario + " --out " + out);
    EXPECT_EQ(r.code, 2) << out << ": " << r.err;
    EXPECT_TRUE(Has(r.err, message)) << out << ": " << r.err;
    EXPECT_FALSE(Has(r.out, "simulated")) << out << ": the run must not start";
  }
  EXPECT_EQ(ReadFile(file), "x\n");
  EXPECT_FALSE(fs::exists("summary.json"));
}

TEST(OutputFolder, ASecondWriterIsRefusedWhileTheFirstWrites) {
  const std::string dir = TempDir() + "/two_writers";
  const int fd = ::open((TempDir() + "/.two_writers.climbsim-lock").c_str(),
                        O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);  // as a first climbsim would
  const CliResult r = RunClimbsim("simulate " + Walk("two.yaml") + " --out " + dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "is being written by another climbsim")) << r.err;
  ::close(fd);
  EXPECT_EQ(RunClimbsim("simulate " + Walk("two.yaml") + " --out " + dir + " --quiet").code, 0);
}

TEST(OutputFolder, RenderAndPlotsNeverReplaceARunsData) {
  const std::string dir = SimulatedRun("render_guard");
  const std::string before = ReadFile(dir + "/trajectory.csv");
  CliResult r = RunClimbsim("render " + dir + " --at 0.1 --out " + dir + "/trajectory.csv");
  EXPECT_EQ(r.code, 2) << r.err;
  r = RunClimbsim("render " + dir + " --at 0.1 --out " + dir + "/summary.png");
  EXPECT_NE(r.code, 2) << "a still beside the data is fine: " << r.err;
  r = RunClimbsim("render " + dir + " --out " + dir + "/events.csv");
  EXPECT_EQ(r.code, 2) << r.err;
  r = RunClimbsim("render " + dir + " --frames " + dir);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(ReadFile(dir + "/trajectory.csv"), before);
  // render --at nan would have made a video named like a still.
  r = RunClimbsim("render " + dir + " --at nan --out " + TempDir() + "/nan.png");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "--at: must be a finite time")) << r.err;
  EXPECT_FALSE(fs::exists(TempDir() + "/nan.png"));
}

// --force deletes only what climbsim made: a marker that is empty or `{}` marks nothing.
TEST(OutputFolder, ForceRefusesAForgedMarkerAndKeepsTheThesis) {
  int k = 0;
  for (const char* marker : {"", "{}"}) {
    const std::string dir = TempDir() + "/forged_" + std::to_string(k++);
    WriteFile(dir + "/.climbsim-run", marker);
    WriteFile(dir + "/thesis.tex", "mine\n");
    const CliResult r =
        RunClimbsimArgs({"simulate", Walk("forged.yaml"), "--out", dir, "--force", "--quiet"});
    EXPECT_EQ(r.code, 2) << marker << ": " << r.err;
    EXPECT_TRUE(Has(r.err, "is not a climbsim run folder")) << r.err;
    EXPECT_EQ(ReadFile(dir + "/thesis.tex"), "mine\n");
  }
}

TEST(OutputFolder, ForceRefusesAUsersNotesAndFolderUnlessToldToKeepThem) {
  const std::string dir = SimulatedRun("notes_run");
  WriteFile(dir + "/notes.txt", "mine\n");
  WriteFile(dir + "/analysis/fit.py", "print(1)\n");
  const std::string scenario = Walk("notes_run.yaml");
  CliResult r = RunClimbsimArgs({"simulate", scenario, "--out", dir, "--force", "--quiet"});
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "analysis/fit.py, notes.txt; --force deletes only climbsim's own"))
      << r.err;
  EXPECT_TRUE(Has(r.err, "--keep-other-files")) << r.err;
  EXPECT_EQ(ReadFile(dir + "/notes.txt"), "mine\n");
  r = RunClimbsimArgs(
      {"simulate", scenario, "--out", dir, "--force", "--keep-other-files", "--quiet"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(ReadFile(dir + "/notes.txt"), "mine\n");
  EXPECT_EQ(ReadFile(dir + "/analysis/fit.py"), "print(1)\n");
  EXPECT_TRUE(fs::exists(dir + "/summary.json"));
}

TEST(OutputFolder, ADanglingLinkIsRefusedNotReplaced) {
  const std::string link = TempDir() + "/dangling_out";
  fs::create_symlink(TempDir() + "/nowhere", link);
  const CliResult r = RunClimbsimArgs({"simulate", Walk("dangling.yaml"), "--out", link});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(Has(r.err, "dangling symlink")) << r.err;
  EXPECT_TRUE(fs::is_symlink(link));
}

// README's flow: simulate, plots and a still into the run folder, simulate --force again. They
// are recorded as climbsim's, so the second run replaces them without a refusal.
TEST(OutputFolder, PlotsAndStillsAddedToARunAreRecordedAndReplacedByTheNextForce) {
  const std::string dir = SimulatedRun("plots_then_force");
  CliResult r = RunClimbsimArgs({"inspect", dir, "--plots"});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto marker = nlohmann::json::parse(ReadFile(dir + "/.climbsim-run"));
  EXPECT_TRUE(Has(marker["files"].dump(), "\"gait.png\"")) << marker.dump();
  r = RunClimbsimArgs({"inspect", dir, "--plots"});
  EXPECT_EQ(r.code, 0) << "plots are redrawn: " << r.err;
  for (int k = 0; k < 2; ++k) {  // a still, then the same still again over climbsim's own
    r = RunClimbsimArgs({"render", dir, "--at", "0.1", "--out", dir + "/still.png", "--width",
                         "64", "--height", "48", "--quality", "reduced", "--quiet"});
    EXPECT_EQ(r.code, 0) << r.err;
  }
  EXPECT_TRUE(Has(ReadFile(dir + "/.climbsim-run"), "\"still.png\""));
  r = RunClimbsimArgs(
      {"simulate", Walk("plots_then_force.yaml"), "--out", dir, "--force", "--quiet"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/gait.png"));
  EXPECT_FALSE(fs::exists(dir + "/still.png"));
}

TEST(OutputFolder, RenderNeverOverwritesAUsersFileNorWritesFramesAmongAUsersFiles) {
  const std::string dir = SimulatedRun("render_users");
  const std::string png = WriteFile("users_still.png", "mine\n");
  CliResult r = RunClimbsimArgs({"render", dir, "--at", "0.1", "--out", png});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(Has(r.err, "climbsim never overwrites a file it did not make")) << r.err;
  EXPECT_TRUE(ReadFile(png) == "mine\n") << "the user's file must survive";
  const std::string frames = TempDir() + "/users_frames";
  WriteFile(frames + "/holiday.jpg", "mine\n");
  r = RunClimbsimArgs({"render", dir, "--frames", frames});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(Has(r.err, "holds files climbsim did not make")) << r.err;
  EXPECT_FALSE(fs::exists(frames + "/frame_00000.png"));
}

// ---- optimise --resume -----------------------------------------------------------------------

const char* kOptimise =
    "optimise:\n  parameters:\n    - {key: cpg.frequency_hz, start: 1, min: 0.5, max: 2}\n"
    "  algorithm: LN_SBPLX\n  max_evaluations: 3\n  starts: 1\n";

TEST(OptimiseResume, AnEditedCheckpointIsRefused) {
  const std::string scenario = Walk("resume_edit.yaml", kOptimise);
  const std::string dir = TempDir() + "/resume_edit";
  ASSERT_EQ(RunClimbsim("optimise " + scenario + " --out " + dir + " --quiet").code, 0);
  nlohmann::json j = nlohmann::json::parse(ReadFile(dir + "/checkpoint.json"));
  ASSERT_TRUE(j.contains("checksum"));
  j["starts"][0][0]["objective"] = -1000.0;  // a fake best
  WriteFile(dir + "/checkpoint.json", j.dump());
  CliResult r = RunClimbsim("optimise " + scenario + " --out " + dir + " --resume --quiet");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "checkpoint.json: checksum: does not match the content")) << r.err;
  // Values of the wrong type: a clear message, not a raw exception.
  WriteFile(dir + "/checkpoint.json", "{\"fingerprint\": 5, \"starts\": {}}");
  r = RunClimbsim("optimise " + scenario + " --out " + dir + " --resume --quiet");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "not a climbsim checkpoint")) << r.err;
  // No checkpoint: --resume has nothing to continue.
  fs::remove(dir + "/checkpoint.json");
  r = RunClimbsim("optimise " + scenario + " --out " + dir + " --resume --quiet");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "checkpoint.json: missing: nothing to resume")) << r.err;
  EXPECT_FALSE(Has(ReadFile(dir + "/best.yaml"), "-1000"));
}

TEST(OptimiseInput, AStringKeyAndZeroEvaluationsAreRefusedBeforeRunning) {
  const std::string scenario =
      Walk("opt_gait.yaml",
           "optimise:\n  parameters:\n    - {key: cpg.gait, start: 1, min: 0, max: 2}\n");
  CliResult r = RunClimbsim("optimise " + scenario + " --out " + TempDir() + "/opt_gait");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "cpg.gait")) << r.err;
  EXPECT_FALSE(fs::exists(TempDir() + "/opt_gait/history.csv"));
  r = RunClimbsim("optimise " + Walk("opt_zero.yaml", kOptimise) + " --out " + TempDir() +
                  "/opt_zero --max-evaluations 0");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_FALSE(fs::exists(TempDir() + "/opt_zero"));
}

// ---- Falls and stalls ------------------------------------------------------------------------

// The gecko on a wall without adhesion slides off. Its distance is the distance up to the
// fall: the base dropped fall.drop_m (0.1 m) along gravity, which on the wall is straight
// down the travel direction, so distance_m is about -0.1 m, not the metres of a free fall.
TEST(Fall, DistanceAndSpeedAreUpToTheFallAndTheTerminalSaysWhen) {
  const std::string scenario = WriteFile("fall.yaml", "robot: gecko\nscene: wall\nduration_s: 3\n");
  const std::string dir = TempDir() + "/fall_run";
  const CliResult r = RunClimbsim("simulate " + scenario + " --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json s = Summary(dir);
  ASSERT_TRUE(s["fell"].get<bool>());
  const double fall_s = s["fall_time_s"].get<double>();
  EXPECT_EQ(s["fall_cause"], "dropped");
  EXPECT_LT(s["duration_s"].get<double>(), 3.0) << "a fall ends the run by default";
  EXPECT_NEAR(s["duration_s"].get<double>(), fall_s, 2e-3);
  EXPECT_LT(s["distance_m"].get<double>(), -0.09);
  EXPECT_GT(s["distance_m"].get<double>(), -0.15);
  EXPECT_NEAR(s["mean_speed_mps"].get<double>(), s["distance_m"].get<double>() / fall_s, 1e-9);
  char at[64];
  std::snprintf(at, sizeof(at), "fell            yes, at %.3f s", fall_s);
  EXPECT_TRUE(Has(r.out, at)) << r.out;

  // fall.stop: false simulates on; the distance stays the one up to the fall.
  const std::string on = WriteFile("fall_on.yaml",
                                   "robot: gecko\nscene: wall\nduration_s: 3\n"
                                   "fall: {stop: false}\n");
  ASSERT_EQ(RunClimbsim("simulate " + on + " --out " + dir + "_on --quiet").code, 0);
  const nlohmann::json s2 = Summary(dir + "_on");
  EXPECT_NEAR(s2["duration_s"].get<double>(), 3.0, 1e-9);
  EXPECT_NEAR(s2["distance_m"].get<double>(), s["distance_m"].get<double>(), 1e-12);
  EXPECT_LT(s2["distance_at_end_m"].get<double>(), -1.0) << "the free fall after it";
}

// wait_for_support asks for a bond fraction the pads never reach under load (1.0; a loaded
// pad holds about 0.9): the gait freezes. The run says so, with the time and the leg.
TEST(Stall, AFrozenGaitIsReportedWithItsTimeAndLeg) {
  std::string text = ReadFile(Source("examples/gecko_wall.yaml"));
  const std::string from = "support_bond_fraction: 0.85";
  ASSERT_NE(text.find(from), std::string::npos);
  text.replace(text.find(from), from.size(), "support_bond_fraction: 1.0");
  text.replace(text.find("duration_s: 20"), 14, "duration_s: 6");
  const std::string dir = TempDir() + "/stall_run";
  const CliResult r = RunClimbsim("simulate " + WriteFile("stall.yaml", text) + " --out " + dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json s = Summary(dir);
  ASSERT_TRUE(s["stalled"].get<bool>()) << s.dump(2);
  EXPECT_LT(s["stall_time_s"].get<double>(), 4.0);
  EXPECT_TRUE(s["stall_leg"].is_string());
  EXPECT_TRUE(Has(s["stall_reason"].get<std::string>(), "cpg.wait_for_support")) << s.dump(2);
  EXPECT_TRUE(Has(r.out, "STALLED")) << r.out;
  // A walk that nothing holds does not stall.
  const std::string ok = SimulatedRun("no_stall");
  EXPECT_FALSE(Summary(ok)["stalled"].get<bool>());
}

// ---- Hostile input ---------------------------------------------------------------------------

CliResult Simulate(const std::string& scenario, const std::string& out_name) {
  return RunClimbsim("simulate " + scenario + " --out " + TempDir() + "/" + out_name);
}

TEST(HostileInput, DevZeroHugeFilesLongListsAndFoldersAreRefusedQuickly) {
  CliResult r = Simulate("/dev/zero", "zero");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "/dev/zero: is not a regular file (a device?)")) << r.err;
  std::string huge(5u << 20, '#');
  huge += "\n";
  r = Simulate(WriteFile("huge.yaml", std::string(kWalk) + huge), "huge");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "larger than 4 MiB")) << r.err;
  std::string list = std::string(kWalk) + "initial:\n  offset_m: [";
  for (int i = 0; i < 20000; ++i) list += "0, ";
  list += "0]\n";
  r = Simulate(WriteFile("long_list.yaml", list), "long_list");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "long_list.yaml:7:13: a list of 20001 items; at most 10000")) << r.err;
  fs::create_directories(TempDir() + "/a_folder.yaml");
  r = Simulate(TempDir() + "/a_folder.yaml", "folder");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "a_folder.yaml: is a folder, not a scenario file")) << r.err;
}

TEST(HostileInput, ATimestepOfANanosecondIsRefusedAtLoad) {
  const std::string s = Walk("ns.yaml", "physics: {timestep_s: 1e-9}\n");
  const CliResult r = Simulate(s, "ns");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err,
                  "ns.yaml:6:23: physics.timestep_s: duration_s / physics.timestep_s "
                  "asks for 200000000 steps; climbsim runs at most 100000000"))
      << r.err;
}

// Without physics.timestep_s the scene's step (1 ms) applies: a million seconds is 10^9 steps.
// A trajectory of more than 2·10^6 rows is refused too (it would be reserved in memory).
TEST(HostileInput, RunsTooLongForMemoryAreRefusedBeforeRunning) {
  CliResult r = Simulate(WriteFile("million_s.yaml",
                                   "robot: gecko\nscene: floor\n"
                                   "duration_s: 1000000\n"),
                         "million_s");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "asks for 1000000000 steps; climbsim runs at most 100000000")) << r.err;
  r = Simulate(WriteFile("rows.yaml",
                         "robot: gecko\nscene: floor\nduration_s: 30000\n"
                         "physics: {timestep_s: 0.01}\n"),
               "rows");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "outputs.trajectory_rate_hz: would record 3000000 rows")) << r.err;
  EXPECT_FALSE(fs::exists(TempDir() + "/rows"));
}

TEST(HostileInput, MultiDocumentYamlAndAPushAfterTheEndAreRefused) {
  CliResult r = Simulate(WriteFile("two_docs.yaml", std::string(kWalk) + "---\nseed: 3\n"), "two");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "two_docs.yaml:7:1: a second YAML document")) << r.err;
  r = Simulate(Walk("late_push.yaml", "perturbations:\n  - {time_s: 5, impulse_ns: [0, 0, 0.1]}\n"),
               "late");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "perturbations[0].time_s: must be before the end of the run")) << r.err;
}

TEST(HostileInput, TheDocumentedLargestSeedIsAccepted) {
  const climbsim::sim::Scenario s =
      climbsim::sim::LoadScenario(Walk("seed_max.yaml", "seed: 2147483647\n"));
  EXPECT_EQ(s.seed, 2147483647);
  EXPECT_THROW(climbsim::sim::LoadScenario(Walk("seed_over.yaml", "seed: 2147483648\n")),
               climbsim::InputError);
}

// A run that goes numerically bad: MuJoCo's warning is in climbsim's message, and no
// MUJOCO_LOG.TXT is left in the working folder.
TEST(HostileInput, MujocoWarningsGoThroughClimbsimNotALogFile) {
  const std::string cwd = TempDir() + "/mujoco_cwd";
  fs::create_directories(cwd);
  const std::string robot = WriteFile("unstable_robot.xml", climbsim::testing::kUnstableRobotMjcf);
  const std::string scenario =
      WriteFile("unstable.yaml", "robot: " + robot +
                                     "\nscene: floor\nduration_s: 1\n"
                                     "physics: {timestep_s: 0.01, integrator: euler}\n");
  const std::string cmd = "cd " + cwd + " && " + climbsim::testing::Climbsim() + " simulate " +
                          scenario + " --out " + TempDir() + "/unstable_run --quiet 2>" + cwd +
                          "/err.txt";
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_FALSE(fs::exists(cwd + "/MUJOCO_LOG.TXT"));
  EXPECT_TRUE(Has(ReadFile(cwd + "/err.txt"), "(MuJoCo: ")) << ReadFile(cwd + "/err.txt");
}

TEST(HostileInput, DamagedRunFilesGiveTheirPlace) {
  const std::string good = SimulatedRun("damaged_src");
  const auto copy = [&](const std::string& name) {
    const std::string to = TempDir() + "/" + name;
    fs::copy(good, to, fs::copy_options::recursive);
    return to;
  };
  // NaN in trajectory.csv: line 3 (the second row), column 2 (base_x_m).
  std::string dir = copy("nan_traj");
  std::string traj = ReadFile(dir + "/trajectory.csv");
  size_t row2 = traj.find('\n', traj.find('\n') + 1) + 1;
  size_t comma = traj.find(',', row2);
  traj.replace(comma + 1, traj.find(',', comma + 1) - comma - 1, "nan");
  WriteFile(dir + "/trajectory.csv", traj);
  CliResult r = RunClimbsim("inspect " + dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "trajectory.csv:3:")) << r.err;
  EXPECT_TRUE(Has(r.err, "expected a finite number, got 'nan'")) << r.err;
  r = RunClimbsim("render " + dir + " --at 0.05 --out " + TempDir() + "/nan_still.png");
  EXPECT_EQ(r.code, 2) << r.err;

  // time_s NaN in events.csv.
  dir = copy("nan_events");
  WriteFile(dir + "/events.csv", std::string(kEventsHeader) +
                                     "0.01,LF_pad,touchdown,,floor,0,0,0,0,0,0\n"
                                     "nan,LF_pad,touchdown,,floor,0,0,0,0,0,0\n");
  r = RunClimbsim("inspect " + dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "events.csv:3:1: time_s: expected a finite number, got 'nan'")) << r.err;

  // A number JSON cannot hold in summary.json.
  dir = copy("huge_summary");
  WriteFile(dir + "/summary.json", "{\n  \"duration_s\": 0.2,\n  \"distance_m\": 1e400\n}\n");
  r = RunClimbsim("inspect " + dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "summary.json:3: not valid climbsim JSON")) << r.err;
}

TEST(HostileInput, SweepRefusesATinyStepAndNan) {
  const std::string s = Walk("sweep_in.yaml");
  CliResult r = RunClimbsim("sweep " + s +
                            " --key cpg.frequency_hz --from 0.5 --to 1 --step 1e-12 "
                            "--out " +
                            TempDir() + "/sweep_tiny");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "--step: gives")) << r.err;
  r = RunClimbsim("sweep " + s + " --key cpg.frequency_hz --from nan --to 1 --step 0.1 --out " +
                  TempDir() + "/sweep_nan");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(Has(r.err, "--from: must be a finite number")) << r.err;
  EXPECT_FALSE(fs::exists(TempDir() + "/sweep_tiny"));
  EXPECT_FALSE(fs::exists(TempDir() + "/sweep_nan"));
}

}  // namespace

// ---- What inspect shows --------------------------------------------------------------------

// A touchdown that neither attached nor was rejected is counted with its reason: the pad
// touched again (it left inside the attach window), or the run ended during the touch.
TEST(InspectTable, TouchdownsThatNeitherAttachedNorWereRejectedAreShownWithTheReason) {
  const std::string dir = TempDir() + "/unanswered";
  fs::copy(SimulatedRun("unanswered_src"), dir, fs::copy_options::recursive);
  WriteFile(dir + "/events.csv", std::string(kEventsHeader) +
                                     "0.01,LF_pad,touchdown,,floor,0,0,0,0,0,0\n"
                                     "0.05,LF_pad,touchdown,,floor,0,0,0,0,0,0\n"
                                     "0.08,LF_pad,attach,,floor,0.9,0,0,0,0,0\n"
                                     "0.1,LF_pad,detach,peel,floor,0,0,0,0,0,0\n"
                                     "0.12,LF_pad,touchdown,,floor,0,0,0,0,0,0\n"
                                     "0.15,LF_pad,attach_rejected,contacts=1,floor,0,0,0,0,0,0\n"
                                     "0.18,LF_pad,touchdown,,floor,0,0,0,0,0,0\n");
  CliResult r = RunClimbsim("inspect " + dir + " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json lf = nlohmann::json::parse(r.out)["legs"][0];
  EXPECT_EQ(lf["touchdowns"], 4);
  EXPECT_EQ(lf["attachments"], 1);
  EXPECT_EQ(lf["rejected"], 1);
  EXPECT_EQ(lf["unanswered_touchdowns"], 2);
  EXPECT_EQ(lf["unanswered_by"],
            nlohmann::json({{"left_within_attach_window", 1}, {"run_ended_during_touch", 1}}));
  r = RunClimbsim("inspect " + dir);
  EXPECT_TRUE(Has(r.out, "touchdowns unanswered              2")) << r.out;
  EXPECT_TRUE(Has(r.out, "  left_within_attach_window        1")) << r.out;
}

// ---- Custom robot files ----------------------------------------------------------------------

const char* kMeshRobot = R"(<mujoco>
  <compiler meshdir="meshes"/>
  <asset><mesh name="tet" file="tet.obj"/></asset>
  <worldbody>
    <body name="base" pos="0 0 0.05"><freejoint name="root"/>
      <geom type="mesh" mesh="tet" mass="0.1"/>
    </body>
  </worldbody>
</mujoco>
)";
const char* kTetObj =
    "v 0 0 0\nv 0.05 0 0\nv 0 0.05 0\nv 0 0 0.05\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

// A robot's meshdir is relative to the robot file, wherever climbsim runs; and a folder
// named with a quote and an ampersand does not break the composed model.xml.
TEST(CustomRobot, MeshdirResolvesAgainstTheRobotFileAndQuotesInFolderNamesWork) {
  for (const std::string folder : {"robot_meshdir", "we\"ird&co"}) {
    const std::string dir = TempDir() + "/" + folder;
    WriteFile(dir + "/robot.xml", kMeshRobot);
    WriteFile(dir + "/meshes/tet.obj", kTetObj);
    const std::string scenario =
        WriteFile(dir + "/s.yaml", "robot: ./robot.xml\nscene: floor\nduration_s: 0.05\n");
    const std::string out = TempDir() + "/" + folder + "_run";
    const std::string cwd = TempDir() + "/elsewhere";
    fs::create_directories(cwd);
    const std::string cmd = "cd " + cwd + " && " + climbsim::testing::Climbsim() + " simulate '" +
                            scenario + "' --out '" + out + "' --quiet 2>" + cwd + "/err.txt";
    const int status = std::system(cmd.c_str());
    EXPECT_EQ(WEXITSTATUS(status), 0) << folder << ": " << ReadFile(cwd + "/err.txt");
    EXPECT_TRUE(fs::exists(out + "/model.xml")) << folder;
    // model.xml names the run's own copy of the mesh (meshes/ beside it), as MuJoCo reads it.
    EXPECT_TRUE(fs::exists(out + "/meshes/tet.obj")) << folder;
    char error[1000] = "";
    mjModel* m = mj_loadXML((out + "/model.xml").c_str(), nullptr, error, sizeof(error));
    EXPECT_NE(m, nullptr) << folder << ": model.xml does not load: " << error;
    if (m != nullptr) mj_deleteModel(m);
  }
}
