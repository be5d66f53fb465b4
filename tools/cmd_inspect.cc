// climbsim inspect RUN_DIR: what every foot did (per-leg table, one leg's events, JSON, plots).
// Reads a simulate run directory, an optimise results folder (its best.yaml is replayed once
// into DIR/best_run) or a pulloff folder (its pulloff.csv is shown).
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "inspect/inspect.h"
#include "common/common.h"
#include "common/run_folder.h"
#include "tools/commands.h"
#include "tools/progress.h"

namespace climbsim::tools {
namespace {

// A pulloff folder: its pulloff.csv as a table or JSON (--leg and --plots do not apply).
void InspectPulloff(const std::string& dir, bool json, bool leg_given, bool plots) {
  if (leg_given || plots) {
    throw InputError("climbsim inspect", 0, 0, !leg_given ? "--plots" : "--leg",
                     "does not apply to a pulloff folder (it holds pulloff.csv and "
                     "pulloff.png)");
  }
  const inspect::TextTable table = inspect::ReadTextCsv(dir + "/pulloff.csv");
  if (json) {
    std::printf("%s\n", inspect::PulloffJson(dir, table).dump(2).c_str());
  } else {
    std::fputs(inspect::PulloffText(table).c_str(), stdout);
  }
}

// The plots go beside the run's data, never over it nor over a user's file, under the run
// folder's lock, and are recorded in its marker as climbsim's. Their list goes to `out`.
void WritePlotsBesideRun(const inspect::Run& run, const inspect::Report& report, FILE* out) {
  std::vector<std::string> names{"gait", "path"}, paths;
  for (const auto& l : run.legs) names.push_back("pad_" + l);
  for (const auto& n : names) {
    for (const char* ext : {".png", ".svg"}) paths.push_back(run.dir + "/" + n + ext);
  }
  sim::RunFolderAdditions added(paths, "--plots");
  std::vector<std::string> notes;
  const auto files = inspect::WritePlots(run, report, run.dir, &notes);
  added.Commit();
  std::fprintf(out, "\nplots:");
  for (const auto& f : files) std::fprintf(out, " %s", f.c_str());
  std::fprintf(out, "\n");
  for (const auto& n : notes) std::fprintf(out, "  note: %s\n", n.c_str());
}

}  // namespace

void AddInspectCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "inspect", "Per-leg adhesion table, one leg's events, JSON and plots of a run");
  static std::string dir, leg;
  static double from_s = 0.0, to_s = std::numeric_limits<double>::infinity();
  static bool json = false, plots = false;
  cmd->add_option("run", dir,
                  "run directory (climbsim simulate), optimise results folder, or pulloff "
                  "folder")
      ->required();
  cmd->add_option("--leg", leg,
                  "list this leg's events in time order with their loads (LF or LF_pad)");
  cmd->add_option("--from", from_s, "start of the time window (s)");
  cmd->add_option("--to", to_s, "end of the time window (s)");
  cmd->add_flag("--json", json, "the same as JSON on stdout (schema in docs/inspect.md)");
  cmd->add_flag("--plots", plots,
                "also draw gait.png/.svg, pad_<leg>.png/.svg and path.png/.svg into the run "
                "directory");
  cmd->footer(
      "An optimise folder is inspected through DIR/best_run, simulated from DIR/best.yaml the\n"
      "first time (as climbsim simulate DIR/best.yaml --out DIR/best_run would).\n"
      "Example:\n  climbsim inspect runs/gecko_wall --leg LF --from 5 --to 10\n"
      "  climbsim inspect runs/gecko_wall --plots");
  cmd->callback([] {
    const inspect::Window window{from_s, to_s};
    const inspect::RunKind kind = inspect::DetectRunKind(dir);
    if (kind == inspect::RunKind::kPulloff) return InspectPulloff(dir, json, !leg.empty(), plots);
    std::string run_dir = dir;
    if (kind == inspect::RunKind::kOptimise) {
      bool replayed = false;
      Progress progress("replaying best.yaml", !json);
      run_dir = inspect::ReplayBest(dir, &replayed, [&](double f) { progress.Update(f); });
      std::fprintf(stderr, "climbsim inspect: %s is an optimise folder; inspecting %s%s\n",
                   dir.c_str(), run_dir.c_str(), replayed ? " (just replayed from best.yaml)" : "");
    }
    const inspect::Run run = inspect::LoadRun(run_dir);
    const inspect::Report report = inspect::Analyse(run, window);
    if (json) {
      nlohmann::json j =
          leg.empty() ? inspect::ReportJson(run, report) : inspect::LegEventsJson(run, leg, window);
      if (kind == inspect::RunKind::kOptimise) {
        j["kind"] = "optimise";
        j["results"] = dir;
        j["best"] = dir + "/best.yaml";
      }
      std::printf("%s\n", j.dump(2).c_str());
    } else {
      std::fputs(leg.empty() ? inspect::ReportText(run, report).c_str()
                             : inspect::LegEventsText(run, leg, window).c_str(),
                 stdout);
    }
    if (plots) WritePlotsBesideRun(run, report, json ? stderr : stdout);
  });
}

}  // namespace climbsim::tools
