// The marker of a run folder (`.climbsim-run`) read and written, and the inventory of what in
// a folder is climbsim's: the internals of sim/run_folder.cc, which holds the contract
// (sim/run_folder.h). Not part of the sim module's public header.
#ifndef CLIMBSIM_COMMON_RUN_MARKER_H_
#define CLIMBSIM_COMMON_RUN_MARKER_H_

#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "common/run_folder.h"

namespace climbsim::sim::run_marker {

// Names climbsim's verbs write as data; never the target of a picture or a plot, even in an
// old run folder without a marker.
const std::set<std::string>& StandardDataFiles();

// One file climbsim wrote, as its marker records it.
struct Entry {
  uintmax_t size = 0;
  std::string hash;
};

// A folder's marker, read. kOld: schema 1 (names only); kDamaged: empty, `{}`, not JSON, or
// without the schema; kInProgress: a live run not yet committed.
struct Marker {
  enum class Kind { kNone, kDamaged, kOld, kInProgress, kComplete } kind = Kind::kNone;
  std::string made_by;
  std::map<std::string, Entry> files;  // relative path → entry
  std::set<std::string> data;          // relative paths of the run's data
  nlohmann::json json;
  bool Usable() const { return kind == Kind::kInProgress || kind == Kind::kComplete; }
};

// A folder's marker, read (Kind::kNone when it has none).
Marker ReadMarker(const std::filesystem::path& dir);

// Walks `dir` (shown as `shown`, at `key` below the marker `m`): files that are not climbsim's
// are added to `others`; a subfolder with a marker of its own (best_run/) is judged by it; an
// empty subfolder is the user's. With `remove`, climbsim's files are unlinked one by one and
// the folders this emptied removed (rmdir: a folder that still holds anything stays).
void Walk(const std::filesystem::path& dir, const Marker& m, const std::string& shown,
          const std::string& key, bool remove, std::vector<std::string>* others);

// What in `dir` is not climbsim's, by its marker (Walk without removing).
std::vector<std::string> OthersIn(const std::filesystem::path& dir);

// The marker's entry of one file: its path relative to the marker, size and hash.
nlohmann::json FileEntry(const std::filesystem::path& file, const std::string& rel);

// Every regular file below `root` (not the marker) by relative path; `top_known_only`: only
// the top-level files with the names the verbs write (a live folder a user could add to).
void ListFiles(const std::filesystem::path& root, bool top_known_only, nlohmann::json* files,
               nlohmann::json* data);

}  // namespace climbsim::sim::run_marker

#endif  // CLIMBSIM_COMMON_RUN_MARKER_H_
