// climbsim simulate SCENARIO --out DIR
#include <cstdio>

#include "experiments/experiments.h"
#include "sim/servo_margin.h"
#include "sim/sim.h"
#include "tools/commands.h"
#include "tools/progress.h"

namespace climbsim::tools {

int& ExitCode() {
  static int code = 0;
  return code;
}

namespace {

void PrintSummary(const nlohmann::json& s, const std::string& dir) {
  std::printf("climbsim simulate: %s on %s, %.2f s simulated in %.2f s (%.1fx real time)\n",
              s["robot"].get<std::string>().c_str(), s["scene"].get<std::string>().c_str(),
              s["duration_s"].get<double>(), s["wall_time_s"].get<double>(),
              s["realtime_factor"].get<double>());
  std::printf("  distance        %.4f m along the travel direction\n",
              s["distance_m"].get<double>());
  std::printf("  mean speed      %.4f m/s\n", s["mean_speed_mps"].get<double>());
  std::printf("  heading         %.1f deg\n", s["heading_deg"].get<double>());
  if (s["fell"].get<bool>()) {
    const std::string cause = s["fall_cause"].get<std::string>();
    std::printf("  fell            yes, at %.3f s (%s)%s\n", s["fall_time_s"].get<double>(),
                cause == "dropped" ? "its base dropped fall.drop_m below the highest point it reached"
                : cause == "left_surface"
                    ? "nothing of it touched or held the surface for fall.airborne_s"
                    : "its base turned over past fall.turn_over_deg",
                s["fall_stopped_run"].get<bool>() ? "; the run ended there" : "");
    std::printf("                  (distance, speed and heading are those up to the fall)\n");
  } else {
    std::printf("  fell            no\n");
  }
  if (s.value("stalled", false)) {
    std::printf("  STALLED         from %.3f s to the end, held by %s: %s\n",
                s["stall_time_s"].get<double>(), s["stall_leg"].get<std::string>().c_str(),
                s["stall_reason"].get<std::string>().c_str());
  }
  std::string effects;
  for (const auto& e : s["effects"])
    effects += (effects.empty() ? "" : ", ") + e.get<std::string>();
  std::printf("  effects         %s\n", effects.empty() ? "(none)" : effects.c_str());
  if (s.contains("objective")) {
    std::printf("  objective       %.17g m/s (optimise cost of this run)\n",
                s["objective"].get<double>());
  }
  if (!s["stable"].get<bool>()) {
    std::printf("  UNSTABLE        %s\n", s["failure"].get<std::string>().c_str());
  }
  std::printf(
      "  outputs         %s/{scenario.yaml,model.xml,trajectory.csv,events.csv,summary.json}\n",
      dir.c_str());
}

// The servo margins on the terminal: the worst servo, and a warning per servo over its rating.
void PrintServoMargins(const sim::ServoMargins& margins) {
  const sim::ServoHold* worst = margins.Worst();
  if (worst == nullptr) return;
  std::printf("  servos          %.1f g robot; worst %s holds %.4f N m of its %.4f rated (%.0f %%) "
              "in stance %s\n",
              1e3 * margins.mass_kg, worst->name.c_str(), worst->holding_torque_nm,
              worst->rated_torque_nm, 100.0 * worst->load_fraction(), worst->stance.c_str());
}

void WarnServoMargins(const sim::ServoMargins& margins, bool strict) {
  for (const std::string& s : margins.Overloaded()) {
    std::fprintf(stderr, "climbsim simulate: %s: servo %s of its rating (half its stall torque) "
                 "holding the robot in a stance set of its gait\n",
                 strict ? "error" : "warning", s.c_str());
  }
}

}  // namespace

void AddSimulateCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("simulate", "Simulate a gait from a scenario file");
  static std::string scenario_path, out_dir;
  static bool quiet = false, force = false, keep = false, strict = false;
  cmd->add_option("scenario", scenario_path, "scenario file (YAML; keys in docs/scenario.md)")
      ->required();
  cmd->add_option("--out", out_dir,
                  "run folder to write: new, empty, or (with --force) an earlier climbsim run "
                  "folder (docs/run-folders.md)")
      ->required();
  cmd->add_flag("--force", force,
                "replace the earlier climbsim run folder at --out (deleting only its own files)");
  cmd->add_flag("--keep-other-files", keep,
                "with --force: carry files climbsim did not write (notes, added folders) into "
                "the new run folder instead of refusing (docs/run-folders.md)");
  cmd->add_flag("--quiet", quiet, "no progress and no summary on the terminal");
  AddSetOption(cmd);
  cmd->add_flag("--strict", strict,
                "exit 2 before the run when a servo holds more than its rating (half its stall "
                "torque) in a stance set of the gait (docs/climbing.md, \"Servo margins\")");
  cmd->footer("Example:\n  climbsim simulate examples/gecko_floor.yaml --out runs/gecko_floor");
  cmd->callback([] {
    const sim::Scenario scenario = sim::LoadScenario(scenario_path);
    // The run's own checks (its size among them) before the statics, which step the model too.
    const auto model = sim::CompileScenario(scenario);
    sim::Simulation run(scenario, *model);
    // The statics next: --strict refuses an overloaded robot before anything is written.
    const sim::ServoMargins margins = sim::MeasureServoMargins(scenario);
    WarnServoMargins(margins, strict);
    if (strict && !margins.Overloaded().empty()) {
      ExitCode() = 2;
      return;
    }
    // The folder is checked and locked before anything runs; the run appears there whole.
    sim::RunFolder folder(out_dir, {.made_by = "simulate",
                                    .force = force,
                                    .keep_other_files = keep,
                                    .inputs = sim::ScenarioInputs(scenario)});
    Progress progress("simulate", !quiet);
    const sim::RunResult r = run.Run([&](double f) { progress.Update(f); });
    // A scenario with an optimise block (best.yaml) also reports the cost the optimiser saw.
    nlohmann::json extra = nlohmann::json::object();
    extra["servo_margins"] = margins.ToJson();
    if (scenario.optimise) extra["objective"] = optimise::NominalCost(run).total;
    sim::WriteRunFiles(folder.path(), run, extra);
    folder.Commit();
    if (!quiet) {
      nlohmann::json summary = run.Summary();
      summary.update(extra);
      PrintSummary(summary, out_dir);
      PrintServoMargins(margins);
    }
    if (!r.stable) {
      std::fprintf(stderr, "climbsim simulate: the run went numerically bad: %s\n",
                   r.failure.c_str());
      ExitCode() = 1;
    }
  });
}

}  // namespace climbsim::tools
