// Run folders: the folders climbsim writes (simulate, optimise, sweep, pulloff, inspect's
// best_run) and the guard around everything else a user has. docs/run-folders.md says the
// same for users.
//
// A run folder holds a marker file, `.climbsim-run` (JSON: which verb made it, from which
// inputs, which files are its data). climbsim writes only into a folder that does not exist,
// an empty folder, or (with --force) a folder that has the marker; it refuses, before any
// work, a folder that holds something else, the input files, the current folder, `/`, a path
// that is a file, and a folder it cannot write. A second writer of the same folder is refused
// too: an flock on `.<name>.climbsim-lock` beside the folder, held until the writer ends.
//
// Staged writing (simulate, sweep, pulloff, best_run): every file goes into a hidden sibling
// `.<name>.climbsim-new.<pid>`; Commit() writes the marker and swaps the sibling with the
// folder in one rename (renameat2 RENAME_EXCHANGE), then removes the old folder. A kill at
// any moment leaves either the old run or the new one at DIR, never a mix; a leftover
// sibling is removed by the next writer of DIR.
//
//   climbsim::sim::RunFolder out("runs/gecko", {.made_by = "simulate", .inputs = {file}});
//   ... run ...
//   climbsim::sim::WriteRunFiles(out.path(), simulation);
//   out.Commit();
//
// Live writing (optimise, which checkpoints while it runs and resumes after a kill): the
// folder is made (or, with --force, replaced whole) at once with its marker, then written in
// place file by file, each file atomically (common::WriteFileAtomic).
//
// Everything here throws climbsim::InputError (exit 2) for a refused path and
// std::runtime_error for a failure of the file system after the checks (disk full).
#ifndef CLIMBSIM_SIM_RUN_FOLDER_H_
#define CLIMBSIM_SIM_RUN_FOLDER_H_

#include <string>
#include <vector>

namespace climbsim::sim {

// The marker file's name inside a run folder.
inline constexpr const char* kRunMarker = ".climbsim-run";

struct RunFolderOptions {
  std::string made_by{};              // the verb: "simulate", "optimise", "sweep", ...
  bool force = false;                 // replace an existing climbsim folder whole
  std::vector<std::string> inputs{};  // files the verb reads: the folder must not hold them
  std::string flag = "--out";         // the option that named the folder, for messages
};

// True when `dir` is a folder with the marker.
bool IsRunFolder(const std::string& dir);
// The verb that made a run folder ("" when it is none).
std::string RunFolderMadeBy(const std::string& dir);

// Checks `dir` as the output folder of a verb without touching anything (the constructor
// below does the same checks). Throws InputError naming the option and the reason.
void CheckOutputFolder(const std::string& dir, const RunFolderOptions& options);

class RunFolder {
 public:
  // Staged: checks `dir`, makes its parent folders, takes the lock and makes the staging
  // sibling. Throws InputError when refused.
  RunFolder(const std::string& dir, RunFolderOptions options);
  // Live (optimise): as above, then the folder itself is made (or replaced, with force) at
  // once with its marker. With `resume`, `dir` must instead be an existing run folder made by
  // options.made_by; it is kept as it is.
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

  // Staged: writes the marker (listing the files now in the staging folder as the run's
  // data) and swaps the staging folder in. Live: rewrites the marker's file list. Once only.
  void Commit();

 private:
  RunFolder() = default;
  void Lock();
  void WriteMarker(const std::string& folder) const;

  std::string dir_;         // absolute path of the folder
  std::string write_path_;  // staging or dir_
  std::string staging_;     // "" when live or committed
  std::string lock_path_;
  RunFolderOptions options_;
  int lock_fd_ = -1;
  bool live_ = false;
  bool committed_ = false;
};

// Checks a file another verb writes next to (or into) runs: render's video or still, a plot.
// Refuses an empty path, a folder, a path whose folder cannot be written, the marker, and any
// data file of a run folder (the files its marker lists; in a folder without a marker that
// holds summary.json, the names climbsim's verbs write). `flag` names the option in messages.
void CheckFileOutput(const std::string& path, const std::string& flag);

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_RUN_FOLDER_H_
