// climbsim::inspect: what every foot did in a run, as a table, plots and pictures. Reads the
// run directories the other verbs write; never runs inside a simulation and never changes one.
//
//   simulate  DIR/{scenario.yaml, model.xml, trajectory.csv, events.csv, summary.json}
//   optimise  DIR/best.yaml (+ history.csv, summary.json ...): best.yaml is replayed once into
//             DIR/best_run with `sim` (bit for bit the optimiser's best), then inspected
//   pulloff   DIR/pulloff.csv: shown as it is
//
//   climbsim::inspect::Run run = climbsim::inspect::LoadRun("runs/gecko_wall");
//   climbsim::inspect::Report r = climbsim::inspect::Analyse(run, {.from_s = 2, .to_s = 10});
//   std::fputs(climbsim::inspect::ReportText(run, r).c_str(), stdout);
//   climbsim::inspect::WritePlots(run, r, run.dir);            // gait.png, pad_LF.png, ...
//   climbsim::inspect::RenderStill(run, {}, 5.0, "still.png");  // MuJoCo offscreen, EGL
//
// Errors: a malformed or incomplete run directory throws climbsim::InputError naming the
// file and, for a bad row, its 1-based line and column ("DIR/events.csv:7:23: fn_n: expected
// a number, got 'abc'"). A missing tool (gnuplot, ffmpeg) or a missing OpenGL driver (EGL)
// throws std::runtime_error.
#ifndef CLIMBSIM_INSPECT_INSPECT_H_
#define CLIMBSIM_INSPECT_INSPECT_H_

#include <Eigen/Core>
#include <functional>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace climbsim::inspect {

// ---------------------------------------------------------------------------------------------
// Files of a run directory.

// The header events.csv must have, exactly (sim/events.h writes it).
inline constexpr std::string_view kEventsHeader =
    "time_s,pad,event,cause,surface,bonded_fraction,fn_n,fx_n,fy_n,mx_nm,my_nm";
// The first columns trajectory.csv must have, in this order; joint angles (`<joint>_rad`,
// `<joint>_m` for slides) and effect columns (`<pad>_bonded_fraction`) follow.
inline constexpr std::string_view kTrajectoryLeadingColumns =
    "time_s,base_x_m,base_y_m,base_z_m,base_qw,base_qx,base_qy,base_qz";

// One row of events.csv. Loads are the pad's load in the pad frame (adhesion/README.md):
// fn_n > 0 pulls the pad off, < 0 presses it on; fx_n, fy_n shear; mx_nm, my_nm peel moments.
struct EventRow {
  double time_s = 0.0;
  std::string pad;      // pad body name, "LF_pad"
  std::string event;    // touchdown, attach, attach_rejected, bonds_lost, detach, or a reflex
  std::string cause;    // as written: "peel", "approach_speed_mps=0.44", "" when none
  std::string surface;  // geom touched, "" when none
  double bonded_fraction = 0.0;
  double fn_n = 0.0, fx_n = 0.0, fy_n = 0.0, mx_nm = 0.0, my_nm = 0.0;
  int line = 0;  // 1-based line in events.csv (the header is line 1)

  // Shear magnitude hypot(fx_n, fy_n), N.
  double shear_n() const;
  // The cause without its value: "approach_speed_mps=0.44" → "approach_speed_mps";
  // "unknown" when the cause is empty.
  std::string cause_name() const;
};

// A CSV file of numbers with a header line (trajectory.csv).
struct NumericTable {
  std::string path;
  std::vector<std::string> columns;
  std::vector<double> values;  // row-major, rows() × columns.size()

  size_t rows() const { return columns.empty() ? 0 : values.size() / columns.size(); }
  // Index of a column, -1 when absent.
  int Column(std::string_view name) const;
  double at(size_t row, size_t column) const { return values[row * columns.size() + column]; }
};

// A CSV file shown as text (pulloff.csv: numbers, causes, "inf", empty cells).
struct TextTable {
  std::string path;
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
};

// Readers. Each throws InputError naming the file: missing file ("missing file"), empty file,
// wrong header (line 1), wrong column count (line, "expected 11 columns, got 9"), a truncated
// last row (the file ends without its newline: the writer was killed), a cell that is not a
// number (line and column), time going backwards, and (events) a pad the robot does not have.
std::vector<EventRow> ReadEvents(const std::string& path);
NumericTable ReadTrajectory(const std::string& path);
TextTable ReadTextCsv(const std::string& path);
// summary.json: a JSON object with a number duration_s >= 0 (InputError with the line
// otherwise: not JSON, a number out of range, duration_s missing or negative).
nlohmann::json ReadSummary(const std::string& path);

// What a folder holds. A folder with events.csv is a simulation run; else with best.yaml an
// optimise results folder; else with pulloff.csv a pulloff folder; else it is taken for an
// incomplete simulation run (LoadRun then names the first missing file).
enum class RunKind { kSimulation, kOptimise, kPulloff };
RunKind DetectRunKind(const std::string& dir);
const char* RunKindName(RunKind kind);  // "simulation", "optimise", "pulloff"

// A simulation run directory, read and checked once.
struct Run {
  std::string dir;
  nlohmann::json summary;         // summary.json
  std::string model_xml;          // model.xml: the model that ran, self-contained
  std::vector<std::string> legs;  // the robot's legs in its order ("LF", ...) from model.xml
  std::vector<std::string> pads;  // pad body of each leg, "<leg>_pad" (mjcf/README.md contract)
  std::vector<EventRow> events;   // file order (time order)
  std::optional<NumericTable> trajectory;  // absent when the run recorded none
  double duration_s = 0.0;                 // simulated time, summary.json "duration_s"
  Eigen::Vector3d travel{1, 0, 0};         // the scene's travel direction (custom numeric
                                           // climbsim_travel), unit length

  // Index of a leg given as "LF" or "LF_pad"; -1 when the robot has none.
  int LegIndex(std::string_view leg_or_pad) const;
};

// Reads DIR/summary.json, model.xml (compiled through sim::CompileMjcf for the legs and the
// travel direction), events.csv and, when present, trajectory.csv. Throws InputError for a
// missing or malformed file (summary.json is written last: without it the run did not finish).
Run LoadRun(const std::string& dir);

// An optimise results folder: DIR/best_run, simulated from DIR/best.yaml unless best_run is
// complete (has summary.json) and newer than best.yaml. `replayed` says whether it ran;
// `progress` (may be empty) gets the simulated fraction. Throws InputError when best.yaml is
// not a valid scenario.
std::string ReplayBest(const std::string& results_dir, bool* replayed,
                       const std::function<void(double)>& progress = {});

// ---------------------------------------------------------------------------------------------
// The per-leg table.

// Time window, s. Clipped to [0, duration_s] of the run; what remains must be non-empty.
struct Window {
  double from_s = 0.0;
  double to_s = std::numeric_limits<double>::infinity();
};

// One attached interval of a pad (attach .. detach), clipped to the window.
struct Stance {
  double start_s = 0.0;
  double end_s = 0.0;
  bool open_start = false;  // attached before the window began
  bool open_end = false;    // still attached at the window's end (or at the end of the run)
  std::string end_cause;    // the detach cause; "" when open_end
  double length_s() const { return end_s - start_s; }
};

// Definitions (docs/inspect.md has the same with an example):
// * Counts (touchdowns, attachments, rejected, detaches, bonds_lost_steps, reflexes) are of
//   events with from ≤ time ≤ to. Reflexes are every event that is not touchdown, attach,
//   attach_rejected, bonds_lost or detach, counted by name.
// * Stances are built over the whole run in file order (an attach opens one when the pad is
//   not attached, a detach closes it; a repeated attach or a detach when not attached is
//   counted but changes nothing; a stance still open at the end ends at duration_s) and then
//   clipped to the window (kept when end ≥ from and start ≤ to).
// * A stance is complete when neither end is clipped or open; mean and shortest stance are
//   over the complete ones (absent when there are none).
// * attached_s = Σ clipped stance lengths; duty_factor = attached_s / observed_s.
// * "While attached" = the rows of the pad from its attach row through its detach row, in
//   file order. peak_normal_n = max fn_n over them (the load that broke a pad is in its
//   detach row); peak_shear_n = max hypot(fx_n, fy_n); lowest_bonded_fraction = min
//   bonded_fraction over those rows before the detach's own time step (that step's rows
//   hold what was left after the pad failed). Only rows inside the window count.
// * peak_utilisation = max of trajectory.csv's `<pad>_utilisation` (the pad's peak bond
//   demand over threshold, 1 breaks a bond) over the rows inside the window; absent when the
//   run has no such column (runs from before it existed). It includes the peel, which takes
//   every pad to 1 on purpose, so it says nothing of the margin; the split does:
//   utilisation_stance_peak and utilisation_stance_p99 (nearest rank) over the rows inside a
//   stance and outside a peel, utilisation_peel_peak over the rows inside both. A peel runs
//   from the pad's `peel` event to its next `peel_end` or `detach`; an interval [start, end)
//   holds a row at time t when start ≤ t < end. Rows every 1/trajectory_rate_hz: summary.json's
//   fields of the same names are over every step (sim/adhesion_effect.h).
struct LegReport {
  std::string leg;
  std::string pad;
  int touchdowns = 0;
  int attachments = 0;
  int rejected = 0;
  std::map<std::string, int> rejected_by;  // by condition: approach_speed_mps, contacts, ...
  // Touchdowns that neither attached nor were rejected, by reason: left_within_attach_window
  // (the pad touched again before any decision: it left the surface before its contacts and
  // preload met the attach conditions), run_ended_during_touch.
  int unanswered_touchdowns = 0;
  std::map<std::string, int> unanswered_by;
  int detaches = 0;
  std::map<std::string, int> detached_by;  // peel, overload, released, contact_lost
  int bonds_lost_steps = 0;
  std::vector<Stance> stances;
  int complete_stances = 0;
  std::optional<double> mean_stance_s;
  std::optional<double> shortest_stance_s;
  double attached_s = 0.0;
  double duty_factor = 0.0;
  std::optional<double> peak_normal_n;           // N, + pulls off
  std::optional<double> peak_shear_n;            // N
  std::optional<double> lowest_bonded_fraction;  // the safety margin while attached
  std::optional<double> peak_utilisation;        // bond demand / threshold, 1 breaks
  std::optional<double> utilisation_stance_peak;  // attached, not peeling: the margin
  std::optional<double> utilisation_stance_p99;
  std::optional<double> utilisation_peel_peak;    // attached, peeling: ~1 on purpose
  std::map<std::string, int> reflexes;           // event name → count
};

struct Report {
  std::string dir;
  double from_s = 0.0;  // the window, clipped to the run
  double to_s = 0.0;
  double observed_s = 0.0;      // to_s − from_s
  std::vector<LegReport> legs;  // robot order
};

// Throws InputError ("climbsim inspect: --from: ...") when the window is empty after clipping.
Report Analyse(const Run& run, const Window& window);

// `climbsim inspect --json`, schema in docs/inspect.md:
// {"kind","run","robot","scene","duration_s","window":{"from_s","to_s","observed_s"},
//  "legs":[{"leg","pad","touchdowns","attachments","rejected","rejected_by":{},"detaches",
//  "detached_by":{},"bonds_lost_steps","stances":[{"start_s","end_s","open_start","open_end",
//  "end_cause"}],"complete_stances","mean_stance_s","shortest_stance_s","attached_s",
//  "duty_factor","peak_normal_n","peak_shear_n","lowest_bonded_fraction","peak_utilisation",
//  "utilisation_stance_peak","utilisation_stance_p99","utilisation_peel_peak","reflexes":{}}]}
// Absent values (no complete stance, never attached) are null.
nlohmann::json ReportJson(const Run& run, const Report& report);
// The table for a terminal: one column per leg, one row per figure.
std::string ReportText(const Run& run, const Report& report);

// One leg's events inside the window, in time order (`--leg`). Throws InputError
// ("climbsim inspect: --leg: ...") naming the legs the robot has when `leg` is not one.
std::vector<EventRow> LegEvents(const Run& run, std::string_view leg, const Window& window);
// {"kind","run","leg","pad","window":{...},"events":[{"time_s","event","cause","surface",
//  "bonded_fraction","fn_n","fx_n","fy_n","shear_n","mx_nm","my_nm","line"}]}
nlohmann::json LegEventsJson(const Run& run, std::string_view leg, const Window& window);
std::string LegEventsText(const Run& run, std::string_view leg, const Window& window);

// pulloff.csv as an aligned table, and as {"kind":"pulloff","run","file","columns","rows"}
// (numbers as numbers, "inf" and text as strings, empty cells null).
std::string PulloffText(const TextTable& table);
nlohmann::json PulloffJson(const std::string& dir, const TextTable& table);

// ---------------------------------------------------------------------------------------------
// Plots (gnuplot, PNG and SVG; each file written to a temporary name and renamed).

// Writes into out_dir, over the report's window:
//   gait.png/.svg        one row per leg, a bar per stance, marks for rejected attaches
//                        (×) and detaches by cause
//   pad_<leg>.png/.svg   bonded fraction (trajectory column, else from the events) and the
//                        pad's load at its events (fn_n, shear), attach and detach marked
//   path.png/.svg        the base's path on the surface (lateral, travel) and its speed along
//                        the travel direction (central difference over 0.5 s); needs
//                        trajectory.csv, skipped (and said in `notes`) without it
// Returns the files written. Throws std::runtime_error when gnuplot fails.
std::vector<std::string> WritePlots(const Run& run, const Report& report,
                                    const std::string& out_dir,
                                    std::vector<std::string>* notes = nullptr);

// ---------------------------------------------------------------------------------------------
// Pictures of the robot: the recorded trajectory replayed offscreen with MuJoCo's renderer
// through EGL (Mesa's llvmpipe, surfaceless), encoded by ffmpeg. Only mj_kinematics runs on a
// private model copy: the recorded state is shown, nothing is simulated.
//
// Each frame: qpos from trajectory.csv, linearly interpolated between rows (the base
// quaternion normalised); pads coloured by bonded fraction (0: the pad's own colour; above 0
// from red at a trace of bonds to green at full); the camera looks at the base's position
// averaged over ±0.25 s, from behind, beside and off the surface, with the image's up along
// −gravity of the run (so a wall climb goes up the screen); the time is printed top left.
//
// Cameras (RenderOptions::camera):
//   follow  the view above, moving with the base: the robot stays in the middle of the image
//   fixed   a world-fixed view from the same direction that frames the whole climb: it looks
//           at the centre of the box the base's recorded positions span over the rendered
//           time (from .. to, clipped to the recording), from far enough that a sphere around
//           that box, grown by the robot's radius, fits in the image (MuJoCo's fovy, and the
//           horizontal angle the width gives); --distance-m overrides the distance
//   NAME    a <camera> of the model (model.xml), as the model places it (its own up)
//   ""      fixed for a video or frame folder (a video shows the climb), follow for a still

enum class Quality {
  kDefault,  // the model's settings: multisampling, shadows, reflections
  kReduced,  // offsamples 0, no shadows, no reflections: several times faster
};

struct RenderOptions {
  int width = 640;  // pixels; a video needs even sizes (H.264 with 4:2:0 chroma)
  int height = 480;
  double fps = 30.0;
  Quality quality = Quality::kDefault;
  double from_s = 0.0;  // video and frames: the time span, clipped to the run
  double to_s = std::numeric_limits<double>::infinity();
  double distance_m = 0.0;  // camera distance; 0: 3.5 times the robot's radius (fixed: framed)
  std::string camera;       // follow, fixed, a camera of the model; "": see above
};

// Where the camera was for a frame (MuJoCo's OpenGL camera, world frame, the two eyes
// averaged), for tests and for users who place their own overlays.
struct CameraPose {
  Eigen::Vector3d pos = Eigen::Vector3d::Zero();
  Eigen::Vector3d forward = Eigen::Vector3d::UnitX();
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  double fovy_deg = 45.0;  // vertical field of view
};

struct RenderStats {
  int frames = 0;
  std::vector<CameraPose> cameras;  // one per frame
  std::string camera;               // the camera used: follow, fixed or the model's NAME
  double render_s = 0.0;           // wall time in MuJoCo's renderer and reading pixels
  double total_s = 0.0;            // wall time including encoding
  std::vector<std::string> notes;  // e.g. joints the trajectory does not hold
};

// Frame times of a video or frame folder: from + k/fps for k = 0, 1, ... while ≤ to.
std::vector<double> FrameTimes(const Run& run, const RenderOptions& options);

// One PNG at time t, which must lie inside the recording (InputError at --at otherwise).
RenderStats RenderStill(const Run& run, const RenderOptions& options, double t_s,
                        const std::string& png_path);
// An H.264 MP4 (libx264, yuv420p).
RenderStats RenderVideo(const Run& run, const RenderOptions& options, const std::string& mp4_path,
                        const std::function<void(double)>& progress = {});
// frame_00000.png, frame_00001.png, ... in out_dir (created).
RenderStats RenderFrames(const Run& run, const RenderOptions& options, const std::string& out_dir,
                         const std::function<void(double)>& progress = {});

// The run's gravity (m/s²): the scenario's (sim::World applies an incline's rotation),
// falling back to model.xml's when scenario.yaml cannot be read. The camera's up is −gravity.
Eigen::Vector3d RunGravity(const Run& run, std::string* note = nullptr);

}  // namespace climbsim::inspect

#endif  // CLIMBSIM_INSPECT_INSPECT_H_
