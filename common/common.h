// climbsim::common, the module's one public header: the pieces every other MuJoCo-side module
// shares, each defined once. cpg and reflex do not use it (they know nothing of MuJoCo).
//
//   InputError         the one exception for bad input (exit code 2 in tools/)
//   CompileMjcfString  the program's one MJCF loader, serialised by one mutex
//   TempSiblingPath    a temporary name beside a file, unique across processes and threads
//   WriteFileAtomic    a file that is either complete or absent
//   Fnv1a64            FNV-1a 64 of bytes, chunk by chunk (guards accidents, not forgery)
//   RunProcess         a program run from an argument vector, never through a shell
//   Process            the same, running beside the caller, fed on its standard input
//   FindInPath         where PATH finds a program ("" when nowhere)
//   RunGnuplot         plots drawn by gnuplot into files that are complete or absent
//   GnuplotQuote       any text as an inert gnuplot string literal
//   ParallelFor        tasks on worker threads; a worker's exception reaches the caller
//
// common/README.md is the overview. Nothing here runs inside a step loop.
#ifndef CLIMBSIM_COMMON_COMMON_H_
#define CLIMBSIM_COMMON_COMMON_H_

#include <mujoco/mujoco.h>
#include <sys/types.h>

#include <cstdint>
#include <functional>
#include <string_view>
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

// FNV-1a 64 of `bytes`, continuing from `hash`: hashing chunks one after the other gives the
// hash of their concatenation. A check against accidental change, not a cryptographic hash.
inline constexpr uint64_t kFnv1a64Basis = 14695981039346656037ull;
uint64_t Fnv1a64(std::string_view bytes, uint64_t hash = kFnv1a64Basis);

// ---- Child processes. No text ever reaches a shell: a program gets its arguments as they
// are (quotes, backticks, `$(...)`, `;`, newlines included), found by PATH like execvp.

// Where a child's standard streams go and where it starts.
struct ProcessOptions {
  std::string working_dir{};              // "": the caller's
  std::string stdout_path = "/dev/null";  // "": the caller's standard output
  std::string stderr_path{};              // a file (truncated); "": the caller's standard error
  bool stdin_pipe = false;                // Process::Write feeds it; else /dev/null
};

// A program started by posix_spawnp from `argv` (argv[0] looked up in PATH), running beside
// the caller. Throws std::runtime_error when it cannot start (not installed, working_dir
// missing). The destructor closes the child's input and waits for it.
class Process {
 public:
  Process(const std::vector<std::string>& argv, const ProcessOptions& options);
  ~Process();
  Process(const Process&) = delete;
  Process& operator=(const Process&) = delete;

  // Writes to the child's standard input (options.stdin_pipe); false when the child stopped
  // reading (it exited). Never raises SIGPIPE.
  bool Write(const void* data, size_t size);
  // Closes the child's input and waits for it: "" when it exited with status 0, else what
  // happened ("ffmpeg exited with status 1", "gnuplot was killed by signal 9 (Killed)").
  std::string Wait();

 private:
  std::string name_;
  pid_t pid_ = -1;
  int stdin_ = -1;
  std::string result_;
};

// Runs `argv` to its end (Process, then Wait). Returns "" on exit status 0, else what went
// wrong, a failure to start included ("cannot start mpirun: No such file or directory").
std::string RunProcess(const std::vector<std::string>& argv, const ProcessOptions& options = {});

// The full path of the executable `program` (a bare name) in PATH; "" when it is not there.
std::string FindInPath(const std::string& program);

// ---- gnuplot. A script is climbsim's own text: user text (a folder, a scenario's name, a
// CSV field) enters it only through GnuplotQuote, and no path at all: gnuplot runs inside
// the output folder, where the script names its files by plain names that climbsim chose.

// Runs `script` with gnuplot (Debian's gnuplot-nox) in `folder`, its working folder. In the
// script, write `set output OUTPUT(k)` for the k-th of `outputs` (plain names of files in
// `folder`): it becomes a temporary name in a private subfolder, renamed to the output only
// when gnuplot exited with status 0 and the file is whole (a PNG to its IEND chunk, an SVG to
// `</svg>`; a full disk leaves a short file). Returns "" on success, else the cause (gnuplot
// missing, its error output, the short file); then no output and no temporary is left.
std::string RunGnuplot(const std::string& folder, const std::string& script,
                       const std::vector<std::string>& outputs);

// `s` as a gnuplot string expression, inert whatever it holds: single-quoted runs (gnuplot
// expands backticks only inside double quotes; a backslash there is literal) joined by "'"
// for each quote, every control character as a space (a newline would end the command).
// Valid wherever gnuplot takes a string: 'it'."'".'s'. A text without quotes is one literal.
std::string GnuplotQuote(const std::string& s);

// Runs task(0) .. task(count - 1) on `threads` threads (the caller's among them; at least
// one, at most `count`). Tasks are handed out in index order. When a task throws, no further
// task starts, the running ones finish, and the exception of the lowest-index task that threw
// is rethrown here: the same error whatever the thread count, and never std::terminate.
void ParallelFor(int count, int threads, const std::function<void(int task)>& task);

}  // namespace climbsim::common

#endif  // CLIMBSIM_COMMON_COMMON_H_
