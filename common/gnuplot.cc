#include <stdlib.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/common.h"

namespace climbsim::common {

namespace fs = std::filesystem;

std::string GnuplotQuote(const std::string& s) {
  // Single-quoted runs joined by "'": gnuplot 5.4 reads a doubled quote inside single quotes
  // as one, but not two in a row ('a''''b' ends after a'), so a quote is never doubled.
  std::string out, run;
  const auto flush = [&] {
    if (!run.empty()) out += (out.empty() ? "'" : ".'") + run + "'";
    run.clear();
  };
  for (char c : s) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (c == '\'') {
      flush();
      out += out.empty() ? "\"'\"" : ".\"'\"";
    } else {
      run += u < 0x20 || u == 0x7f ? ' ' : c;
    }
  }
  flush();
  return out.empty() ? "\"\"" : out;
}

namespace {

std::string ReadAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// "" when `path` is a whole image, else why not. A write that failed (disk full) leaves an
// empty or cut file while gnuplot still exits with status 0.
std::string Incomplete(const fs::path& path) {
  std::error_code ec;
  const auto size = fs::file_size(path, ec);
  if (ec) return "gnuplot wrote no file";
  if (size == 0) return "gnuplot wrote an empty file (disk full?)";
  const std::string ext = path.extension().string();
  if (ext != ".png" && ext != ".svg") return "";
  const std::string text = ReadAll(path);
  if (ext == ".png") {
    // A PNG ends with its IEND chunk: length 0, "IEND", CRC ae426082.
    static const std::string kEnd("\0\0\0\0IEND\xae\x42\x60\x82", 12);
    if (text.size() < 20 || text.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0 ||
        text.compare(text.size() - kEnd.size(), kEnd.size(), kEnd) != 0) {
      return "gnuplot wrote a cut PNG of " + std::to_string(size) + " bytes (disk full?)";
    }
  } else if (text.rfind("</svg>") == std::string::npos) {
    return "gnuplot wrote a cut SVG of " + std::to_string(size) + " bytes (disk full?)";
  }
  return "";
}

// `script` with OUTPUT(k) replaced by the quoted k-th of `names`.
std::string WithOutputs(std::string script, const std::vector<std::string>& names) {
  for (size_t k = 0; k < names.size(); ++k) {
    const std::string mark = "OUTPUT(" + std::to_string(k) + ")";
    const std::string quoted = GnuplotQuote(names[k]);
    for (size_t at = script.find(mark); at != std::string::npos;
         at = script.find(mark, at + quoted.size())) {
      script.replace(at, mark.size(), quoted);
    }
  }
  return script;
}

}  // namespace

std::string RunGnuplot(const std::string& folder, const std::string& script,
                       const std::vector<std::string>& outputs) {
  // A private folder inside `folder` holds the script, gnuplot's messages and the unfinished
  // plots: the same file system (an atomic rename), and one thing to remove.
  std::string work = (fs::path(folder) / ".climbsim-plot.XXXXXX").string();
  if (::mkdtemp(work.data()) == nullptr) {
    return "cannot make a temporary folder in " + folder + ": " + std::strerror(errno);
  }
  const std::string rel = fs::path(work).filename().string();  // [A-Za-z0-9.-] only
  std::vector<std::string> temps;
  for (size_t k = 0; k < outputs.size(); ++k) {
    temps.push_back(rel + "/" + std::to_string(k) + fs::path(outputs[k]).extension().string());
  }
  std::string error;
  {
    std::ofstream out(work + "/plot.gp", std::ios::binary);
    out << WithOutputs(script, temps);
    out.flush();
    if (!out) error = "cannot write the gnuplot script in " + folder + " (disk full?)";
  }
  if (error.empty()) {
    error = RunProcess({"gnuplot", rel + "/plot.gp"},
                       {.working_dir = folder, .stderr_path = work + "/gnuplot.err"});
    if (error.find("cannot start") == 0) {
      error += " (is gnuplot installed? scripts/setup.sh installs gnuplot-nox)";
    } else if (!error.empty()) {
      error += ": " + ReadAll(work + "/gnuplot.err");
    }
  }
  for (size_t k = 0; k < outputs.size() && error.empty(); ++k) {
    const std::string why = Incomplete(fs::path(folder) / temps[k]);
    if (!why.empty()) error = outputs[k] + ": " + why;
  }
  std::error_code ec;
  for (size_t k = 0; k < outputs.size() && error.empty(); ++k) {
    fs::rename(fs::path(folder) / temps[k], fs::path(folder) / outputs[k], ec);
    if (!ec) continue;
    error = "cannot write " + folder + "/" + outputs[k] + ": " + ec.message();
    while (k-- > 0) fs::remove(fs::path(folder) / outputs[k], ec);  // all or none
  }
  fs::remove_all(work, ec);
  return error;
}

}  // namespace climbsim::common
