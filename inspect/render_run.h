// `climbsim render` as a library call: the outputs checked and locked, an optimise folder's
// best.yaml replayed, then a still, a video or a folder of frames rendered (inspect.h).
#ifndef CLIMBSIM_INSPECT_RENDER_RUN_H_
#define CLIMBSIM_INSPECT_RENDER_RUN_H_

#include <functional>
#include <optional>
#include <string>

#include "inspect/inspect.h"

namespace climbsim::inspect {

struct RenderRequest {
  std::string dir;               // a simulate run folder or an optimise results folder
  std::string out;               // the MP4 video (with at_s: the PNG still)
  std::string frames;            // or a folder of PNG frames
  std::optional<double> at_s;    // a still at this time
  RenderOptions options;
};

struct RenderOutcome {
  RenderStats stats;
  std::string written;  // what was written, as the summary line names it
};

// Throws InputError (exit code 2) before any work when the request does not fit: none or
// two of the outputs, a name whose kind does not match (.png still, .mp4 video), an output
// that would replace a run's data, a pulloff folder. replay_progress follows the replay of
// an optimise folder's best.yaml, render_progress the frames of a video or frame folder.
RenderOutcome RenderRunFolder(const RenderRequest& request,
                              const std::function<void(double)>& replay_progress = {},
                              const std::function<void(double)>& render_progress = {});

}  // namespace climbsim::inspect

#endif  // CLIMBSIM_INSPECT_RENDER_RUN_H_
