#include "sim/run_folder.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "common/common.h"

namespace climbsim::sim {
namespace {

namespace fs = std::filesystem;

// Names climbsim's verbs write as data; never the target of a picture or a plot, even in an
// old run folder without a marker.
const std::set<std::string>& StandardDataFiles() {
  static const std::set<std::string> k{
      "scenario.yaml", "model.xml",       "trajectory.csv", "events.csv",
      "summary.json",  "checkpoint.json", "history.csv",    "best.yaml",
      "failures.log",  "convergence.csv", "sweep.csv",      "pulloff.csv",
      "pulloff.gp",    "accuracy.csv",    "accuracy.dat",   kRunMarker};
  return k;
}

std::string Quoted(const std::string& s) { return "'" + s + "'"; }

InputError Refuse(const RunFolderOptions& o, const std::string& message) {
  return InputError("climbsim " + o.made_by, 0, 0, o.flag, message);
}

std::string ReadSmallFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::string text;
  char buf[4096];
  while (in && text.size() < (1u << 20)) {
    in.read(buf, sizeof(buf));
    text.append(buf, static_cast<size_t>(in.gcount()));
  }
  return text;
}

nlohmann::json ReadMarker(const fs::path& dir) {
  try {
    return nlohmann::json::parse(ReadSmallFile(dir / kRunMarker));
  } catch (const std::exception&) {
    return nlohmann::json::object();  // a damaged marker still marks the folder as climbsim's
  }
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
  if (fs::exists(abs, ec) && !fs::is_directory(abs, ec)) {
    throw Refuse(o, Quoted(dir) + " is a file, not a folder");
  }
  return abs;
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
  const bool exists = fs::exists(abs, ec);
  const bool marked = exists && fs::is_regular_file(abs / kRunMarker, ec);
  if (resume) {
    if (!marked) {
      throw Refuse(o, Quoted(dir) + (exists ? " is not a climbsim run folder" : " does not exist") +
                          ": nothing to resume (drop --resume to start a new run)");
    }
    const std::string by = ReadMarker(abs).value("made_by", "");
    if (by != o.made_by) {
      throw Refuse(o, Quoted(dir) + " was made by climbsim " + (by.empty() ? "?" : by) + ", not " +
                          o.made_by + ": nothing to resume");
    }
    return;
  }
  if (!exists || IsEmptyFolder(abs)) return;
  if (marked) {
    if (o.force) return;
    const std::string by = ReadMarker(abs).value("made_by", "");
    throw Refuse(o, Quoted(dir) + " holds a previous climbsim run (made by climbsim " +
                        (by.empty() ? "?" : by) +
                        "); --force replaces it whole, or give a new folder");
  }
  throw Refuse(o, Quoted(dir) + " holds files climbsim did not make (no " + kRunMarker +
                      " marker): give a new or empty folder; climbsim never writes among a "
                      "user's files");
}

std::string UtcNow() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

// Removes leftovers of killed writers of `abs` (the caller holds the lock).
void RemoveStaleSiblings(const fs::path& abs) {
  const std::string prefix = "." + abs.filename().string() + ".climbsim-";
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(abs.parent_path(), ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix + "new.", 0) == 0 || name.rfind(prefix + "old.", 0) == 0) {
      if (e.is_directory(ec)) fs::remove_all(e.path(), ec);
    }
  }
}

// Puts `from` (a folder) at `to`: a rename when `to` is absent or an empty folder, else an
// atomic exchange (the old folder ends up at `from`, then removed). Where the file system
// cannot exchange, two renames: `to` is absent for a moment, but never a mix.
void SwapIn(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  if (!fs::exists(to, ec) || IsEmptyFolder(to)) {
    if (::rename(from.c_str(), to.c_str()) == 0) return;
  }
  if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), RENAME_EXCHANGE) == 0) {
    fs::remove_all(from, ec);
    return;
  }
  const fs::path old = to.parent_path() / ("." + to.filename().string() + ".climbsim-old." +
                                           std::to_string(::getpid()));
  if (::rename(to.c_str(), old.c_str()) != 0 || ::rename(from.c_str(), to.c_str()) != 0) {
    throw std::runtime_error("cannot put the new run at " + to.string() + ": " +
                             std::strerror(errno));
  }
  fs::remove_all(old, ec);
}

}  // namespace

bool IsRunFolder(const std::string& dir) {
  std::error_code ec;
  return fs::is_regular_file(fs::path(dir) / kRunMarker, ec);
}

std::string RunFolderMadeBy(const std::string& dir) {
  if (!IsRunFolder(dir)) return "";
  return ReadMarker(dir).value("made_by", "unknown");
}

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
  } catch (...) {
    ::close(lock_fd_);  // no destructor runs for a constructor that throws
    throw;
  }
  write_path_ = staging_;
}

RunFolder RunFolder::Live(const std::string& dir, RunFolderOptions options, bool resume) {
  if (!resume) {
    RunFolder f(dir, std::move(options));
    f.WriteMarker(f.staging_);
    SwapIn(f.staging_, f.dir_);
    f.staging_.clear();
    f.write_path_ = f.dir_;
    f.live_ = true;
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
      committed_(o.committed_) {
  o.lock_fd_ = -1;
  o.staging_.clear();
}

RunFolder::~RunFolder() {
  if (!staging_.empty() && !committed_) {
    std::error_code ec;
    fs::remove_all(staging_, ec);
  }
  if (lock_fd_ >= 0) ::close(lock_fd_);  // releases the flock
}

void RunFolder::Lock() {
  const fs::path abs(dir_);
  lock_path_ = (abs.parent_path() / ("." + abs.filename().string() + ".climbsim-lock")).string();
  lock_fd_ = ::open(lock_path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0) {
    throw Refuse(options_,
                 Quoted(dir_) + " cannot be written: " + lock_path_ + ": " + std::strerror(errno));
  }
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    throw Refuse(options_, Quoted(dir_) + " is being written by another climbsim right now (lock " +
                               lock_path_ + "); wait for it or give another folder");
  }
}

void RunFolder::WriteMarker(const std::string& folder) const {
  nlohmann::json files = nlohmann::json::array();
  std::error_code ec;
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(folder, ec)) {
    const std::string name = e.path().filename().string();
    if (name != kRunMarker && e.is_regular_file(ec)) names.insert(name);
  }
  for (const auto& n : names) files.push_back(n);
  nlohmann::json inputs = nlohmann::json::array();
  for (const auto& i : options_.inputs) {
    if (!i.empty()) inputs.push_back(fs::absolute(i, ec).lexically_normal().string());
  }
  const nlohmann::json marker{
      {"climbsim_run_folder", 1},
      {"made_by", options_.made_by},
      {"climbsim_version", CLIMBSIM_VERSION},
      {"written_utc", UtcNow()},
      {"inputs", inputs},
      {"data_files", files},
      {"note",
       "made by climbsim; climbsim replaces this folder whole only when given --force "
       "(docs/run-folders.md)"}};
  common::WriteFileAtomic(folder + "/" + kRunMarker, marker.dump(2) + "\n");
}

void RunFolder::Commit() {
  if (committed_) return;
  if (live_) {
    WriteMarker(dir_);
  } else {
    WriteMarker(staging_);
    SwapIn(staging_, dir_);
    staging_.clear();
    write_path_ = dir_;
  }
  committed_ = true;
}

void CheckFileOutput(const std::string& path, const std::string& flag) {
  const auto refuse = [&](const std::string& m) { return InputError(path, 0, 0, flag, m); };
  if (path.empty()) throw InputError("climbsim", 0, 0, flag, "must not be empty");
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec) throw refuse("cannot be used: " + ec.message());
  if (fs::is_directory(p, ec)) throw refuse("is a folder; give a file name");
  const std::string name = p.filename().string();
  const fs::path folder = p.parent_path();
  if (name == kRunMarker) throw refuse("is the marker of a climbsim run folder");
  const bool run_folder = IsRunFolder(folder.string());
  const bool old_run =
      fs::exists(folder / "summary.json", ec) || fs::exists(folder / "best.yaml", ec);
  if (run_folder || old_run) {
    std::set<std::string> data = StandardDataFiles();
    if (run_folder) {
      const nlohmann::json m = ReadMarker(folder);
      if (m.contains("data_files") && m["data_files"].is_array()) {
        for (const auto& f : m["data_files"]) {
          if (f.is_string()) data.insert(f.get<std::string>());
        }
      }
    }
    if (data.count(name) > 0) {
      throw refuse("is a data file of the climbsim run in " + Quoted(folder.string()) +
                   "; climbsim never overwrites a run's data: give another name");
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

}  // namespace climbsim::sim
