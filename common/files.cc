#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "common/common.h"

namespace climbsim::common {
namespace {

namespace fs = std::filesystem;

// The message of a failed write: the file the user asked for, and the cause by name
// ("cannot write runs/x/summary.json: No space left on device").
std::runtime_error WriteError(const std::string& path, int error) {
  return std::runtime_error("cannot write " + path + ": " + std::strerror(error));
}

// Writes all of `content` to `fd` (write may write less than asked); 0 or the errno.
int WriteAll(int fd, const std::string& content) {
  const char* p = content.data();
  size_t left = content.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return errno;
    if (n == 0) return EIO;
    p += n;
    left -= static_cast<size_t>(n);
  }
  return 0;
}

}  // namespace

uint64_t Fnv1a64(std::string_view bytes, uint64_t hash) {
  for (unsigned char c : bytes) hash = (hash ^ c) * 1099511628211ull;  // the FNV 64 prime
  return hash;
}

std::string TempSiblingPath(const std::string& path) {
  static std::atomic<long> counter{0};
  const fs::path p(path);
  const std::string tag = std::to_string(::getpid()) + "_" + std::to_string(counter++);
  return (p.parent_path() / (p.stem().string() + ".tmp." + tag + p.extension().string()))
      .string();
}

// POSIX calls, each checked: a full disk shows at write, fsync or close, and its cause is kept.
void WriteFileAtomic(const std::string& path, const std::string& content) {
  const std::string tmp = TempSiblingPath(path);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) throw WriteError(path, errno);
  int error = WriteAll(fd, content);
  if (error == 0 && ::fsync(fd) != 0) error = errno;
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error == 0 && ::rename(tmp.c_str(), path.c_str()) != 0) error = errno;
  if (error != 0) {
    ::unlink(tmp.c_str());
    throw WriteError(path, error);
  }
}

}  // namespace climbsim::common
