// climbsim._core: the Python bindings (pybind11 + NumPy). Scenarios from files, YAML text or
// dicts (climbsim/__init__.py), runs with their trajectory, events and summary as NumPy
// arrays and dicts, a controller written in Python (the C++ interface of sim/controller.h
// through a trampoline), optimise and pulloff. docs/python.md shows the use.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>

#include "adhesion/adhesion.h"
#include "optimise/optimise.h"
#include "sim/sim.h"
#include "sim/trajectory.h"

namespace py = pybind11;

namespace climbsim::python {
namespace {

using sim::Command;
using sim::Controller;
using sim::Observation;
using sim::StartPose;

py::object FromJson(const nlohmann::json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

// A NumPy view of memory owned by `owner` (kept alive by the view).
template <class T>
py::array View(T* data, size_t n, py::handle owner, bool writable) {
  py::array_t<std::remove_const_t<T>> a({static_cast<py::ssize_t>(n)}, {sizeof(T)},
                                        const_cast<std::remove_const_t<T>*>(data), owner);
  if (!writable) a.attr("setflags")(py::arg("write") = false);
  return a;  // moved implicitly (C++20)
}

// The trampoline: a Python subclass of climbsim.Controller overrides update (and optionally
// reset, initial_pose, control_period_s, name).
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
    PYBIND11_OVERRIDE_NAME(void, Controller, "initial_pose", InitialPose, pose);
  }
  void Reset() override { PYBIND11_OVERRIDE_NAME(void, Controller, "reset", Reset); }
  void Update(const Observation& obs, Command* cmd) override {
    PYBIND11_OVERRIDE_PURE_NAME(void, Controller, "update", Update, &obs, cmd);
  }

 private:
  mutable std::string name_;
};

// A Simulation with its compiled model and the Python controller it runs.
class PySimulation {
 public:
  PySimulation(const sim::Scenario& scenario, std::shared_ptr<Controller> controller)
      : model_(sim::CompileScenario(scenario)),
        sim_(std::make_unique<sim::Simulation>(scenario, *model_, controller)),
        controller_(std::move(controller)) {}

  sim::Simulation& get() { return *sim_; }
  const sim::Simulation& get_const() const { return *sim_; }

  py::dict Trajectory() const {
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

  py::dict Events() const {
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

 private:
  std::unique_ptr<sim::CompiledModel> model_;
  std::unique_ptr<sim::Simulation> sim_;
  std::shared_ptr<Controller> controller_;
};

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
  return d;
}

}  // namespace
}  // namespace climbsim::python

PYBIND11_MODULE(_core, m) {
  using namespace climbsim;
  using namespace climbsim::python;
  m.doc() = "climbsim: climbing robots with adhesive pads in MuJoCo (docs/python.md)";

  py::register_exception<InputError>(m, "InputError", PyExc_ValueError);

  py::class_<sim::Scenario>(m, "Scenario")
      .def_readwrite("duration_s", &sim::Scenario::duration_s)
      .def_readwrite("robot", &sim::Scenario::robot)
      .def_readonly("source_file", &sim::Scenario::source_file)
      .def(
          "to_yaml", [](const sim::Scenario& s) { return sim::ScenarioToYamlText(s); },
          "The resolved scenario (every key, defaults filled in) as YAML text.");

  m.def("load_scenario", &sim::LoadScenario, py::arg("path"),
        "A scenario file (raises climbsim.InputError with file:line:col on bad input).");
  m.def(
      "scenario_from_yaml",
      [](const std::string& text, const std::string& name) {
        YAML::Node root;
        try {
          root = YAML::Load(text);
        } catch (const YAML::Exception& e) {
          throw InputError(name, e.mark.line + 1, e.mark.column + 1, "", e.msg);
        }
        const std::string file = std::filesystem::absolute(name).string();
        return sim::ParseScenario(root, file);
      },
      py::arg("text"), py::arg("name") = "scenario.yaml",
      "A scenario from YAML text; `name` is its file name in messages and the folder that "
      "relative paths resolve against.");
  m.def("mjcf_dir", &sim::MjcfDir, "The folder of the bundled MJCF models.");

  // --- Controller interface ---
  py::class_<sim::PadSense>(m, "PadSense")
      .def_readonly("touching", &sim::PadSense::touching)
      .def_readonly("attached", &sim::PadSense::attached)
      .def_readonly("bonded_fraction", &sim::PadSense::bonded_fraction)
      .def_readonly("normal_load_n", &sim::PadSense::normal_load_n)
      .def_readonly("preload_n", &sim::PadSense::preload_n)
      .def_readonly("utilisation", &sim::PadSense::utilisation);

  // NumPy views into the run's buffers: valid for the tick (copy what you keep).
  py::class_<Observation>(m, "Observation")
      .def_readonly("step", &Observation::step)
      .def_readonly("time_s", &Observation::time_s)
      .def_readonly("legs", &Observation::legs)
      .def_property_readonly("joint_angle_rad",
                             [](py::object self) {
                               auto& o = self.cast<const Observation&>();
                               return View(o.joint_angle_rad.data(), o.joint_angle_rad.size(), self,
                                           false);
                             })
      .def_property_readonly("joint_velocity_rad_s",
                             [](py::object self) {
                               auto& o = self.cast<const Observation&>();
                               return View(o.joint_velocity_rad_s.data(),
                                           o.joint_velocity_rad_s.size(), self, false);
                             })
      .def_property_readonly("base_pos_m",
                             [](py::object self) {
                               auto& o = self.cast<const Observation&>();
                               return View(o.base_pos_m.data(), 3, self, false);
                             })
      .def_property_readonly("base_quat",
                             [](py::object self) {
                               auto& o = self.cast<const Observation&>();
                               return View(o.base_quat.data(), 4, self, false);
                             })
      .def_property_readonly("base_linvel_m_s",
                             [](py::object self) {
                               auto& o = self.cast<const Observation&>();
                               return View(o.base_linvel_m_s.data(), 3, self, false);
                             })
      .def_property_readonly("base_angvel_rad_s",
                             [](py::object self) {
                               auto& o = self.cast<const Observation&>();
                               return View(o.base_angvel_rad_s.data(), 3, self, false);
                             })
      .def_property_readonly("cpg_phase_rad",
                             [](py::object self) {
                               auto& o = self.cast<const Observation&>();
                               return View(o.cpg_phase_rad.data(), o.cpg_phase_rad.size(), self,
                                           false);
                             })
      .def_property_readonly("cpg_stance",
                             [](py::object self) {
                               auto& o = self.cast<const Observation&>();
                               return View(o.cpg_stance.data(), o.cpg_stance.size(), self, false);
                             })
      .def_property_readonly("pads",
                             [](const Observation& o) {
                               return std::vector<sim::PadSense>(o.pads.begin(), o.pads.end());
                             })
      .def_property_readonly("bonded_fraction",
                             [](const Observation& o) {
                               py::array_t<double> a(static_cast<py::ssize_t>(o.pads.size()));
                               for (size_t i = 0; i < o.pads.size(); ++i)
                                 a.mutable_at(i) = o.pads[i].bonded_fraction;
                               return a;
                             })
      .def_property_readonly("attached", [](const Observation& o) {
        py::array_t<bool> a(static_cast<py::ssize_t>(o.pads.size()));
        for (size_t i = 0; i < o.pads.size(); ++i) a.mutable_at(i) = o.pads[i].attached;
        return a;
      });

  py::class_<Command>(m, "Command")
      .def_property_readonly("target_rad",
                             [](py::object self) {
                               auto& c = self.cast<Command&>();
                               return View(c.target_rad.data(), c.target_rad.size(), self, true);
                             })
      .def_property_readonly("offset_rad",
                             [](py::object self) {
                               auto& c = self.cast<Command&>();
                               return View(c.offset_rad.data(), c.offset_rad.size(), self, true);
                             })
      .def_property_readonly("release", [](py::object self) {
        auto& c = self.cast<Command&>();
        return View(c.release.data(), c.release.size(), self, true);
      });

  py::class_<StartPose>(m, "StartPose")
      .def_property_readonly("joint_angle_rad",
                             [](py::object self) {
                               auto& p = self.cast<StartPose&>();
                               return View(p.joint_angle_rad.data(), p.joint_angle_rad.size(), self,
                                           true);
                             })
      .def_property_readonly("base_pos_m", [](py::object self) {
        auto& p = self.cast<StartPose&>();
        return View(p.base_pos_m.data(), 3, self, true);
      });

  py::class_<Controller, PyController, std::shared_ptr<Controller>>(m, "Controller", R"doc(
Subclass and override update(self, obs, cmd); optionally reset(self), initial_pose(self, pose),
control_period_s(self) (used when the scenario has no cpg block; 0 = every step) and
name(self). cmd arrives holding the built-in CPG's targets when the scenario has a cpg block
(write cmd.offset_rad to act on top of it, or cmd.target_rad to replace it), else the targets
held since the last tick.)doc")
      .def(py::init<>())
      .def("update", &Controller::Update)
      .def("reset", &Controller::Reset)
      .def("initial_pose", &Controller::InitialPose)
      .def("control_period_s", &Controller::control_period_s)
      .def("name", [](const Controller& c) { return std::string(c.name()); });

  py::class_<SineOffsetController, Controller, std::shared_ptr<SineOffsetController>>(
      m, "SineOffsetController",
      "C++ reference controller: offset a·sin(2πft) on every hip_pitch (for benchmarks).")
      .def(py::init<double, double, double>(), py::arg("amplitude_rad"), py::arg("frequency_hz"),
           py::arg("period_s") = 0.0);

  py::class_<PySimulation>(m, "Simulation")
      .def(py::init<const sim::Scenario&, std::shared_ptr<Controller>>(), py::arg("scenario"),
           py::arg("controller") = nullptr, py::keep_alive<1, 3>())
      .def("reset", [](PySimulation& s) { s.get().Reset(); })
      .def(
          "step", [](PySimulation& s) { return s.get().Step(); },
          "One physics step; False when the run must stop (unstable, or fallen with stop).")
      .def(
          "run",
          [](PySimulation& s) {
            s.get().Run();
            return FromJson(s.get().Summary());
          },
          "Steps to the scenario's duration (or until it must stop); returns the summary.")
      .def("summary", [](const PySimulation& s) { return FromJson(s.get_const().Summary()); })
      .def("trajectory", &PySimulation::Trajectory,
           "Recorded trajectory: dict column -> 1-D array (the columns of trajectory.csv).")
      .def("events", &PySimulation::Events, "Events: dict column -> 1-D array (events.csv).")
      .def(
          "write",
          [](const PySimulation& s, const std::string& dir) {
            sim::WriteRunDirectory(dir, s.get_const());
          },
          py::arg("dir"), "Writes the run folder (scenario.yaml, model.xml, trajectory.csv, ...).")
      .def_property_readonly(
          "time_s", [](const PySimulation& s) { return s.get_const().world().data()->time; })
      .def_property_readonly("steps_total",
                             [](const PySimulation& s) { return s.get_const().steps_total(); })
      .def_property_readonly("qpos",
                             [](const PySimulation& s) {
                               const mjData* d = s.get_const().world().data();
                               return py::array_t<double>(s.get_const().world().model()->nq,
                                                          d->qpos);
                             })
      .def_property_readonly("control_period_steps",
                             [](const PySimulation& s) {
                               const auto* c = s.get_const().controller();
                               return c ? c->period_steps() : 0;
                             })
      .def_property_readonly("control_ticks",
                             [](const PySimulation& s) {
                               const auto* c = s.get_const().controller();
                               return c ? c->ticks() : 0L;
                             })
      .def(
          "command",
          [](const PySimulation& s) -> py::object {
            const auto* c = s.get_const().controller();
            if (c == nullptr) return py::none();
            return CommandDict(c->command());
          },
          "The last command applied (copies): target_rad, offset_rad, release.");

  m.def(
      "optimise",
      [](const std::string& scenario_file, const std::string& out_dir, int threads,
         int max_evaluations) {
        optimise::Options o;
        o.out_dir = out_dir;
        o.threads = threads;
        o.max_evaluations = max_evaluations;
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
        for (size_t i = 0; i < r.history.size(); ++i)
          history.mutable_at(i) = r.history[i].objective;
        d["history_objective"] = history;
        d["wall_time_s"] = r.wall_time_s;
        return d;
      },
      py::arg("scenario_file"), py::arg("out_dir"), py::arg("threads") = 0,
      py::arg("max_evaluations") = 0,
      "`climbsim optimise`: writes out_dir like the command does and returns the best.");

  m.def(
      "pulloff",
      [](double angle_deg, const std::string& model, double width_m, double length_m, int grid,
         double sigma_t_pa, double mu, double arm_m, double ramp_time_s) {
        adhesion::PulloffRigParams p;
        p.pad.width_m = width_m;
        p.pad.length_m = length_m > 0 ? length_m : width_m;
        p.pad.grid_x = p.pad.grid_y = grid;
        p.pad.sigma_t_pa = sigma_t_pa;
        p.pad.mu = mu;
        p.arm_m = arm_m;
        p.ramp_time_s = ramp_time_s;
        if (model != "bonds" && model != "mujoco") {
          throw std::invalid_argument("model must be bonds or mujoco, got " + model);
        }
        adhesion::PulloffRig rig(
            model == "bonds" ? adhesion::AdhesionModel::kBonds : adhesion::AdhesionModel::kMujoco,
            p);
        const adhesion::PulloffRun r = rig.Run(angle_deg * M_PI / 180.0);
        py::dict d;
        d["detached"] = r.detached;
        d["force_n"] = r.force_n;
        d["time_s"] = r.time_s;
        d["cause"] = std::string(r.cause);
        d["capacity_n"] = sigma_t_pa * p.pad.width_m * p.pad.length_m;
        return d;
      },
      py::arg("angle_deg"), py::arg("model") = "bonds", py::arg("width_m") = 0.025,
      py::arg("length_m") = 0.0, py::arg("grid") = 16, py::arg("sigma_t_pa") = 10e3,
      py::arg("mu") = 0.0, py::arg("arm_m") = 0.0, py::arg("ramp_time_s") = 2.0,
      "One pull of `climbsim pulloff`'s rig at angle_deg from the surface: the pull-off "
      "force, the cause and σ_T·A.");
}
