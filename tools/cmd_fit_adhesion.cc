// climbsim fit-adhesion DATA.csv --law LAW --out DIR: a pad law's parameters from measured
// pull-off forces (experiments/fit_adhesion.h runs it; docs/calibrate-adhesion.md).
#include <cstdio>
#include <string>

#include "experiments/fit_adhesion.h"
#include "experiments/option_ranges.h"
#include "tools/commands.h"

namespace climbsim::tools {

void AddFitAdhesionCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "fit-adhesion",
      "Fit a pad law to measured pull-off forces (one row per pull: angle_from_normal_deg, "
      "force_n, ...), through the pull-off search on the bond grid the simulations use; writes "
      "the parameters with uncertainties, the residuals, a plot against the other laws, a "
      "verdict and fitted.yaml (an adhesion: block for a scenario)");
  static optimise::FitAdhesionRunOptions o;
  cmd->add_option("data", o.data_file,
                  "CSV with a header: angle_from_normal_deg, force_n, and optionally azimuth_deg, "
                  "pad_width_m, pad_length_m, lever_arm_m, preload_n, repeat")
      ->required();
  cmd->add_option("--law", o.fit.law, "the law to fit: von_mises, frictional or tabulated")
      ->check(CLI::IsMember({"von_mises", "frictional", "tabulated"}))
      ->required();
  cmd->add_option("--out", o.out_dir,
                  "folder for the results: new, empty, or (with --force) an earlier climbsim "
                  "folder (docs/run-folders.md)")
      ->required();
  cmd->add_flag("--force", o.force,
                "replace the earlier climbsim folder at --out (deleting only its own files)");
  cmd->add_flag("--keep-other-files", o.keep_other_files,
                "with --force: carry files climbsim did not write into the new run folder");
  cmd->add_option("--width-m", o.width_m, "pad width (m) when the CSV has no pad_width_m column")
      ->check(InRange(optimise::kPadWidthRangeM));
  cmd->add_option("--length-m", o.length_m, "pad length (m); default: the width")
      ->check(InRange(optimise::kPadWidthRangeM));
  cmd->add_option("--grid", o.fit.grid, "bonds per side of the predictions' grid")
      ->check(InRange(optimise::kGridRange))
      ->capture_default_str();
  cmd->add_option("--grip-deg", o.fit.grip_deg,
                  "frictional: the gripping direction's azimuth in the data (deg)")
      ->check(InRange(optimise::kAzimuthRangeDeg))
      ->capture_default_str();
  cmd->add_option("--assumed-spread", o.fit.assumed_spread,
                  "measurement spread as a share of the forces when the data has no repeats")
      ->check(CLI::Range(0.001, 1.0))
      ->capture_default_str();
  cmd->add_flag("--quiet", o.quiet, "no table and no progress on the terminal");
  cmd->footer(
      "Angles are from the pad normal (0 pulls straight off, 90 shears); azimuth from pad +x\n"
      "towards +y. Outputs: parameters.csv, residuals.csv, curves.csv, fit.gp, fit.png,\n"
      "fitted.yaml, verdict.txt.\n"
      "Example:\n  climbsim fit-adhesion examples/pad_pulloff.csv --law tabulated --out runs/fit");
  cmd->callback([] {
    if (!o.quiet) {
      o.fit.progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
    }
    if (!optimise::RunFitAdhesion(o)) ExitCode() = 1;
  });
}

}  // namespace climbsim::tools
