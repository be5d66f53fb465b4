// climbsim render RUN_DIR --out video.mp4 | --frames DIR | --at T --out still.png: the recorded
// trajectory replayed offscreen with MuJoCo's renderer (EGL, no display needed), pads coloured
// by bonded fraction, encoded by ffmpeg. Nothing is simulated: the run is shown as recorded.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <vector>

#include "common/common.h"
#include "inspect/inspect.h"
#include "common/run_folder.h"
#include "tools/commands.h"
#include "tools/progress.h"

namespace climbsim::tools {
namespace {

// The folder of --frames: new, empty, or one an earlier render made (replaced); never another
// run folder, nor one that holds the run.
sim::RunFolder FramesFolder(const std::string& frames, const std::string& run_dir) {
  const std::string by = sim::RunFolderMadeBy(frames);
  if ((!by.empty() && by != "render") || std::filesystem::exists(frames + "/summary.json")) {
    throw InputError(
        frames, 0, 0, "--frames",
        "is a run folder; give a folder of its own for the frames (e.g. " + frames + "/frames)");
  }
  return sim::RunFolder(
      frames,
      {.made_by = "render", .force = by == "render", .inputs = {run_dir}, .flag = "--frames"});
}

}  // namespace

void AddRenderCommand(CLI::App& app) {
  auto* cmd =
      app.add_subcommand("render", "Replay a run offscreen: MP4 video, PNG frames or a still");
  static std::string dir, out, frames, quality = "default";
  static double at_s = std::numeric_limits<double>::quiet_NaN();
  static inspect::RenderOptions o;
  static bool quiet = false;
  cmd->add_option("run", dir, "run directory (climbsim simulate) or optimise results folder")
      ->required();
  cmd->add_option("--out", out, "the MP4 video to write (with --at: the PNG still)");
  cmd->add_option("--frames", frames, "write PNG frames frame_00000.png ... into this folder");
  cmd->add_option("--at", at_s, "render one still at this time (s) into --out");
  cmd->add_option("--width", o.width, "image width (px; even for a video)")->capture_default_str();
  cmd->add_option("--height", o.height, "image height (px; even for a video)")
      ->capture_default_str();
  cmd->add_option("--fps", o.fps, "frames per second of simulated time")->capture_default_str();
  cmd->add_option("--quality", quality,
                  "default (the model's: multisampling, shadows, reflections) or reduced "
                  "(none of them: several times faster)")
      ->check(CLI::IsMember({"default", "reduced"}))
      ->capture_default_str();
  cmd->add_option("--from", o.from_s, "start of the video (s)");
  cmd->add_option("--to", o.to_s, "end of the video (s)");
  cmd->add_option("--distance-m", o.distance_m,
                  "camera distance (m); default 3.5 times the robot's radius");
  cmd->add_flag("--quiet", quiet, "no progress and no summary");
  cmd->footer(
      "Example:\n  climbsim render runs/gecko_wall --at 10 --out runs/gecko_wall/still.png\n"
      "  climbsim render runs/gecko_wall --out runs/gecko_wall/video.mp4 --quality reduced");
  auto* at_option = cmd->get_option("--at");
  cmd->callback([at_option] {
    o.quality = quality == "reduced" ? inspect::Quality::kReduced : inspect::Quality::kDefault;
    if (at_option->count() > 0 && !std::isfinite(at_s)) {
      throw InputError("climbsim render", 0, 0, "--at", "must be a finite time in seconds");
    }
    const bool still = at_option->count() > 0;
    if (still && (out.empty() || !frames.empty())) {
      throw InputError("climbsim render", 0, 0, "--at", "needs --out STILL.png (and no --frames)");
    }
    if (!still && out.empty() == frames.empty()) {
      throw InputError("climbsim render", 0, 0, "--out",
                       "give one of --out VIDEO.mp4, --frames DIR or --at T --out STILL.png");
    }
    // Outputs never replace a run's data, and their kind matches their name.
    if (!out.empty()) {
      const std::string ext = std::filesystem::path(out).extension().string();
      if (still && ext != ".png") {
        throw InputError(out, 0, 0, "--out", "a still is a PNG: give a name ending in .png");
      }
      if (!still && ext != ".mp4") {
        throw InputError(out, 0, 0, "--out",
                         "the video is MP4 (H.264): give a name ending in .mp4, or --at T for a "
                         "still");
      }
    }
    // Checked and locked before the work: --out never replaces a file climbsim did not make
    // and is recorded in its run folder's marker; --frames is a run folder of its own.
    std::optional<sim::RunFolderAdditions> added;
    std::optional<sim::RunFolder> frames_folder;
    if (!out.empty()) added.emplace(std::vector<std::string>{out}, "--out");
    if (!frames.empty()) frames_folder.emplace(FramesFolder(frames, dir));
    const inspect::RunKind kind = inspect::DetectRunKind(dir);
    if (kind == inspect::RunKind::kPulloff) {
      throw InputError(dir, 0, 0, "", "a pulloff folder holds no trajectory to render");
    }
    std::string run_dir = dir;
    if (kind == inspect::RunKind::kOptimise) {
      bool replayed = false;
      Progress progress("replaying best.yaml", !quiet);
      run_dir = inspect::ReplayBest(dir, &replayed, [&](double f) { progress.Update(f); });
    }
    const inspect::Run run = inspect::LoadRun(run_dir);
    Progress progress("render", !quiet && !still);
    const auto report = [&](double f) { progress.Update(f); };
    inspect::RenderStats stats;
    std::string written;
    if (still) {
      stats = inspect::RenderStill(run, o, at_s, out);
      written = out;
    } else if (!out.empty()) {
      stats = inspect::RenderVideo(run, o, out, report);
      written = out;
    } else {
      stats = inspect::RenderFrames(run, o, frames_folder->path(), report);
      frames_folder->Commit();
      written = frames + "/frame_*.png";
    }
    if (added) added->Commit();
    if (quiet) return;
    for (const auto& n : stats.notes) std::printf("note: %s\n", n.c_str());
    std::printf(
        "climbsim render: %d frame%s %dx%d (%s quality) in %.2f s; renderer %.2f s = %.1f "
        "frames/s\n  wrote %s\n",
        stats.frames, stats.frames == 1 ? "" : "s", o.width, o.height, quality.c_str(),
        stats.total_s, stats.render_s, stats.render_s > 0 ? stats.frames / stats.render_s : 0.0,
        written.c_str());
  });
}

}  // namespace climbsim::tools
