#include "sim/cpg_effect.h"

#include <cmath>

namespace climbsim::sim {

CpgEffect::CpgEffect(const Scenario& scenario, const CpgParams& p, const World& world)
    : params_(p) {
  const int n = static_cast<int>(world.robot().legs.size());
  if (n == 0) {
    throw ScenarioError(scenario, "cpg",
                        "the robot declares no legs (custom text climbsim_legs)");
  }
  Eigen::MatrixXd bias;
  double duty = 0.5;
  if (!p.phase_bias_rad.empty()) {
    if (static_cast<int>(p.phase_bias_rad.size()) != n) {
      throw ScenarioError(scenario, "cpg.phase_bias_rad",
                          "must be " + std::to_string(n) + " x " + std::to_string(n) +
                              " for this robot's legs");
    }
    bias.resize(n, n);
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) bias(i, j) = p.phase_bias_rad[i][j];
    }
    // Offsets consistent with the bias relative to leg 0 (φ_i0 = 2π(o_i − o_0)).
    for (int i = 0; i < n; ++i) offsets_cycles_.push_back(bias(i, 0) / (2 * M_PI));
    gait_name_ = "explicit";
  } else if (!p.offsets_cycles.empty()) {
    if (static_cast<int>(p.offsets_cycles.size()) != n) {
      throw ScenarioError(scenario, "cpg.offsets_cycles",
                          "needs one offset per leg (" + std::to_string(n) + ")");
    }
    offsets_cycles_ = p.offsets_cycles;
    bias = cpg::PhaseBiasFromOffsets(offsets_cycles_);
    gait_name_ = "explicit";
  } else {
    gait_name_ = p.gait.empty() ? (n == 6 ? "tripod" : "trot") : p.gait;
    try {
      const cpg::Gait g = cpg::GaitPreset(gait_name_, n);
      offsets_cycles_ = g.offsets_cycles;
      duty = g.duty_factor;
    } catch (const std::invalid_argument& e) {
      throw ScenarioError(scenario, p.gait.empty() ? "cpg" : "cpg.gait", e.what());
    }
    bias = cpg::PhaseBiasFromOffsets(offsets_cycles_);
  }
  shape_.duty_factor = p.duty_factor.value_or(duty);
  for (int k = 0; k < 3; ++k) {
    shape_.stride_rad[k] = p.stride_rad[k];
    shape_.lift_rad[k] = p.lift_rad[k];
  }

  const double dt = world.model()->opt.timestep;
  period_steps_ =
      p.control_period_s ? static_cast<int>(std::lround(*p.control_period_s / dt)) : 1;
  period_s_ = period_steps_ * dt;

  phase_params_.frequency_hz = p.frequency_hz;
  phase_params_.coupling_per_s = Eigen::MatrixXd::Constant(n, n, p.coupling_per_s);
  phase_params_.coupling_per_s.diagonal().setZero();
  phase_params_.phase_bias_rad = bias;
  phase_params_.target_amplitude = Eigen::VectorXd::Constant(n, p.amplitude);
  phase_params_.amplitude_rate_per_s = p.amplitude_rate_per_s;
  phase_params_.stepper.type = p.stepper == "euler"   ? cpg::Stepper::kEuler
                               : p.stepper == "dopri5" ? cpg::Stepper::kDopri5
                                                       : cpg::Stepper::kRk4;
  phase_params_.stepper.abs_tol = p.abs_tol;
  phase_params_.stepper.rel_tol = p.rel_tol;
  try {
    network_ = std::make_unique<cpg::PhaseNetwork>(phase_params_);
  } catch (const std::invalid_argument& e) {
    throw ScenarioError(scenario, "cpg", e.what());
  }
  feedback_.assign(n, 0.0);
}

void CpgEffect::Reset(World& world, RunContext& ctx) {
  const int n = network_->size();
  // Start on the locked gait: θ_i = −2π·offset_i, so no transient of the phases.
  Eigen::VectorXd theta(n), r(n);
  for (int i = 0; i < n; ++i) {
    theta[i] = std::fmod(-2 * M_PI * offsets_cycles_[i] + 4 * M_PI, 2 * M_PI);
    r[i] = params_.start_amplitude;
  }
  network_ = std::make_unique<cpg::PhaseNetwork>(phase_params_);
  static_cast<cpg::PhaseNetwork*>(network_.get())->Reset(theta, r);
  WriteTargets(world, ctx);
}

void CpgEffect::BeforeStep(World& world, RunContext& ctx) {
  if (ctx.step % period_steps_ != 0) return;
  WriteTargets(world, ctx);
  network_->Step(period_s_, feedback_);
}

void CpgEffect::WriteTargets(World& world, RunContext& ctx) {
  const auto phase = network_->phase_rad();
  const auto amp = network_->amplitude();
  const auto& legs = world.robot().legs;
  double* ctrl = world.data()->ctrl;
  for (size_t i = 0; i < legs.size(); ++i) {
    const cpg::LegCommand c = cpg::ShapeLeg(shape_, phase[i], amp[i]);
    LegSignals& s = (*ctx.legs)[i];
    s.phase_rad = phase[i];
    s.stance = c.stance;
    s.progress = c.progress;
    for (int k = 0; k < 3; ++k) {
      s.cpg_target_rad[k] = c.joint_rad[k];
      ctrl[legs[i].actuator[k]] = c.joint_rad[k] + s.offset_rad[k];
    }
  }
}

void CpgEffect::Summarise(const World&, nlohmann::json* summary) const {
  (*summary)["cpg"] = {{"gait", gait_name_},
                       {"duty_factor", shape_.duty_factor},
                       {"frequency_hz", params_.frequency_hz}};
}

}  // namespace climbsim::sim
