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

// --set KEY=VALUE (repeatable) on a verb that reads scenario files (tools/scenario_flags.cc):
// replaces a dotted key (cpg.frequency_hz, cpg.stride_rad[0]) in every scenario file the
// verb reads, before anything runs; checked as the file's own, a refusal names the flag.
void AddSetOption(CLI::App* cmd);

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
