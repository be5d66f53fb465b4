// climbsim bench speed|accuracy|optimise|robustness SCENARIO
#include <algorithm>
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "common/common.h"
#include "experiments/experiments.h"
#include "sim/sim.h"
#include "tools/commands.h"
#include "tools/progress.h"

namespace climbsim::tools {
namespace {

void Speed(const std::string& file, double duration_s, int repetitions, double profile_from_s) {
  if (profile_from_s >= duration_s) {
    throw InputError("climbsim bench speed", 0, 0, "--profile-from",
                     "must be less than --duration (" + std::to_string(duration_s) + " s)");
  }
  const sim::Scenario s = sim::LoadScenario(file);
  const sim::SpeedReport r = sim::BenchSpeed(s, duration_s, repetitions, profile_from_s);
  std::printf("climbsim bench speed: %s, %ld steps per run, %d repetitions, interleaved\n",
              file.c_str(), r.steps, r.repetitions);
  std::printf("  %-16s %14s %12s %s\n", "variant", "steps/s", "vs bare", "(median; each run)");
  for (const auto& v : r.variants) {
    std::printf("  %-16s %14.0f %+11.1f%%  (", v.name.c_str(), v.median_steps_per_s,
                100 * v.overhead);
    for (size_t k = 0; k < v.steps_per_s.size(); ++k) {
      std::printf("%s%.0f", k ? " " : "", v.steps_per_s[k]);
    }
    std::printf(")\n");
  }
  double effects = 0.0;
  for (const auto& e : r.effect_s) effects += e.second;
  if (r.profile_from_s > 0) {
    std::printf("  profile of the full scenario from %g s (%ld steps; time inside each part of "
                "the step):\n", r.profile_from_s, r.profiled_steps);
  } else {
    std::printf("  profile of the full scenario (time inside each part of the step):\n");
  }
  // Names as wide as the longest one (the controller's: cpg+reflex+transition).
  int w = 14;
  for (const auto& e : r.effect_s) w = std::max(w, static_cast<int>(e.first.size()));
  std::printf("    %-*s %9.3f s\n", w, "mj_step", r.mj_step_s);
  for (const auto& e : r.effect_s) {
    std::printf("    %-*s %9.3f s  %+6.2f%% of mj_step\n", w, e.first.c_str(), e.second,
                100 * e.second / r.mj_step_s);
  }
  std::printf("    %-*s %9.3f s  %+6.2f%% of mj_step\n", w, "monitor", r.monitor_s,
              100 * r.monitor_s / r.mj_step_s);
  std::printf("    %-*s %9.3f s  %+6.2f%% of mj_step\n", w, "all effects", effects,
              100 * effects / r.mj_step_s);
}

// `--versus KEY=VALUE ...`: the scenario as written (A) against the same scenario with those
// keys changed (B), every effect on, interleaved.
void SpeedVersus(const std::string& file, const std::vector<std::string>& versus,
                 double duration_s, int repetitions) {
  const sim::Scenario a = sim::LoadScenario(file);
  YAML::Node tree = sim::LoadYamlFile(file);
  std::string label;
  for (const std::string& kv : versus) {
    const size_t eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw InputError("--versus", 0, 0, kv,
                       "expected KEY=VALUE, e.g. physics.integrator=implicit");
    }
    try {
      optimise::SetDottedKeyText(tree, kv.substr(0, eq), kv.substr(eq + 1));
    } catch (const std::invalid_argument& e) {
      throw InputError("--versus", 0, 0, kv, e.what());
    }
    label += (label.empty() ? "" : " ") + kv;
  }
  const sim::Scenario b = sim::ParseScenario(tree, file + " with --versus " + label);
  const sim::SpeedComparison c = sim::BenchSpeedCompare(a, b, duration_s, repetitions);
  std::printf("climbsim bench speed: %s, every effect on, %d repetitions, interleaved A B A B\n",
              file.c_str(), repetitions);
  std::printf("  %-3s %-44s %12s %10s %s\n", "", "setting", "steps/s", "distance", "(each run)");
  auto side = [](const char* name, const std::string& what, const sim::SpeedComparison::Side& s) {
    std::printf("  %-3s %-44s %12.0f %9.4fm%s (", name, what.c_str(), s.median_steps_per_s,
                s.distance_m, s.fell ? " fell" : (s.stable ? "" : " unstable"));
    for (size_t k = 0; k < s.steps_per_s.size(); ++k) {
      std::printf("%s%.0f", k ? " " : "", s.steps_per_s[k]);
    }
    std::printf(")\n");
  };
  side("A", "as written", c.a);
  side("B", label, c.b);
  std::printf("  A runs %.2fx the steps/s of B (%ld vs %ld steps per run)\n", c.ratio, c.a.steps,
              c.b.steps);
}

void Accuracy(const std::string& file, double duration_s, int threads, const std::string& out) {
  // A run folder (docs/run-folders.md), checked before the runs; an earlier bench's replaced.
  sim::RunFolder folder(out, {.made_by = "bench accuracy",
                              .force = sim::RunFolderMadeBy(out) == "bench accuracy",
                              .inputs = {file}});
  const optimise::AccuracyReport r = optimise::BenchAccuracy(file, duration_s, threads);
  const std::string warning = optimise::WriteAccuracy(folder.path(), r);
  folder.Commit();
  std::printf("climbsim bench accuracy: %s, %.1f s simulated per run\n", file.c_str(),
              r.duration_s);
  std::printf("  reference (finest of every knob): %.4f m climbed in %.2f s wall%s\n",
              r.reference.distance_m, r.reference.wall_s, r.reference.fell ? ", fell" : "");
  std::printf("  %-18s %-14s %8s %12s %12s %6s %10s %10s\n", "knob", "setting", "wall [s]",
              "dist err [m]", "detach [s]", "n diff", "peak load", "pull-off");
  for (const auto& row : r.rows) {
    std::printf("  %-18s %-14s %8.2f %12.2e %12.2e %6d %10.2e %10.2e%s\n", row.knob.c_str(),
                row.setting.c_str(), row.run.wall_s, row.distance_error_m,
                row.detach_time_error_s, row.detach_count_diff, row.peak_load_error,
                row.pulloff_error, row.run.fell ? "  fell" : "");
  }
  std::printf("  outputs %s/{accuracy.csv,accuracy.png}%s%s\n", out.c_str(),
              warning.empty() ? "" : "  plot: ", warning.c_str());
}

// CPU seconds (user + system) of this process and, separately, of the children it waited for.
double CpuSeconds(int who) {
  rusage u{};
  getrusage(who, &u);
  return u.ru_utime.tv_sec + 1e-6 * u.ru_utime.tv_usec + u.ru_stime.tv_sec +
         1e-6 * u.ru_stime.tv_usec;
}

double LoadAverage() {
  double load = 0.0;
  std::ifstream("/proc/loadavg") >> load;
  return load;
}

// The options of one of bench optimise's runs in `dir`: an earlier bench's run is replaced
// whole, anything else a user has there is refused.
sim::RunFolderOptions BenchRunFolder(const std::string& dir, const std::string& file) {
  return {
      .made_by = "optimise", .force = sim::RunFolderMadeBy(dir) == "optimise", .inputs = {file}};
}

// One MPI run: `climbsim optimise` under mpirun, from an argument vector (no shell). Returns
// "" or why it failed.
std::string MpiRun(const std::string& file, int evaluations, const std::string& dir, int ranks) {
  std::vector<std::string> argv = {"mpirun", "-np", std::to_string(ranks), "--oversubscribe"};
  // Open MPI refuses root unless told (containers and CI often run as root).
  if (geteuid() == 0) argv.push_back("--allow-run-as-root");
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  argv.insert(argv.end(), {self, "optimise", file, "--out", dir, "--max-evaluations",
                           std::to_string(evaluations), "--threads", "1", "--quiet"});
  if (BenchRunFolder(dir, file).force) argv.push_back("--force");  // an earlier bench's run
  return common::RunProcess(argv, {.stdout_path = ""});
}

// Evaluations per second of `climbsim optimise` with 1 and 2 threads on a short budget, and
// with 1 and 2 MPI ranks of one thread each when built with MPI and mpirun is on the PATH.
// Each run also reports the CPU seconds it took (all threads, or all ranks) and the load
// average when it ended: on a shared machine the wall time says little without them.
void OptimiseSpeed(const std::string& file, int evaluations, const std::string& out,
                   const std::string& only) {
  // The scenario and every output folder are checked before any work (and before anything in
  // a folder is replaced): bad input is exit 2 here, not a failed mpirun later.
  optimise::Problem problem(file);
  for (const char* sub : {"threads1", "threads2", "mpi1", "mpi2"}) {
    const std::string dir = out + "/" + sub;
    sim::CheckOutputFolder(dir, BenchRunFolder(dir, file));
  }
  std::printf("climbsim bench optimise: %s, %d evaluations\n", file.c_str(), evaluations);
  if (only != "mpi") {
    double rate[2] = {0, 0};
    for (int threads : {1, 2}) {
      optimise::Options o;
      o.out_dir = out + "/threads" + std::to_string(threads);
      o.force = BenchRunFolder(o.out_dir, file).force;  // an earlier bench's run
      o.threads = threads;
      o.max_evaluations = evaluations;
      const double cpu0 = CpuSeconds(RUSAGE_SELF);
      const optimise::Result r = optimise::Optimise(file, o);
      const double cpu = CpuSeconds(RUSAGE_SELF) - cpu0;
      rate[threads - 1] = r.evaluations_computed / r.wall_time_s;
      std::printf("  --threads %d: %.2f evaluations/s (%d in %.1f s, CPU %.1f s, load %.1f), "
                  "best J %.6f\n",
                  threads, rate[threads - 1], r.evaluations_computed, r.wall_time_s, cpu,
                  LoadAverage(), r.best.objective);
    }
    std::printf("  speed-up with 2 threads: %.2fx\n", rate[1] / rate[0]);
  }
  if (only != "threads" && optimise::BuiltWithMpi() && !common::FindInPath("mpirun").empty()) {
    // The same optimisation as 1 and 2 MPI ranks of one thread each (mpirun from PATH).
    double mpi_rate[2] = {0, 0};
    for (int ranks : {1, 2}) {
      const std::string dir = out + "/mpi" + std::to_string(ranks);
      const double cpu0 = CpuSeconds(RUSAGE_CHILDREN);
      const std::string error = MpiRun(file, evaluations, dir, ranks);
      if (!error.empty()) throw std::runtime_error("bench optimise: mpirun failed: " + error);
      const double cpu = CpuSeconds(RUSAGE_CHILDREN) - cpu0;
      std::ifstream in(dir + "/summary.json");
      const nlohmann::json j = nlohmann::json::parse(in);
      mpi_rate[ranks - 1] = j["evaluations_per_s"].get<double>();
      std::printf("  mpirun -np %d --threads 1: %.2f evaluations/s (%d in %.1f s, CPU %.1f s, "
                  "load %.1f), best J %.6f\n",
                  ranks, mpi_rate[ranks - 1], j["evaluations_computed"].get<int>(),
                  j["wall_time_s"].get<double>(), cpu, LoadAverage(),
                  j["best_objective"].get<double>());
    }
    std::printf("  speed-up with 2 MPI ranks: %.2fx\n", mpi_rate[1] / mpi_rate[0]);
  }
}

// The largest disturbance of each family the robot survives, reflexes on and spindle + GTO off.
void Robustness(const std::string& file, const optimise::RobustnessOptions& options,
                const std::string& out) {
  // A run folder (docs/run-folders.md), checked and locked before the runs; an earlier
  // bench's replaced.
  sim::RunFolder folder(
      out, {.made_by = "bench robustness",
            .force = sim::RunFolderMadeBy(out) == "bench robustness",
            .inputs = {file}});
  Progress bar("robustness");
  const optimise::RobustnessReport r =
      optimise::BenchRobustness(file, options, [&](double f) { bar.Update(f); });
  const std::string warning = optimise::WriteRobustness(folder.path(), r);
  folder.Commit();
  std::fputs(optimise::RobustnessTable(r).c_str(), stdout);
  std::printf("  outputs %s/{robustness.csv,robustness.png}%s%s\n", out.c_str(),
              warning.empty() ? "" : "  plot: ", warning.c_str());
}

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
    if (versus.empty()) {
      Speed(file, duration_s, repetitions, profile_from_s);
    } else {
      SpeedVersus(file, versus, duration_s, repetitions);
    }
  });

  auto* accuracy =
      cmd->add_subcommand("accuracy", "error of the observables against wall time, per knob");
  accuracy->add_option("scenario", file, "scenario file")->required();
  accuracy->add_option("--duration", duration_s, "simulated seconds per run")
      ->check(CLI::PositiveNumber);
  accuracy->add_option("--threads", threads, "runs side by side (default: all cores)")
      ->check(CLI::Range(0, 1024));
  accuracy->add_option("--out", out_dir, "folder for accuracy.csv and accuracy.png");
  accuracy->footer(
      "Example:\n  climbsim bench accuracy examples/gecko_wall.yaml --duration 5 --out runs/acc");
  accuracy->callback([] { Accuracy(file, duration_s, threads, out_dir); });

  auto* opt = cmd->add_subcommand(
      "optimise", "evaluations per second with 1 and 2 threads (and 1 and 2 MPI ranks)");
  opt->add_option("scenario", file, "scenario file with an optimise block")->required();
  opt->add_option("--evaluations", evaluations, "evaluations per run")
      ->check(CLI::Range(2, 100000));
  opt->add_option("--out", out_dir, "folder for the two optimisation runs");
  static std::string only = "all";
  opt->add_option("--only", only, "threads: only the 1- and 2-thread runs; mpi: only the 1- and "
                  "2-rank runs")->check(CLI::IsMember({"all", "threads", "mpi"}));
  opt->footer(
      "Examples:\n  climbsim bench optimise examples/gecko_wall.yaml --evaluations 8\n"
      "  climbsim bench optimise examples/gecko_wall.yaml --evaluations 400 --only threads");
  opt->callback([] { OptimiseSpeed(file, evaluations, out_dir, only); });

  static optimise::RobustnessOptions robust;
  static std::string robust_out, families;
  auto* rob = cmd->add_subcommand(
      "robustness",
      "largest disturbance of each family survived, reflexes on and spindle + GTO off");
  rob->add_option("scenario", file, "scenario file")->required();
  rob->add_option("--out", robust_out,
                  "folder for robustness.csv and robustness.png: new, empty, or an earlier "
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
                  "weak_patch, roughness (default: all the scenario can take)");
  rob->add_option("--threads", robust.threads, "searches side by side (default: all cores)")
      ->check(CLI::Range(0, 1024));
  rob->footer(
      "Survived: no fall and at least half the undisturbed distance, in every seed (and push "
      "phase); bisection to 10 %.\nExample:\n  climbsim bench robustness examples/gecko_wall.yaml "
      "--duration 3 --seeds 1 --phases 1 --families push_down,pad_failure --out "
      "runs/robustness_quick");
  rob->callback([] {
    if (push_time->count() > 0) robust.push_time_s = push_time_s;
    robust.families.clear();
    std::string cur;
    for (char c : families + ",") {
      if (c == ',') {
        if (!cur.empty()) robust.families.push_back(cur);
        cur.clear();
      } else if (c != ' ') {
        cur += c;
      }
    }
    Robustness(file, robust, robust_out);
  });
}

}  // namespace climbsim::tools
