// No text from a user, a file name or a run folder reaches a shell or gnuplot as code: every
// plotting verb is run with folder and scenario names that hold a backtick, quotes, `$(...)`,
// `;`, a backslash and a newline, and inspect on a received run whose events.csv holds a
// backtick command; the command must never run (no PWNED file anywhere) and the plot must
// appear. bench optimise hands mpirun its arguments as a vector and fails when mpirun fails.
// A write that fails (a file-size limit standing for a full disk) fails the verb, naming why,
// and leaves no empty or cut plot. climbsim runs from argument vectors here (never a shell).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "common/common.h"
#include "tests/common/test_util.h"

namespace {

namespace fs = std::filesystem;
using climbsim::testing::CliResult;
using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsimArgs;
using climbsim::testing::Source;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

// Every way out of a quoted string that gnuplot or a shell knows, each running `touch PWNED`.
const std::string kHostile =
    "q`touch PWNED`'.system(\"touch PWNED\").'\"$(touch PWNED);touch PWNED;\\\n"
    "''.system(\"touch PWNED\").''x";

// A fresh folder under TempDir(), the working folder of one climbsim run.
std::string Fresh(const std::string& name) {
  const std::string dir = TempDir() + "/" + name;
  fs::create_directories(dir);
  return dir;
}

// The PWNED files under `root` and in the test's working folder (none, if nothing ran).
std::vector<std::string> Pwned(const std::string& root) {
  std::vector<std::string> found;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    const std::string name = e.path().filename().string();
    if (name == "PWNED" || name == "pwned") found.push_back(e.path().string());
  }
  if (fs::exists("PWNED")) found.push_back(fs::absolute("PWNED").string());
  return found;
}

void ExpectPng(const std::string& path) {
  const std::string png = ReadFile(path);
  ASSERT_GT(png.size(), 1000u) << path;
  EXPECT_EQ(png.substr(0, 8), "\x89PNG\r\n\x1a\n") << path;
}

// A gecko on the floor, a few steps of simulated time, with an optimise block of two
// evaluations: enough for every verb that takes a scenario.
std::string ShortScenario(const std::string& path) {
  return WriteFile(path,
                   "robot: gecko\nscene: floor\nduration_s: 0.2\n"
                   "cpg:\n  gait: trot\n  frequency_hz: 1.0\n  stride_rad: [0.35, 0.0, 0.0]\n"
                   "  lift_rad: [0.0, 0.4, 0.3]\n"
                   "outputs:\n  trajectory_rate_hz: 0\n"
                   "optimise:\n  parameters:\n"
                   "    - {key: cpg.frequency_hz, start: 1.0, min: 0.5, max: 2.5}\n"
                   "  algorithm: chain\n  max_evaluations: 2\n  starts: 1\n");
}

// gnuplot reads back the text GnuplotQuote made of each hostile string, unchanged but for
// control characters (spaces), and runs none of it.
TEST(GnuplotQuote, EveryStringReadsBackAsItselfAndNothingRuns) {
  const std::string dir = Fresh("quote");
  const std::vector<std::string> texts = {kHostile,           "a''b\\",  "'", "''`touch PWNED`''",
                                          "@macro `x` \"y\"", "t\tu\rv", ""};
  std::string script = "set print 'echo.txt'\n";
  std::string expected;
  for (const std::string& t : texts) {
    script += "print " + climbsim::common::GnuplotQuote(t) + "\n";
    expected += std::regex_replace(t, std::regex("[\t\r\n]"), " ") + "\n";
  }
  WriteFile(dir + "/echo.gp", script);
  EXPECT_EQ(climbsim::common::RunProcess({"gnuplot", "echo.gp"}, {.working_dir = dir}), "");
  EXPECT_EQ(ReadFile(dir + "/echo.txt"), expected);
  EXPECT_EQ(Pwned(dir), std::vector<std::string>{});
}

TEST(Process, ReportsExitStatusAndAMissingProgram) {
  EXPECT_EQ(climbsim::common::RunProcess({"true"}), "");
  EXPECT_EQ(climbsim::common::RunProcess({"false"}), "false exited with status 1");
  EXPECT_NE(climbsim::common::RunProcess({"no-such-program-climbsim"}).find("cannot start"),
            std::string::npos);
  EXPECT_NE(climbsim::common::FindInPath("sh"), "");
  EXPECT_EQ(climbsim::common::FindInPath("no-such-program-climbsim"), "");
}

TEST(Injection, PulloffFolderNameIsNeverCode) {
  const std::string cwd = Fresh("pulloff");
  for (const std::string law : {"von_mises", "frictional"}) {
    const std::string out = cwd + "/" + kHostile + law;
    CliResult r = RunClimbsimArgs({"pulloff", "--model", "bonds", "--grid", "2", "--step-deg", "90",
                                   "--law", law, "--out", out, "--quiet"},
                                  cwd);
    ASSERT_EQ(r.code, 0) << law << r.err;
    ExpectPng(out + "/pulloff.png");
    // The kept script names no folder: `cd DIR && gnuplot pulloff.gp` is as safe.
    EXPECT_EQ(ReadFile(out + "/pulloff.gp").find("touch"), std::string::npos);
  }
  EXPECT_EQ(Pwned(cwd), std::vector<std::string>{});
}

TEST(Injection, SweepScenarioAndFolderNamesAreNeverCode) {
  const std::string cwd = Fresh("sweep");
  const std::string scenario = ShortScenario(cwd + "/a'.system(\"touch PWNED\").'.yaml");
  const std::string out = cwd + "/" + kHostile;
  const CliResult r =
      RunClimbsimArgs({"sweep", scenario, "--key", "cpg.frequency_hz", "--from", "1", "--to", "1.5",
                       "--step", "0.5", "--threads", "1", "--out", out},
                      cwd);
  ASSERT_EQ(r.code, 0) << r.err;
  ExpectPng(out + "/sweep.png");
  EXPECT_EQ(Pwned(cwd), std::vector<std::string>{});
}

TEST(Injection, OptimiseFolderNameIsNeverCode) {
  const std::string cwd = Fresh("optimise");
  const std::string out = cwd + "/" + kHostile;
  const CliResult r = RunClimbsimArgs(
      {"optimise", ShortScenario(cwd + "/s.yaml"), "--out", out, "--threads", "1", "--quiet"}, cwd);
  ASSERT_EQ(r.code, 0) << r.err;
  ExpectPng(out + "/convergence.png");
  EXPECT_EQ(Pwned(cwd), std::vector<std::string>{});
}

TEST(Injection, BenchAccuracyFolderNameIsNeverCode) {
  const std::string cwd = Fresh("accuracy");
  const std::string out = cwd + "/" + kHostile;
  const CliResult r = RunClimbsimArgs({"bench", "accuracy", ShortScenario(cwd + "/s.yaml"),
                                       "--duration", "0.1", "--threads", "1", "--out", out},
                                      cwd);
  ASSERT_EQ(r.code, 0) << r.err;
  ExpectPng(out + "/accuracy.png");
  EXPECT_EQ(Pwned(cwd), std::vector<std::string>{});
}

TEST(Injection, BenchRobustnessScenarioAndFolderNamesAreNeverCode) {
  const std::string cwd = Fresh("robustness");
  const std::string scenario = ShortScenario(cwd + "/" + kHostile + ".yaml");
  const std::string out = cwd + "/" + kHostile + "_out";
  const CliResult r =
      RunClimbsimArgs({"bench", "robustness", scenario, "--duration", "0.2", "--seeds", "1",
                       "--phases", "1", "--families", "payload", "--threads", "1", "--out", out},
                      cwd);
  ASSERT_EQ(r.code, 0) << r.err;
  ExpectPng(out + "/robustness.png");
  EXPECT_EQ(Pwned(cwd), std::vector<std::string>{});
}

// A short run on the wall (it peels and detaches), simulated into `dir`.
void SimulateWallRun(const std::string& cwd, const std::string& dir) {
  std::string text = ReadFile(Source("examples/gecko_wall.yaml"));
  text = std::regex_replace(text, std::regex("^duration_s:.*$", std::regex::multiline),
                            "duration_s: 0.6");
  const std::string scenario = WriteFile(cwd + "/wall.yaml", text);
  const CliResult r = RunClimbsimArgs({"simulate", scenario, "--out", dir, "--quiet"}, cwd);
  ASSERT_EQ(r.code, 0) << r.err;
}

// A received run folder: its name and a detach's cause in events.csv are a stranger's text.
TEST(Injection, InspectPlotsOfAReceivedRunNeverRunItsFields) {
  const std::string cwd = Fresh("inspect");
  const std::string dir = cwd + "/" + kHostile;
  SimulateWallRun(cwd, dir);
  const std::string events = ReadFile(dir + "/events.csv");
  const std::regex cause("^([^,\n]*,[^,\n]*,detach,)[^,\n]*,", std::regex::multiline);
  // The first detach's cause is long (a title cut to a fixed buffer would leave its quote
  // open and expose the next one); the others hold the commands.
  std::string edited = std::regex_replace(events, cause, "$1" + std::string(300, 'A') + ",",
                                          std::regex_constants::format_first_only);
  const std::regex other("^([^,\n]*,[^,\n]*,detach,)(?!A{300})[^,\n]*,", std::regex::multiline);
  edited = std::regex_replace(edited, other, "$1`touch PWNED`'\";touch PWNED,");
  ASSERT_NE(edited.find("`touch PWNED`"), std::string::npos) << "one detach only";
  WriteFile(dir + "/events.csv", edited);
  const CliResult r = RunClimbsimArgs({"inspect", dir, "--plots"}, cwd);
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* name : {"gait", "pad_LF", "path"}) ExpectPng(dir + "/" + name + ".png");
  EXPECT_NE(ReadFile(dir + "/gait.svg").find("detach: `touch PWNED`"), std::string::npos);
  EXPECT_EQ(Pwned(cwd), std::vector<std::string>{});
}

#ifdef CLIMBSIM_MPI
// A stand-in mpirun, first in PATH: it writes its arguments (each ended by a NUL) to
// `args_file` and fails with status 3.
class FakeMpirun {
 public:
  explicit FakeMpirun(const std::string& args_file) : old_path_(std::getenv("PATH")) {
    const std::string bin = Fresh("fake_bin");
    WriteFile(bin + "/mpirun", "#!/bin/sh\nprintf '%s\\000' \"$@\" > " + args_file + "\nexit 3\n");
    fs::permissions(bin + "/mpirun", fs::perms::owner_all);
    ::setenv("PATH", (bin + ":" + old_path_).c_str(), 1);
  }
  ~FakeMpirun() { ::setenv("PATH", old_path_.c_str(), 1); }

 private:
  std::string old_path_;
};

TEST(Injection, BenchOptimiseHandsMpirunThePathAsOneArgumentAndFailsWithIt) {
  const std::string cwd = Fresh("bench_mpi");
  const std::string args_file = cwd + "/args";
  FakeMpirun fake(args_file);
  const std::string scenario = ShortScenario(cwd + "/b';touch pwned;'$(touch PWNED).yaml");
  const CliResult r = RunClimbsimArgs(
      {"bench", "optimise", scenario, "--only", "mpi", "--evaluations", "2", "--out", cwd + "/out"},
      cwd);
  EXPECT_EQ(r.code, 1) << r.out << r.err;
  EXPECT_NE(r.err.find("mpirun"), std::string::npos) << r.err;
  const std::string args = ReadFile(args_file);
  EXPECT_NE(args.find(std::string("\0", 1) + scenario + std::string("\0", 1)), std::string::npos)
      << args;
  EXPECT_EQ(Pwned(cwd), std::vector<std::string>{});
}

TEST(Injection, BenchOptimiseRefusesAUsersFolderBeforeDeletingAnything) {
  const std::string cwd = Fresh("bench_user");
  FakeMpirun fake(cwd + "/args");
  const std::string mine = WriteFile(cwd + "/userX/mpi1/summary.json", "{\"mine\": 1}\n");
  const CliResult r =
      RunClimbsimArgs({"bench", "optimise", ShortScenario(cwd + "/s.yaml"), "--only", "mpi",
                       "--evaluations", "2", "--out", cwd + "/userX"},
                      cwd);
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_EQ(ReadFile(mine), "{\"mine\": 1}\n");
  EXPECT_FALSE(fs::exists(cwd + "/args")) << "mpirun ran";
}

// A scenario the optimiser cannot take is bad input (exit 2) before mpirun starts, not a
// failed mpirun after it.
TEST(Injection, BenchOptimiseRefusesAScenarioWithoutAnOptimiseBlockBeforeMpirun) {
  const std::string cwd = Fresh("bench_plain");
  FakeMpirun fake(cwd + "/args");
  const std::string plain =
      WriteFile(cwd + "/plain.yaml", "robot: gecko\nscene: floor\nduration_s: 0.1\n");
  const CliResult r = RunClimbsimArgs(
      {"bench", "optimise", plain, "--only", "mpi", "--evaluations", "2", "--out", cwd + "/out"},
      cwd);
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("no optimise block"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(cwd + "/args")) << "mpirun ran";
  EXPECT_FALSE(fs::exists(cwd + "/out"));
}
#endif

// Every plot in `dir` is whole, and no temporary is left.
void ExpectNoCutPlots(const std::string& dir) {
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    EXPECT_EQ(name.find("climbsim-plot"), std::string::npos) << name;
    EXPECT_EQ(name.find(".tmp."), std::string::npos) << name;
    if (e.path().extension() == ".png") ExpectPng(e.path().string());
    if (e.path().extension() == ".svg") {
      EXPECT_NE(ReadFile(e.path().string()).find("</svg>"), std::string::npos) << name;
    }
  }
}

// A disk that fills while gnuplot writes (RLIMIT_FSIZE of 8 kB: every file climbsim writes
// first fits, no plot does): the verb fails, names why, and leaves no empty or cut plot.
TEST(DiskFull, InspectPlotsFailNamingTheCauseAndLeaveNoCutPlot) {
  const std::string cwd = Fresh("full_inspect");
  const std::string dir = cwd + "/run";
  SimulateWallRun(cwd, dir);
  const CliResult r = RunClimbsimArgs({"inspect", dir, "--plots"}, cwd, 8000);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("disk full"), std::string::npos) << r.err;
  ExpectNoCutPlots(dir);
}

TEST(DiskFull, PulloffFailsNamingTheCauseAndLeavesNoCutPlot) {
  const std::string cwd = Fresh("full_pulloff");
  const CliResult r = RunClimbsimArgs({"pulloff", "--model", "bonds", "--grid", "2", "--step-deg",
                                       "90", "--out", cwd + "/out", "--quiet"},
                                      cwd, 8000);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("disk full"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(cwd + "/out/pulloff.csv"));
  ExpectNoCutPlots(cwd + "/out");
}

// optimise keeps its results when only the plot fails, but installs no cut convergence.png,
// says why (and in summary.json) and exits 1.
TEST(DiskFull, OptimiseFailsNamingTheCauseAndInstallsNoCutPlot) {
  const std::string cwd = Fresh("full_optimise");
  const CliResult r = RunClimbsimArgs({"optimise", ShortScenario(cwd + "/s.yaml"), "--out",
                                       cwd + "/out", "--threads", "1", "--quiet"},
                                      cwd, 8000);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("disk full"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(cwd + "/out/convergence.png"));
  EXPECT_NE(ReadFile(cwd + "/out/summary.json").find("disk full"), std::string::npos);
  ExpectNoCutPlots(cwd + "/out");
}

}  // namespace
