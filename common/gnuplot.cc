#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/common.h"

namespace climbsim::common {

std::string GnuplotQuote(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

std::string RunGnuplot(const std::string& script, const std::vector<std::string>& outputs) {
  namespace fs = std::filesystem;
  // Process id and a counter: unique across processes and across threads of one process.
  static std::atomic<long> counter{0};
  const std::string pid = std::to_string(::getpid()) + "_" + std::to_string(counter++);
  std::string text = script;
  std::vector<std::string> temps;
  for (size_t k = 0; k < outputs.size(); ++k) {
    const std::string tmp = TempSiblingPath(outputs[k]);
    temps.push_back(tmp);
    const std::string mark = "OUTPUT(" + std::to_string(k) + ")";
    for (size_t at = text.find(mark); at != std::string::npos; at = text.find(mark, at)) {
      text.replace(at, mark.size(), GnuplotQuote(tmp));
    }
  }
  const fs::path script_path = fs::temp_directory_path() / ("climbsim_plot_" + pid + ".gp");
  const fs::path err_path = fs::temp_directory_path() / ("climbsim_plot_" + pid + ".err");
  std::ofstream(script_path) << text;
  const std::string cmd =
      "gnuplot " + script_path.string() + " >/dev/null 2>" + err_path.string();
  const int status = std::system(cmd.c_str());
  std::string error;
  if (status != 0) {
    std::ifstream in(err_path);
    std::stringstream e;
    e << in.rdbuf();
    error = "gnuplot failed (exit " + std::to_string(status) + "): " + e.str();
    if (e.str().empty()) error += "is gnuplot installed? (scripts/setup.sh installs gnuplot-nox)";
  }
  std::error_code ec;
  fs::remove(script_path, ec);
  fs::remove(err_path, ec);
  for (size_t k = 0; k < outputs.size(); ++k) {
    if (error.empty() && fs::exists(temps[k])) {
      fs::rename(temps[k], outputs[k]);
    } else {
      fs::remove(temps[k], ec);
      if (error.empty()) error = "gnuplot wrote no " + outputs[k];
    }
  }
  return error;
}

}  // namespace climbsim::common
