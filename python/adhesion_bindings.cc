// climbsim._core's pad functions: pulloff (one pull of `climbsim pulloff`, any law) and
// fit_adhesion (`climbsim fit-adhesion`, the same fit and the same numbers). Angles are from
// the pad normal everywhere, and the argument says so: angle_from_normal_deg.
#include "python/adhesion_bindings.h"

#include <pybind11/stl.h>

#include <cmath>
#include <optional>

#include "adhesion/adhesion.h"
#include "common/common.h"
#include "experiments/fit_adhesion.h"
#include "experiments/option_ranges.h"

namespace py = pybind11;

namespace climbsim::python {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr const char* kWhere = "climbsim.pulloff";

struct PullArgs {
  double angle_from_normal_deg, azimuth_deg, width_m;
  std::optional<double> length_m;
  long long grid;
  double sigma_t_pa, mu, arm_m, ramp_time_s;
};

adhesion::PulloffRigParams RigParams(const PullArgs& a) {
  using optimise::CheckInRange;
  CheckInRange(kWhere, "angle_from_normal_deg", a.angle_from_normal_deg,
               optimise::kPullAngleRangeDeg);  // --from-deg, --to-deg
  CheckInRange(kWhere, "azimuth_deg", a.azimuth_deg, optimise::kAzimuthRangeDeg);
  CheckInRange(kWhere, "width_m", a.width_m, optimise::kPadWidthRangeM);
  if (a.length_m) CheckInRange(kWhere, "length_m", *a.length_m, optimise::kPadWidthRangeM);
  CheckInRange(kWhere, "grid", a.grid, optimise::kGridRange);
  CheckInRange(kWhere, "sigma_t_pa", a.sigma_t_pa, optimise::kSigmaTRangePa);
  CheckInRange(kWhere, "mu", a.mu, optimise::kMuRange);
  CheckInRange(kWhere, "arm_m", a.arm_m, optimise::kArmRangeM);
  CheckInRange(kWhere, "ramp_time_s", a.ramp_time_s, optimise::kRampTimeRangeS);
  adhesion::PulloffRigParams p;
  p.pad.width_m = a.width_m;
  p.pad.length_m = a.length_m.value_or(a.width_m);
  p.pad.grid_x = p.pad.grid_y = static_cast<int>(a.grid);
  p.pad.sigma_t_pa = a.sigma_t_pa;
  p.pad.mu = a.mu;
  p.arm_m = a.arm_m;
  p.azimuth_rad = a.azimuth_deg * kDeg;
  p.ramp_time_s = a.ramp_time_s;
  return p;
}

// A law's module error (std::invalid_argument naming the key) as the binding's InputError.
template <class F>
auto Checked(const std::string& key, F f) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    throw InputError(kWhere, 0, 0, key, e.what());
  }
}

py::dict QuasiStatic(const adhesion::PulloffResult& r, double capacity_n) {
  py::dict d;
  d["detached"] = r.detaches;
  d["force_n"] = r.force_n;
  d["cause"] = std::string("quasi_static");
  d["capacity_n"] = capacity_n;
  d["rounds"] = r.rounds;
  return d;
}

py::dict Pulloff(double angle_from_normal_deg, const std::string& model, const std::string& law,
                 double width_m, std::optional<double> length_m, long long grid,
                 double sigma_t_pa, double mu, double arm_m, double ramp_time_s,
                 double azimuth_deg, const adhesion::FrictionalParams& frictional,
                 const std::optional<adhesion::TabulatedParams>& table) {
  const adhesion::PulloffRigParams p = RigParams({angle_from_normal_deg, azimuth_deg, width_m,
                                                  length_m, grid, sigma_t_pa, mu, arm_m,
                                                  ramp_time_s});
  const adhesion::PullSetup setup{.angle_rad = angle_from_normal_deg * kDeg,
                                  .azimuth_rad = p.azimuth_rad, .arm_m = arm_m};
  adhesion::PulloffOptions qs;
  qs.max_force_factor = p.max_force_factor;
  if (law == "frictional") {  // quasi-static, as `climbsim pulloff --law frictional`
    return QuasiStatic(Checked("law", [&] {
                         return adhesion::FrictionalPullOff(p.pad, frictional, setup, qs);
                       }),
                       frictional.shear_limit_pa * p.pad.width_m * p.pad.length_m);
  }
  if (law == "tabulated") {
    if (!table) throw InputError(kWhere, 0, 0, "table", "law tabulated needs table=");
    const double area = p.pad.width_m * p.pad.length_m;
    const auto r =
        Checked("table", [&] { return adhesion::TabulatedPullOff(p.pad, *table, setup, qs); });
    return QuasiStatic(r, adhesion::TabulatedLaw(*table).PulloffCentral(area, setup.angle_rad,
                                                                        setup.azimuth_rad));
  }
  if (law != "von_mises") {
    throw InputError(kWhere, 0, 0, "law", "must be von_mises, frictional or tabulated, got " + law);
  }
  if (model != "bonds" && model != "mujoco") {
    throw InputError(kWhere, 0, 0, "model", "must be bonds or mujoco, got " + model);
  }
  adhesion::PulloffRig rig(
      model == "bonds" ? adhesion::AdhesionModel::kBonds : adhesion::AdhesionModel::kMujoco, p);
  const adhesion::PulloffRun r = rig.Run(setup.angle_rad);
  py::dict d;
  d["detached"] = r.detached;
  d["force_n"] = r.force_n;
  d["time_s"] = r.time_s;
  d["cause"] = std::string(r.cause);
  d["capacity_n"] = rig.capacity_n();
  return d;
}

py::dict FitDict(const optimise::AdhesionFit& fit, const optimise::PulloffData& data) {
  py::list parameters;
  for (const optimise::FittedParameter& q : fit.parameters) {
    py::dict p;
    p["key"] = q.key;
    p["unit"] = q.unit;
    p["value"] = q.value;
    p["uncertainty"] = q.uncertainty;
    p["low95"] = q.low95;
    p["high95"] = q.high95;
    parameters.append(p);
  }
  py::dict d;
  d["law"] = fit.law;
  d["parameters"] = parameters;
  d["predicted_n"] = fit.predicted_n;
  d["rms_n"] = fit.rms_n;
  d["worst_n"] = fit.worst_n;
  d["spread_n"] = fit.spread_n;
  d["represents"] = fit.represents;
  d["verdict"] = fit.verdict;
  d["fitted_yaml"] = optimise::FittedYaml(fit, data);
  return d;
}

py::dict FitAdhesion(const std::string& data_file, const std::string& law,
                     std::optional<std::string> out_dir, double width_m, double length_m,
                     long long grid, double grip_deg, double assumed_spread) {
  using optimise::CheckInRange;
  const char* where = "climbsim.fit_adhesion";
  if (width_m != 0) CheckInRange(where, "width_m", width_m, optimise::kPadWidthRangeM);
  if (length_m != 0) CheckInRange(where, "length_m", length_m, optimise::kPadWidthRangeM);
  CheckInRange(where, "grid", grid, optimise::kGridRange);
  CheckInRange(where, "grip_deg", grip_deg, optimise::kAzimuthRangeDeg);
  if (!(assumed_spread >= 0.001 && assumed_spread <= 1.0)) {
    throw InputError(where, 0, 0, "assumed_spread", "must be in [0.001, 1]");
  }
  optimise::FitAdhesionRunOptions o;
  o.data_file = data_file;
  o.width_m = width_m;
  o.length_m = length_m;
  o.quiet = true;
  o.fit.law = law;
  o.fit.grid = static_cast<int>(grid);
  o.fit.grip_deg = grip_deg;
  o.fit.assumed_spread = assumed_spread;
  const optimise::PulloffData data = optimise::ReadPulloffCsv(data_file, width_m, length_m);
  optimise::CheckFitData(data, law);
  if (out_dir) {  // the command's folder too (it fits the same way: the same numbers)
    o.out_dir = *out_dir;
    optimise::RunFitAdhesion(o);
  }
  return FitDict(optimise::FitAdhesion(data, o.fit), data);
}

}  // namespace

void BindAdhesion(py::module_& m) {
  // Replaces the module's first pulloff (von Mises only; its argument did not name the angle's
  // convention): no sibling, so this is the one `pulloff`.
  m.attr("pulloff") = py::cpp_function(
      [](double angle_from_normal_deg, const std::string& model, const std::string& law,
         double width_m, std::optional<double> length_m, long long grid, double sigma_t_pa,
         double mu, double arm_m, double ramp_time_s, double azimuth_deg,
         double critical_angle_deg, double shear_limit_pa, double friction_mu, double grip_deg,
         std::optional<py::dict> table) {
        adhesion::FrictionalParams f;
        f.critical_angle_deg = critical_angle_deg;
        f.shear_limit_pa = shear_limit_pa;
        f.friction_mu = friction_mu;
        f.grip_x = std::cos(grip_deg * kDeg);
        f.grip_y = std::sin(grip_deg * kDeg);
        std::optional<adhesion::TabulatedParams> t;
        if (table) {
          t.emplace();
          for (auto [key, value] : *table) {
            const std::string k = py::str(key);
            if (k == "angle_from_normal_deg") t->angle_from_normal_deg = value.cast<std::vector<double>>();
            else if (k == "azimuth_deg") t->azimuth_deg = value.cast<std::vector<double>>();
            else if (k == "pulloff_n") t->pulloff_n = value.cast<std::vector<double>>();
            else if (k == "width_m") t->width_m = value.cast<double>();
            else if (k == "length_m") t->length_m = value.cast<double>();
            else throw InputError(kWhere, 0, 0, "table", "unknown key '" + k + "'");
          }
        }
        return Pulloff(angle_from_normal_deg, model, law, width_m, length_m, grid, sigma_t_pa, mu,
                       arm_m, ramp_time_s, azimuth_deg, f, t);
      },
      py::name("pulloff"), py::scope(m), py::arg("angle_from_normal_deg"),
      py::arg("model") = "bonds", py::arg("law") = "von_mises", py::arg("width_m") = 0.025,
      py::arg("length_m") = py::none(), py::arg("grid") = 16, py::arg("sigma_t_pa") = 10e3,
      py::arg("mu") = 0.0, py::arg("arm_m") = 0.0, py::arg("ramp_time_s") = 2.0,
      py::arg("azimuth_deg") = 0.0, py::arg("critical_angle_deg") = 30.0,
      py::arg("shear_limit_pa") = 10e3, py::arg("friction_mu") = 1.0, py::arg("grip_deg") = 0.0,
      py::arg("table") = py::none(),
      "One pull at angle_from_normal_deg from the pad NORMAL (0 pulls straight off, 90 shears, "
      "180 pushes; 0..180), its in-plane part at azimuth_deg from pad +x towards +y. law "
      "von_mises: `climbsim pulloff`'s MuJoCo rig (model bonds or mujoco): force_n, time_s, "
      "cause, capacity_n = sigma_T*A. law frictional (critical_angle_deg, shear_limit_pa, "
      "friction_mu, grip_deg) or tabulated (table: a dict like fitted.yaml's "
      "adhesion.tabulated): the quasi-static search on the bond grid, as `climbsim pulloff "
      "--law frictional` and `climbsim fit-adhesion` compute it. length_m None: the width.");
  m.def("fit_adhesion", &FitAdhesion, py::arg("data_file"), py::arg("law"),
        py::arg("out_dir") = py::none(), py::arg("width_m") = 0.0, py::arg("length_m") = 0.0,
        py::arg("grid") = 16, py::arg("grip_deg") = 0.0, py::arg("assumed_spread") = 0.05,
        "`climbsim fit-adhesion DATA --law LAW [--out DIR]`: the same fit and numbers; returns "
        "law, parameters (key, unit, value, uncertainty, low95, high95), predicted_n, rms_n, "
        "worst_n, spread_n, represents, verdict and fitted_yaml. Angles in the CSV: "
        "angle_from_normal_deg (from the pad normal).");
}

}  // namespace climbsim::python
