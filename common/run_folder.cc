#include "common/run_folder.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "common/common.h"
#include "common/run_marker.h"

namespace climbsim::sim {
namespace {

namespace fs = std::filesystem;
using run_marker::FileEntry;
using run_marker::ListFiles;
using run_marker::Marker;
using run_marker::OthersIn;
using run_marker::ReadMarker;
using run_marker::StandardDataFiles;
using run_marker::Walk;

std::string Quoted(const std::string& s) { return "'" + s + "'"; }

InputError Refuse(const RunFolderOptions& o, const std::string& message) {
  return InputError("climbsim " + o.made_by, 0, 0, o.flag, message);
}

// The first few of `names`, for a message.
std::string List(const std::vector<std::string>& names) {
  std::string s;
  for (size_t k = 0; k < names.size() && k < 8; ++k) s += (k ? ", " : "") + names[k];
  if (names.size() > 8) s += " and " + std::to_string(names.size() - 8) + " more";
  return s;
}

bool IsEmptyFolder(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec) && fs::directory_iterator(p, ec) == fs::directory_iterator();
}

// `inner` is `outer` or inside it (both absolute and normal).
bool Within(const fs::path& inner, const fs::path& outer) {
  auto i = inner.begin();
  for (auto o = outer.begin(); o != outer.end(); ++o, ++i) {
    if (o->empty()) continue;  // a trailing separator
    if (i == inner.end() || *i != *o) return false;
  }
  return true;
}

// The absolute, normal form of a path whose tail may not exist yet.
fs::path Resolve(const std::string& dir, const RunFolderOptions& o) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(dir, ec), ec);
  if (ec) throw Refuse(o, Quoted(dir) + " cannot be used: " + ec.message());
  std::string s = p.string();
  while (s.size() > 1 && s.back() == '/') s.pop_back();
  return fs::path(s);
}

// Checks that need no lock: the path itself, the current folder, what is in the way.
fs::path CheckPath(const std::string& dir, const RunFolderOptions& o) {
  if (dir.empty()) throw Refuse(o, "must not be empty: give a folder for the run");
  const fs::path abs = Resolve(dir, o);
  if (abs == abs.root_path()) throw Refuse(o, Quoted(dir) + " is the root folder");
  std::error_code ec;
  const fs::path cwd = fs::current_path(ec);
  if (!ec && Within(cwd, abs)) {
    throw Refuse(o, Quoted(dir) +
                        (abs == cwd ? " is the current folder" : " holds the current folder") +
                        ": give a new folder for the run, e.g. runs/NAME");
  }
  // The nearest existing ancestor must be a folder climbsim can write into.
  for (fs::path p = abs.parent_path(); !p.empty(); p = p.parent_path()) {
    if (fs::exists(p, ec)) {
      if (!fs::is_directory(p, ec)) {
        throw Refuse(
            o, Quoted(dir) + " cannot be made: " + Quoted(p.string()) + " is a file, not a folder");
      }
      if (::access(p.c_str(), W_OK | X_OK) != 0) {
        throw Refuse(o, Quoted(dir) + " cannot be written: " + Quoted(p.string()) + ": " +
                            std::strerror(errno));
      }
      break;
    }
    if (p == p.root_path()) break;
  }
  // A link that leads nowhere: a rename would replace the link, not make its target.
  if (fs::is_symlink(fs::symlink_status(abs, ec))) {
    throw Refuse(o, Quoted(dir) + " is a link to nothing (a dangling symlink): give a folder");
  }
  if (fs::exists(abs, ec) && !fs::is_directory(abs, ec)) {
    throw Refuse(o, Quoted(dir) + " is a file, not a folder");
  }
  return abs;
}

void CheckResume(const std::string& dir, const fs::path& abs, const RunFolderOptions& o) {
  std::error_code ec;
  const Marker m = ReadMarker(abs);
  if (m.kind == Marker::Kind::kNone || m.kind == Marker::Kind::kDamaged) {
    throw Refuse(o,
                 Quoted(dir) +
                     (fs::exists(abs, ec) ? " is not a climbsim run folder" : " does not exist") +
                     ": nothing to resume (drop --resume to start a new run)");
  }
  if (m.made_by != o.made_by) {
    throw Refuse(o, Quoted(dir) + " was made by climbsim " + m.made_by + ", not " + o.made_by +
                        ": nothing to resume");
  }
}

// Checks of the folder's content; under the lock when called from RunFolder.
void CheckContent(const std::string& dir, const fs::path& abs, const RunFolderOptions& o,
                  bool resume) {
  std::error_code ec;
  for (const std::string& input : o.inputs) {
    if (input.empty()) continue;
    const fs::path in = fs::weakly_canonical(fs::absolute(input, ec), ec);
    if (!ec && Within(in, abs)) {
      throw Refuse(o, Quoted(dir) + " holds the input " + Quoted(input) +
                          ": climbsim never writes where its inputs are; give another folder");
    }
  }
  if (resume) return CheckResume(dir, abs, o);
  if (!fs::exists(abs, ec) || IsEmptyFolder(abs)) return;
  const Marker m = ReadMarker(abs);
  switch (m.kind) {
    case Marker::Kind::kNone:
      throw Refuse(o, Quoted(dir) + " holds files climbsim did not make (no " + kRunMarker +
                          " marker): give a new or empty folder; climbsim never writes among a "
                          "user's files");
    case Marker::Kind::kDamaged:
      throw Refuse(o, Quoted(dir) + " is not a climbsim run folder: its " + kRunMarker +
                          " is empty, damaged or without climbsim's schema; climbsim deletes "
                          "nothing there: give a new folder");
    case Marker::Kind::kOld:
      throw Refuse(o, Quoted(dir) + " holds a run of an earlier climbsim, whose " + kRunMarker +
                          " lists no file sizes: climbsim cannot tell its files from yours "
                          "there; remove the folder yourself, or give a new folder");
    default:
      break;
  }
  if (!o.force) {
    throw Refuse(o, Quoted(dir) + " holds a previous climbsim run (made by climbsim " + m.made_by +
                        "); --force replaces it (deleting only climbsim's own files), or give "
                        "a new folder");
  }
  const std::vector<std::string> others = OthersIn(abs);
  if (!others.empty() && !o.keep_other_files) {
    throw Refuse(o, Quoted(dir) +
                        " holds files climbsim did not write there, or that changed "
                        "since: " +
                        List(others) +
                        "; --force deletes only climbsim's own files: move these away, or add "
                        "--keep-other-files to carry them into the new run");
  }
}

std::string UtcNow(const char* format = "%Y-%m-%dT%H:%M:%SZ") {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof(buf), format, &tm);
  return buf;
}

// A visible name beside `dir` that no one has: DIR.<what>-<UTC>-<pid>.
std::string AsideName(const std::string& dir, const std::string& what) {
  return dir + "." + what + "-" + UtcNow("%Y%m%dT%H%M%SZ") + "-" + std::to_string(::getpid());
}

// Removes leftovers of killed writers of `abs` (the caller holds the lock): a staging folder
// whole (only climbsim writes there; its marker says "staging"), of a swapped-out folder only
// climbsim's files; what is left of one is kept under a visible name.
void RemoveStaleSiblings(const fs::path& abs) {
  const std::string prefix = "." + abs.filename().string() + ".climbsim-";
  std::error_code ec;
  std::vector<fs::path> stale;
  for (const auto& e : fs::directory_iterator(abs.parent_path(), ec)) {
    const std::string name = e.path().filename().string();
    if ((name.rfind(prefix + "new.", 0) == 0 || name.rfind(prefix + "old.", 0) == 0) &&
        fs::is_directory(e.symlink_status(ec))) {
      stale.push_back(e.path());
    }
  }
  for (const fs::path& p : stale) {
    const Marker m = ReadMarker(p);
    if (m.Usable() && m.json.value("staging", false)) {
      fs::remove_all(p, ec);
      continue;
    }
    std::vector<std::string> others;
    if (m.Usable()) Walk(p, m, "", "", /*remove=*/true, &others);
    if (::rmdir(p.c_str()) != 0) {
      ::renameat2(AT_FDCWD, p.c_str(), AT_FDCWD, AsideName(abs.string(), "previous").c_str(),
                  RENAME_NOREPLACE);
    }
  }
}

// Opens and flocks `.<name>.climbsim-lock` beside `dir`: the fd, or -1 when another holds it.
// Throws `refuse(message)` when the lock file cannot be made.
template <class Refusal>
int TakeLock(const fs::path& dir, std::string* lock_path, Refusal refuse) {
  *lock_path = (dir.parent_path() / ("." + dir.filename().string() + ".climbsim-lock")).string();
  const int fd = ::open(lock_path->c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) {
    throw refuse(Quoted(dir.string()) + " cannot be written: " + *lock_path + ": " +
                 std::strerror(errno));
  }
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd);
    throw refuse(Quoted(dir.string()) + " is being written by another climbsim right now (lock " +
                 *lock_path + "); wait for it or give another folder");
  }
  return fd;
}

}  // namespace

void CheckOutputFolder(const std::string& dir, const RunFolderOptions& options) {
  CheckContent(dir, CheckPath(dir, options), options, false);
}

RunFolder::RunFolder(const std::string& dir, RunFolderOptions options) {
  options_ = std::move(options);
  const fs::path abs = CheckPath(dir, options_);
  dir_ = abs.string();
  std::error_code ec;
  fs::create_directories(abs.parent_path(), ec);
  if (ec) throw Refuse(options_, Quoted(dir) + " cannot be made: " + ec.message());
  Lock();
  try {
    CheckContent(dir, abs, options_, false);
    Remember();
    RemoveStaleSiblings(abs);
    const std::string staging =
        (abs.parent_path() /
         ("." + abs.filename().string() + ".climbsim-new." + std::to_string(::getpid())))
            .string();
    if (!fs::create_directory(staging, ec) || ec) {
      throw Refuse(options_, Quoted(dir) + " cannot be written: " +
                                 (ec ? ec.message() : "the staging folder exists"));
    }
    staging_ = staging;
    WriteMarker(staging_, /*in_progress=*/true);  // says "staging" until the commit
  } catch (...) {
    // No destructor runs for a constructor that throws.
    if (!staging_.empty()) fs::remove_all(staging_, ec);
    ::close(lock_fd_);
    throw;
  }
  write_path_ = staging_;
}

RunFolder RunFolder::Live(const std::string& dir, RunFolderOptions options, bool resume) {
  if (!resume) {
    RunFolder f(dir, std::move(options));
    f.live_ = true;
    f.WriteMarker(f.staging_, /*in_progress=*/true);
    f.Place();
    f.staging_.clear();
    f.write_path_ = f.dir_;
    return f;
  }
  RunFolder f;
  f.options_ = std::move(options);
  const fs::path abs = CheckPath(dir, f.options_);
  f.dir_ = abs.string();
  f.Lock();
  CheckContent(dir, abs, f.options_, true);
  RemoveStaleSiblings(abs);
  f.write_path_ = f.dir_;
  f.live_ = true;
  return f;
}

RunFolder::RunFolder(RunFolder&& o) noexcept
    : dir_(std::move(o.dir_)),
      write_path_(std::move(o.write_path_)),
      staging_(std::move(o.staging_)),
      lock_path_(std::move(o.lock_path_)),
      options_(std::move(o.options_)),
      lock_fd_(o.lock_fd_),
      live_(o.live_),
      committed_(o.committed_),
      existed_(o.existed_),
      dev_(o.dev_),
      ino_(o.ino_) {
  o.lock_fd_ = -1;
  o.staging_.clear();
}

RunFolder::~RunFolder() {
  if (!staging_.empty() && !committed_) {
    std::error_code ec;
    fs::remove_all(staging_, ec);  // only climbsim wrote there
  }
  if (lock_fd_ >= 0) ::close(lock_fd_);  // releases the flock
}

void RunFolder::Lock() {
  lock_fd_ = TakeLock(fs::path(dir_), &lock_path_,
                      [&](const std::string& m) { return Refuse(options_, m); });
}

// The identity of the folder that was checked, for Commit to swap out only that one.
void RunFolder::Remember() {
  struct stat st {};
  existed_ = ::lstat(dir_.c_str(), &st) == 0;
  dev_ = existed_ ? st.st_dev : 0;
  ino_ = existed_ ? st.st_ino : 0;
}

void RunFolder::WriteMarker(const std::string& folder, bool in_progress) const {
  nlohmann::json files = nlohmann::json::array(), data = nlohmann::json::array();
  if (!in_progress) ListFiles(folder, live_, &files, &data);
  nlohmann::json inputs = nlohmann::json::array();
  std::error_code ec;
  for (const auto& i : options_.inputs) {
    if (!i.empty()) inputs.push_back(fs::absolute(i, ec).lexically_normal().string());
  }
  nlohmann::json marker{
      {"climbsim_run_folder", 2},
      {"made_by", options_.made_by},
      {"climbsim_version", CLIMBSIM_VERSION},
      {"written_utc", UtcNow()},
      {"inputs", inputs},
      {"files", files},
      {"data_files", data},
      {"note",
       "made by climbsim; with --force climbsim deletes only the files listed here, when their "
       "size and FNV-1a 64 hash still match (docs/run-folders.md)"}};
  if (in_progress) marker["in_progress"] = true;
  if (in_progress && !live_) marker["staging"] = true;  // a staging folder: all climbsim's
  common::WriteFileAtomic(folder + "/" + kRunMarker, marker.dump(2) + "\n");
}

void RunFolder::KeepNewRunAside(const std::string& why) {
  const std::string aside = AsideName(dir_, "new-run");
  const std::string kept =
      ::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, aside.c_str(), RENAME_NOREPLACE) == 0
          ? aside
          : staging_;
  staging_.clear();  // never removed: it is the user's result now
  throw std::runtime_error("the new run was not put at " + dir_ + ": " + why +
                           "; nothing was deleted; the new run is kept at " + kept);
}

// A folder that did not exist when checked: it must still not exist.
void RunFolder::Place() {
  if (existed_) return PlaceOverExisting();
  if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, dir_.c_str(), RENAME_NOREPLACE) == 0) {
    return;
  }
  int error = errno;
  if (error == EINVAL) {  // a file system without RENAME_NOREPLACE: check, then rename
    struct stat st {};
    if (::lstat(dir_.c_str(), &st) == 0) {
      error = EEXIST;
    } else if (::rename(staging_.c_str(), dir_.c_str()) == 0) {
      return;
    } else {
      error = errno;
    }
  }
  if (error == EEXIST || error == ENOTEMPTY) {
    KeepNewRunAside("something appeared there while the run was in progress");
  }
  throw std::runtime_error("cannot put the new run at " + dir_ + ": " + std::strerror(error));
}

// The folder checked goes out, the new run in; returns where the old folder now is. Anything
// else found at dir_ stays there, and the new run is kept aside.
std::string RunFolder::SwapOut() {
  const std::string swapped = staging_;
  if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, dir_.c_str(), RENAME_EXCHANGE) == 0) {
    struct stat st {};
    if (::lstat(swapped.c_str(), &st) == 0 && st.st_dev == dev_ && st.st_ino == ino_) {
      staging_.clear();
      return swapped;
    }
    // Replaced between the last look and the exchange: swap back, delete nothing.
    if (::renameat2(AT_FDCWD, swapped.c_str(), AT_FDCWD, dir_.c_str(), RENAME_EXCHANGE) != 0) {
      staging_ = dir_;  // the new run stays at dir_: say so rather than guess
    }
    KeepNewRunAside("the folder there was replaced while the run was in progress");
  }
  if (errno != EINVAL) {
    throw std::runtime_error("cannot put the new run at " + dir_ + ": " + std::strerror(errno));
  }
  // A file system that cannot exchange: two renames (dir_ is absent for a moment).
  const std::string old =
      (fs::path(dir_).parent_path() /
       ("." + fs::path(dir_).filename().string() + ".climbsim-old." + std::to_string(::getpid())))
          .string();
  struct stat st {};
  if (::rename(dir_.c_str(), old.c_str()) != 0) {
    throw std::runtime_error("cannot put the new run at " + dir_ + ": " + std::strerror(errno));
  }
  if (::lstat(old.c_str(), &st) != 0 || st.st_dev != dev_ || st.st_ino != ino_ ||
      ::rename(staging_.c_str(), dir_.c_str()) != 0) {
    ::rename(old.c_str(), dir_.c_str());
    KeepNewRunAside("the folder there was replaced while the run was in progress");
  }
  staging_.clear();
  return old;
}

// A folder that existed when checked: only that folder is swapped out; of its content the
// files that are not climbsim's are carried into the new run (keep_other_files) or kept, and
// only climbsim's own files are deleted.
void RunFolder::PlaceOverExisting() {
  struct stat st {};
  if (::lstat(dir_.c_str(), &st) != 0 || st.st_dev != dev_ || st.st_ino != ino_) {
    KeepNewRunAside("the folder there was removed or replaced while the run was in progress");
  }
  const std::vector<std::string> others = OthersIn(dir_);
  if (!others.empty() && !options_.keep_other_files) {
    KeepNewRunAside("files climbsim did not write appeared there during the run: " + List(others));
  }
  CarryAndRemove(SwapOut());
}

void RunFolder::CarryAndRemove(const std::string& old) {
  const Marker m = ReadMarker(old);
  std::vector<std::string> others;
  if (options_.keep_other_files) Walk(old, m, "", "", false, &others);
  std::set<std::string> tops;
  for (const auto& o : others) tops.insert(o.substr(0, o.find('/')));
  std::vector<std::string> carried;
  for (const auto& t : tops) {
    // A live run would write over a file with one of its names: never carry one.
    if (live_ && KnownOutputName(t)) continue;
    const std::string from = old + "/" + t, to = dir_ + "/" + t;
    if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_NOREPLACE) == 0) {
      carried.push_back(t);
    }
  }
  if (!carried.empty()) {
    std::fprintf(stderr, "climbsim: carried into the new run at %s: %s\n", dir_.c_str(),
                 List(carried).c_str());
  }
  others.clear();
  Walk(old, m, "", "", /*remove=*/true, &others);
  if (::rmdir(old.c_str()) == 0) return;
  const std::string aside = AsideName(dir_, "previous");
  const std::string kept =
      ::renameat2(AT_FDCWD, old.c_str(), AT_FDCWD, aside.c_str(), RENAME_NOREPLACE) == 0 ? aside
                                                                                         : old;
  std::fprintf(stderr,
               "climbsim: files of the previous folder that are not climbsim's (%s) share a name "
               "with the new run's or appeared during it; they are kept in %s\n",
               List(others).c_str(), kept.c_str());
}

void RunFolder::Commit() {
  if (committed_) return;
  if (live_) {
    WriteMarker(dir_, /*in_progress=*/false);
  } else {
    WriteMarker(staging_, /*in_progress=*/false);
    Place();
    staging_.clear();
    write_path_ = dir_;
  }
  committed_ = true;
}

void CheckFileOutput(const std::string& path, const std::string& flag) {
  const auto refuse = [&](const std::string& m) { return InputError(path, 0, 0, flag, m); };
  if (path.empty()) throw InputError("climbsim", 0, 0, flag, "must not be empty");
  std::error_code ec;
  if (fs::is_symlink(fs::symlink_status(path, ec))) throw refuse("is a link; give a file name");
  const fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec) throw refuse("cannot be used: " + ec.message());
  if (fs::is_directory(p, ec)) throw refuse("is a folder; give a file name");
  const std::string name = p.filename().string();
  const fs::path folder = p.parent_path();
  if (name == kRunMarker) throw refuse("is the marker of a climbsim run folder");
  const Marker m = ReadMarker(folder);
  const bool old_run =
      fs::exists(folder / "summary.json", ec) || fs::exists(folder / "best.yaml", ec);
  if (m.kind != Marker::Kind::kNone || old_run) {
    std::set<std::string> data = StandardDataFiles();
    data.insert(m.data.begin(), m.data.end());
    if (data.count(name) > 0) {
      throw refuse("is a data file of the climbsim run in " + Quoted(folder.string()) +
                   "; climbsim never overwrites a run's data: give another name");
    }
  }
  if (fs::exists(fs::symlink_status(p, ec))) {
    const auto it = m.files.find(name);
    const bool ours = m.Usable() && it != m.files.end() &&
                      it->second.size == fs::file_size(p, ec) && !ec &&
                      it->second.hash == FileHash(p.string());
    if (!ours) {
      throw refuse(
          "exists, and no climbsim run folder records it as climbsim's: climbsim never "
          "overwrites a file it did not make; remove it or give another name");
    }
  }
  for (fs::path a = folder; !a.empty(); a = a.parent_path()) {
    if (fs::exists(a, ec)) {
      if (!fs::is_directory(a, ec)) throw refuse(Quoted(a.string()) + " is a file, not a folder");
      if (::access(a.c_str(), W_OK | X_OK) != 0) {
        throw refuse("cannot be written: " + Quoted(a.string()) + ": " + std::strerror(errno));
      }
      break;
    }
    if (a == a.root_path()) break;
  }
}

RunFolderAdditions::RunFolderAdditions(std::vector<std::string> files, const std::string& flag) {
  std::error_code ec;
  for (const auto& f : files) {
    CheckFileOutput(f, flag);
    files_.push_back(fs::weakly_canonical(fs::absolute(f, ec), ec).string());
  }
  if (files_.empty()) return;
  const fs::path folder = fs::path(files_.front()).parent_path();
  for (const auto& f : files_) {
    if (fs::path(f).parent_path() != folder) return;  // not one run folder: nothing to record
  }
  if (!ReadMarker(folder).Usable()) return;
  std::string lock_path;
  lock_fd_ = TakeLock(folder, &lock_path, [&](const std::string& m) {
    return InputError(files.front(), 0, 0, flag, m);
  });
  folder_ = folder.string();
}

RunFolderAdditions::~RunFolderAdditions() {
  if (lock_fd_ >= 0) ::close(lock_fd_);
}

void RunFolderAdditions::Commit() {
  if (folder_.empty()) return;
  Marker m = ReadMarker(folder_);
  if (!m.Usable()) return;
  nlohmann::json& list = m.json["files"];
  for (const auto& f : files_) {
    std::error_code ec;
    if (!fs::is_regular_file(fs::symlink_status(f, ec))) continue;
    const std::string rel = fs::path(f).filename().string();
    for (auto it = list.begin(); it != list.end();) {
      it = (*it)["path"] == rel ? list.erase(it) : it + 1;
    }
    list.push_back(FileEntry(f, rel));
  }
  common::WriteFileAtomic(folder_ + "/" + kRunMarker, m.json.dump(2) + "\n");
}

}  // namespace climbsim::sim
