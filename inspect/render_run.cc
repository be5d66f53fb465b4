#include "inspect/render_run.h"

#include <cmath>
#include <filesystem>
#include <vector>

#include "common/common.h"
#include "common/run_folder.h"

namespace climbsim::inspect {
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

// Exactly one output, and its kind matches its name.
void CheckOutputs(const RenderRequest& r) {
  const bool still = r.at_s.has_value();
  if (still && !std::isfinite(*r.at_s)) {
    throw InputError("climbsim render", 0, 0, "--at", "must be a finite time in seconds");
  }
  if (still && (r.out.empty() || !r.frames.empty())) {
    throw InputError("climbsim render", 0, 0, "--at", "needs --out STILL.png (and no --frames)");
  }
  if (!still && r.out.empty() == r.frames.empty()) {
    throw InputError("climbsim render", 0, 0, "--out",
                     "give one of --out VIDEO.mp4, --frames DIR or --at T --out STILL.png");
  }
  // Outputs never replace a run's data, and their kind matches their name.
  if (!r.out.empty()) {
    const std::string ext = std::filesystem::path(r.out).extension().string();
    if (still && ext != ".png") {
      throw InputError(r.out, 0, 0, "--out", "a still is a PNG: give a name ending in .png");
    }
    if (!still && ext != ".mp4") {
      throw InputError(r.out, 0, 0, "--out",
                       "the video is MP4 (H.264): give a name ending in .mp4, or --at T for a "
                       "still");
    }
  }
}

// The run folder that holds the trajectory: `dir` itself, or the replay of an optimise
// folder's best.yaml.
std::string TrajectoryFolder(const std::string& dir,
                             const std::function<void(double)>& replay_progress) {
  const RunKind kind = DetectRunKind(dir);
  if (kind == RunKind::kPulloff) {
    throw InputError(dir, 0, 0, "", "a pulloff folder holds no trajectory to render");
  }
  if (kind != RunKind::kOptimise) return dir;
  bool replayed = false;
  return ReplayBest(dir, &replayed, replay_progress);
}

}  // namespace

RenderOutcome RenderRunFolder(const RenderRequest& request,
                              const std::function<void(double)>& replay_progress,
                              const std::function<void(double)>& render_progress) {
  CheckOutputs(request);
  // Checked and locked before the work: --out never replaces a file climbsim did not make
  // and is recorded in its run folder's marker; --frames is a run folder of its own.
  std::optional<sim::RunFolderAdditions> added;
  std::optional<sim::RunFolder> frames_folder;
  if (!request.out.empty()) added.emplace(std::vector<std::string>{request.out}, "--out");
  if (!request.frames.empty()) frames_folder.emplace(FramesFolder(request.frames, request.dir));
  const Run run = LoadRun(TrajectoryFolder(request.dir, replay_progress));
  RenderOutcome outcome;
  if (request.at_s) {
    outcome.stats = RenderStill(run, request.options, *request.at_s, request.out);
    outcome.written = request.out;
  } else if (!request.out.empty()) {
    outcome.stats = RenderVideo(run, request.options, request.out, render_progress);
    outcome.written = request.out;
  } else {
    outcome.stats = RenderFrames(run, request.options, frames_folder->path(), render_progress);
    frames_folder->Commit();
    outcome.written = request.frames + "/frame_*.png";
  }
  if (added) added->Commit();
  return outcome;
}

}  // namespace climbsim::inspect
