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
#include <stdexcept>
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

// The message of the std::runtime_error `body` throws ("" when it throws none).
template <class Body>
std::string Failure(Body body) {
  try {
    body();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

// Folders beside `dir` whose names begin with DIR.<what>- (kept aside by a commit).
std::vector<std::string> Aside(const std::string& dir, const std::string& what) {
  std::vector<std::string> found;
  const std::string prefix = fs::path(dir).filename().string() + "." + what + "-";
  for (const auto& e : fs::directory_iterator(fs::path(dir).parent_path())) {
    if (e.path().filename().string().rfind(prefix, 0) == 0) found.push_back(e.path().string());
  }
  return found;
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

// ---- What --force may delete -----------------------------------------------------------------

TEST(RunFolder, TheMarkerRecordsEveryFileWithItsSizeAndHash) {
  const std::string dir = TempDir() + "/rf_hashes";
  {
    RunFolder f(dir, {.made_by = "simulate"});
    common::WriteFileAtomic(f.File("a.txt"), "a");
    fs::create_directories(f.File("meshes"));
    common::WriteFileAtomic(f.File("meshes/b.stl"), "");
    f.Commit();
  }
  const auto marker = nlohmann::json::parse(ReadFile(dir + "/" + kRunMarker));
  EXPECT_EQ(marker["climbsim_run_folder"], 2);
  // FNV-1a 64 of "a" and of nothing (the offset basis), from the algorithm's reference values.
  const nlohmann::json files = nlohmann::json::array(
      {{{"path", "a.txt"}, {"size", 1}, {"fnv1a64", "af63dc4c8601ec8c"}},
       {{"path", "meshes/b.stl"}, {"size", 0}, {"fnv1a64", "cbf29ce484222325"}}});
  EXPECT_EQ(marker["files"], files);
  EXPECT_EQ(FileHash(dir + "/a.txt"), "af63dc4c8601ec8c");
  MakeRun(dir, {{"summary.json", "new\n"}}, /*force=*/true);
  EXPECT_FALSE(fs::exists(dir + "/meshes")) << "a subfolder climbsim made goes with its run";
}

TEST(RunFolder, AnEmptyForgedOrEarlierMarkerIsRefusedWithForce) {
  const std::pair<std::string, std::string> cases[] = {
      {"", "not a climbsim run folder"},
      {"{}", "not a climbsim run folder"},
      {"{\"climbsim_run_folder\": 2, \"made_by\": \"simulate\"}", "not a climbsim run folder"},
      {"not json", "not a climbsim run folder"},
      {R"({"climbsim_run_folder": 1, "made_by": "simulate", "data_files": ["thesis.tex"]})",
       "earlier climbsim"}};
  int k = 0;
  for (const auto& [marker, message] : cases) {
    const std::string dir = TempDir() + "/rf_forged_" + std::to_string(k++);
    WriteFile(dir + "/" + kRunMarker, marker);
    WriteFile(dir + "/thesis.tex", "mine\n");
    const std::string refused = Refusal([&] {
      MakeRun(dir, {{"summary.json", "new\n"}}, /*force=*/true);
    });
    EXPECT_NE(refused.find(message), std::string::npos) << marker << ": " << refused;
    EXPECT_EQ(ReadFile(dir + "/thesis.tex"), "mine\n") << marker;
    EXPECT_FALSE(fs::exists(dir + "/summary.json")) << marker;
  }
}

// A run with a nested run folder (best_run/, with its lock file beside it) and files a user
// added or edited: force refuses, naming the user's files only, and deletes nothing.
TEST(RunFolder, ForceRefusesAUsersNotesSubfolderAndEditedFileNamingThem) {
  const std::string dir = TempDir() + "/rf_added";
  const auto make = [&] {
    MakeRun(dir, {{"summary.json", "old\n"}}, /*force=*/true);
    MakeRun(dir + "/best_run", {{"summary.json", "best\n"}}, /*force=*/true);
  };
  make();
  MakeRun(dir, {{"summary.json", "new\n"}}, /*force=*/true);  // climbsim's own: no refusal
  EXPECT_FALSE(fs::exists(dir + "/best_run"));
  const std::vector<std::pair<std::string, std::string>> added{{"notes.txt", "mine\n"},
                                                               {"figures/fig1.svg", "<svg/>\n"},
                                                               {"summary.json", "edited\n"},
                                                               {"best_run/notes.txt", "mine\n"}};
  for (const auto& [name, text] : added) {
    make();
    WriteFile(dir + "/" + name, text);
    const std::string refused = Refusal([&] {
      MakeRun(dir, {{"summary.json", "new\n"}}, /*force=*/true);
    });
    EXPECT_NE(refused.find("did not write there, or that changed since: " + name),
              std::string::npos)
        << refused;
    EXPECT_EQ(ReadFile(dir + "/" + name), text);
    EXPECT_TRUE(fs::exists(dir + "/best_run/summary.json"));
    fs::remove(dir + "/" + name);
    fs::remove(dir + "/figures");  // a folder the user left empty is theirs too
  }
}

TEST(RunFolder, KeepOtherFilesCarriesThemIntoTheNewRun) {
  const std::string dir = TempDir() + "/rf_keep";
  MakeRun(dir, {{"summary.json", "old\n"}, {"events.csv", "old\n"}});
  WriteFile(dir + "/notes.txt", "mine\n");
  WriteFile(dir + "/figures/fig1.svg", "<svg/>\n");
  {
    RunFolder f(dir, {.made_by = "simulate", .force = true, .keep_other_files = true});
    common::WriteFileAtomic(f.File("summary.json"), "new\n");
    f.Commit();
  }
  EXPECT_EQ(ReadFile(dir + "/summary.json"), "new\n");
  EXPECT_FALSE(fs::exists(dir + "/events.csv"));
  EXPECT_EQ(ReadFile(dir + "/notes.txt"), "mine\n");
  EXPECT_EQ(ReadFile(dir + "/figures/fig1.svg"), "<svg/>\n");
  EXPECT_TRUE(Aside(dir, "previous").empty());
  // An edited file whose name the new run writes too: the old folder is kept aside with it.
  WriteFile(dir + "/summary.json", "edited\n");
  EXPECT_FALSE(Refusal([&] {
                 MakeRun(dir, {{"summary.json", "newer\n"}}, /*force=*/true);
               }).empty());
  EXPECT_EQ(ReadFile(dir + "/summary.json"), "edited\n") << "refused without the flag";
  RunFolder f(dir, {.made_by = "simulate", .force = true, .keep_other_files = true});
  common::WriteFileAtomic(f.File("summary.json"), "newer\n");
  f.Commit();
  EXPECT_EQ(ReadFile(dir + "/summary.json"), "newer\n");
  const auto kept = Aside(dir, "previous");
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_EQ(ReadFile(kept[0] + "/summary.json"), "edited\n");
  EXPECT_EQ(ReadFile(dir + "/notes.txt"), "mine\n");
}

// The race: a folder that appears at DIR while a run is in progress is not replaced; the new
// run is kept aside, named in the error.
TEST(RunFolder, AFolderThatAppearsDuringTheRunIsKeptAndTheNewRunPutAside) {
  const std::string dir = TempDir() + "/rf_race_new";
  RunFolder f(dir, {.made_by = "simulate"});
  common::WriteFileAtomic(f.File("summary.json"), "new\n");
  WriteFile(dir + "/thesis.tex", "mine\n");
  const std::string failure = Failure([&] { f.Commit(); });
  EXPECT_NE(failure.find("nothing was deleted; the new run is kept at"), std::string::npos)
      << failure;
  EXPECT_EQ(ReadFile(dir + "/thesis.tex"), "mine\n");
  const auto aside = Aside(dir, "new-run");
  ASSERT_EQ(aside.size(), 1u);
  EXPECT_NE(failure.find(aside[0]), std::string::npos);
  EXPECT_EQ(ReadFile(aside[0] + "/summary.json"), "new\n");
}

// The race with --force: the user moves the old run away and puts a folder of theirs at DIR,
// or adds a file to the old run, while the new run is in progress.
TEST(RunFolder, AFolderSwappedInOrAddedToDuringAForceRunIsKept) {
  const std::string dir = TempDir() + "/rf_race_force";
  MakeRun(dir, {{"summary.json", "old\n"}});
  {
    RunFolder f(dir, {.made_by = "simulate", .force = true});
    common::WriteFileAtomic(f.File("summary.json"), "new\n");
    fs::rename(dir, dir + "_moved");
    WriteFile(dir + "/thesis.tex", "mine\n");
    WriteFile(dir + "/" + kRunMarker, "{}");
    EXPECT_NE(Failure([&] { f.Commit(); }).find("replaced while the run"), std::string::npos);
  }
  EXPECT_EQ(ReadFile(dir + "/thesis.tex"), "mine\n");
  EXPECT_EQ(ReadFile(dir + "_moved/summary.json"), "old\n");
  fs::remove_all(dir);
  fs::rename(dir + "_moved", dir);
  {
    RunFolder f(dir, {.made_by = "simulate", .force = true});
    common::WriteFileAtomic(f.File("summary.json"), "new\n");
    WriteFile(dir + "/notes.txt", "mine\n");
    EXPECT_NE(Failure([&] { f.Commit(); }).find("appeared there during the run: notes.txt"),
              std::string::npos);
  }
  EXPECT_EQ(ReadFile(dir + "/notes.txt"), "mine\n");
  EXPECT_EQ(ReadFile(dir + "/summary.json"), "old\n");
}

TEST(RunFolder, ADanglingLinkIsRefusedAndKept) {
  const std::string link = TempDir() + "/rf_dangling";
  fs::create_symlink(TempDir() + "/rf_nowhere", link);
  EXPECT_NE(Refusal([&] {
              MakeRun(link, {{"summary.json", "new\n"}});
            }).find("dangling"),
            std::string::npos);
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_FALSE(fs::exists(TempDir() + "/rf_nowhere"));
}

// A killed optimisation (live, never committed) can be forced, its files bearing the names
// the verb writes; a user's file there still refuses.
TEST(RunFolder, AKilledLiveRunIsClimbsimsButNotTheUsersFileInIt) {
  const std::string dir = TempDir() + "/rf_live_killed";
  {
    RunFolder f = RunFolder::Live(dir, {.made_by = "optimise"}, /*resume=*/false);
    common::WriteFileAtomic(f.File("checkpoint.json"), "{}\n");
  }
  WriteFile(dir + "/notes.txt", "mine\n");
  const std::string refused = Refusal(
      [&] { RunFolder::Live(dir, {.made_by = "optimise", .force = true}, /*resume=*/false); });
  EXPECT_NE(refused.find("changed since: notes.txt;"), std::string::npos) << refused;
  fs::remove(dir + "/notes.txt");
  RunFolder::Live(dir, {.made_by = "optimise", .force = true}, /*resume=*/false);
  EXPECT_FALSE(fs::exists(dir + "/checkpoint.json"));
}

// An optimisation writes in place: its marker lists only the names the verb writes, never a
// file a user put there meanwhile (which the next force then refuses).
TEST(RunFolder, ALiveRunListsItsOwnFilesNotOneAUserAddedMeanwhile) {
  const std::string dir = TempDir() + "/rf_live_notes";
  {
    RunFolder f = RunFolder::Live(dir, {.made_by = "optimise"}, /*resume=*/false);
    common::WriteFileAtomic(f.File("history.csv"), "h\n");
    WriteFile(dir + "/notes.txt", "mine\n");
    f.Commit();
  }
  const auto marker = nlohmann::json::parse(ReadFile(dir + "/" + kRunMarker));
  EXPECT_EQ(marker["data_files"], nlohmann::json::array({"history.csv"}));
  EXPECT_FALSE(marker.contains("in_progress"));
  const std::string refused = Refusal(
      [&] { RunFolder::Live(dir, {.made_by = "optimise", .force = true}, /*resume=*/false); });
  EXPECT_NE(refused.find("changed since: notes.txt;"), std::string::npos) << refused;
  EXPECT_EQ(ReadFile(dir + "/notes.txt"), "mine\n");
}

// render and inspect --plots: a file added to a run folder is recorded (then force deletes it);
// an existing file that no marker records is never overwritten.
TEST(RunFolderAdditions, RecordedFilesAreClimbsimsAndAUsersFileIsNeverOverwritten) {
  const std::string dir = TempDir() + "/rf_additions";
  MakeRun(dir, {{"summary.json", "run\n"}});
  {
    RunFolderAdditions added({dir + "/still.png"}, "--out");
    EXPECT_NE(Refusal([&] {
                RunFolder f(dir, {.made_by = "simulate", .force = true});
              }).find("being written by another climbsim"),
              std::string::npos)
        << "the addition holds the run folder's lock";
    WriteFile(dir + "/still.png", "png\n");
    added.Commit();
  }
  EXPECT_EQ(Refusal([&] { CheckFileOutput(dir + "/still.png", "--out"); }), "") << "redrawn";
  WriteFile(dir + "/user.png", "mine\n");
  WriteFile(TempDir() + "/rf_user.png", "mine\n");
  for (const std::string& p : {dir + "/user.png", TempDir() + "/rf_user.png"}) {
    EXPECT_NE(Refusal([&] { RunFolderAdditions added({p}, "--out"); }).find("climbsim never"),
              std::string::npos)
        << p;
  }
  fs::remove(dir + "/user.png");
  MakeRun(dir, {{"summary.json", "new\n"}}, /*force=*/true);
  EXPECT_FALSE(fs::exists(dir + "/still.png"));
}

}  // namespace
}  // namespace climbsim::sim
