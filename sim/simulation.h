// One run of a scenario: the World, the effects the scenario names, the step loop and its
// monitor. Construction does everything that can fail on input (InputError); stepping
// never allocates, takes no locks, and reports trouble through its return value: a run that
// goes numerically bad stops with the step, the time and MuJoCo's warning.
#ifndef CLIMBSIM_SIM_SIMULATION_H_
#define CLIMBSIM_SIM_SIMULATION_H_

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "sim/controller.h"
#include "sim/effect.h"
#include "sim/events.h"
#include "common/run_folder.h"
#include "scenario/scenario.h"
#include "sim/world.h"

namespace climbsim::sim {

class TrajectoryRecorder;

// What the effects of a scenario add to the MJCF (welds, sensors, actuators), so the
// compiled model can be built once and shared read-only by many runs.
MjcfAdditions EffectAdditions(const Scenario& scenario);

// Compiles the model a scenario needs.
std::unique_ptr<CompiledModel> CompileScenario(const Scenario& scenario);

struct RunResult {
  bool stable = true;
  std::string failure;       // "step 1234, t = 1.234 s: mjWARN_BADQACC ..." when unstable
  long steps = 0;
  double sim_time_s = 0.0;
  double wall_time_s = 0.0;
  bool fell = false;
  double fall_time_s = -1.0;
  const char* fall_cause = "";  // "dropped", "turned_over" or "left_surface" when fell
  // travel · base displacement, from the start to the end of the run or, when the robot
  // fell, to the fall: a free fall (or a drift off the surface) after it is not progress.
  double distance_m = 0.0;
  double distance_at_end_m = 0.0;  // the same to the end of the run, fall or not
  double heading_deg = 0.0;        // heading about the start surface normal (at the end, or at the
                                   // fall), 0 = as started
  double actuator_work_j = 0.0;  // Σ over steps and actuators of |force · velocity| · dt

  // distance_m over the time it took: to the fall when the robot fell, else the whole run.
  double mean_speed_mps() const {
    const double t = fell ? fall_time_s : sim_time_s;
    return t > 0 ? distance_m / t : 0.0;
  }
};

class Simulation {
 public:
  // `controller` (optional) is the user's controller (sim/controller.h): it runs at each
  // control tick after the built-in CPG + reflexes (when the scenario has a cpg block) and
  // may change their command; without a cpg block it alone drives the servos.
  Simulation(const Scenario& scenario, const CompiledModel& compiled,
             std::shared_ptr<Controller> controller = nullptr);
  ~Simulation();

  // Back to t = 0 (mj_resetData, then each effect's Reset). The constructor calls it.
  void Reset();
  // One physics step with every effect. False when the run must stop: numerically unstable
  // (failure() says why) or fallen with fall.stop set.
  bool Step();

  // Time spent per part of the step, for `climbsim bench speed`: mj_step, each effect's hooks
  // (in pipeline order, BeforeStep + AfterStep), and the monitor. StepProfiled is Step with a
  // clock read between parts; Step itself never reads a clock. Each part's time holds one lap
  // of the clock per call (an effect: one per hook it has, each step; mj_step and the monitor:
  // one per step), what LapSeconds() measures with nothing inside: 20–60 ns, so a part that
  // does nothing would read 0.1–0.2 % of mj_step.
  struct Profile {
    double mj_step_s = 0.0;
    std::vector<double> effect_s;  // one per effect
    double monitor_s = 0.0;
    long steps = 0;
    // The least mean time of a lap with nothing inside over a few batches (so that taking it
    // off never takes off more than the clock costs).
    static double LapSeconds();
  };
  bool StepProfiled(Profile* profile);
  // Steps to the scenario's duration or until Step() says stop. `progress` (may be empty)
  // is called with the simulated fraction done, now and then.
  RunResult Run(const std::function<void(double)>& progress = {});
  // Brings result() (and so Summary()) up to the steps done so far, as Run() does at its end:
  // steps, time, distance and heading (to the fall when the robot fell). For a caller that
  // drives Step() itself; wall_time_s is the time its steps took.
  void UpdateResult(double wall_time_s);

  const RunResult& result() const { return result_; }
  long steps_total() const { return steps_total_; }
  World& world() { return world_; }
  const World& world() const { return world_; }
  const Scenario& scenario() const { return scenario_; }
  const std::vector<std::unique_ptr<Effect>>& effects() const { return effects_; }
  const EventLog& events() const { return events_; }
  // The effect that runs the controllers; null when the scenario has none.
  const ControllerEffect* controller() const { return controller_; }
  // The trajectory recorder; null when the trajectory is not recorded.
  const TrajectoryRecorder* trajectory() const { return trajectory_; }
  std::vector<LegSignals>& legs() { return legs_; }

  // Outputs of the run so far.
  nlohmann::json Summary() const;
  std::string TrajectoryCsv() const;  // empty when the trajectory is not recorded
  std::string EventsCsv() const;

 private:
  // The construction's checks and wiring, in this order.
  // The run's steps (checked against kMaxScenarioSteps, and its trajectory rows).
  double CheckRunSize() const;
  // cpg.control_period_s a whole multiple of the time step.
  void CheckCpgPeriod(bool timestep_given) const;
  // Each leg's pad in the EventLog; *pad_names: the sticky pads first, then the other legs'.
  std::vector<int> EventPads(const AdhesionEffect* adhesion,
                             std::vector<std::string>* pad_names) const;
  // The controller chain's effect: the built-in CPG, reflexes and transition, then the user's.
  void AddController(std::shared_ptr<Controller> controller, AdhesionEffect* adhesion,
                     const std::vector<int>& leg_event_pad);
  // The perturbations and the trajectory recorder; then the step's hook lists.
  void AddRecorders();
  bool Monitor();  // false to stop; fills result_
  double Heading() const;  // deg, forward axis about the start normal

  Scenario scenario_;
  World world_;
  std::vector<std::unique_ptr<Effect>> effects_;
  std::vector<Effect*> before_, after_;
  TrajectoryRecorder* trajectory_ = nullptr;
  ControllerEffect* controller_ = nullptr;
  std::vector<LegSignals> legs_;
  EventLog events_;
  RunContext ctx_;
  RunResult result_;
  long steps_total_ = 0;

  // Monitor state.
  std::array<int, mjNWARNING> warnings_seen_{};
  Eigen::Vector3d start_pos_, up0_, forward0_, down_;
  double turn_over_cos_ = 0.0;  // cos of fall.turn_over_deg
  double highest_ = 0.0;
  double touched_s_ = 0.0;    // the last time any part of the robot touched or held the scene
  Eigen::Vector3d fall_pos_;  // base position at the fall
  double fall_heading_deg_ = 0.0;
};

// The files a run reads: the scenario file, and the robot and scene files it names by path.
// A run folder must not hold them (RunFolderOptions::inputs).
std::vector<std::string> ScenarioInputs(const Scenario& scenario);

// Writes the files of a run into `dir` (a RunFolder's path()): scenario.yaml, model.xml,
// trajectory.csv (when recorded), events.csv and, last, summary.json. `extra` is merged into
// summary.json (figures computed outside sim, such as the objective).
void WriteRunFiles(const std::string& dir, const Simulation& sim,
                   const nlohmann::json& extra = nlohmann::json::object());

// WriteRunFiles into a RunFolder at `dir` made by "simulate", committed at once: the run
// folder appears whole or not at all. Throws InputError when `dir` is refused
// (sim/run_folder.h; `force` replaces an earlier climbsim run folder).
void WriteRunDirectory(const std::string& dir, const Simulation& sim,
                       const nlohmann::json& extra = nlohmann::json::object(), bool force = false);

// Routes MuJoCo's warnings through climbsim instead of MUJOCO_LOG.TXT in the working folder:
// a warning is kept (per thread, without allocating) for the run's failure message. Errors
// keep MuJoCo's handler unless one is set (the climbsim executable sets its own). Called by
// every Simulation; idempotent.
void InstallMujocoHandlers();
// The last MuJoCo warning text of this thread ("" when none since the last call), cleared.
std::string TakeMujocoWarning();

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_SIMULATION_H_
