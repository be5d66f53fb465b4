#include "sim/servo_margin.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <set>

#include "adhesion/weld.h"
#include "cpg/gait.h"
#include "sim/world.h"

namespace climbsim::sim {
namespace {

// The weld that holds a stance pad in this check (not the adhesion's: effects are left out).
std::string MarginWeldName(const std::string& pad_body) { return "climbsim_margin_" + pad_body; }

// The gait of the scenario's cpg block as offsets and duty factor; no cpg: one stance set, all
// legs (the robot stands on every pad).
void ScenarioGait(const Scenario& s, int n, std::vector<double>* offsets, double* duty) {
  offsets->assign(n, 0.0);
  *duty = 1.0;
  if (!s.cpg) return;
  const CpgParams& p = *s.cpg;
  double preset_duty = 0.5;
  // A gait that does not fit the robot is refused when the cpg is built; until then: all legs.
  if (!p.phase_bias_rad.empty()) {
    if (static_cast<int>(p.phase_bias_rad.size()) != n) return;
    for (int i = 0; i < n; ++i) {
      if (p.phase_bias_rad[i].empty()) return;
      (*offsets)[i] = p.phase_bias_rad[i][0] / (2 * M_PI);
    }
  } else if (!p.offsets_cycles.empty()) {
    if (static_cast<int>(p.offsets_cycles.size()) != n) return;
    *offsets = p.offsets_cycles;
  } else {
    const std::string name = p.gait.empty() ? (n == 6 ? "tripod" : "trot") : p.gait;
    if (!cpg::GaitPresetProblem(name, n).empty()) return;
    const cpg::Gait g = cpg::GaitPreset(name, n);
    *offsets = g.offsets_cycles;
    preset_duty = g.duty_factor;
  }
  *duty = p.duty_factor.value_or(preset_duty);
}

std::string SetName(const RobotInfo& robot, const std::vector<int>& set) {
  std::string s;
  for (int leg : set) s += (s.empty() ? "" : " ") + robot.legs[leg].name;
  return s;
}

// The scenario with what the check leaves out (effects, pushes) and one inactive weld per pad.
std::unique_ptr<CompiledModel> CompileForMargins(const Scenario& scenario, Scenario* bare) {
  *bare = scenario;
  bare->adhesion.reset();
  bare->reflex.reset();
  bare->cpg.reset();
  bare->transition.reset();
  bare->perturbations.clear();
  const std::unique_ptr<CompiledModel> plain = CompiledModel::Build(*bare, MjcfAdditions{});
  MjcfAdditions welds;
  for (const LegInfo& leg : plain->robot().legs) {
    const std::string pad = mj_id2name(plain->model(), mjOBJ_BODY, leg.pad_body);
    welds.equality += "    <weld name=\"" + MarginWeldName(pad) + "\" body1=\"" + pad +
                      "\" active=\"false\"/>\n";
  }
  return CompiledModel::Build(*bare, welds);
}

}  // namespace

std::vector<std::vector<int>> GaitStanceSets(const std::vector<double>& offsets_cycles,
                                             double duty) {
  const int n = static_cast<int>(offsets_cycles.size());
  std::set<std::vector<int>> seen;
  std::vector<std::vector<int>> sets;
  // Midpoints of 720 equal steps: no sample falls on a preset's switch (multiples of 1/12).
  constexpr int kSamples = 720;
  for (int k = 0; k < kSamples && duty < 1.0; ++k) {
    const double t = (k + 0.5) / kSamples;
    std::vector<int> set;
    for (int i = 0; i < n; ++i) {
      const double u = t - offsets_cycles[i] - std::floor(t - offsets_cycles[i]);
      if (u >= 1.0 - duty) set.push_back(i);
    }
    if (set.size() >= 2 && static_cast<int>(set.size()) < n && seen.insert(set).second) {
      sets.push_back(set);
    }
  }
  std::vector<int> all(n);
  for (int i = 0; i < n; ++i) all[i] = i;
  sets.push_back(all);
  return sets;
}

std::vector<double> SettledActuatorForces(mjModel* m, mjData* d, const std::vector<int>& welds,
                                          const std::vector<int>& stance_legs,
                                          const std::vector<int>& lift_actuators, int steps) {
  mj_resetData(m, d);
  mj_forward(m, d);
  for (int w : welds) adhesion::SetWeldActive(m, d, w, false);
  for (int leg : stance_legs) {
    adhesion::SetWeldFromCurrentPoses(m, d, welds[leg], 0, Eigen::Vector3d::Zero());
    adhesion::SetWeldActive(m, d, welds[leg], true);
  }
  for (int a : lift_actuators) {
    const double hi = m->actuator_ctrllimited[a] ? m->actuator_ctrlrange[2 * a + 1] : 1e9;
    d->ctrl[a] = std::min(kServoMarginLiftRad, hi);
  }
  for (int i = 0; i < steps; ++i) mj_step(m, d);
  std::vector<double> force(m->nu);
  for (int a = 0; a < m->nu; ++a) force[a] = std::abs(d->actuator_force[a]);
  return force;
}

ServoMargins MeasureServoMargins(const Scenario& scenario) {
  Scenario bare;
  const std::unique_ptr<CompiledModel> compiled = CompileForMargins(scenario, &bare);
  World world(*compiled, bare);
  mjModel* m = world.model();
  const RobotInfo& robot = world.robot();
  const int n = static_cast<int>(robot.legs.size());
  std::vector<int> welds;
  for (const LegInfo& leg : robot.legs) {
    const std::string pad = mj_id2name(m, mjOBJ_BODY, leg.pad_body);
    welds.push_back(mj_name2id(m, mjOBJ_EQUALITY, MarginWeldName(pad).c_str()));
  }
  std::vector<double> offsets;
  double duty = 1.0;
  ScenarioGait(scenario, n, &offsets, &duty);
  ServoMargins out;
  out.mass_kg = m->body_subtreemass[robot.base_body];
  for (int a = 0; a < m->nu; ++a) {
    if (!m->actuator_forcelimited[a] || m->actuator_trntype[a] != mjTRN_JOINT) continue;
    out.servos.push_back({mj_id2name(m, mjOBJ_ACTUATOR, a), 0.0,
                          0.5 * m->actuator_forcerange[2 * a + 1], ""});
  }
  const int steps = static_cast<int>(std::lround(kServoMarginSettleS / m->opt.timestep));
  for (const std::vector<int>& set : GaitStanceSets(offsets, duty)) {
    std::vector<int> lift;
    for (int leg = 0; leg < n; ++leg) {
      if (!std::count(set.begin(), set.end(), leg)) lift.push_back(robot.legs[leg].actuator[1]);
    }
    const std::vector<double> f = SettledActuatorForces(m, world.data(), welds, set, lift, steps);
    out.stance_sets.push_back({});
    for (int leg : set) out.stance_sets.back().push_back(robot.legs[leg].name);
    for (ServoHold& s : out.servos) {
      const double t = f[mj_name2id(m, mjOBJ_ACTUATOR, s.name.c_str())];
      if (t > s.holding_torque_nm) s = {s.name, t, s.rated_torque_nm, SetName(robot, set)};
    }
  }
  return out;
}

std::vector<std::string> ServoMargins::Overloaded() const {
  std::vector<std::string> over;
  for (const ServoHold& s : servos) {
    if (s.holding_torque_nm <= s.rated_torque_nm) continue;
    char pct[32];
    std::snprintf(pct, sizeof pct, " %.0f %%", 100.0 * s.load_fraction());
    over.push_back(s.name + pct);
  }
  return over;
}

const ServoHold* ServoMargins::Worst() const {
  const ServoHold* worst = nullptr;
  for (const ServoHold& s : servos) {
    if (!worst || s.load_fraction() > worst->load_fraction()) worst = &s;
  }
  return worst;
}

nlohmann::json ServoMargins::ToJson() const {
  nlohmann::json j;
  j["mass_kg"] = mass_kg;
  j["settle_s"] = kServoMarginSettleS;
  j["stance_sets"] = stance_sets;
  nlohmann::json list = nlohmann::json::array();
  for (const ServoHold& s : servos) {
    list.push_back({{"name", s.name},
                    {"holding_torque_nm", s.holding_torque_nm},
                    {"rated_torque_nm", s.rated_torque_nm},
                    {"load_fraction", s.load_fraction()},
                    {"stance", s.stance}});
  }
  j["servos"] = list;
  j["overloaded"] = Overloaded();
  return j;
}

}  // namespace climbsim::sim
