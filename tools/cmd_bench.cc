// climbsim bench speed|accuracy|optimise|robustness SCENARIO: the options; the verbs run in
// experiments/bench_verbs.h.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "experiments/bench_verbs.h"
#include "tools/commands.h"
#include "tools/progress.h"

namespace climbsim::tools {
namespace {

// --families: comma-separated, spaces ignored.
std::vector<std::string> SplitFamilies(const std::string& families) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : families + ",") {
    if (c == ',') {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else if (c != ' ') {
      cur += c;
    }
  }
  return out;
}

void Print(const std::string& text) { std::fputs(text.c_str(), stdout); }

}  // namespace

void AddBenchCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("bench", "What accuracy costs in time, and what effects cost");
  cmd->require_subcommand(1);
  cmd->footer("Example:\n  climbsim bench speed examples/gecko_wall.yaml --duration 5");

  static std::string file, out_dir = "runs/bench";
  static double duration_s = 10.0, profile_from_s = 0.0;
  static int repetitions = 5, threads = 0, evaluations = 8;
  static std::vector<std::string> versus;

  auto* speed = cmd->add_subcommand("speed", "steps per second: bare mj_step against each effect");
  speed->add_option("scenario", file, "scenario file")->required();
  AddSetOption(speed);
  speed->add_option("--duration", duration_s, "simulated seconds per run")
      ->check(CLI::PositiveNumber);
  speed->add_option("--repetitions", repetitions, "runs per variant, interleaved")
      ->check(CLI::Range(1, 1000));
  speed->add_option("--profile-from", profile_from_s,
                    "simulated time at which the profile starts (e.g. a corner's trigger time "
                    "from summary.json); the steps before it run unprofiled")
      ->check(CLI::NonNegativeNumber);
  speed->add_option("--versus", versus,
                    "KEY=VALUE (repeatable): instead of the effect variants, compare the "
                    "scenario as written with the same scenario with these keys changed");
  speed->footer(
      "Examples:\n  climbsim bench speed examples/gecko_wall.yaml --duration 5\n"
      "  climbsim bench speed examples/gecko_wall.yaml --duration 5 --versus "
      "physics.integrator=implicit\n"
      "  climbsim bench speed examples/spider_floor_to_wall.yaml --duration 39 "
      "--profile-from 6.7");
  speed->callback([] {
    Print(versus.empty()
              ? optimise::RunBenchSpeed(file, duration_s, repetitions, profile_from_s)
              : optimise::RunBenchSpeedVersus(file, versus, duration_s, repetitions));
  });

  auto* accuracy =
      cmd->add_subcommand("accuracy", "error of the observables against wall time, per knob");
  accuracy->add_option("scenario", file, "scenario file")->required();
  AddSetOption(accuracy);
  accuracy->add_option("--duration", duration_s, "simulated seconds per run")
      ->check(CLI::PositiveNumber);
  accuracy->add_option("--threads", threads, "runs side by side (default: all cores)")
      ->check(CLI::Range(0, 1024));
  accuracy->add_option("--out", out_dir, "folder for accuracy.csv and accuracy.png");
  accuracy->footer(
      "Example:\n  climbsim bench accuracy examples/gecko_wall.yaml --duration 5 --out runs/acc");
  accuracy->callback(
      [] { Print(optimise::RunBenchAccuracy(file, duration_s, threads, out_dir)); });

  auto* opt = cmd->add_subcommand(
      "optimise", "evaluations per second with 1 and 2 threads (and 1 and 2 MPI ranks)");
  opt->add_option("scenario", file, "scenario file with an optimise block")->required();
  AddSetOption(opt);
  opt->add_option("--evaluations", evaluations, "evaluations per run")
      ->check(CLI::Range(2, 100000));
  opt->add_option("--out", out_dir, "folder for the two optimisation runs");
  static std::string only = "all";
  opt->add_option("--only", only, "threads: only the 1- and 2-thread runs; mpi: only the 1- and "
                  "2-rank runs")->check(CLI::IsMember({"all", "threads", "mpi"}));
  opt->footer(
      "Examples:\n  climbsim bench optimise examples/gecko_wall.yaml --evaluations 8\n"
      "  climbsim bench optimise examples/gecko_wall.yaml --evaluations 400 --only threads");
  opt->callback([] {
    // mpirun starts this executable.
    const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
    optimise::RunBenchOptimise(file, evaluations, out_dir, only, self, Print);
  });

  static optimise::RobustnessOptions robust;
  static std::string robust_out, families;
  auto* rob = cmd->add_subcommand(
      "robustness",
      "largest disturbance of each family survived, reflexes on and spindle + GTO off");
  rob->add_option("scenario", file, "scenario file")->required();
  AddSetOption(rob);
  rob->add_option("--out", robust_out,
                  "folder for robustness.csv, robustness.png and failing/: new, empty, or an earlier "
                  "bench folder (docs/run-folders.md)")
      ->required();
  rob->add_option("--duration", robust.duration_s, "simulated seconds per run (0: the scenario's)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  rob->add_option("--seeds", robust.seeds, "cases per magnitude (start jitter, random draws)")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  rob->add_option("--phases", robust.phases, "push times spread over one gait cycle")
      ->check(CLI::Range(1, 32))
      ->capture_default_str();
  // Given or not: not given, the default depends on the duration (optimise.h).
  static double push_time_s = 0.0;
  static CLI::Option* push_time = nullptr;
  push_time = rob->add_option(
      "--push-time", push_time_s,
      "first push [s], at most a third of the duration (default: 4, or a third if earlier)");
  rob->add_option("--families", families,
                  "comma-separated: push_off, push_down, push_side, payload, pad_failure, "
                  "weak_patch, roughness, terrain (default: all the scenario can take but terrain)");
  rob->add_option("--threads", robust.threads,
                  "runs side by side: every search's current magnitude's seeds and phases "
                  "(default: all cores)")
      ->check(CLI::Range(0, 1024));
  rob->footer(
      "Survived: no fall and at least half the undisturbed distance, in every seed (and push "
      "phase); bisection to 10 %.\nExample:\n  climbsim bench robustness examples/gecko_wall.yaml "
      "--duration 3 --seeds 1 --phases 1 --families push_down,pad_failure --out "
      "runs/robustness_quick");
  rob->callback([] {
    if (push_time->count() > 0) robust.push_time_s = push_time_s;
    robust.families = SplitFamilies(families);
    Progress bar("robustness");
    Print(optimise::RunBenchRobustness(file, robust, robust_out,
                                       [&](double f) { bar.Update(f); }));
  });
}

}  // namespace climbsim::tools
