// climbsim._core: the Python bindings (pybind11 + NumPy). Scenarios from files, YAML text or
// dicts (climbsim/__init__.py), runs with their trajectory, events and summary as NumPy
// arrays and dicts, a controller written in Python (the C++ interface of sim/controller.h
// through a trampoline), optimise and pulloff. docs/python.md shows the use.
//
// As strict as the command line: every argument and setter is checked by the rule the
// scenario loader or the CLI applies to the same key, and refused with climbsim.InputError
// (a ValueError) naming the key and the value. Nothing handed to Python points into a run's
// buffers (python/tick_objects.h).
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <yaml-cpp/yaml.h>

#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <optional>

#include "adhesion/adhesion.h"
#include "experiments/experiments.h"
#include "experiments/option_ranges.h"
#include "python/adhesion_bindings.h"
#include "python/scenario_keys.h"
#include "python/tick_objects.h"
#include "sim/sim.h"
#include "sim/trajectory.h"
#include "scenario/yaml_reader.h"

namespace py = pybind11;

namespace climbsim::python {
namespace {

using sim::Command;
using sim::Controller;
using sim::ExactNumber;
using sim::Observation;
using sim::StartPose;

py::object FromJson(const nlohmann::json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

void CheckFinite(const char* where, const char* key, double v) {
  if (!std::isfinite(v)) {
    throw InputError(where, 0, 0, key, "must be finite, got " + ExactNumber(v));
  }
}

// Sets one top-level key of `s` through the scenario loader: the checks and messages of a
// file (the key and the value; no line, since the value came from Python). Every other key
// keeps its value and the place it was read at.
void SetScenarioKey(sim::Scenario* s, const std::string& key, const YAML::Node& value) {
  YAML::Node root = sim::ScenarioToYaml(*s);
  root[key] = value;
  sim::Scenario next = sim::ParseScenario(root, s->source_file);
  sim::SourceMap places = s->places;
  places[key] = sim::SourcePlace{};
  next.places = std::move(places);
  *s = std::move(next);
}

// A double as the resolved scenario writes it (bit for bit), or YAML's .nan / .inf, which the
// loader then refuses by name.
YAML::Node YamlNumber(double v) {
  return std::isfinite(v) ? YAML::Node(ExactNumber(v)) : YAML::Node(v);
}

// The trampoline: a Python subclass of climbsim.Controller overrides update (and optionally
// reset, initial_pose, control_period_s, name). The callbacks get tick objects
// (tick_objects.h), expired when they return.
class PyController : public Controller {
 public:
  using Controller::Controller;
  const char* name() const override {
    py::gil_scoped_acquire gil;
    py::function f = py::get_override(static_cast<const Controller*>(this), "name");
    if (f) {
      name_ = f().cast<std::string>();
      return name_.c_str();
    }
    return "python";
  }
  double control_period_s() const override {
    PYBIND11_OVERRIDE_NAME(double, Controller, "control_period_s", control_period_s);
  }
  void InitialPose(StartPose* pose) override {
    py::gil_scoped_acquire gil;
    py::function f = py::get_override(static_cast<const Controller*>(this), "initial_pose");
    if (!f) return;
    TickScope<TickPose> p(pose);
    f(p.object());
    p.tick().Flush();
  }
  void Reset() override { PYBIND11_OVERRIDE_NAME(void, Controller, "reset", Reset); }
  void Update(const Observation& obs, Command* cmd) override {
    py::gil_scoped_acquire gil;
    py::function f = py::get_override(static_cast<const Controller*>(this), "update");
    if (!f) throw py::type_error("a climbsim.Controller must override update(obs, cmd)");
    TickScope<TickObservation> o(&obs);
    TickScope<TickCommand> c(cmd);
    f(o.object(), c.object());
    c.tick().Flush();
  }

 private:
  mutable std::string name_;
};

// A Simulation with its compiled model and the controller it runs, stepped from Python. Its
// result (summary(), write()) is brought up to the steps done, and step() says False once
// the run has ended, as run() would have ended it: the duration reached, or Step() said stop.
class PySimulation {
 public:
  PySimulation(const sim::Scenario& scenario, std::shared_ptr<Controller> controller)
      : model_(sim::CompileScenario(scenario)), controller_(std::move(controller)) {
    sim_ = std::make_unique<sim::Simulation>(scenario, *model_, controller_);
  }

  bool Step() {
    const Busy busy(this);
    CheckNotInterrupted();
    if (done_) return false;
    const auto start = Clock::now();
    const bool go_on = steps_ < sim_->steps_total() && sim_->Step();
    if (go_on) ++steps_;
    wall_s_ += Seconds(start);
    if (!go_on || steps_ >= sim_->steps_total()) Finish();
    return !done_;
  }
  py::object Run() {
    const Busy busy(this);
    CheckNotInterrupted();
    if (!done_) {
      const auto start = Clock::now();
      sim_->Run();  // on from the steps done
      wall_s_ += Seconds(start);
      Finish();
    }
    return FromJson(sim_->Summary());
  }
  void Reset() {
    const Busy busy(this);
    sim_->Reset();
    steps_ = 0;
    wall_s_ = 0.0;
    done_ = false;
    interrupted_ = false;
  }
  // The simulation with its result up to the steps done.
  const sim::Simulation& Current() {
    if (!done_) sim_->UpdateResult(wall_s_);
    return *sim_;
  }
  const sim::Simulation& get() const { return *sim_; }
  py::dict Trajectory() const;
  py::dict Events() const;

 private:
  using Clock = std::chrono::steady_clock;
  // Marks a step, run or reset in progress: a controller callback that calls one of them on
  // its own simulation would step or reset the run in the middle of a step. An exception
  // that leaves one (raised by a callback) leaves the run part way through a step: it is
  // marked interrupted, and only reset() goes on from there.
  class Busy {
   public:
    explicit Busy(PySimulation* s) : s_(s), exceptions_(std::uncaught_exceptions()) {
      if (s_->busy_) {
        throw std::runtime_error(
            "Simulation.step/run/reset called from a callback of its own controller");
      }
      s_->busy_ = true;
    }
    ~Busy() {
      s_->busy_ = false;
      if (std::uncaught_exceptions() > exceptions_) s_->interrupted_ = true;
    }
    Busy(const Busy&) = delete;
    Busy& operator=(const Busy&) = delete;

   private:
    PySimulation* s_;
    int exceptions_;
  };
  void CheckNotInterrupted() const {
    if (interrupted_) {
      throw std::runtime_error(
          "this simulation stopped part way through a step (an exception in a controller "
          "callback): reset() to run it again");
    }
  }
  static double Seconds(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
  }
  void Finish() {
    done_ = true;
    sim_->UpdateResult(wall_s_);
  }

  std::unique_ptr<sim::CompiledModel> model_;
  std::shared_ptr<Controller> controller_;
  std::unique_ptr<sim::Simulation> sim_;
  long steps_ = 0;            // steps done since the last reset
  double wall_s_ = 0.0;       // the time they took
  bool done_ = false;         // the run has ended
  bool busy_ = false;         // see Busy
  bool interrupted_ = false;  // see Busy
};

py::dict PySimulation::Trajectory() const {
  py::dict out;
  const sim::TrajectoryRecorder* t = sim_->trajectory();
  if (t == nullptr) return out;
  const size_t cols = t->columns().size();
  const size_t rows = cols ? t->rows().size() / cols : 0;
  for (size_t c = 0; c < cols; ++c) {
    py::array_t<double> a(static_cast<py::ssize_t>(rows));
    auto v = a.mutable_unchecked<1>();
    for (size_t r = 0; r < rows; ++r) v(r) = t->rows()[r * cols + c];
    out[py::str(t->columns()[c])] = a;
  }
  return out;
}

py::dict PySimulation::Events() const {
  const auto& rows = sim_->events().rows();
  const auto& pads = sim_->events().pad_names();
  const py::ssize_t n = static_cast<py::ssize_t>(rows.size());
  py::array_t<double> time(n), bonded(n);
  py::array_t<int> pad(n);
  py::array_t<double> load({n, static_cast<py::ssize_t>(5)});
  py::list pad_name, kind, cause;
  for (py::ssize_t i = 0; i < n; ++i) {
    const sim::Event& e = rows[i];
    time.mutable_at(i) = e.time_s;
    bonded.mutable_at(i) = e.bonded_fraction;
    pad.mutable_at(i) = e.pad;
    for (int k = 0; k < 5; ++k) load.mutable_at(i, k) = e.load[k];
    pad_name.append(e.pad >= 0 && e.pad < static_cast<int>(pads.size()) ? pads[e.pad] : "");
    kind.append(e.kind);
    cause.append(e.cause);
  }
  py::module_ np = py::module_::import("numpy");
  py::dict out;
  out["time_s"] = time;
  out["pad"] = pad;
  out["pad_name"] = np.attr("array")(pad_name, "U");
  out["event"] = np.attr("array")(kind, "U");
  out["cause"] = np.attr("array")(cause, "U");
  out["bonded_fraction"] = bonded;
  out["load"] = load;  // fn_n, fx_n, fy_n, mx_nm, my_nm in the pad frame
  return out;
}

// A C++ controller with the same law as bench_controller.py's Python one, for measuring what
// a Python controller costs: a sine offset on every hip_pitch, on top of whatever runs.
class SineOffsetController final : public Controller {
 public:
  SineOffsetController(double amplitude_rad, double frequency_hz, double period_s)
      : amplitude_(amplitude_rad), frequency_(frequency_hz), period_(period_s) {}
  const char* name() const override { return "sine_offset"; }
  double control_period_s() const override { return period_; }
  void Update(const Observation& obs, Command* cmd) override {
    const double v = amplitude_ * std::sin(2 * M_PI * frequency_ * obs.time_s);
    for (int leg = 0; leg < obs.legs; ++leg) cmd->offset_rad[3 * leg + 1] = v;
  }

 private:
  double amplitude_, frequency_, period_;
};

py::dict CommandDict(const Command& c) {
  py::dict d;
  d["target_rad"] = py::array_t<double>(c.target_rad.size(), c.target_rad.data());
  d["offset_rad"] = py::array_t<double>(c.offset_rad.size(), c.offset_rad.data());
  d["release"] = py::array_t<uint8_t>(c.release.size(), c.release.data());
  d["kp_scale"] = py::array_t<double>(c.kp_scale.size(), c.kp_scale.data());
  return d;
}

void BindScenario(py::module_& m) {
  py::class_<sim::Scenario> cls(m, "Scenario", R"doc(
A scenario: s["cpg.frequency_hz"] reads and s["cpg.frequency_hz"] = 0.8 writes any key of the
file, dotted as optimise parameters and --set are (cpg.stride_rad[0]); a write is checked as
the file's and raises climbsim.InputError with its text. get, keys, `in`, del, to_dict.)doc");
  BindScenarioKeys(cls);
  cls.def_property(
          "duration_s", [](const sim::Scenario& s) { return s.duration_s; },
          [](sim::Scenario& s, double v) { SetScenarioKey(&s, "duration_s", YamlNumber(v)); },
          "Simulated time (s), checked like the file's key.")
      .def_property(
          "robot", [](const sim::Scenario& s) { return s.robot; },
          [](sim::Scenario& s, const std::string& v) {
            SetScenarioKey(&s, "robot", YAML::Node(v));
          },
          "gecko, spider, or an MJCF file (relative to the scenario's folder).")
      .def_readonly("source_file", &sim::Scenario::source_file)
      .def(
          "to_yaml", [](const sim::Scenario& s) { return sim::ScenarioToYamlText(s); },
          "The resolved scenario (every key, defaults filled in) as YAML text.");

  m.def("load_scenario", &sim::LoadScenario, py::arg("path"),
        "A scenario file (raises climbsim.InputError with file:line:col on bad input).");
  m.def(
      "scenario_from_yaml",
      [](const std::string& text, const std::string& name) {
        const std::string file = std::filesystem::absolute(name).string();
        return sim::ParseScenario(sim::LoadYamlText(text, name), file);
      },
      py::arg("text"), py::arg("name") = "scenario.yaml",
      "A scenario from YAML text, checked like a file; `name` is its file name in messages and "
      "the folder that relative paths resolve against.");
  m.def("mjcf_dir", &sim::MjcfDir, "The folder of the bundled MJCF models.");
}

void BindTickObjects(py::module_& m) {
  py::class_<sim::PadSense>(m, "PadSense")
      .def_readonly("touching", &sim::PadSense::touching)
      .def_readonly("attached", &sim::PadSense::attached)
      .def_readonly("bonded_fraction", &sim::PadSense::bonded_fraction)
      .def_readonly("normal_load_n", &sim::PadSense::normal_load_n)
      .def_readonly("preload_n", &sim::PadSense::preload_n)
      .def_readonly("utilisation", &sim::PadSense::utilisation);

  using O = TickObservation;
  auto array = [](auto member) {
    return [member](const O& o) { return ReadOnlyCopy(o.get().*member); };
  };
  py::class_<O>(m, "Observation", "What update() reads; read-only copies, for its call only.")
      .def_property_readonly("step", [](const O& o) { return o.get().step; })
      .def_property_readonly("time_s", [](const O& o) { return o.get().time_s; })
      .def_property_readonly("legs", [](const O& o) { return o.get().legs; })
      .def_property_readonly("joint_angle_rad", array(&Observation::joint_angle_rad))
      .def_property_readonly("joint_velocity_rad_s", array(&Observation::joint_velocity_rad_s))
      .def_property_readonly("base_pos_m", array(&Observation::base_pos_m))
      .def_property_readonly("base_quat", array(&Observation::base_quat))
      .def_property_readonly("base_linvel_m_s", array(&Observation::base_linvel_m_s))
      .def_property_readonly("base_angvel_rad_s", array(&Observation::base_angvel_rad_s))
      .def_property_readonly("cpg_phase_rad", array(&Observation::cpg_phase_rad))
      .def_property_readonly("cpg_stance", array(&Observation::cpg_stance))
      .def_property_readonly("pads",
                             [](const O& o) {
                               const auto& pads = o.get().pads;
                               return std::vector<sim::PadSense>(pads.begin(), pads.end());
                             })
      .def_property_readonly("bonded_fraction",
                             [](const O& o) {
                               const auto& pads = o.get().pads;
                               py::array_t<double> a(static_cast<py::ssize_t>(pads.size()));
                               for (size_t i = 0; i < pads.size(); ++i)
                                 a.mutable_at(i) = pads[i].bonded_fraction;
                               return a;
                             })
      .def_property_readonly("attached", [](const O& o) {
        const auto& pads = o.get().pads;
        py::array_t<bool> a(static_cast<py::ssize_t>(pads.size()));
        for (size_t i = 0; i < pads.size(); ++i) a.mutable_at(i) = pads[i].attached;
        return a;
      });

  py::class_<TickCommand>(m, "Command", "What update() writes, for its call only.")
      .def_property_readonly("target_rad", &TickCommand::target)
      .def_property_readonly("offset_rad", &TickCommand::offset)
      .def_property_readonly("release", &TickCommand::release)
      .def_property_readonly("kp_scale", &TickCommand::kp_scale,
                             "Servo stiffness over its own kp, legs x 3, clamped to [0, 1]; "
                             "held from tick to tick (the reflexes' compliance and GTO write "
                             "it when the scenario has them).");

  py::class_<TickPose>(m, "StartPose", "What initial_pose() writes, for its call only.")
      .def_property_readonly("joint_angle_rad", &TickPose::joints)
      .def_property_readonly("base_pos_m", &TickPose::base);
}

void BindController(py::module_& m) {
  py::class_<Controller, PyController, std::shared_ptr<Controller>>(m, "Controller", R"doc(
Subclass and override update(self, obs, cmd); optionally reset(self), initial_pose(self, pose),
control_period_s(self) (used when the scenario has no cpg block; 0 = every step, else a whole
multiple of the time step) and name(self). cmd arrives holding the built-in CPG's targets when
the scenario has a cpg block (write cmd.offset_rad to act on top of it, or cmd.target_rad to
replace it), else the targets held since the last tick. obs, cmd and pose are valid during the
call only; their arrays are copies (cmd's and pose's are written back when the call returns).)doc")
      .def(py::init<>())
      .def("update", [](Controller& c, const TickObservation& o,
                        TickCommand& cmd) { c.Update(o.get(), &cmd.Flushed()); })
      .def("reset", &Controller::Reset)
      .def("initial_pose", [](Controller& c, TickPose& p) { c.InitialPose(&p.Flushed()); })
      .def("control_period_s", &Controller::control_period_s)
      .def("name", [](const Controller& c) { return std::string(c.name()); });

  py::class_<SineOffsetController, Controller, std::shared_ptr<SineOffsetController>>(
      m, "SineOffsetController",
      "C++ reference controller: offset a·sin(2πft) on every hip_pitch (for benchmarks).")
      .def(py::init([](double amplitude_rad, double frequency_hz, double period_s) {
             const char* where = "climbsim.SineOffsetController";
             CheckFinite(where, "amplitude_rad", amplitude_rad);
             CheckFinite(where, "frequency_hz", frequency_hz);
             // period_s: checked with the run's time step by sim::Simulation.
             return std::make_shared<SineOffsetController>(amplitude_rad, frequency_hz, period_s);
           }),
           py::arg("amplitude_rad"), py::arg("frequency_hz"), py::arg("period_s") = 0.0);
}

void BindSimulation(py::module_& m) {
  py::class_<PySimulation>(m, "Simulation")
      .def(py::init<const sim::Scenario&, std::shared_ptr<Controller>>(), py::arg("scenario"),
           py::arg("controller") = nullptr, py::keep_alive<1, 3>())
      .def("reset", &PySimulation::Reset, "Back to t = 0: a fresh run.")
      .def("step", &PySimulation::Step,
           "One physics step. False once the run has ended (the step that reached the duration, "
           "or a fall with fall.stop, or numerically unstable; then no more steps are taken): "
           "`while sim.step(): ...` runs what run() runs.")
      .def("run", &PySimulation::Run,
           "Steps on to the scenario's duration (or until the run must stop); returns the "
           "summary.")
      .def(
          "summary", [](PySimulation& s) { return FromJson(s.Current().Summary()); },
          "The summary of the steps done (summary.json): after the last step, run()'s.")
      .def("trajectory", &PySimulation::Trajectory,
           "Recorded trajectory: dict column -> 1-D array (the columns of trajectory.csv).")
      .def("events", &PySimulation::Events, "Events: dict column -> 1-D array (events.csv).")
      .def(
          "write",
          [](PySimulation& s, const std::string& dir) { sim::WriteRunDirectory(dir, s.Current()); },
          py::arg("dir"), "Writes the run folder (scenario.yaml, model.xml, trajectory.csv, ...).")
      .def_property_readonly("time_s",
                             [](const PySimulation& s) { return s.get().world().data()->time; })
      .def_property_readonly("steps_total",
                             [](const PySimulation& s) { return s.get().steps_total(); })
      .def_property_readonly("qpos",
                             [](const PySimulation& s) {
                               const mjData* d = s.get().world().data();
                               return py::array_t<double>(s.get().world().model()->nq, d->qpos);
                             })
      .def_property_readonly("control_period_steps",
                             [](const PySimulation& s) {
                               const auto* c = s.get().controller();
                               return c ? c->period_steps() : 0;
                             })
      .def_property_readonly("control_ticks",
                             [](const PySimulation& s) {
                               const auto* c = s.get().controller();
                               return c ? c->ticks() : 0L;
                             })
      .def(
          "command",
          [](const PySimulation& s) -> py::object {
            const auto* c = s.get().controller();
            if (c == nullptr) return py::none();
            return CommandDict(c->command());
          },
          "The last command applied (copies): target_rad, offset_rad, release, kp_scale.");
}

py::dict Optimise(const std::string& scenario_file, const std::string& out_dir, long long threads,
                  std::optional<long long> max_evaluations) {
  // The ranges of `climbsim optimise --threads / --max-evaluations` (None: the file's).
  optimise::CheckInRange("climbsim.optimise", "threads", threads, optimise::kThreadsRange);
  if (max_evaluations) {
    optimise::CheckInRange("climbsim.optimise", "max_evaluations", *max_evaluations,
                           optimise::kMaxEvaluationsRange);
  }
  optimise::Options o;
  o.out_dir = out_dir;
  o.threads = static_cast<int>(threads);
  o.max_evaluations = static_cast<int>(max_evaluations.value_or(0));
  o.quiet = true;
  optimise::Result r;
  {
    py::gil_scoped_release release;
    r = optimise::Optimise(scenario_file, o);
  }
  py::dict d;
  d["best_objective"] = r.best.objective;
  d["best_x"] = py::array_t<double>(r.best.x.size(), r.best.x.data());
  d["start_objective"] = r.start_objective;
  d["evaluations"] = r.history.size();
  py::array_t<double> history(static_cast<py::ssize_t>(r.history.size()));
  for (size_t i = 0; i < r.history.size(); ++i) history.mutable_at(i) = r.history[i].objective;
  d["history_objective"] = history;
  d["wall_time_s"] = r.wall_time_s;
  return d;
}

void BindTools(py::module_& m) {
  m.def("optimise", &Optimise, py::arg("scenario_file"), py::arg("out_dir"), py::arg("threads") = 0,
        py::arg("max_evaluations") = py::none(),
        "`climbsim optimise`: writes out_dir like the command does and returns the best. "
        "threads 0: the cores; max_evaluations None: the file's optimise.max_evaluations.");
}

}  // namespace
}  // namespace climbsim::python

PYBIND11_MODULE(_core, m) {
  using namespace climbsim::python;
  m.doc() = "climbsim: climbing robots with adhesive pads in MuJoCo (docs/python.md)";
  py::register_exception<climbsim::InputError>(m, "InputError", PyExc_ValueError);
  BindScenario(m);
  BindTickObjects(m);
  BindController(m);
  BindSimulation(m);
  BindTools(m);
  BindAdhesion(m);  // python/adhesion_bindings.h: pulloff (any law), fit_adhesion
}
