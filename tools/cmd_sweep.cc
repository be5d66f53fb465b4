// climbsim sweep SCENARIO... --key KEY --from A --to B --step S --out DIR
// Under mpirun the runs are spread over the ranks; rank 0 writes DIR and prints.
#include <cstdio>
#include <optional>

#include "experiments/experiments.h"
#include "sim/sim.h"
#include "tools/commands.h"

namespace climbsim::tools {

void AddSweepCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "sweep", "Run scenarios with one numeric key swept over a range (e.g. the incline)");
  static std::vector<std::string> files;
  static optimise::SweepOptions o;
  static std::string out_dir;
  static bool force = false, keep = false;
  cmd->add_option("scenarios", files, "scenario files (one curve each)")->required();
  AddSetOption(cmd);
  cmd->add_option("--key", o.key, "dotted key to sweep, e.g. scene.incline_deg")->required();
  cmd->add_option("--from", o.from, "first value")->required();
  cmd->add_option("--to", o.to, "last value")->required();
  cmd->add_option("--step", o.step, "step (> 0)")->required()->check(CLI::PositiveNumber);
  cmd->add_option("--threads", o.threads, "worker threads (default: all cores)")
      ->check(CLI::Range(0, 1024));
  cmd->add_option("--out", out_dir,
                  "folder for sweep.csv and sweep.png: new, empty, or (with --force) an earlier "
                  "climbsim folder (docs/run-folders.md)")
      ->required();
  cmd->add_flag("--force", force,
                "replace the earlier climbsim folder at --out (deleting only its own files)");
  cmd->add_flag("--keep-other-files", keep,
                "with --force: carry files climbsim did not write (notes, added folders) into "
                "the new run folder instead of refusing (docs/run-folders.md)");
  cmd->footer(
      "Example:\n  climbsim sweep examples/gecko_incline.yaml examples/spider_incline.yaml "
      "--key scene.incline_deg --from 0 --to 180 --step 15 --out runs/incline");
  cmd->callback([] {
    optimise::CheckSweepRange(o);
    // The output folder is checked and locked before anything runs; it appears whole.
    // Under mpirun rank 0 alone owns it.
    std::vector<std::string> inputs = files;
    std::optional<sim::RunFolder> folder;
    if (optimise::ProcessRank() == 0) {
      folder.emplace(
          out_dir,
          sim::RunFolderOptions{
              .made_by = "sweep", .force = force, .keep_other_files = keep, .inputs = inputs});
    }
    const auto rows = optimise::Sweep(files, o);
    if (optimise::ProcessRank() != 0) return;  // under mpirun rank 0 writes and prints
    const std::string warning = optimise::WriteSweep(folder->path(), files, o, rows);
    folder->Commit();
    std::fputs(optimise::SweepTable(files, o, rows, out_dir, warning).c_str(), stdout);
  });
}

}  // namespace climbsim::tools
