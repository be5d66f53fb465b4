// Helpers shared by the sim tests: scenario files written to a private temporary folder.
#ifndef CLIMBSIM_TESTS_SIM_TEST_UTIL_H_
#define CLIMBSIM_TESTS_SIM_TEST_UTIL_H_

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace climbsim::testing {

// A fresh folder per test process, removed by nobody (tests may inspect it after failure).
inline std::string TempDir() {
  static const std::string dir = [] {
    auto d = std::filesystem::temp_directory_path() /
             ("climbsim_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d.string();
  }();
  return dir;
}

inline std::string WriteFile(const std::string& name, const std::string& text) {
  const std::string path = TempDir() + "/" + name;
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream(path) << text;
  return path;
}

inline std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline std::string Source(const std::string& rel) {
  return std::string(CLIMBSIM_SOURCE_DIR) + "/" + rel;
}

}  // namespace climbsim::testing

#endif  // CLIMBSIM_TESTS_SIM_TEST_UTIL_H_
