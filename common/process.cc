#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "common/common.h"

extern char** environ;

namespace climbsim::common {

std::string FindInPath(const std::string& program) {
  if (program.empty() || program.find('/') != std::string::npos) return "";
  const char* path = std::getenv("PATH");
  std::string dirs = path != nullptr ? path : "/usr/bin:/bin";
  for (size_t start = 0; start <= dirs.size();) {
    size_t end = dirs.find(':', start);
    if (end == std::string::npos) end = dirs.size();
    // An empty entry is the current folder (POSIX).
    const std::string dir = end > start ? dirs.substr(start, end - start) : ".";
    const std::string candidate = dir + "/" + program;
    struct stat st {};
    if (::stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
        ::access(candidate.c_str(), X_OK) == 0) {
      return candidate;
    }
    start = end + 1;
  }
  return "";
}

namespace {

// posix_spawn's file actions, freed on every path out.
struct FileActions {
  posix_spawn_file_actions_t actions;
  FileActions() { posix_spawn_file_actions_init(&actions); }
  ~FileActions() { posix_spawn_file_actions_destroy(&actions); }
};

std::string Errno(int error) { return std::strerror(error); }

}  // namespace

Process::Process(const std::vector<std::string>& argv, const ProcessOptions& options)
    : name_(argv.empty() ? "" : argv[0]) {
  if (argv.empty()) throw std::runtime_error("no program to run");
  FileActions fa;
  int ours = -1;
  if (options.stdin_pipe) {
    // A socket, not a pipe: send() with MSG_NOSIGNAL reports a dead reader as EPIPE instead
    // of raising SIGPIPE in the whole process.
    int fds[2];
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) {
      throw std::runtime_error("cannot start " + name_ + ": " + Errno(errno));
    }
    ours = fds[0];
    posix_spawn_file_actions_adddup2(&fa.actions, fds[1], STDIN_FILENO);
    stdin_ = fds[1];  // closed below, once the child holds it
  } else {
    posix_spawn_file_actions_addopen(&fa.actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  }
  const int out_flags = O_WRONLY | O_CREAT | O_TRUNC;
  if (!options.stdout_path.empty()) {
    posix_spawn_file_actions_addopen(&fa.actions, STDOUT_FILENO, options.stdout_path.c_str(),
                                     out_flags, 0644);
  }
  if (!options.stderr_path.empty()) {
    posix_spawn_file_actions_addopen(&fa.actions, STDERR_FILENO, options.stderr_path.c_str(),
                                     out_flags, 0644);
  }
  if (!options.working_dir.empty()) {
    posix_spawn_file_actions_addchdir_np(&fa.actions, options.working_dir.c_str());
  }
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const int error = ::posix_spawnp(&pid_, args[0], &fa.actions, nullptr, args.data(), environ);
  if (stdin_ >= 0) ::close(stdin_);
  stdin_ = ours;
  if (error != 0) {
    pid_ = -1;
    if (stdin_ >= 0) ::close(stdin_);
    stdin_ = -1;
    throw std::runtime_error("cannot start " + name_ + ": " + Errno(error));
  }
}

Process::~Process() { Wait(); }

bool Process::Write(const void* data, size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0 && stdin_ >= 0) {
    const ssize_t n = ::send(stdin_, p, size, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    size -= static_cast<size_t>(n);
  }
  return size == 0;
}

std::string Process::Wait() {
  if (stdin_ >= 0) ::close(stdin_);
  stdin_ = -1;
  if (pid_ < 0) return result_;
  int status = 0;
  pid_t got;
  do {
    got = ::waitpid(pid_, &status, 0);
  } while (got < 0 && errno == EINTR);
  pid_ = -1;
  if (got < 0) {
    result_ = name_ + ": cannot wait for it: " + Errno(errno);
  } else if (WIFEXITED(status) && WEXITSTATUS(status) != 0) {
    result_ = name_ + " exited with status " + std::to_string(WEXITSTATUS(status));
  } else if (WIFSIGNALED(status)) {
    result_ = name_ + " was killed by signal " + std::to_string(WTERMSIG(status)) + " (" +
              strsignal(WTERMSIG(status)) + ")";
  }
  return result_;
}

std::string RunProcess(const std::vector<std::string>& argv, const ProcessOptions& options) {
  try {
    Process child(argv, options);
    return child.Wait();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
}

}  // namespace climbsim::common
