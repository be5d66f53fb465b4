// Run folders: the folders climbsim writes (simulate, optimise, sweep, pulloff, bench accuracy
// and robustness, render --frames, inspect's best_run) and the guard around everything else a
// user has. docs/run-folders.md says the same for users.
//
// A run folder holds a marker file, `.climbsim-run` (JSON, schema 2: which verb made it, from
// which inputs, and every file climbsim wrote there by relative path with its size and its
// FNV-1a 64 hash). A file is climbsim's only while it matches its entry: the hash guards
// against accidents (a user's notes, an edited file), not against forgery.
//
// climbsim writes only into a folder that does not exist, an empty folder, or (with force) a
// folder whose marker parses; it refuses, before any work, a folder that holds something else,
// a marker that is empty, damaged or of an earlier climbsim (no sizes), the input files, the
// current folder, `/`, a path that is a file or a dangling link, and a folder it cannot write.
// With force, anything in the folder that its marker does not list with the same size and hash
// is a refusal listing those files, unless keep_other_files: then they are carried into the
// new run folder (or, where a name clashes with the new run's, the old folder is kept beside
// it as NAME.previous-STAMP). climbsim deletes only listed files that still match (one unlink
// each) and folders it emptied (rmdir); never a folder whole.
//
// A second writer of the same folder is refused: an flock on `.<name>.climbsim-lock` beside
// the folder, held until the writer ends. Every verb that writes a folder takes it, and so do
// render and inspect --plots when they add a file to a run folder (RunFolderAdditions).
//
// Staged writing (simulate, sweep, pulloff, bench, best_run, frames): every file goes into a
// hidden sibling `.<name>.climbsim-new.<pid>`; Commit() writes the marker and puts the sibling
// at the folder in one rename. The folder that was checked is remembered by device and inode
// (or as absent): a new folder is put with renameat2(RENAME_NOREPLACE); an existing one is
// exchanged (RENAME_EXCHANGE) and the folder swapped out is verified to be the one checked,
// else swapped back. When something else is found at the folder at commit, nothing is deleted:
// the new run is kept as NAME.new-run-STAMP and Commit throws std::runtime_error saying where.
// A kill at any moment leaves either the old run or the new one at DIR, never a mix; a
// leftover sibling is removed by the next writer of DIR.
//
//   climbsim::sim::RunFolder out("runs/gecko", {.made_by = "simulate", .inputs = {file}});
//   ... run ...
//   climbsim::sim::WriteRunFiles(out.path(), simulation);
//   out.Commit();
//
// Live writing (optimise, which checkpoints while it runs and resumes after a kill): the
// folder is put in place at once (by the same rules) with a marker that says the run is in
// progress, then written in place file by file, each file atomically (common::WriteFileAtomic).
// Commit lists the files with the names the verbs write (KnownOutputName). In a folder whose
// run is still in progress (killed), those names count as climbsim's without a hash.
//
// Everything here throws climbsim::InputError (exit 2) for a refused path and
// std::runtime_error for a failure of the file system after the checks (disk full) or a
// folder changed under a run (the message says where the new run was kept).
#ifndef CLIMBSIM_COMMON_RUN_FOLDER_H_
#define CLIMBSIM_COMMON_RUN_FOLDER_H_

#include <sys/types.h>

#include <string>
#include <vector>

namespace climbsim::sim {

// The marker file's name inside a run folder.
inline constexpr const char* kRunMarker = ".climbsim-run";

struct RunFolderOptions {
  std::string made_by{};              // the verb: "simulate", "optimise", "sweep", ...
  bool force = false;                 // replace an existing climbsim folder
  bool keep_other_files = false;      // with force: carry files that are not climbsim's along
  std::vector<std::string> inputs{};  // files the verb reads: the folder must not hold them
  std::string flag = "--out";         // the option that named the folder, for messages
};

// True when `dir` is a folder with the marker.
bool IsRunFolder(const std::string& dir);
// The verb that made a run folder ("" when it is none).
std::string RunFolderMadeBy(const std::string& dir);
// True for the names climbsim's verbs write into a run folder (summary.json, sweep.png, ...).
bool KnownOutputName(const std::string& name);
// FNV-1a 64 of a file's bytes as 16 hex digits; "" when it cannot be read.
std::string FileHash(const std::string& path);

// Checks `dir` as the output folder of a verb without touching anything (the constructor
// below does the same checks). Throws InputError naming the option and the reason.
void CheckOutputFolder(const std::string& dir, const RunFolderOptions& options);

class RunFolder {
 public:
  // Staged: checks `dir`, makes its parent folders, takes the lock and makes the staging
  // sibling. Throws InputError when refused.
  RunFolder(const std::string& dir, RunFolderOptions options);
  // Live (optimise): as above, then the folder itself is put in place at once with a marker
  // that says the run is in progress. With `resume`, `dir` must instead be an existing run
  // folder made by options.made_by; it is kept as it is.
  static RunFolder Live(const std::string& dir, RunFolderOptions options, bool resume);

  RunFolder(RunFolder&& other) noexcept;
  RunFolder& operator=(RunFolder&&) = delete;
  RunFolder(const RunFolder&) = delete;
  // Releases the lock; an uncommitted staging folder is removed (the old run stays).
  ~RunFolder();

  // Where to write now: the staging folder, or the folder itself when live or committed.
  const std::string& path() const { return write_path_; }
  // The folder as the user named it (made absolute).
  const std::string& dir() const { return dir_; }
  std::string File(const std::string& name) const { return write_path_ + "/" + name; }

  // Staged: writes the marker (every file now in the staging folder, with size and hash) and
  // puts the staging folder at dir() as described above. Live: rewrites the marker's file
  // list. Once only. Throws std::runtime_error when the folder changed under the run.
  void Commit();

 private:
  RunFolder() = default;
  void Lock();
  void Remember();
  void WriteMarker(const std::string& folder, bool in_progress) const;
  void Place();
  void PlaceOverExisting();
  std::string SwapOut();
  void CarryAndRemove(const std::string& old);
  [[noreturn]] void KeepNewRunAside(const std::string& why);

  std::string dir_;         // absolute path of the folder
  std::string write_path_;  // staging or dir_
  std::string staging_;     // "" when live or committed
  std::string lock_path_;
  RunFolderOptions options_;
  int lock_fd_ = -1;
  bool live_ = false;
  bool committed_ = false;
  bool existed_ = false;  // whether dir_ existed when checked, and then its identity
  dev_t dev_ = 0;
  ino_t ino_ = 0;
};

// Checks a file another verb writes next to (or into) runs: render's video or still, a plot.
// Refuses an empty path, a folder, a link, a path whose folder cannot be written, the marker,
// any data file of a run folder (the files its marker lists as data; in a folder without a
// marker that holds summary.json, the names climbsim's verbs write), and an existing file
// climbsim did not make (one its folder's marker does not list with the same size and hash).
// `flag` names the option in messages.
void CheckFileOutput(const std::string& path, const std::string& flag);

// Files a verb adds to a folder after a run (render's video or still, inspect's plots). The
// constructor checks each with CheckFileOutput and, where the folder is a run folder, takes its
// lock (InputError while another climbsim writes it). Commit records the files that now exist
// in the marker with their size and hash, so that a later force does not take them for a
// user's. Throws std::runtime_error when the marker cannot be written.
class RunFolderAdditions {
 public:
  RunFolderAdditions(std::vector<std::string> files, const std::string& flag);
  RunFolderAdditions(const RunFolderAdditions&) = delete;
  RunFolderAdditions& operator=(const RunFolderAdditions&) = delete;
  ~RunFolderAdditions();
  void Commit();

 private:
  std::vector<std::string> files_;  // absolute
  std::string folder_;              // the run folder holding them, "" when none
  int lock_fd_ = -1;
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_COMMON_RUN_FOLDER_H_
