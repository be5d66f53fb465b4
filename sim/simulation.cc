#include "sim/simulation.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <mutex>
#include <sstream>

#include "sim/adhesion_effect.h"
#include "sim/controller.h"
#include "sim/cpg_effect.h"
#include "sim/perturbation_effect.h"
#include "sim/reflex_effect.h"
#include "sim/surface.h"
#include "sim/terrain.h"
#include "sim/trajectory.h"
#include "sim/transition_effect.h"

namespace climbsim::sim {
namespace {

// Warnings after which the state cannot be trusted. MuJoCo resets mjData on bad qpos, qvel
// or qacc and carries on; climbsim stops instead and says where it happened.
constexpr mjtWarning kFatalWarnings[] = {mjWARN_BADQPOS,     mjWARN_BADQVEL, mjWARN_BADQACC,
                                         mjWARN_BADCTRL,     mjWARN_CONTACTFULL,
                                         mjWARN_CNSTRFULL};

const char* WarningName(int w) {
  switch (w) {
    case mjWARN_BADQPOS: return "mjWARN_BADQPOS (bad number in qpos)";
    case mjWARN_BADQVEL: return "mjWARN_BADQVEL (bad number in qvel)";
    case mjWARN_BADQACC: return "mjWARN_BADQACC (bad number in qacc)";
    case mjWARN_BADCTRL: return "mjWARN_BADCTRL (bad number in ctrl)";
    case mjWARN_CONTACTFULL: return "mjWARN_CONTACTFULL (too many contacts)";
    case mjWARN_CNSTRFULL: return "mjWARN_CNSTRFULL (too many constraints)";
    default: return "MuJoCo warning";
  }
}

Eigen::Vector3d BaseAxis(const mjData* d, const RobotInfo& r, int axis) {
  double mat[9];
  mju_quat2Mat(mat, d->qpos + r.root_qpos_adr + 3);
  return {mat[axis], mat[3 + axis], mat[6 + axis]};
}

// Whether any part of the robot touches the scene (a contact with a body outside the robot) or
// holds it (an active weld between the robot and the scene: a bonded pad). Allocates nothing.
bool TouchesScene(const mjModel* m, const mjData* d, const RobotInfo& r) {
  const int robot = m->body_rootid[r.base_body];
  const auto outside = [&](int body) { return m->body_rootid[body] != robot; };
  for (int i = 0; i < d->ncon; ++i) {
    const bool out1 = outside(m->geom_bodyid[d->contact[i].geom1]);
    if (out1 != outside(m->geom_bodyid[d->contact[i].geom2])) return true;
  }
  for (int i = 0; i < m->neq; ++i) {
    if (m->eq_active[i] && m->eq_type[i] == mjEQ_WELD &&
        outside(m->eq_obj1id[i]) != outside(m->eq_obj2id[i])) {
      return true;
    }
  }
  return false;
}

Eigen::Vector3d BasePos(const mjData* d, const RobotInfo& r) {
  const double* q = d->qpos + r.root_qpos_adr;
  return {q[0], q[1], q[2]};
}

// MuJoCo's last warning on this thread: a fixed buffer, so the handler never allocates.
thread_local char mujoco_warning[512] = "";

void KeepMujocoWarning(const char* msg) {
  std::strncpy(mujoco_warning, msg, sizeof(mujoco_warning) - 1);
  mujoco_warning[sizeof(mujoco_warning) - 1] = '\0';
}

void PrintMujocoError(const char* msg) {
  std::fprintf(stderr, "climbsim: MuJoCo error: %s\n", msg);
  std::exit(1);
}

// A user controller's period by the rule of cpg.control_period_s (a whole multiple of the
// physics time step), where 0 (every step, the controller API's default) is allowed too: the
// run would otherwise round any value, NaN included, to a number of steps.
void CheckControlPeriod(const Controller& c, double timestep_s) {
  const double period_s = c.control_period_s();
  const double ratio = period_s / timestep_s;
  const bool multiple = std::isfinite(period_s) && ratio >= 0.5 && ratio <= kMaxScenarioSteps &&
                        std::abs(ratio - std::round(ratio)) <= 1e-9 * ratio;
  if (period_s != 0.0 && !multiple) {
    throw InputError(std::string("controller '") + c.name() + "'", 0, 0, "control_period_s()",
                     "must be 0 (every step) or a whole multiple of the time step (" +
                         ExactNumber(timestep_s) + " s), at most " +
                         ExactNumber(kMaxScenarioSteps) + " of them; got " +
                         ExactNumber(period_s));
  }
}

}  // namespace

void InstallMujocoHandlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    mju_user_warning = KeepMujocoWarning;
    if (mju_user_error == nullptr) mju_user_error = PrintMujocoError;
  });
}

std::string TakeMujocoWarning() {
  std::string s = mujoco_warning;
  mujoco_warning[0] = '\0';
  return s;
}

MjcfAdditions EffectAdditions(const Scenario& scenario) {
  MjcfAdditions additions;
  if (scenario.adhesion) AddAdhesionMjcf(scenario, *scenario.adhesion, &additions);
  additions.worldbody += RoughnessMjcf(scenario);
  AddTerrainMjcf(scenario, &additions);
  return additions;
}

std::unique_ptr<CompiledModel> CompileScenario(const Scenario& scenario) {
  return CompiledModel::Build(scenario, EffectAdditions(scenario));
}

Simulation::Simulation(const Scenario& scenario, const CompiledModel& compiled,
                       std::shared_ptr<Controller> controller)
    : scenario_(scenario), world_(compiled, scenario_) {
  InstallMujocoHandlers();
  const double steps = CheckRunSize();
  legs_.resize(world_.robot().legs.size());
  // scenario.yaml records every physics option the run used, the scene's included.
  const bool timestep_given = scenario_.physics.timestep_s.has_value();
  scenario_.physics = PhysicsOf(world_.model());
  CheckCpgPeriod(timestep_given);

  // Effects in pipeline order; only those the scenario names.
  if (scenario_.adhesion) {
    effects_.push_back(std::make_unique<AdhesionEffect>(scenario_, *scenario_.adhesion, world_));
  }
  AdhesionEffect* adhesion = FindAdhesion(effects_);
  std::vector<std::string> pad_names;
  const std::vector<int> leg_event_pad = EventPads(adhesion, &pad_names);
  if (scenario_.reflex && !scenario_.cpg) {
    throw ScenarioError(scenario_, "reflex", "needs the cpg block: reflexes act on its gait");
  }
  if (scenario_.transition && !scenario_.cpg) {
    throw ScenarioError(scenario_, "transition",
                        "needs the cpg block: the robot walks to the corner with its gait");
  }
  AddController(std::move(controller), adhesion, leg_event_pad);
  AddRecorders();

  // Room for a few adhesion and reflex events per pad per stride at up to 10 strides a second,
  // at most a million rows (a longer run counts the rest in events_dropped).
  const size_t capacity = static_cast<size_t>(
      std::min(1e6, 64 + 400.0 * scenario_.duration_s * std::max<size_t>(1, pad_names.size())));
  events_.Configure(std::move(pad_names), capacity);

  steps_total_ = std::lround(steps);
  Reset();
}

double Simulation::CheckRunSize() const {
  // Bounds before anything is sized for the run: steps (10^9 steps of 1 ns would run for days
  // and write nothing; the step may be the scene's), and rows of trajectory.csv.
  const double steps = scenario_.duration_s / world_.model()->opt.timestep;
  if (steps > kMaxScenarioSteps) {
    throw ScenarioError(
        scenario_, "physics.timestep_s",
        "duration_s / physics.timestep_s asks for " +
            (steps < 9e18 ? std::to_string(std::llround(steps)) : ExactNumber(steps)) +
            " steps; climbsim runs at most " + std::to_string(std::llround(kMaxScenarioSteps)) +
            ": raise the time step or shorten the run");
  }
  const double rate_hz = scenario_.outputs.trajectory_rate_hz;
  if (rate_hz > 0) {
    const double every = std::max(1.0, std::round(1.0 / (rate_hz * world_.model()->opt.timestep)));
    if (const double rows = steps / every; rows > kMaxTrajectoryRows) {
      throw ScenarioError(scenario_, "outputs.trajectory_rate_hz",
                          "would record " + std::to_string(std::llround(rows)) +
                              " rows of trajectory.csv; at most " +
                              std::to_string(std::llround(kMaxTrajectoryRows)) +
                              ": lower the rate (0 records none) or shorten the run");
    }
  }
  return steps;
}

void Simulation::CheckCpgPeriod(bool timestep_given) const {
  if (!scenario_.cpg || !scenario_.cpg->control_period_s) return;
  const double ratio = *scenario_.cpg->control_period_s / world_.model()->opt.timestep;
  if (std::abs(ratio - std::round(ratio)) > 1e-9 * ratio || ratio < 0.5) {
    throw ScenarioError(scenario_, "cpg.control_period_s",
                        "must be a whole multiple of physics.timestep_s (" +
                            ExactNumber(world_.model()->opt.timestep) + " s, " +
                            (timestep_given ? "given" : "the scene's") + ")");
  }
}

std::vector<int> Simulation::EventPads(const AdhesionEffect* adhesion,
                                       std::vector<std::string>* pad_names) const {
  // Events name the sticky pads first (the adhesion effect's indices), then any other leg pad
  // (reflex events go to the leg's pad).
  if (adhesion != nullptr) {
    for (int i = 0; i < adhesion->pad_count(); ++i) pad_names->push_back(adhesion->pad_name(i));
  }
  std::vector<int> leg_event_pad;
  for (const LegInfo& l : world_.robot().legs) {
    const std::string name = mj_id2name(world_.model(), mjOBJ_BODY, l.pad_body);
    const auto it = std::find(pad_names->begin(), pad_names->end(), name);
    leg_event_pad.push_back(static_cast<int>(it - pad_names->begin()));
    if (it == pad_names->end()) pad_names->push_back(name);
  }
  if (scenario_.reflex && scenario_.reflex->tail) {  // the tail reflex's rows (sim/tail_driver.h)
    leg_event_pad.push_back(static_cast<int>(pad_names->size()));
    pad_names->push_back("tail");
  }
  return leg_event_pad;
}

void Simulation::AddController(std::shared_ptr<Controller> controller, AdhesionEffect* adhesion,
                               const std::vector<int>& leg_event_pad) {
  // The controllers: the built-in CPG + reflexes when the scenario has a cpg block, then the
  // user's; one effect runs the chain at the control period (sim/controller.h).
  std::vector<std::shared_ptr<Controller>> chain;
  if (controller) CheckControlPeriod(*controller, world_.model()->opt.timestep);
  double period_s = controller ? controller->control_period_s() : 0.0;
  if (scenario_.cpg) {
    auto cpg = std::make_unique<CpgEffect>(scenario_, *scenario_.cpg, world_);
    scenario_.cpg = cpg->resolved();  // scenario.yaml shows the gait and defaults used
    std::unique_ptr<ReflexEffect> reflex;
    if (scenario_.reflex) {
      // Before the CPG: its offsets and holds act at the same control tick.
      reflex = std::make_unique<ReflexEffect>(scenario_, *scenario_.reflex, world_, *cpg,
                                              adhesion, leg_event_pad);
    }
    period_s = cpg->control_period_s();
    std::unique_ptr<TransitionEffect> transition;
    if (scenario_.transition) {
      transition = std::make_unique<TransitionEffect>(scenario_, *scenario_.transition, world_,
                                                      adhesion, cpg.get(), period_s,
                                                      leg_event_pad);
    }
    chain.push_back(std::make_shared<CpgReflexController>(
        world_, ctx_, std::move(cpg), std::move(reflex), std::move(transition)));
  }
  if (controller) chain.push_back(std::move(controller));
  if (chain.empty()) return;
  const int period_steps =
      std::max(1, static_cast<int>(std::lround(period_s / world_.model()->opt.timestep)));
  auto effect = std::make_unique<ControllerEffect>(world_, std::move(chain), period_steps,
                                                   adhesion, scenario_.cpg.has_value());
  controller_ = effect.get();
  effects_.push_back(std::move(effect));
}

void Simulation::AddRecorders() {
  if (!scenario_.perturbations.empty()) {
    effects_.push_back(std::make_unique<PerturbationEffect>(scenario_, world_));
  }
  std::vector<const Effect*> column_sources;
  for (const auto& e : effects_) column_sources.push_back(e.get());
  if (scenario_.outputs.trajectory_rate_hz > 0.0) {
    auto rec = std::make_unique<TrajectoryRecorder>(world_, scenario_.outputs.trajectory_rate_hz,
                                                    scenario_.duration_s, column_sources);
    trajectory_ = rec.get();
    effects_.push_back(std::move(rec));
  }
  for (const auto& e : effects_) {
    if (e->has_before_step()) before_.push_back(e.get());
    if (e->has_after_step()) after_.push_back(e.get());
  }
}

Simulation::~Simulation() = default;

void Simulation::Reset() {
  mjModel* m = world_.model();
  mjData* d = world_.data();
  mj_resetData(m, d);
  for (auto& l : legs_) l = LegSignals{};
  events_.Clear();
  ctx_ = RunContext{};
  ctx_.legs = &legs_;
  ctx_.events = &events_;
  result_ = RunResult{};
  for (auto& e : effects_) e->InitialPose(world_, ctx_);
  mj_kinematics(m, d);
  for (auto& e : effects_) e->Reset(world_, ctx_);
  world_.MarkStart();

  for (int w = 0; w < mjNWARNING; ++w) warnings_seen_[w] = d->warning[w].number;
  const RobotInfo& r = world_.robot();
  start_pos_ = BasePos(d, r);
  up0_ = BaseAxis(d, r, 2);
  turn_over_cos_ = std::cos(scenario_.fall.turn_over_deg * M_PI / 180.0);
  forward0_ = BaseAxis(d, r, 0);
  const Eigen::Vector3d g = world_.gravity();
  down_ = g.norm() > 0 ? Eigen::Vector3d(g.normalized()) : Eigen::Vector3d(0, 0, -1);
  highest_ = -down_.dot(start_pos_);
  touched_s_ = d->time;
}

bool Simulation::Step() {
  mjModel* m = world_.model();
  mjData* d = world_.data();
  ctx_.time_s = d->time;
  for (Effect* e : before_) e->BeforeStep(world_, ctx_);
  mj_step(m, d);
  for (Effect* e : after_) e->AfterStep(world_, ctx_);
  ++ctx_.step;
  return Monitor();
}

namespace {
using ProfileClock = std::chrono::steady_clock;

// Seconds since *t, and *t moved to now: one lap of the profile.
double Lap(ProfileClock::time_point* t) {
  const ProfileClock::time_point now = ProfileClock::now();
  const double s = std::chrono::duration<double>(now - *t).count();
  *t = now;
  return s;
}
}  // namespace

double Simulation::Profile::LapSeconds() {
  constexpr int kBatches = 10, kLaps = 1000;
  double least = std::numeric_limits<double>::infinity();
  for (int b = 0; b < kBatches; ++b) {
    ProfileClock::time_point t = ProfileClock::now();
    double sum = 0.0;
    for (int k = 0; k < kLaps; ++k) sum += Lap(&t);
    least = std::min(least, sum / kLaps);
  }
  return least;
}

bool Simulation::StepProfiled(Profile* p) {
  mjModel* m = world_.model();
  mjData* d = world_.data();
  if (p->effect_s.size() != effects_.size()) p->effect_s.assign(effects_.size(), 0.0);
  ctx_.time_s = d->time;
  ProfileClock::time_point t = ProfileClock::now();
  for (size_t i = 0; i < effects_.size(); ++i) {
    if (!effects_[i]->has_before_step()) continue;
    effects_[i]->BeforeStep(world_, ctx_);
    p->effect_s[i] += Lap(&t);
  }
  mj_step(m, d);
  p->mj_step_s += Lap(&t);
  for (size_t i = 0; i < effects_.size(); ++i) {
    if (!effects_[i]->has_after_step()) continue;
    effects_[i]->AfterStep(world_, ctx_);
    p->effect_s[i] += Lap(&t);
  }
  ++ctx_.step;
  const bool ok = Monitor();
  p->monitor_s += Lap(&t);
  ++p->steps;
  return ok;
}

double Simulation::Heading() const {
  // The body's forward axis turned about the start surface normal.
  const Eigen::Vector3d f = BaseAxis(world_.data(), world_.robot(), 0);
  const Eigen::Vector3d side = up0_.cross(forward0_);
  return std::atan2(f.dot(side), f.dot(forward0_)) * 180.0 / M_PI;
}

bool Simulation::Monitor() {
  const mjData* d = world_.data();
  const double t = ctx_.time_s + world_.model()->opt.timestep;
  for (mjtWarning w : kFatalWarnings) {
    if (d->warning[w].number > warnings_seen_[w]) {
      char buf[256];
      std::snprintf(buf, sizeof(buf), "step %ld, t = %.6f s: %s at index %d", ctx_.step, t,
                    WarningName(w), d->warning[w].lastinfo);
      result_.stable = false;
      result_.failure = buf;  // the run ends here; these allocations are fine
      if (const std::string m = TakeMujocoWarning(); !m.empty()) {
        result_.failure += " (MuJoCo: " + m + ")";
      }
      return false;
    }
  }
  // Mechanical work of the actuators (positive and negative alike cost a servo energy).
  const mjModel* m = world_.model();
  double power_w = 0.0;
  for (int i = 0; i < m->nu; ++i)
    power_w += std::abs(d->actuator_force[i] * d->actuator_velocity[i]);
  result_.actuator_work_j += power_w * m->opt.timestep;

  const RobotInfo& r = world_.robot();
  const Eigen::Vector3d pos = BasePos(d, r);
  if (!pos.allFinite()) {
    char buf[128];
    std::snprintf(buf, sizeof(buf), "step %ld, t = %.6f s: base position is not finite",
                  ctx_.step, t);
    result_.stable = false;
    result_.failure = buf;
    return false;
  }
  if (!result_.fell) {
    const double height = -down_.dot(pos);
    highest_ = std::max(highest_, height);
    const bool dropped = highest_ - height > scenario_.fall.drop_m;
    const bool turned_over = BaseAxis(d, r, 2).dot(up0_) < turn_over_cos_;
    if (TouchesScene(world_.model(), d, r)) touched_s_ = t;
    const bool left = t - touched_s_ > scenario_.fall.airborne_s;
    if (dropped || turned_over || left) {
      result_.fell = true;
      result_.fall_time_s = t;
      result_.fall_cause = dropped ? "dropped" : turned_over ? "turned_over" : "left_surface";
      fall_pos_ = pos;
      fall_heading_deg_ = Heading();
      if (scenario_.fall.stop) return false;
    }
  }
  return true;
}

RunResult Simulation::Run(const std::function<void(double)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  const long report_every = std::max<long>(1, steps_total_ / 200);
  while (ctx_.step < steps_total_) {
    if (!Step()) break;
    if (progress && ctx_.step % report_every == 0) {
      progress(static_cast<double>(ctx_.step) / steps_total_);
    }
  }
  const std::chrono::duration<double> wall = std::chrono::steady_clock::now() - start;
  UpdateResult(wall.count());
  if (progress) progress(1.0);
  return result_;
}

void Simulation::UpdateResult(double wall_time_s) {
  const mjData* d = world_.data();
  const RobotInfo& r = world_.robot();
  result_.steps = ctx_.step;
  result_.sim_time_s = ctx_.step * world_.model()->opt.timestep;
  result_.wall_time_s = wall_time_s;
  if (result_.stable) {
    const Eigen::Vector3d& travel = world_.scene().travel;
    result_.distance_at_end_m = travel.dot(BasePos(d, r) - start_pos_);
    result_.distance_m =
        result_.fell ? travel.dot(fall_pos_ - start_pos_) : result_.distance_at_end_m;
    result_.heading_deg = result_.fell ? fall_heading_deg_ : Heading();
  }
}

nlohmann::json Simulation::Summary() const {
  nlohmann::json j;
  j["scenario"] = scenario_.source_file;
  j["robot"] = scenario_.robot;
  j["scene"] = scenario_.scene.name;
  j["duration_s"] = result_.sim_time_s;
  j["steps"] = result_.steps;
  j["timestep_s"] = world_.model()->opt.timestep;
  j["wall_time_s"] = result_.wall_time_s;
  j["realtime_factor"] =
      result_.wall_time_s > 0 ? result_.sim_time_s / result_.wall_time_s : 0.0;
  j["stable"] = result_.stable;
  j["failure"] = result_.failure;
  j["distance_m"] = result_.distance_m;
  j["mean_speed_mps"] = result_.mean_speed_mps();
  j["heading_deg"] = result_.heading_deg;
  j["fell"] = result_.fell;
  j["fall_time_s"] = result_.fell ? nlohmann::json(result_.fall_time_s) : nlohmann::json();
  if (result_.fell) {
    // How: the fall criterion that fired, and whether the run went on after it.
    j["fall_cause"] = result_.fall_cause;
    j["fall_stopped_run"] = scenario_.fall.stop;
    if (!scenario_.fall.stop) j["distance_at_end_m"] = result_.distance_at_end_m;
  }
  // A gait that froze (CpgEffect::Summarise overwrites these when it did).
  j["stalled"] = false;
  j["robot_mass_kg"] = world_.robot().mass_kg;
  j["actuator_work_j"] = result_.actuator_work_j;
  // Cost of transport: work per weight and distance (distance floored at 1 mm).
  j["cost_of_transport"] = result_.actuator_work_j /
                           (world_.robot().mass_kg * world_.gravity().norm() *
                            std::max(result_.distance_m, 1e-3));
  nlohmann::json names = nlohmann::json::array();
  for (const auto& e : effects_) names.push_back(e->name());
  j["effects"] = names;
  j["events"] = events_.rows().size();
  j["events_dropped"] = events_.dropped();
  for (const auto& e : effects_) e->Summarise(world_, &j);
  return j;
}

std::string Simulation::TrajectoryCsv() const {
  return trajectory_ != nullptr ? trajectory_->ToCsv() : std::string();
}

std::string Simulation::EventsCsv() const { return events_.ToCsv(world_.model()); }

std::vector<std::string> ScenarioInputs(const Scenario& s) {
  std::vector<std::string> inputs{s.source_file};
  if (s.robot.find('/') != std::string::npos) inputs.push_back(RobotFile(s));
  if (s.scene.name.find('/') != std::string::npos) inputs.push_back(SceneFile(s));
  return inputs;
}

void WriteRunFiles(const std::string& dir, const Simulation& sim, const nlohmann::json& extra) {
  common::WriteFileAtomic(dir + "/scenario.yaml", ScenarioToYamlText(sim.scenario()));
  // model.xml and the mesh files it reads, in meshes/ beside it: the folder travels.
  const CarriedModel model = CarryMeshes(sim.world().Xml());
  if (!model.meshes.empty()) std::filesystem::create_directories(dir + "/" + kRunMeshDir);
  for (const CarriedModel::Mesh& mesh : model.meshes) {
    std::ifstream in(mesh.source, std::ios::binary);
    if (!in) throw std::runtime_error("cannot read the mesh file " + mesh.source);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    common::WriteFileAtomic(dir + "/" + kRunMeshDir + mesh.name, bytes.str());
  }
  common::WriteFileAtomic(dir + "/model.xml", model.xml);
  const std::string traj = sim.TrajectoryCsv();
  if (!traj.empty()) common::WriteFileAtomic(dir + "/trajectory.csv", traj);
  common::WriteFileAtomic(dir + "/events.csv", sim.EventsCsv());
  // The summary last: its presence says the run directory is complete.
  nlohmann::json summary = sim.Summary();
  summary.update(extra);
  common::WriteFileAtomic(dir + "/summary.json", summary.dump(2) + "\n");
}

void WriteRunDirectory(const std::string& dir, const Simulation& sim, const nlohmann::json& extra,
                       bool force) {
  RunFolder folder(
      dir, {.made_by = "simulate", .force = force, .inputs = ScenarioInputs(sim.scenario())});
  WriteRunFiles(folder.path(), sim, extra);
  folder.Commit();
}

}  // namespace climbsim::sim
