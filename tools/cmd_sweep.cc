// climbsim sweep SCENARIO... --key KEY --from A --to B --step S --out DIR
// Under mpirun the runs are spread over the ranks; rank 0 writes DIR and prints.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "experiments/experiments.h"
#include "sim/sim.h"
#include "tools/commands.h"

namespace climbsim::tools {
namespace {
constexpr int kMaxSweepValues = 10000;  // values of the swept key
}  // namespace

void AddSweepCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "sweep", "Run scenarios with one numeric key swept over a range (e.g. the incline)");
  static std::vector<std::string> files;
  static optimise::SweepOptions o;
  static std::string out_dir;
  static bool force = false, keep = false;
  cmd->add_option("scenarios", files, "scenario files (one curve each)")->required();
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
    const auto bad = [](const char* flag, const std::string& m) {
      return InputError("climbsim sweep", 0, 0, flag, m);
    };
    if (!std::isfinite(o.from)) throw bad("--from", "must be a finite number");
    if (!std::isfinite(o.to)) throw bad("--to", "must be a finite number");
    if (!std::isfinite(o.step)) throw bad("--step", "must be a finite number");
    if (o.to < o.from) throw bad("--to", "must not be below --from");
    const double values = std::floor((o.to - o.from) / o.step + 1e-9) + 1;
    if (!(values <= kMaxSweepValues)) {
      throw bad("--step", "gives " + sim::ExactNumber(values) +
                              " values from --from to --to; at most " +
                              std::to_string(kMaxSweepValues) + " are allowed");
    }
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
    std::printf("%12s", o.key.c_str());
    for (const auto& f : files) {
      std::printf("  %26s", std::filesystem::path(f).stem().string().c_str());
    }
    std::printf("\n%12s", "");
    for (size_t f = 0; f < files.size(); ++f)
      std::printf("  %14s %11s", "speed [cm/s]", "fell at [s]");
    std::printf("\n");
    for (const auto& r : rows) {
      std::printf("%12g", r.value);
      for (const auto& res : r.results) {
        const double v = res.mean_speed_mps();
        if (res.fell) {
          std::printf("  %14s %11.2f", "-", res.fall_time_s);
        } else {
          std::printf("  %14.2f %11s", 100 * v, "-");
        }
      }
      std::printf("\n");
    }
    std::printf("  outputs %s/{sweep.csv,sweep.png}%s%s\n", out_dir.c_str(),
                warning.empty() ? "" : "  (plot: ", warning.empty() ? "" : (warning + ")").c_str());
  });
}

}  // namespace climbsim::tools
