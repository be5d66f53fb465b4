// climbsim sweep SCENARIO... --key KEY --from A --to B --step S --out DIR
// Under mpirun the runs are spread over the ranks; rank 0 writes DIR and prints.
#include <cstdio>
#include <filesystem>

#include "optimise/optimise.h"
#include "tools/commands.h"

namespace climbsim::tools {

void AddSweepCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "sweep", "Run scenarios with one numeric key swept over a range (e.g. the incline)");
  static std::vector<std::string> files;
  static optimise::SweepOptions o;
  static std::string out_dir;
  cmd->add_option("scenarios", files, "scenario files (one curve each)")->required();
  cmd->add_option("--key", o.key, "dotted key to sweep, e.g. scene.incline_deg")->required();
  cmd->add_option("--from", o.from, "first value")->required();
  cmd->add_option("--to", o.to, "last value")->required();
  cmd->add_option("--step", o.step, "step (> 0)")->required()->check(CLI::PositiveNumber);
  cmd->add_option("--threads", o.threads, "worker threads (default: all cores)")
      ->check(CLI::Range(0, 1024));
  cmd->add_option("--out", out_dir, "folder for sweep.csv and sweep.png")->required();
  cmd->footer(
      "Example:\n  climbsim sweep examples/gecko_incline.yaml examples/spider_incline.yaml "
      "--key scene.incline_deg --from 0 --to 180 --step 15 --out runs/incline");
  cmd->callback([] {
    if (o.to < o.from) {
      throw InputError("--to", 0, 0, "", "must not be below --from");
    }
    const auto rows = optimise::Sweep(files, o);
    if (optimise::ProcessRank() != 0) return;  // under mpirun rank 0 writes and prints
    const std::string warning = optimise::WriteSweep(out_dir, files, o, rows);
    std::printf("%12s", o.key.c_str());
    for (const auto& f : files) {
      std::printf("  %26s", std::filesystem::path(f).stem().string().c_str());
    }
    std::printf("\n%12s", "");
    for (size_t f = 0; f < files.size(); ++f) std::printf("  %14s %11s", "speed [cm/s]", "fell at [s]");
    std::printf("\n");
    for (const auto& r : rows) {
      std::printf("%12g", r.value);
      for (const auto& res : r.results) {
        const double v = res.sim_time_s > 0 ? res.distance_m / res.sim_time_s : 0.0;
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
