#include "sim/cpg_effect.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "adhesion/adhesion.h"

namespace climbsim::sim {
namespace {

// Leg j supports leg i when j is in stance throughout i's swing (phase fractions; leg j
// lags leg i by offset_j − offset_i): for a trot, the other diagonal pair.
std::vector<std::vector<int>> SupportLegs(const std::vector<double>& offsets, double duty) {
  const int n = static_cast<int>(offsets.size());
  std::vector<std::vector<int>> support(n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (j == i) continue;
      bool always = true;
      for (int k = 0; k <= 40 && always; ++k) {
        const double u_i = (1.0 - duty) * k / 40.0;  // i's swing: [0, 1 − D]
        double u_j = u_i - (offsets[j] - offsets[i]);
        u_j -= std::floor(u_j);
        always = u_j >= 1.0 - duty - 1e-9 || u_j < 1e-9;
      }
      if (always) support[i].push_back(j);
    }
  }
  return support;
}

// The gait preset used when none is named: trot for 4 legs, tripod for 6.
std::string DefaultGait(const std::string& gait, int num_legs) {
  return gait.empty() ? (num_legs == 6 ? "tripod" : "trot") : gait;
}

}  // namespace

CpgEffect::CpgEffect(const Scenario& scenario, const CpgParams& p, const World& world)
    : params_(p) {
  const int n = static_cast<int>(world.robot().legs.size());
  CheckFitsScenario(scenario, n);
  if (p.spine && world.robot().spine_actuator < 0) {
    throw ScenarioError(scenario, "cpg.spine",
                        "the robot has no spine: give it one (robot.body.spine) or drop this key");
  }
  ResolveGait(n);
  support_ = SupportLegs(offsets_cycles_, *params_.duty_factor);
  ResolveShape(scenario, world);
  const double dt = world.model()->opt.timestep;
  period_steps_ =
      p.control_period_s ? static_cast<int>(std::lround(*p.control_period_s / dt)) : 1;
  period_s_ = period_steps_ * dt;
  network_ = MakeNetwork();  // the keys were checked where they were read: it cannot throw
  feedback_.assign(n, 0.0);
  held_.assign(n, 0);
  ResolveSqueezeSigns(world);
  blend_.assign(n, {0, 0, 0});
}

// The reader checked every key alone; what it cannot know is the robot (its legs) and
// whether the adhesion block that some keys read from is there.
void CpgEffect::CheckFitsScenario(const Scenario& scenario, int n) const {
  const CpgParams& p = params_;
  if (n == 0) {
    throw ScenarioError(scenario, "cpg",
                        "the robot declares no legs (custom text climbsim_legs)");
  }
  if (!p.phase_bias_rad.empty() && static_cast<int>(p.phase_bias_rad.size()) != n) {
    throw ScenarioError(scenario, "cpg.phase_bias_rad",
                        "must be " + std::to_string(n) + " x " + std::to_string(n) +
                            " for this robot's legs");
  }
  if (p.phase_bias_rad.empty() && !p.offsets_cycles.empty() &&
      static_cast<int>(p.offsets_cycles.size()) != n) {
    throw ScenarioError(scenario, "cpg.offsets_cycles",
                        "needs one offset per leg (" + std::to_string(n) + ")");
  }
  if (p.phase_bias_rad.empty() && p.offsets_cycles.empty()) {
    const std::string problem = cpg::GaitPresetProblem(DefaultGait(p.gait, n), n);
    if (!problem.empty()) throw ScenarioError(scenario, p.gait.empty() ? "cpg" : "cpg.gait", problem);
  }
  if (p.tegotae_sigma_rad_per_n_s > 0 && !scenario.adhesion) {
    throw ScenarioError(scenario, "cpg.tegotae_sigma_rad_per_n_s",
                        "needs the adhesion block: the pad loads come from it");
  }
  if (p.wait_for_support && !scenario.adhesion) {
    throw ScenarioError(scenario, "cpg.wait_for_support",
                        "needs the adhesion block: attachment comes from it");
  }
}

// The gait as offsets and phase biases, from whichever of phase_bias_rad, offsets_cycles and
// gait was given; the duty factor defaults to the preset's.
void CpgEffect::ResolveGait(int n) {
  const CpgParams& p = params_;
  if (!p.phase_bias_rad.empty()) {
    bias_.resize(n, n);
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) bias_(i, j) = p.phase_bias_rad[i][j];
    }
    // Offsets consistent with the bias relative to leg 0 (φ_i0 = 2π(o_i − o_0)).
    for (int i = 0; i < n; ++i) offsets_cycles_.push_back(bias_(i, 0) / (2 * M_PI));
  } else if (!p.offsets_cycles.empty()) {
    offsets_cycles_ = p.offsets_cycles;
    bias_ = cpg::PhaseBiasFromOffsets(offsets_cycles_);
  } else {
    params_.gait = DefaultGait(p.gait, n);
    const cpg::Gait g = cpg::GaitPreset(params_.gait, n);
    offsets_cycles_ = g.offsets_cycles;
    gait_duty_ = g.duty_factor;
    bias_ = cpg::PhaseBiasFromOffsets(offsets_cycles_);
  }
  params_.duty_factor = p.duty_factor.value_or(gait_duty_);
}

// The leg shape: foot space (an IK table sized for the stride, lift, press and crouch) or
// joint space (the joint excursions, defaults filled in).
void CpgEffect::ResolveShape(const Scenario& scenario, const World& world) {
  const CpgParams& p = params_;
  // Hopf phases run at a uniform rate within stance and within swing, so they are shaped
  // with duty ½ in phase space (their time duty comes from the two frequencies).
  shape_.duty_factor = p.oscillator == "hopf" ? 0.5 : *params_.duty_factor;
  shape_.lift_share = p.lift_share;
  if (p.stride_m) {
    shape_.stride_rad = {0, 0, 0};
    shape_.lift_rad = {0, 0, 0};
    // The table covers the stride, the swing and a margin into the surface for the press.
    const double reach_x = 0.5 * *p.stride_m * std::max(1.0, p.amplitude) + 0.005;
    // The GTO posture's crouch comes on top of the scenario's (ReflexEffect).
    const double posture_m = scenario.reflex && scenario.reflex->PostureOn()
                                 ? scenario.reflex->gto.posture.max_crouch_m
                                 : 0.0;
    // As many cells more as the posture widens the range: its grid is no coarser than
    // without it (the table's interpolation error stays what it was).
    const double below = p.press_m + 0.01, above = p.crouch_m + p.lift_m + 0.01;
    const int cells = static_cast<int>(
        std::ceil(LegIk::kDefaultCells * (below + above + posture_m) / (below + above)));
    ik_.emplace(world.model(), world.robot(), reach_x, below, above + posture_m, cells);
  } else {
    if (params_.stride_rad.empty()) params_.stride_rad = {0.35, 0.0, 0.0};
    if (params_.lift_rad.empty()) params_.lift_rad = {0.0, 0.5, 0.5};
    for (int k = 0; k < 3; ++k) {
      shape_.stride_rad[k] = params_.stride_rad[k];
      shape_.lift_rad[k] = params_.lift_rad[k];
    }
  }
}

// squeeze_m: each leg's side of the middle of the body along its axis (hips at the mean x:
// none).
void CpgEffect::ResolveSqueezeSigns(const World& world) {
  const int n = static_cast<int>(world.robot().legs.size());
  const mjModel* m = world.model();
  double mean_x = 0.0;
  std::vector<double> hip_x(n);
  for (int i = 0; i < n; ++i) {
    const int body = m->jnt_bodyid[world.robot().legs[i].joint[0]];
    hip_x[i] = m->body_pos[3 * body];
    mean_x += hip_x[i] / n;
  }
  squeeze_sign_.resize(n);
  for (int i = 0; i < n; ++i) {
    const double dx = hip_x[i] - mean_x;
    squeeze_sign_[i] = std::abs(dx) < 1e-6 ? 0.0 : (dx > 0 ? 1.0 : -1.0);
  }
}

std::unique_ptr<cpg::OscillatorNetwork> CpgEffect::MakeNetwork() const {
  const int n = static_cast<int>(offsets_cycles_.size());
  cpg::StepperParams stepper;
  stepper.type = params_.stepper == "euler"    ? cpg::Stepper::kEuler
                 : params_.stepper == "dopri5" ? cpg::Stepper::kDopri5
                                               : cpg::Stepper::kRk4;
  stepper.abs_tol = params_.abs_tol;
  stepper.rel_tol = params_.rel_tol;
  Eigen::VectorXd theta(n);
  // Start on the locked gait: θ_i = −2π·offset_i, so the phases have no transient.
  for (int i = 0; i < n; ++i)
    theta[i] = std::fmod(-2 * M_PI * offsets_cycles_[i] + 4 * M_PI, 2 * M_PI);
  if (params_.oscillator == "hopf") {
    cpg::HopfNetworkParams h;
    const cpg::HopfFrequencies f =
        cpg::HopfFrequenciesForGait(params_.frequency_hz, *params_.duty_factor);
    h.stance_frequency_hz = f.stance_frequency_hz;
    h.swing_frequency_hz = f.swing_frequency_hz;
    h.mu = params_.hopf.mu;
    h.alpha_per_s = params_.hopf.alpha_per_s;
    h.beta_per_s = params_.hopf.beta_per_s;
    h.b = params_.hopf.switch_sharpness;
    h.coupling_per_s = cpg::AllToAllCoupling(n, params_.coupling_per_s);
    h.phase_bias_rad = bias_;
    h.stepper = stepper;
    auto net = std::make_unique<cpg::HopfNetwork>(h);
    net->Reset(theta, Eigen::VectorXd::Constant(n, std::sqrt(params_.hopf.mu)));
    return net;
  }
  cpg::PhaseNetworkParams pp;
  pp.frequency_hz = params_.frequency_hz;
  pp.coupling_per_s = cpg::AllToAllCoupling(n, params_.coupling_per_s);
  pp.phase_bias_rad = bias_;
  pp.target_amplitude = Eigen::VectorXd::Constant(n, params_.amplitude);
  pp.amplitude_rate_per_s = params_.amplitude_rate_per_s;
  pp.stepper = stepper;
  auto net = std::make_unique<cpg::PhaseNetwork>(pp);
  net->Reset(theta, Eigen::VectorXd::Constant(n, params_.start_amplitude));
  return net;
}

void CpgEffect::InitialPose(World& world, RunContext& ctx) {
  network_ = MakeNetwork();  // fresh stepper state too (Dopri5's step size)
  // The feet are placed standing: the posture's crouch of an earlier run is not this one's
  // (InitialPose runs before any effect's Reset).
  posture_crouch_m_ = 0.0;
  const auto& legs = world.robot().legs;
  if (ik_ && params_.crouch_m > 0.0) {
    // Crouched feet reach the surface only if the body starts that much lower, along its
    // own normal (the surface's at the spawn).
    double* root = world.data()->qpos + world.robot().root_qpos_adr;
    double mat[9];
    mju_quat2Mat(mat, root + 3);
    for (int k = 0; k < 3; ++k) root[k] -= params_.crouch_m * mat[3 * k + 2];
  }
  // The feet are placed without the squeeze: once welded, the squeeze is the grasp's force.
  placing_ = true;
  for (size_t i = 0; i < legs.size(); ++i) {
    const std::array<double, 3> q = Targets(i, &(*ctx.legs)[i]);
    for (int k = 0; k < 3; ++k) world.data()->qpos[legs[i].qpos_adr[k]] = q[k];
  }
  if (params_.spine) world.data()->qpos[world.robot().spine_qpos_adr] = SpineTarget();
  placing_ = false;
}

void CpgEffect::Reset(World& world, RunContext& ctx) {
  blend_left_ = 0;
  hold_since_s_ = -1.0;
  hold_ = Hold{};
  WriteTargets(world, ctx);
}

void CpgEffect::BeforeStep(World& world, RunContext& ctx) {
  if (ctx.step % period_steps_ != 0) return;
  WriteTargets(world, ctx);
  Feedback(ctx);
  network_->Step(period_s_, feedback_, held_);
}

void CpgEffect::Feedback(RunContext& ctx) {
  const auto phase = network_->phase_rad();
  const std::vector<LegSignals>& legs = *ctx.legs;
  // A leg waits at the very end of its stance (the last two ticks) for its support legs.
  const double gate = 1.0 - 2.0 * params_.frequency_hz * period_s_ / *params_.duty_factor;
  // Any hold pauses every stance leg, not only the one that asks: stance feet welded to a
  // wall must keep moving together, or the legs that go on push against the one that waits.
  // Legs in swing go on (their feet are free), so the legs being waited for can land.
  // hold_stance ("do not leave stance yet") acts where the leg would leave: at the gate.
  bool hold = ctx.hold_all_stance;
  Hold why{hold ? HoldCause::kReflexAll : HoldCause::kNone};
  for (size_t i = 0; i < legs.size() && !hold; ++i) {
    const bool leaving = legs[i].stance && legs[i].progress >= gate;
    hold = legs[i].hold_phase || (leaving && legs[i].hold_stance);
    if (hold) {
      why = {legs[i].hold_phase ? HoldCause::kHoldPhase : HoldCause::kHoldStance,
             static_cast<int>(i)};
    }
    if (params_.wait_for_support && leaving) {
      for (int j : support_[i]) {
        if (hold) break;
        // Built: the share of what the pad touches (a pad over an edge cannot bond the rest),
        // or all that its torn bonds leave.
        hold = !legs[j].attached ||
               !adhesion::SupportBuilt(legs[j].bonded_fraction, legs[j].touched_fraction,
                                       legs[j].bondable_fraction, params_.support_bond_fraction);
        if (hold) {
          why = {HoldCause::kWaitForSupport, j, static_cast<int>(i), legs[j].attached,
                 legs[j].bonded_fraction};
        }
      }
    }
  }
  // Stall watch: when the current hold began, and what holds it now.
  if (!hold) {
    hold_since_s_ = -1.0;
  } else {
    if (hold_since_s_ < 0) hold_since_s_ = ctx.time_s;
    hold_ = why;
  }
  for (size_t i = 0; i < legs.size(); ++i) {
    double f = 0.0;
    if (params_.tegotae_sigma_rad_per_n_s > 0.0) {
      // N_i: the load the pad carries along its normal (either sign when attached, the
      // contact's compression when it only touches).
      const double load = legs[i].attached ? std::abs(legs[i].normal_load_n) : legs[i].preload_n;
      f += cpg::TegotaeFeedback(params_.tegotae_sigma_rad_per_n_s, load, phase[i]);
    }
    feedback_[i] = f;
    held_[i] = legs[i].hold_phase || (hold && legs[i].stance);
  }
}

std::array<double, 3> CpgEffect::Targets(size_t i, LegSignals* s) const {
  const double phase = network_->phase_rad()[i];
  const double amp = network_->amplitude()[i];
  if (!std::isfinite(phase) || !std::isfinite(amp)) {
    // The network went numerically bad (status() kNonFinite: a coupling too stiff for an
    // explicit stepper at this period). Bad targets, not an exception: MuJoCo flags the ctrl
    // (mjWARN_BADCTRL) and the monitor stops the run with the step, the time and the cause.
    s->phase_rad = phase;
    s->cpg_target_rad.fill(std::numeric_limits<double>::quiet_NaN());
    return s->cpg_target_rad;
  }
  const cpg::LegCommand c = cpg::ShapeLeg(shape_, phase, amp);
  s->phase_rad = phase;
  s->stance = c.stance;
  s->progress = c.progress;
  std::array<double, 3> q = c.joint_rad;
  if (ik_) {
    // Foot space: the stride moves the foot along the body axis, the lift along its normal.
    double dx = amp * c.stride * 0.5 * *params_.stride_m;
    if (c.stance && params_.squeeze_m != 0.0 && !placing_) {
      // Aimed towards the middle of the body, reached over the first tenth of the stance.
      const double u = std::min(1.0, c.progress / 0.1);
      dx -= squeeze_sign_[i] * params_.squeeze_m * u * u * (3.0 - 2.0 * u);
    }
    const double dz =
        params_.crouch_m + posture_crouch_m_ + c.lift * params_.lift_m - params_.press_m;
    q = ik_->Solve(static_cast<int>(i), dx, dz);
  }
  s->cpg_target_rad = q;
  return q;
}

bool CpgEffect::FootAt(int i, double theta_rad, double* dx, double* dz) const {
  const double amp = network_->amplitude()[i];
  const cpg::LegCommand c = cpg::ShapeLeg(shape_, theta_rad, amp);
  *dx = params_.stride_m ? amp * c.stride * 0.5 * *params_.stride_m : 0.0;
  *dz = params_.crouch_m + posture_crouch_m_ + c.lift * params_.lift_m - params_.press_m;
  return c.stance;
}

void CpgEffect::ResumePhases(std::span<double> theta) const {
  const int n = static_cast<int>(offsets_cycles_.size());
  // Leg `next` two ticks before the end of its stance; of the legs, the one that leaves the
  // others lowest (the gaits here: every other foot down).
  const double shape_duty = shape_.duty_factor;
  const double end = 2 * M_PI - 2 * 2 * M_PI * params_.frequency_hz * period_s_ *
                                    (shape_duty / *params_.duty_factor);
  double best_lift = 1e9;
  int best = 0;
  for (int next = 0; next < n; ++next) {
    double worst = 0.0;
    for (int i = 0; i < n; ++i) {
      const double th = end - 2 * M_PI * (offsets_cycles_[i] - offsets_cycles_[next]);
      const cpg::LegCommand c =
          cpg::ShapeLeg(shape_, std::fmod(th + 8 * M_PI, 2 * M_PI), network_->amplitude()[i]);
      worst = std::max(worst, c.lift);
    }
    if (worst < best_lift) best_lift = worst, best = next;
  }
  for (int i = 0; i < n; ++i) {
    theta[i] = std::fmod(end - 2 * M_PI * (offsets_cycles_[i] - offsets_cycles_[best]) + 8 * M_PI,
                         2 * M_PI);
  }
}

void CpgEffect::Resume(std::span<const double> theta, const World& world) {
  network_->Rephase(theta);
  hold_since_s_ = -1.0;
  hold_ = Hold{};
  const double* ctrl = world.data()->ctrl;
  const auto& legs = world.robot().legs;
  for (size_t i = 0; i < legs.size(); ++i) {
    LegSignals s;
    const std::array<double, 3> q = Targets(i, &s);
    for (int k = 0; k < 3; ++k) blend_[i][k] = ctrl[legs[i].actuator[k]] - q[k];
  }
  blend_ticks_ = blend_left_ = std::max(1, static_cast<int>(std::lround(kResumeBlendS / period_s_)));
}

void CpgEffect::WriteTargets(World& world, RunContext& ctx) {
  posture_crouch_m_ = ik_ ? ctx.crouch_m : 0.0;
  const auto& legs = world.robot().legs;
  double* ctrl = world.data()->ctrl;
  // After a Resume: from where the other controller left the servos into the gait.
  const double w = blend_left_ > 0 ? static_cast<double>(blend_left_) / blend_ticks_ : 0.0;
  if (blend_left_ > 0) --blend_left_;
  for (size_t i = 0; i < legs.size(); ++i) {
    LegSignals& s = (*ctx.legs)[i];
    const std::array<double, 3> q = Targets(i, &s);
    for (int k = 0; k < 3; ++k) {
      ctrl[legs[i].actuator[k]] = q[k] + s.offset_rad[k] + (w > 0.0 ? w * blend_[i][k] : 0.0);
    }
  }
  if (params_.spine) ctrl[world.robot().spine_actuator] = SpineTarget();
}

double CpgEffect::SpineTarget() const {
  const double phase = network_->phase_rad()[0];
  return params_.spine->amplitude_rad * std::sin(phase + params_.spine->phase_rad);
}

void CpgEffect::Summarise(const World& world, nlohmann::json* summary) const {
  // Stalled: the gait has been held for at least two strides (and 1 s) when the run ends.
  const double end_s = world.data()->time;
  const double stall_after_s = std::max(1.0, 2.0 / params_.frequency_hz);
  if (hold_since_s_ >= 0.0 && end_s - hold_since_s_ >= stall_after_s) {
    const auto& legs = world.robot().legs;
    const auto name = [&](int leg) {
      return leg >= 0 && leg < static_cast<int>(legs.size()) ? legs[leg].name : std::string("?");
    };
    std::string reason;
    std::string leg = name(hold_.leg);
    switch (hold_.cause) {
      case HoldCause::kWaitForSupport: {
        char buf[200];
        if (hold_.attached) {
          std::snprintf(buf, sizeof(buf), "bonded fraction %.3f < cpg.support_bond_fraction %.3f",
                        hold_.bonded_fraction, params_.support_bond_fraction);
        } else {
          std::snprintf(buf, sizeof(buf), "pad not attached");
        }
        reason = "cpg.wait_for_support: " + name(hold_.waiting_leg) + " waits to swing for " + leg +
                 " (" + buf + ")";
        break;
      }
      case HoldCause::kHoldPhase:
        reason = "reflex: " + leg + " holds its phase";
        break;
      case HoldCause::kHoldStance:
        reason = "reflex: " + leg + " holds stance";
        break;
      case HoldCause::kReflexAll:
        leg = "all";
        // A spindle's hold that never ends is a posture, not a push: name the key that bounds it.
        reason =
            "reflex: every stance leg is held (a re-grip, or a leg its spindle finds pushed; "
            "reflex.spindle.max_hold_s bounds that hold)";
        break;
      case HoldCause::kNone:
        break;
    }
    (*summary)["stalled"] = true;
    (*summary)["stall_time_s"] = hold_since_s_;
    (*summary)["stall_leg"] = leg;
    (*summary)["stall_reason"] = reason;
  }
  (*summary)["cpg"] = {{"oscillator", params_.oscillator},
                       {"gait", params_.gait.empty() ? "explicit" : params_.gait},
                       {"duty_factor", *params_.duty_factor},
                       {"frequency_hz", params_.frequency_hz}};
}

}  // namespace climbsim::sim
