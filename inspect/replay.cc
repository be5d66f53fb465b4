// An optimise results folder: best.yaml replayed once into best_run.
#include <filesystem>

#include "inspect/inspect.h"
#include "sim/sim.h"

namespace climbsim::inspect {

std::string ReplayBest(const std::string& results_dir, bool* replayed,
                       const std::function<void(double)>& progress) {
  namespace fs = std::filesystem;
  const fs::path best = fs::path(results_dir) / "best.yaml";
  const fs::path out = fs::path(results_dir) / "best_run";
  *replayed = false;
  std::error_code ec;
  const fs::path summary = out / "summary.json";
  if (fs::exists(summary, ec) &&
      fs::last_write_time(summary, ec) >= fs::last_write_time(best, ec) && !ec) {
    return out.string();
  }
  // Same as `climbsim simulate best.yaml --out DIR/best_run`: the optimiser's best, bit for bit.
  const sim::Scenario scenario = sim::LoadScenario(best.string());
  // best_run is climbsim's own: replaced whole (and refused if something else is there).
  sim::RunFolder folder(
      out.string(),
      {.made_by = "simulate", .force = true, .inputs = sim::ScenarioInputs(scenario)});
  const auto model = sim::CompileScenario(scenario);
  sim::Simulation run(scenario, *model);
  run.Run(progress);
  sim::WriteRunFiles(folder.path(), run);
  folder.Commit();
  *replayed = true;
  return out.string();
}

}  // namespace climbsim::inspect
