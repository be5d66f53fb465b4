// climbsim optimise SCENARIO --out DIR [--threads N] [--resume]
// Under mpirun every rank runs this command; rank 0 writes DIR and the terminal output.
#include <cstdio>

#include "experiments/experiments.h"
#include "common/common.h"
#include "tools/commands.h"
#include "tools/progress.h"

namespace climbsim::tools {

void AddOptimiseCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("optimise", "Tune CPG and reflex parameters offline with NLopt");
  static std::string scenario_path, out_dir;
  static int threads = 0, max_evaluations = 0;
  static bool resume = false, quiet = false, force = false, keep = false;
  cmd->add_option("scenario", scenario_path, "scenario file with an optimise: block")->required();
  AddSetOption(cmd);
  cmd->add_option("--out", out_dir,
                  "results folder: new, empty, or (with --force) an earlier climbsim folder "
                  "(docs/run-folders.md)")
      ->required();
  cmd->add_flag("--force", force,
                "replace the earlier climbsim folder at --out (deleting only its own files)");
  cmd->add_flag("--keep-other-files", keep,
                "with --force: carry files climbsim did not write (notes, added folders) into "
                "the new run folder instead of refusing (docs/run-folders.md)");
  cmd->add_option("--threads", threads,
                  "worker threads per process (default: the cores, shared by the MPI ranks on "
                  "the machine); the result does not depend on it")
      ->check(InRange(optimise::kThreadsRange));
  cmd->add_option("--max-evaluations", max_evaluations,
                  "override optimise.max_evaluations (evaluations in all, at least 1)")
      ->check(InRange(optimise::kMaxEvaluationsRange));
  cmd->add_flag("--resume", resume,
                "continue from DIR/checkpoint.json after a kill (same end result as an "
                "uninterrupted run)");
  cmd->add_flag("--quiet", quiet, "no progress and no summary on the terminal");
  cmd->footer(
      "Examples:\n  climbsim optimise examples/gecko_wall.yaml --out runs/gecko_opt "
      "--max-evaluations 20\n"
      "  mpirun -np 4 climbsim optimise examples/gecko_wall.yaml --out runs/gecko_opt_mpi "
      "--max-evaluations 20   (the same best.yaml)");
  cmd->callback([] {
    optimise::Options o;
    o.out_dir = out_dir;
    o.threads = threads;
    o.resume = resume;
    o.force = force;
    o.keep_other_files = keep;
    if (resume && force) {
      throw InputError("climbsim optimise", 0, 0, "--force",
                       "cannot go with --resume (--force starts over, --resume continues)");
    }
    o.max_evaluations = max_evaluations;
    o.quiet = quiet;
    const bool root = optimise::ProcessRank() == 0;
    Progress progress("optimise", !quiet && root);
    char note[96];
    const optimise::Result r = optimise::Optimise(scenario_path, o, [&](double f, double best) {
      std::snprintf(note, sizeof(note), "best J %.5f m/s", best);
      progress.Update(f, note);
    });
    if (!r.plot_warning.empty()) {  // the results stand; the promised plot is missing
      std::fprintf(stderr, "climbsim optimise: no convergence.png: %s\n", r.plot_warning.c_str());
      ExitCode() = 1;
    }
    if (quiet || !root) return;
    std::fputs(optimise::ResultText(r, out_dir).c_str(), stdout);
  });
}

}  // namespace climbsim::tools
