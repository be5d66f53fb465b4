// sim/run_folder.h: a run folder appears whole or not at all, replaces only a climbsim folder
// (and only with force), refuses a user's files and the inputs, keeps out a second writer,
// and a writer killed before its commit leaves the old run as it was.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "sim/sim.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

namespace fs = std::filesystem;
using climbsim::testing::ReadFile;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

// Writes files (name → text) through a committed RunFolder.
void MakeRun(const std::string& dir, const std::vector<std::pair<std::string, std::string>>& files,
             bool force = false) {
  RunFolder f(dir, {.made_by = "simulate", .force = force});
  for (const auto& [name, text] : files) common::WriteFileAtomic(f.File(name), text);
  f.Commit();
}

// The message of the InputError `body` throws ("" when it throws none).
template <class Body>
std::string Refusal(Body body) {
  try {
    body();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::vector<std::string> Siblings(const std::string& dir) {
  std::vector<std::string> names;
  const std::string prefix = "." + fs::path(dir).filename().string() + ".climbsim-";
  for (const auto& e : fs::directory_iterator(fs::path(dir).parent_path())) {
    const std::string n = e.path().filename().string();
    if (n.rfind(prefix, 0) == 0 && n != prefix + "lock") names.push_back(n);
  }
  return names;
}

TEST(RunFolder, ANewRunAppearsOnlyAtCommitWithItsMarker) {
  const std::string dir = TempDir() + "/rf_new";
  RunFolder f(dir, {.made_by = "simulate", .inputs = {}});
  common::WriteFileAtomic(f.File("summary.json"), "{}\n");
  EXPECT_FALSE(fs::exists(dir)) << "nothing at DIR before the commit";
  f.Commit();
  EXPECT_EQ(ReadFile(dir + "/summary.json"), "{}\n");
  EXPECT_TRUE(IsRunFolder(dir));
  EXPECT_EQ(RunFolderMadeBy(dir), "simulate");
  const auto marker = nlohmann::json::parse(ReadFile(dir + "/" + kRunMarker));
  EXPECT_EQ(marker["data_files"], nlohmann::json::array({"summary.json"}));
  EXPECT_TRUE(Siblings(dir).empty());
}

TEST(RunFolder, AnEarlierRunNeedsForceAndIsReplacedWhole) {
  const std::string dir = TempDir() + "/rf_replace";
  MakeRun(dir, {{"summary.json", "old\n"}, {"trajectory.csv", "old\n"}});
  const std::string refused = Refusal([&] { MakeRun(dir, {{"summary.json", "new\n"}}); });
  EXPECT_NE(refused.find("holds a previous climbsim run (made by climbsim simulate); --force"),
            std::string::npos)
      << refused;
  EXPECT_EQ(ReadFile(dir + "/summary.json"), "old\n");
  MakeRun(dir, {{"summary.json", "new\n"}}, /*force=*/true);
  EXPECT_EQ(ReadFile(dir + "/summary.json"), "new\n");
  EXPECT_FALSE(fs::exists(dir + "/trajectory.csv")) << "the old run's files must not mix in";
  EXPECT_TRUE(Siblings(dir).empty());
}

TEST(RunFolder, AUsersFolderIsRefusedEvenWithForce) {
  const std::string dir = TempDir() + "/rf_user";
  WriteFile(dir + "/thesis.tex", "mine\n");
  for (bool force : {false, true}) {
    const std::string refused = Refusal([&] { MakeRun(dir, {{"summary.json", "new\n"}}, force); });
    EXPECT_NE(refused.find("holds files climbsim did not make"), std::string::npos) << refused;
  }
  EXPECT_EQ(ReadFile(dir + "/thesis.tex"), "mine\n");
  EXPECT_FALSE(fs::exists(dir + "/summary.json"));
  // An empty folder is fine.
  fs::create_directories(TempDir() + "/rf_empty");
  MakeRun(TempDir() + "/rf_empty", {{"summary.json", "new\n"}});
  EXPECT_TRUE(IsRunFolder(TempDir() + "/rf_empty"));
}

TEST(RunFolder, RefusesPathsThatCannotBeARunFolder) {
  const std::string file = WriteFile("rf_a_file", "x\n");
  const std::string inputs = TempDir() + "/rf_inputs";
  const std::string scenario = WriteFile(inputs + "/s.yaml", "robot: gecko\n");
  const auto refuse = [](const std::string& dir, std::vector<std::string> in = {}) {
    return Refusal([&] { RunFolder f(dir, {.made_by = "simulate", .force = true, .inputs = in}); });
  };
  EXPECT_NE(refuse("").find("--out: must not be empty"), std::string::npos);
  EXPECT_NE(refuse("/").find("is the root folder"), std::string::npos);
  EXPECT_NE(refuse(".").find("is the current folder"), std::string::npos);
  EXPECT_NE(refuse("..").find("holds the current folder"), std::string::npos);
  EXPECT_NE(refuse(file).find("is a file, not a folder"), std::string::npos);
  EXPECT_NE(refuse(file + "/run").find("is a file, not a folder"), std::string::npos);
  EXPECT_NE(refuse(inputs, {scenario}).find("holds the input"), std::string::npos);
  EXPECT_NE(refuse(TempDir(), {scenario}).find("holds the input"), std::string::npos);
  EXPECT_NE(refuse("/proc/climbsim_run").find("cannot be"), std::string::npos);
  EXPECT_EQ(ReadFile(scenario), "robot: gecko\n");
  EXPECT_EQ(ReadFile(file), "x\n");
}

TEST(RunFolder, ASecondWriterIsRefusedWhileTheFirstHoldsTheFolder) {
  const std::string dir = TempDir() + "/rf_locked";
  RunFolder first(dir, {.made_by = "simulate"});
  const std::string refused = Refusal([&] { RunFolder second(dir, {.made_by = "simulate"}); });
  EXPECT_NE(refused.find("is being written by another climbsim"), std::string::npos) << refused;
  common::WriteFileAtomic(first.File("summary.json"), "first\n");
  first.Commit();
  EXPECT_EQ(ReadFile(dir + "/summary.json"), "first\n");
}

// A writer killed at any moment before its commit (here: _exit without destructors, as
// SIGKILL) leaves the old run whole; its leftover is removed by the next writer.
TEST(RunFolder, AWriterKilledBeforeItsCommitLeavesTheOldRun) {
  const std::string dir = TempDir() + "/rf_killed";
  MakeRun(dir, {{"summary.json", "old\n"}, {"events.csv", "old\n"}});
  const pid_t pid = fork();
  if (pid == 0) {
    RunFolder f(dir, {.made_by = "simulate", .force = true});
    common::WriteFileAtomic(f.File("summary.json"), "new\n");
    _exit(0);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(ReadFile(dir + "/summary.json"), "old\n");
  EXPECT_EQ(ReadFile(dir + "/events.csv"), "old\n");
  EXPECT_EQ(Siblings(dir).size(), 1u) << "the killed writer's staging folder";
  MakeRun(dir, {{"summary.json", "new\n"}}, /*force=*/true);
  EXPECT_EQ(ReadFile(dir + "/summary.json"), "new\n");
  EXPECT_FALSE(fs::exists(dir + "/events.csv"));
  EXPECT_TRUE(Siblings(dir).empty());
}

// An uncommitted RunFolder (the run threw) removes its staging folder and keeps the old run.
TEST(RunFolder, AFailedRunLeavesTheOldRunAndNoLeftover) {
  const std::string dir = TempDir() + "/rf_failed";
  MakeRun(dir, {{"summary.json", "old\n"}});
  {
    RunFolder f(dir, {.made_by = "simulate", .force = true});
    common::WriteFileAtomic(f.File("summary.json"), "new\n");
  }
  EXPECT_EQ(ReadFile(dir + "/summary.json"), "old\n");
  EXPECT_TRUE(Siblings(dir).empty());
}

TEST(RunFolder, LiveFolderResumesOnlyItsOwnKind) {
  const std::string dir = TempDir() + "/rf_live";
  {
    RunFolder f = RunFolder::Live(dir, {.made_by = "optimise"}, /*resume=*/false);
    EXPECT_TRUE(IsRunFolder(dir)) << "a live folder exists from the start";
    common::WriteFileAtomic(f.File("checkpoint.json"), "{}\n");
  }
  { RunFolder f = RunFolder::Live(dir, {.made_by = "optimise"}, /*resume=*/true); }
  EXPECT_EQ(ReadFile(dir + "/checkpoint.json"), "{}\n");
  const std::string sim_run = TempDir() + "/rf_live_sim";
  MakeRun(sim_run, {{"summary.json", "x\n"}});
  const std::string refused =
      Refusal([&] { RunFolder::Live(sim_run, {.made_by = "optimise"}, /*resume=*/true); });
  EXPECT_NE(refused.find("was made by climbsim simulate, not optimise"), std::string::npos)
      << refused;
  EXPECT_NE(Refusal([&] {
              RunFolder::Live(TempDir() + "/rf_live_none", {.made_by = "optimise"}, true);
            }).find("does not exist: nothing to resume"),
            std::string::npos);
}

TEST(RunFolder, FileOutputsNeverReplaceARunsData) {
  const std::string dir = TempDir() + "/rf_data";
  MakeRun(dir, {{"trajectory.csv", "t\n"}, {"my_extra.dat", "x\n"}});
  for (const std::string name : {"trajectory.csv", "my_extra.dat", kRunMarker}) {
    const std::string refused = Refusal([&] { CheckFileOutput(dir + "/" + name, "--out"); });
    EXPECT_FALSE(refused.empty()) << name;
  }
  EXPECT_EQ(Refusal([&] { CheckFileOutput(dir + "/still.png", "--out"); }), "");
  EXPECT_NE(Refusal([&] { CheckFileOutput(dir, "--out"); }).find("is a folder"), std::string::npos);
  // An old run folder without a marker: climbsim's file names are protected too.
  const std::string old = TempDir() + "/rf_old";
  WriteFile(old + "/summary.json", "{}\n");
  EXPECT_FALSE(Refusal([&] { CheckFileOutput(old + "/events.csv", "--out"); }).empty());
}

}  // namespace
}  // namespace climbsim::sim
