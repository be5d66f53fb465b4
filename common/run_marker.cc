#include "common/run_marker.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>

#include "common/common.h"

namespace climbsim::sim::run_marker {
namespace {

namespace fs = std::filesystem;

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

// The schema-2 `files` list, or false when it is malformed.
bool ReadEntries(const nlohmann::json& files, Marker* m) {
  if (!files.is_array()) return false;
  for (const auto& f : files) {
    if (!f.is_object() || !f.contains("path") || !f["path"].is_string() || !f.contains("size") ||
        !f["size"].is_number_unsigned() || !f.contains("fnv1a64") || !f["fnv1a64"].is_string()) {
      return false;
    }
    m->files[f["path"].get<std::string>()] = {f["size"].get<uintmax_t>(),
                                              f["fnv1a64"].get<std::string>()};
  }
  return true;
}

// `name` without the `.tmp.<pid>_<n>` that common::TempSiblingPath puts before the extension.
std::string WithoutTempTag(const std::string& name) {
  const size_t at = name.find(".tmp.");
  if (at == std::string::npos) return name;
  size_t end = at + 5;
  while (end < name.size() &&
         (std::isdigit(static_cast<unsigned char>(name[end])) || name[end] == '_')) {
    ++end;
  }
  return name.substr(0, at) + name.substr(end);
}

// `.<name>.climbsim-lock`: the lock file of a folder (left in place by design).
bool IsLockName(const std::string& name) {
  const std::string tail = ".climbsim-lock";
  return name.size() > tail.size() + 1 && name[0] == '.' &&
         name.compare(name.size() - tail.size(), tail.size(), tail) == 0;
}

// Whether `e` (a regular file in a folder at `key` below the marker `m`) is climbsim's.
bool Ours(const fs::directory_entry& e, const Marker& m, const std::string& key) {
  std::error_code ec;
  if (!fs::is_regular_file(e.symlink_status(ec))) return false;
  const std::string name = e.path().filename().string();
  const uintmax_t size = fs::file_size(e.path(), ec);
  if (ec) return false;
  if (key.empty() && name == kRunMarker) return true;
  if (IsLockName(name) && size == 0) return true;
  if (m.kind == Marker::Kind::kInProgress && key.empty() && KnownOutputName(WithoutTempTag(name))) {
    return true;  // a killed live run: its files were never listed
  }
  const auto it = m.files.find(key + name);
  return it != m.files.end() && it->second.size == size && FileHash(e.path()) == it->second.hash;
}

}  // namespace

nlohmann::json FileEntry(const fs::path& file, const std::string& rel) {
  std::error_code ec;
  return {{"path", rel},
          {"size", static_cast<uintmax_t>(fs::file_size(file, ec))},
          {"fnv1a64", FileHash(file.string())}};
}

const std::set<std::string>& StandardDataFiles() {
  static const std::set<std::string> k{
      "scenario.yaml", "model.xml",       "trajectory.csv", "events.csv",
      "summary.json",  "checkpoint.json", "history.csv",    "best.yaml",
      "failures.log",  "convergence.csv", "sweep.csv",      "pulloff.csv",
      "pulloff.gp",    "accuracy.csv",    "accuracy.dat",   kRunMarker};
  return k;
}

Marker ReadMarker(const fs::path& dir) {
  Marker m;
  std::error_code ec;
  const auto st = fs::symlink_status(dir / kRunMarker, ec);
  if (!fs::exists(st)) return m;
  m.kind = Marker::Kind::kDamaged;
  if (!fs::is_regular_file(st)) return m;
  try {
    m.json = nlohmann::json::parse(ReadSmallFile(dir / kRunMarker));
  } catch (const std::exception&) {
    return m;
  }
  const auto& j = m.json;
  if (!j.is_object() || !j.contains("climbsim_run_folder") ||
      !j["climbsim_run_folder"].is_number_integer() || !j.contains("made_by") ||
      !j["made_by"].is_string() || j["made_by"].get<std::string>().empty()) {
    return m;
  }
  m.made_by = j["made_by"].get<std::string>();
  if (j.contains("data_files") && j["data_files"].is_array()) {
    for (const auto& f : j["data_files"]) {
      if (f.is_string()) m.data.insert(f.get<std::string>());
    }
  }
  const int version = j["climbsim_run_folder"].get<int>();
  if (version == 1) m.kind = Marker::Kind::kOld;
  if (version != 2 || !j.contains("files") || !ReadEntries(j["files"], &m)) return m;
  m.kind = j.value("in_progress", false) ? Marker::Kind::kInProgress : Marker::Kind::kComplete;
  return m;
}

void Walk(const fs::path& dir, const Marker& m, const std::string& shown, const std::string& key,
          bool remove, std::vector<std::string>* others) {
  std::error_code ec;
  std::vector<fs::directory_entry> entries;
  for (const auto& e : fs::directory_iterator(dir, ec)) entries.push_back(e);
  std::sort(entries.begin(), entries.end());
  for (const auto& e : entries) {
    const std::string name = e.path().filename().string();
    if (fs::is_directory(e.symlink_status(ec))) {
      if (fs::is_empty(e.path(), ec)) {
        others->push_back(shown + name + "/");
        continue;
      }
      const Marker nested = ReadMarker(e.path());
      if (nested.Usable()) {
        Walk(e.path(), nested, shown + name + "/", "", remove, others);
      } else {
        Walk(e.path(), m, shown + name + "/", key + name + "/", remove, others);
      }
      if (remove) ::rmdir(e.path().c_str());
    } else if (!Ours(e, m, key)) {
      others->push_back(shown + name);
    } else if (remove) {
      ::unlink(e.path().c_str());
    }
  }
}

std::vector<std::string> OthersIn(const fs::path& dir) {
  std::vector<std::string> others;
  Walk(dir, ReadMarker(dir), "", "", false, &others);
  return others;
}

void ListFiles(const fs::path& root, bool top_known_only, nlohmann::json* files,
               nlohmann::json* data) {
  std::error_code ec;
  std::vector<std::string> rels;
  for (auto it = fs::recursive_directory_iterator(root, ec); !ec && it != fs::end(it);
       it.increment(ec)) {
    if (!fs::is_regular_file(it->symlink_status(ec))) continue;
    const std::string rel = it->path().lexically_relative(root).string();
    if (rel == kRunMarker) continue;
    if (top_known_only && (it.depth() > 0 || !KnownOutputName(rel))) continue;
    rels.push_back(rel);
  }
  std::sort(rels.begin(), rels.end());
  for (const auto& rel : rels) {
    files->push_back(FileEntry(root / rel, rel));
    data->push_back(rel);
  }
}

}  // namespace climbsim::sim::run_marker

namespace climbsim::sim {

namespace fs = std::filesystem;
using run_marker::Marker;
using run_marker::ReadMarker;
using run_marker::StandardDataFiles;

bool IsRunFolder(const std::string& dir) {
  std::error_code ec;
  return fs::is_regular_file(fs::path(dir) / kRunMarker, ec);
}

std::string RunFolderMadeBy(const std::string& dir) {
  if (!IsRunFolder(dir)) return "";
  const Marker m = ReadMarker(dir);
  return m.made_by.empty() ? "unknown" : m.made_by;
}

bool KnownOutputName(const std::string& name) {
  static const std::set<std::string> k{"convergence.png", "sweep.png",      "pulloff.png",
                                       "accuracy.png",    "robustness.csv", "robustness.dat",
                                       "robustness.png"};
  return (StandardDataFiles().count(name) > 0 && name != kRunMarker) || k.count(name) > 0;
}

std::string FileHash(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  uint64_t h = common::kFnv1a64Basis;
  char buf[1 << 16];
  while (in) {
    in.read(buf, sizeof(buf));
    h = common::Fnv1a64(std::string_view(buf, static_cast<size_t>(in.gcount())), h);
  }
  char hex[17];
  std::snprintf(hex, sizeof(hex), "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

}  // namespace climbsim::sim
