// climbsim keys: every scenario key as a Markdown table (the source of docs/scenario.md).
#include <cstdio>

#include "sim/sim.h"
#include "tools/commands.h"

namespace climbsim::tools {

void AddKeysCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("keys", "List every scenario key with unit, default, meaning");
  cmd->footer("Example:\n  climbsim keys");
  cmd->callback([] {
    std::fputs(sim::ScenarioKeysMarkdown().c_str(), stdout);
  });
}

}  // namespace climbsim::tools
