// climbsim sweep SCENARIO... --key KEY --from A --to B --step S --out DIR [--seeds N] [--keep-runs]
// climbsim sweep SCENARIO --find KEY --low A --high B --condition 'FIELD>=X' --out DIR
// Under mpirun the runs are spread over the ranks; rank 0 writes DIR and prints.
#include <cstdio>
#include <optional>

#include "experiments/experiments.h"
#include "sim/sim.h"
#include "tools/commands.h"

namespace climbsim::tools {
namespace {

struct SweepArgs {
  std::vector<std::string> files;
  optimise::SweepOptions o;
  std::string out_dir;
  bool force = false, keep = false, keep_runs = false;
  std::string find, condition;
  double low = 0.0, high = 0.0, tolerance = 0.01;
};

InputError Bad(const char* flag, const std::string& m) {
  return InputError("climbsim sweep", 0, 0, flag, m);
}

// --find: the threshold mode's options, checked before anything runs.
optimise::FindOptions FindOptionsOf(const SweepArgs& a) {
  if (a.files.size() != 1) throw Bad("--find", "takes one scenario file");
  if (!a.o.key.empty()) throw Bad("--key", "not with --find (which names the key)");
  if (a.condition.empty()) throw Bad("--condition", "is required with --find");
  optimise::FindOptions f;
  f.key = a.find;
  f.low = a.low;
  f.high = a.high;
  f.condition = optimise::ParseCondition(a.condition);
  f.tolerance = a.tolerance;
  f.seeds = a.o.seeds;
  f.threads = a.o.threads;
  return f;
}

void RunSweep(SweepArgs& a) {
  const bool find = !a.find.empty();
  std::optional<optimise::FindOptions> f;
  if (find) {
    f = FindOptionsOf(a);
  } else {
    if (a.o.key.empty()) throw Bad("--key", "is required (or --find KEY)");
    optimise::CheckSweepRange(a.o);
  }
  // The output folder is checked and locked before anything runs; it appears whole.
  // Under mpirun rank 0 alone owns it.
  std::optional<sim::RunFolder> folder;
  if (optimise::ProcessRank() == 0) {
    folder.emplace(a.out_dir, sim::RunFolderOptions{.made_by = "sweep",
                                                    .force = a.force,
                                                    .keep_other_files = a.keep,
                                                    .inputs = a.files});
    if (a.keep_runs) (find ? f->runs_dir : a.o.runs_dir) = folder->path() + "/runs";
  }
  if (find) {
    const optimise::FindResult r = optimise::FindThreshold(a.files[0], *f);
    if (optimise::ProcessRank() != 0) return;
    optimise::WriteFind(folder->path(), *f, r);
    folder->Commit();
    std::fputs(optimise::FindText(*f, r).c_str(), stdout);
    std::printf("  outputs %s/find.csv%s\n", a.out_dir.c_str(), a.keep_runs ? ", runs/" : "");
    return;
  }
  const auto rows = optimise::Sweep(a.files, a.o);
  if (optimise::ProcessRank() != 0) return;  // under mpirun rank 0 writes and prints
  const std::string warning = optimise::WriteSweep(folder->path(), a.files, a.o, rows);
  folder->Commit();
  std::fputs(optimise::SweepTable(a.files, a.o, rows, a.out_dir, warning).c_str(), stdout);
}

}  // namespace

void AddSweepCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "sweep", "Run scenarios with one numeric key swept over a range (e.g. the incline), or "
               "find where a condition stops holding (--find)");
  static SweepArgs a;
  cmd->add_option("scenarios", a.files, "scenario files (one curve each)")->required();
  AddSetOption(cmd);
  cmd->add_option("--key", a.o.key, "dotted key to sweep, e.g. scene.incline_deg");
  cmd->add_option("--from", a.o.from, "first value");
  cmd->add_option("--to", a.o.to, "last value");
  cmd->add_option("--step", a.o.step, "step (> 0)")->check(CLI::PositiveNumber);
  cmd->add_option("--seeds", a.o.seeds,
                  "runs per point: seed cases 0..N-1 as bench robustness makes them (seed + k, "
                  "the start moved by up to 5 mm and 5 deg); worst and mean reported")
      ->check(CLI::Range(1, optimise::kMaxSweepSeeds));
  cmd->add_flag("--keep-runs", a.keep_runs,
                "keep every run's folder under DIR/runs (trajectory, events, summary.json)");
  cmd->add_option("--find", a.find,
                  "threshold mode: bisect this dotted key between --low and --high for where "
                  "--condition stops holding on every seed");
  cmd->add_option("--low", a.low, "--find: one end of the interval");
  cmd->add_option("--high", a.high, "--find: the other end (above --low)");
  cmd->add_option("--condition", a.condition,
                  "--find: FIELD OP NUMBER on the run's summary.json (OP: < <= > >= == !=), "
                  "terms joined by ' and ', e.g. 'distance_m>=0.1 and fell==0'");
  cmd->add_option("--tolerance", a.tolerance,
                  "--find: stop when the interval is within this share of the edge")
      ->check(CLI::Range(1e-6, 0.5));
  cmd->add_option("--threads", a.o.threads, "worker threads (default: all cores)")
      ->check(CLI::Range(0, 1024));
  cmd->add_option("--out", a.out_dir,
                  "folder for sweep.csv and sweep.png (find.csv with --find): new, empty, or "
                  "(with --force) an earlier climbsim folder (docs/run-folders.md)")
      ->required();
  cmd->add_flag("--force", a.force,
                "replace the earlier climbsim folder at --out (deleting only its own files)");
  cmd->add_flag("--keep-other-files", a.keep,
                "with --force: carry files climbsim did not write (notes, added folders) into "
                "the new run folder instead of refusing (docs/run-folders.md)");
  cmd->footer(
      "Examples:\n  climbsim sweep examples/gecko_incline.yaml examples/spider_incline.yaml "
      "--key scene.incline_deg --from 0 --to 180 --step 15 --out runs/incline\n"
      "  climbsim sweep examples/gecko_wall.yaml --find adhesion.sigma_t_pa --low 3000 "
      "--high 12000 --condition 'distance_m>=0.1 and fell==0' --out runs/sigma_edge");
  cmd->callback([] { RunSweep(a); });
}

}  // namespace climbsim::tools
