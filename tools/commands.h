// The verbs of the climbsim executable. Each Add*Command registers its options on the app
// and sets the callback that runs it; a callback returns the process exit code through
// ExitCode (0 ok, 1 failed run, 2 bad input).
#ifndef CLIMBSIM_TOOLS_COMMANDS_H_
#define CLIMBSIM_TOOLS_COMMANDS_H_

#include <CLI/CLI.hpp>

#include "experiments/option_ranges.h"

namespace climbsim::tools {

// The CLI11 check of a range the library declares (experiments/option_ranges.h).
template <class T>
CLI::Range InRange(const optimise::OptionRange<T>& range) {
  return CLI::Range(range.lo, range.hi);
}

// Exit code the chosen verb asked for.
int& ExitCode();

void AddSimulateCommand(CLI::App& app);
void AddKeysCommand(CLI::App& app);
void AddOptimiseCommand(CLI::App& app);
void AddSweepCommand(CLI::App& app);
void AddBenchCommand(CLI::App& app);
void AddPulloffCommand(CLI::App& app);
void AddFitAdhesionCommand(CLI::App& app);
void AddInspectCommand(CLI::App& app);
void AddRenderCommand(CLI::App& app);
void AddModelCommand(CLI::App& app);

}  // namespace climbsim::tools

#endif  // CLIMBSIM_TOOLS_COMMANDS_H_
