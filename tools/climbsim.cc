// climbsim: simulate, optimise and inspect bio-inspired climbing robots.
// Exit codes: 0 ok, 1 a run failed (numerically unstable), 2 bad input.
#include <mujoco/mujoco.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "common/common.h"
#include "sim/sim.h"
#include "tools/commands.h"

namespace {

// MuJoCo's fatal errors (e.g. its arena is exhausted) would otherwise exit(1) silently.
void MujocoError(const char* msg) {
  std::fprintf(stderr, "climbsim: MuJoCo error: %s\n", msg);
  std::exit(1);
}

}  // namespace

int main(int argc, char** argv) {
  mju_user_error = MujocoError;
  // MuJoCo's warnings go to climbsim's reports (a run's failure), not to MUJOCO_LOG.TXT.
  climbsim::sim::InstallMujocoHandlers();
  CLI::App app{"climbsim: simulate, optimise and inspect bio-inspired climbing robots"};
  app.require_subcommand(1);
  app.footer(
      "Example:\n  climbsim simulate examples/gecko_floor.yaml --out runs/gecko_floor\n"
      "Exit codes: 0 ok, 1 failed run, 2 bad input.");
  climbsim::tools::AddSimulateCommand(app);
  climbsim::tools::AddOptimiseCommand(app);
  climbsim::tools::AddSweepCommand(app);
  climbsim::tools::AddBenchCommand(app);
  climbsim::tools::AddPulloffCommand(app);
  climbsim::tools::AddFitAdhesionCommand(app);
  climbsim::tools::AddInspectCommand(app);
  climbsim::tools::AddRenderCommand(app);
  climbsim::tools::AddModelCommand(app);
  climbsim::tools::AddKeysCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  } catch (const climbsim::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "climbsim: %s\n", e.what());
    return 1;
  }
  return climbsim::tools::ExitCode();
}
