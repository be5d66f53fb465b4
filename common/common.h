// climbsim::common, the module's one public header: the pieces every other MuJoCo-side module
// shares, each defined once. cpg and reflex do not use it (they know nothing of MuJoCo).
//
//   InputError         the one exception for bad input (exit code 2 in tools/)
//   CompileMjcfString  the program's one MJCF loader, serialised by one mutex
//   TempSiblingPath    a temporary name beside a file, unique across processes and threads
//   WriteFileAtomic    a file that is either complete or absent
//   RunGnuplot         plots drawn by gnuplot into files that are complete or absent
//   ParallelFor        tasks on worker threads; a worker's exception reaches the caller
//
// common/README.md is the overview. Nothing here runs inside a step loop.
#ifndef CLIMBSIM_COMMON_COMMON_H_
#define CLIMBSIM_COMMON_COMMON_H_

#include <mujoco/mujoco.h>

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace climbsim {

// climbsim::InputError: the one exception for bad input (scenario files, command-line
// values, run directories). Library code throws it; only tools/ catches it, prints what()
// and exits with code 2. The message always starts with the place: "file:line:col: key: ...".
class InputError : public std::runtime_error {
 public:
  // line and column are 1-based; 0 means "not known" and is left out of the message.
  InputError(const std::string& file, int line, int column, const std::string& key,
             const std::string& message)
      : std::runtime_error(Format(file, line, column, key, message)),
        file_(file),
        line_(line),
        column_(column),
        key_(key),
        message_(message) {}

  const std::string& file() const { return file_; }
  int line() const { return line_; }
  int column() const { return column_; }
  const std::string& key() const { return key_; }
  const std::string& message() const { return message_; }  // without the place

 private:
  static std::string Format(const std::string& file, int line, int column,
                            const std::string& key, const std::string& message) {
    std::string s = file;
    if (line > 0) s.append(":").append(std::to_string(line));
    if (line > 0 && column > 0) s.append(":").append(std::to_string(column));
    s.append(": ");
    if (!key.empty()) s.append(key).append(": ");
    s.append(message);
    return s;
  }

  std::string file_;
  int line_;
  int column_;
  std::string key_;
  std::string message_;
};

}  // namespace climbsim

namespace climbsim::common {

// Compiles MJCF text through an in-memory file (includes by absolute path). Returns nullptr
// and fills `error` on failure. MuJoCo 2.2.2's XML loader keeps process-wide state: every
// load of the program goes through here, serialised by one mutex (docs/mujoco.md).
mjModel* CompileMjcfString(const std::string& xml, std::string* error);

// "<folder>/<stem>.tmp.<pid>_<n><extension>" beside `path`: the same folder (so a rename is
// atomic), the same extension (viewers and encoders look at it), unique across processes
// (the process id) and across threads of one process (a counter).
std::string TempSiblingPath(const std::string& path);

// Writes `content` to a temporary sibling (TempSiblingPath) and renames it to `path`, so
// `path` is either the old file or the whole new one. Throws std::runtime_error (disk full,
// no permission); the temporary file is then removed.
void WriteFileAtomic(const std::string& path, const std::string& content);

// Runs `script` with gnuplot (Debian's gnuplot-nox), as a child process. In the script,
// write `set output OUTPUT(k)` for the k-th file of `outputs` (it is replaced by the quoted
// temporary name of that file, renamed when gnuplot succeeds). Returns "" on success, else
// what went wrong (gnuplot missing, gnuplot's error output); the outputs are then absent.
std::string RunGnuplot(const std::string& script, const std::vector<std::string>& outputs);

// Escapes a string for a gnuplot double-quoted string.
std::string GnuplotQuote(const std::string& s);

// Runs task(0) .. task(count - 1) on `threads` threads (the caller's among them; at least
// one, at most `count`). Tasks are handed out in index order. When a task throws, no further
// task starts, the running ones finish, and the exception of the lowest-index task that threw
// is rethrown here: the same error whatever the thread count, and never std::terminate.
void ParallelFor(int count, int threads, const std::function<void(int task)>& task);

}  // namespace climbsim::common

#endif  // CLIMBSIM_COMMON_COMMON_H_
