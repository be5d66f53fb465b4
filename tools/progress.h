// Progress on stderr: a bar redrawn in place on a terminal, a plain line every 10 %
// otherwise (logs and CI stay readable).
#ifndef CLIMBSIM_TOOLS_PROGRESS_H_
#define CLIMBSIM_TOOLS_PROGRESS_H_

#include <unistd.h>

#include <cstdio>
#include <string>

namespace climbsim::tools {

class Progress {
 public:
  explicit Progress(std::string label, bool enabled = true)
      : label_(std::move(label)), enabled_(enabled), tty_(isatty(STDERR_FILENO) == 1) {}

  // fraction in [0, 1]; `note` is shown after the bar (e.g. "best 0.031 m/s").
  void Update(double fraction, const char* note = "") {
    if (!enabled_) return;
    const int percent = static_cast<int>(fraction * 100.0 + 1e-9);
    if (tty_) {
      const int width = 30, filled = static_cast<int>(fraction * width);
      std::string bar(filled, '#');
      bar.resize(width, '.');
      std::fprintf(stderr, "\r%s [%s] %3d%% %s", label_.c_str(), bar.c_str(), percent, note);
      if (fraction >= 1.0) std::fprintf(stderr, "\n");
      std::fflush(stderr);
    } else if (percent / 10 > last_decile_) {
      last_decile_ = percent / 10;
      std::fprintf(stderr, "%s: %d%%%s%s\n", label_.c_str(), last_decile_ * 10, *note ? " " : "",
                   note);
    }
  }

 private:
  std::string label_;
  bool enabled_;
  bool tty_;
  int last_decile_ = 0;
};

}  // namespace climbsim::tools

#endif  // CLIMBSIM_TOOLS_PROGRESS_H_
