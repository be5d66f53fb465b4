// Helpers shared by the tests: a private temporary folder, files written and read, the source
// tree, the climbsim executable as a user runs it, and a robot MuJoCo is sure to flag.
#ifndef CLIMBSIM_TESTS_COMMON_TEST_UTIL_H_
#define CLIMBSIM_TESTS_COMMON_TEST_UTIL_H_

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>
#include <sstream>

#include <gtest/gtest.h>

namespace climbsim::testing {

// The cells of one CSV line (no quoting in climbsim's files); a trailing comma is an empty
// last cell.
inline std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream s(line);
  for (std::string c; std::getline(s, c, ',');) cells.push_back(c);
  if (!line.empty() && line.back() == ',') cells.push_back("");
  return cells;
}

// One events.csv row: its first five columns (time_s, pad, event, cause, surface).
struct EventRow {
  double t;
  std::string pad, event, cause, surface;
};

// The rows of an events.csv text (its header skipped).
inline std::vector<EventRow> ParseEvents(const std::string& csv) {
  std::vector<EventRow> rows;
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> f = SplitCsv(line);
    f.resize(5);
    rows.push_back({std::stod(f[0]), f[1], f[2], f[3], f[4]});
  }
  return rows;
}

// A fresh folder per test process. mkdtemp makes a new one every time: a folder named by the
// pid alone was found again when the pid was reused, with an earlier process's runs in it (a
// run folder there refused a new run). At exit it is removed if every test of the process
// passed, and kept (its path on stderr) if one failed, so that its files can be read: kept
// always, the suite left 6 GB in /tmp after a few hundred runs. (Children from fork leave by
// _exit and never run the handler; std::system's shell replaces its image.)
inline std::string TempDir() {
  static const std::string dir = [] {
    std::string tmpl = (std::filesystem::temp_directory_path() / "climbsim_test_XXXXXX").string();
    if (::mkdtemp(tmpl.data()) == nullptr) throw std::runtime_error("mkdtemp " + tmpl);
    return tmpl;
  }();
  // Registered once `dir` is made, so that the handler runs before `dir` is destroyed.
  [[maybe_unused]] static const int registered = std::atexit([] {
    if (::testing::UnitTest::GetInstance()->Passed()) {
      std::error_code ignored;
      std::filesystem::remove_all(dir, ignored);
    } else {
      std::fprintf(stderr, "test files kept in %s\n", dir.c_str());
    }
  });
  return dir;
}

// Writes text to path (an absolute path, or a name under TempDir()), making its folders;
// returns the path written.
inline std::string WriteFile(const std::string& path_or_name, const std::string& text) {
  const std::filesystem::path p(path_or_name);
  const std::string path = p.is_absolute() ? path_or_name : TempDir() + "/" + path_or_name;
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

inline std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// True when `text` holds `part` (a message, a file's content).
inline bool Has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

inline std::string Source(const std::string& rel) {
  return std::string(CLIMBSIM_SOURCE_DIR) + "/" + rel;
}

inline std::string Climbsim() { return std::string(CLIMBSIM_BINARY_DIR) + "/climbsim"; }

struct CliResult {
  int code;  // the exit code; -1 when killed by a signal
  std::string out, err;
};

// Runs `climbsim ARGS` in a shell, stdout and stderr captured (each call its own files, so
// a failed test leaves every output behind).
inline CliResult RunClimbsim(const std::string& args) {
  static int n = 0;
  const std::string base = TempDir() + "/cli_" + std::to_string(n++);
  const std::string cmd = Climbsim() + " " + args + " >" + base + ".out 2>" + base + ".err";
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, ReadFile(base + ".out"),
          ReadFile(base + ".err")};
}

// Runs climbsim with an argument vector (no shell: arguments may hold quotes, backticks,
// `$(...)`, `;` or newlines, and reach climbsim as they are), in `cwd` when given, with
// stdout and stderr captured. Optional limits for the child: `file_size_limit_bytes` > 0 sets
// RLIMIT_FSIZE (a write past it fails with EFBIG, as on a full disk; SIGXFSZ is ignored).
inline CliResult RunClimbsimArgs(const std::vector<std::string>& args, const std::string& cwd = "",
                                 long file_size_limit_bytes = 0) {
  static int n = 0;
  const std::string base = TempDir() + "/cliv_" + std::to_string(n++);
  const std::string out = base + ".out", err = base + ".err";
  std::vector<std::string> argv_s{Climbsim()};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (!cwd.empty() && ::chdir(cwd.c_str()) != 0) ::_exit(126);
    if (std::freopen(out.c_str(), "w", stdout) == nullptr) ::_exit(126);
    if (std::freopen(err.c_str(), "w", stderr) == nullptr) ::_exit(126);
    if (file_size_limit_bytes > 0) {
      std::signal(SIGXFSZ, SIG_IGN);
      const rlimit lim{static_cast<rlim_t>(file_size_limit_bytes),
                       static_cast<rlim_t>(file_size_limit_bytes)};
      ::setrlimit(RLIMIT_FSIZE, &lim);
    }
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, ReadFile(out), ReadFile(err)};
}

// A robot that diverges: a 1e9 N·m/rad spring on a 1 g link. Its frequency sqrt(k/I) is
// ~1e8 rad/s against the explicit-Euler stability limit 2/dt (200 rad/s at 10 ms), so it
// blows up within a few steps and MuJoCo flags the bad acceleration (mjWARN_BADQACC).
inline constexpr const char* kUnstableRobotMjcf = R"(<mujoco>
  <compiler autolimits="true"/>
  <worldbody>
    <body name="base" pos="0 0 0.5"><freejoint name="root"/>
      <geom type="box" size="0.05 0.05 0.01" mass="0.1"/>
      <body pos="0.1 0 0"><joint name="spring" type="hinge" axis="0 1 0" stiffness="1e9"
        springref="1"/><geom type="capsule" fromto="0 0 0 0.05 0 0" size="0.005" mass="0.001"/>
      </body>
    </body>
  </worldbody>
</mujoco>)";

}  // namespace climbsim::testing

#endif  // CLIMBSIM_TESTS_COMMON_TEST_UTIL_H_
