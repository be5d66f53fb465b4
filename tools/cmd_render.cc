// climbsim render RUN_DIR --out video.mp4 | --frames DIR | --at T --out still.png: the recorded
// trajectory replayed offscreen with MuJoCo's renderer (EGL, no display needed), pads coloured
// by bonded fraction, encoded by ffmpeg. Nothing is simulated: the run is shown as recorded.
#include <cstdio>
#include <limits>

#include "inspect/render_run.h"
#include "tools/commands.h"
#include "tools/progress.h"

namespace climbsim::tools {

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
  cmd->add_option("--camera", o.camera,
                  "follow (moves with the robot), fixed (a world-fixed view that frames the "
                  "whole climb) or the name of a camera in the model; default: fixed for a "
                  "video or frames, follow for a still");
  cmd->add_flag("--quiet", quiet, "no progress and no summary");
  cmd->footer(
      "Example:\n  climbsim render runs/gecko_wall --at 10 --out runs/gecko_wall/still.png\n"
      "  climbsim render runs/gecko_wall --out runs/gecko_wall/video.mp4 --quality reduced\n"
      "  climbsim render runs/gecko_wall --out runs/gecko_wall/close.mp4 --camera follow");
  auto* at_option = cmd->get_option("--at");
  cmd->callback([at_option] {
    o.quality = quality == "reduced" ? inspect::Quality::kReduced : inspect::Quality::kDefault;
    inspect::RenderRequest request;
    request.dir = dir;
    request.out = out;
    request.frames = frames;
    request.options = o;
    if (at_option->count() > 0) request.at_s = at_s;
    Progress replay_bar("replaying best.yaml", !quiet);
    Progress bar("render", !quiet && !request.at_s);
    const inspect::RenderOutcome r = inspect::RenderRunFolder(
        request, [&](double f) { replay_bar.Update(f); }, [&](double f) { bar.Update(f); });
    if (quiet) return;
    for (const auto& n : r.stats.notes) std::printf("note: %s\n", n.c_str());
    std::printf(
        "climbsim render: %d frame%s %dx%d (%s quality, %s camera) in %.2f s; renderer %.2f "
        "s = %.1f frames/s\n  wrote %s\n",
        r.stats.frames, r.stats.frames == 1 ? "" : "s", o.width, o.height, quality.c_str(),
        r.stats.camera.c_str(), r.stats.total_s, r.stats.render_s,
        r.stats.render_s > 0 ? r.stats.frames / r.stats.render_s : 0.0, r.written.c_str());
  });
}

}  // namespace climbsim::tools
