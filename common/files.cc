#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "common/common.h"

namespace climbsim::common {

namespace fs = std::filesystem;

std::string TempSiblingPath(const std::string& path) {
  static std::atomic<long> counter{0};
  const fs::path p(path);
  const std::string tag = std::to_string(::getpid()) + "_" + std::to_string(counter++);
  return (p.parent_path() / (p.stem().string() + ".tmp." + tag + p.extension().string()))
      .string();
}

void WriteFileAtomic(const std::string& path, const std::string& content) {
  const std::string tmp = TempSiblingPath(path);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << content;
    out.flush();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw std::runtime_error("cannot write " + path);
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::error_code ec;
    fs::remove(tmp, ec);
    throw std::runtime_error("cannot write " + path + ": " + why);
  }
}

}  // namespace climbsim::common
