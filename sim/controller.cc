#include "sim/controller.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sim/adhesion_effect.h"
#include "sim/cpg_effect.h"
#include "sim/reflex_effect.h"
#include "sim/transition_effect.h"

namespace climbsim::sim {

// --- CpgReflexController ---

CpgReflexController::CpgReflexController(World& world, RunContext& ctx,
                                         std::unique_ptr<CpgEffect> cpg,
                                         std::unique_ptr<ReflexEffect> reflex,
                                         std::unique_ptr<TransitionEffect> transition)
    : world_(world),
      ctx_(ctx),
      cpg_(std::move(cpg)),
      reflex_(std::move(reflex)),
      transition_(std::move(transition)) {}

CpgReflexController::~CpgReflexController() = default;

double CpgReflexController::control_period_s() const { return cpg_->control_period_s(); }

void CpgReflexController::InitialPose(StartPose* pose) {
  if (reflex_) reflex_->InitialPose(world_, ctx_);
  cpg_->InitialPose(world_, ctx_);
  const mjData* d = world_.data();
  const RobotInfo& r = world_.robot();
  for (size_t i = 0; i < r.legs.size(); ++i) {
    for (int k = 0; k < 3; ++k) pose->joint_angle_rad[3 * i + k] = d->qpos[r.legs[i].qpos_adr[k]];
  }
  for (int k = 0; k < 3; ++k) pose->base_pos_m[k] = d->qpos[r.root_qpos_adr + k];
}

void CpgReflexController::Reset() {
  if (reflex_) reflex_->Reset(world_, ctx_);
  cpg_->Reset(world_, ctx_);
  if (transition_) transition_->Reset(world_, ctx_);
}

void CpgReflexController::Update(const Observation&, Command* cmd) {
  if (transition_ && transition_->active()) {
    transition_->Update(world_, ctx_);
    if (transition_->resume_pending()) {
      // The feet are where the gait has them: it goes on from there, the reflexes afresh.
      cpg_->Resume(transition_->resume_theta(), world_);
      if (reflex_) reflex_->Reset(world_, ctx_);
      transition_->ClearResume();
    }
  } else {
    // The effects' own hooks, in their pipeline order; the CPG writes ctrl (targets plus reflex
    // offsets), which becomes this controller's command.
    if (reflex_) reflex_->BeforeStep(world_, ctx_);
    cpg_->BeforeStep(world_, ctx_);
    if (transition_ && transition_->Watch(world_, ctx_)) {
      if (reflex_) reflex_->Suspend(world_, ctx_);
      cpg_->Suspend();
    }
  }
  const double* ctrl = world_.data()->ctrl;
  const RobotInfo& r = world_.robot();
  for (size_t i = 0; i < r.legs.size(); ++i) {
    for (int k = 0; k < 3; ++k) cmd->target_rad[3 * i + k] = ctrl[r.legs[i].actuator[k]];
  }
  // The reflexes' stiffness (stance compliance, GTO unloading) goes out through the command,
  // as a user's would; during a manoeuvre the transition sets the servos itself, and the
  // scale is held at what the suspended reflexes left (1).
  if (reflex_ && !(transition_ && transition_->active())) {
    const std::vector<LegSignals>& legs = *ctx_.legs;
    for (size_t i = 0; i < legs.size(); ++i) {
      for (int k = 0; k < 3; ++k) cmd->kp_scale[3 * i + k] = legs[i].kp_fraction[k];
    }
  }
}

void CpgReflexController::Summarise(nlohmann::json* summary) const {
  if (reflex_) reflex_->Summarise(world_, summary);
  cpg_->Summarise(world_, summary);
  if (transition_) transition_->Summarise(world_, summary);
}

// --- ControllerEffect ---

ControllerEffect::ControllerEffect(const World& world,
                                   std::vector<std::shared_ptr<Controller>> chain, int period_steps,
                                   AdhesionEffect* adhesion, bool has_cpg)
    : chain_(std::move(chain)),
      period_steps_(std::max(1, period_steps)),
      adhesion_(adhesion),
      has_cpg_(has_cpg) {
  for (const auto& c : chain_) {
    name_ += (name_.empty() ? "" : "+") + std::string(c->name());
    // The built-in controller reads the world itself: the default pipeline skips observing.
    observe_ |= dynamic_cast<const CpgReflexController*>(c.get()) == nullptr;
  }
  const size_t n = world.robot().legs.size();
  q_.assign(3 * n, 0.0);
  qd_.assign(3 * n, 0.0);
  target_.assign(3 * n, 0.0);
  offset_.assign(3 * n, 0.0);
  release_.assign(n, 0);
  kp_scale_.assign(3 * n, 1.0);
  kp_applied_.assign(3 * n, 1.0);
  const mjModel* m = world.model();
  for (const LegInfo& leg : world.robot().legs) {
    for (int k = 0; k < 3; ++k) {
      const int a = leg.actuator[k];
      actuator_.push_back(a);
      kp_own_.push_back(ServoKp(m, a));
      scalable_.push_back(m->actuator_biastype[a] == mjBIAS_AFFINE &&
                          m->actuator_biasprm[a * mjNBIAS + 1] == -ServoKp(m, a));
    }
  }
  pads_.assign(n, PadSense{});
  if (has_cpg_) {
    phase_.assign(n, 0.0);
    stance_.assign(n, 0);
  }
  obs_.legs = static_cast<int>(n);
  obs_.joint_angle_rad = q_;
  obs_.joint_velocity_rad_s = qd_;
  obs_.pads = pads_;
  obs_.cpg_phase_rad = phase_;
  obs_.cpg_stance = stance_;
  command_.target_rad = target_;
  command_.offset_rad = offset_;
  command_.release = release_;
  command_.kp_scale = kp_scale_;
}

void ControllerEffect::InitialPose(World& world, RunContext&) {
  mjData* d = world.data();
  const RobotInfo& r = world.robot();
  StartPose pose;
  pose.joint_angle_rad = q_;
  for (size_t i = 0; i < r.legs.size(); ++i) {
    for (int k = 0; k < 3; ++k) q_[3 * i + k] = d->qpos[r.legs[i].qpos_adr[k]];
  }
  if (r.root_qpos_adr >= 0) {
    for (int k = 0; k < 3; ++k) pose.base_pos_m[k] = d->qpos[r.root_qpos_adr + k];
  }
  for (const auto& c : chain_) c->InitialPose(&pose);
  for (size_t i = 0; i < r.legs.size(); ++i) {
    for (int k = 0; k < 3; ++k) d->qpos[r.legs[i].qpos_adr[k]] = q_[3 * i + k];
  }
  if (r.root_qpos_adr >= 0) {
    for (int k = 0; k < 3; ++k) d->qpos[r.root_qpos_adr + k] = pose.base_pos_m[k];
  }
}

void ControllerEffect::Reset(World& world, RunContext& ctx) {
  ticks_ = 0;
  RestoreStiffness(world);
  for (const auto& c : chain_) c->Reset();
  // Until the first tick the servos hold what the controllers left in ctrl (the CPG's
  // starting targets; zero otherwise).
  const double* ctrl = world.data()->ctrl;
  const RobotInfo& r = world.robot();
  for (size_t i = 0; i < r.legs.size(); ++i) {
    for (int k = 0; k < 3; ++k) target_[3 * i + k] = ctrl[r.legs[i].actuator[k]];
  }
  std::fill(offset_.begin(), offset_.end(), 0.0);
  std::fill(release_.begin(), release_.end(), 0);
  if (observe_) Observe(world, ctx);
}

void ControllerEffect::ObservePhases(const RunContext& ctx) {
  if (!has_cpg_) return;
  const std::vector<LegSignals>& legs = *ctx.legs;
  for (size_t i = 0; i < legs.size(); ++i) {
    phase_[i] = legs[i].phase_rad;
    stance_[i] = legs[i].stance ? 1 : 0;
  }
}

void ControllerEffect::Observe(const World& world, const RunContext& ctx) {
  const mjData* d = world.data();
  const RobotInfo& r = world.robot();
  obs_.step = ctx.step;
  obs_.time_s = d->time;
  for (size_t i = 0; i < r.legs.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      q_[3 * i + k] = d->qpos[r.legs[i].qpos_adr[k]];
      qd_[3 * i + k] = d->qvel[r.legs[i].dof_adr[k]];
    }
  }
  if (r.root_qpos_adr >= 0) {
    for (int k = 0; k < 3; ++k) obs_.base_pos_m[k] = d->qpos[r.root_qpos_adr + k];
    for (int k = 0; k < 4; ++k) obs_.base_quat[k] = d->qpos[r.root_qpos_adr + 3 + k];
    for (int k = 0; k < 3; ++k) obs_.base_linvel_m_s[k] = d->qvel[r.root_dof_adr + k];
    for (int k = 0; k < 3; ++k) obs_.base_angvel_rad_s[k] = d->qvel[r.root_dof_adr + 3 + k];
  }
  const std::vector<LegSignals>& legs = *ctx.legs;
  for (size_t i = 0; i < legs.size(); ++i) {
    PadSense& p = pads_[i];
    p.touching = legs[i].touching;
    p.attached = legs[i].attached;
    p.bonded_fraction = legs[i].bonded_fraction;
    p.normal_load_n = legs[i].normal_load_n;
    p.preload_n = legs[i].preload_n;
    p.utilisation = legs[i].utilisation;  // the adhesion effect's, capped, 0 when not attached
  }
  ObservePhases(ctx);
}

void ControllerEffect::BeforeStep(World& world, RunContext& ctx) {
  if (ctx.step % period_steps_ != 0) return;
  if (observe_) Observe(world, ctx);
  // Targets held from the last tick; offsets and releases fresh.
  std::fill(offset_.begin(), offset_.end(), 0.0);
  std::fill(release_.begin(), release_.end(), 0);
  for (const auto& c : chain_) {
    c->Update(obs_, &command_);
    ObservePhases(ctx);  // the built-in CPG has just advanced: the next one sees this tick's
  }
  double* ctrl = world.data()->ctrl;
  const RobotInfo& r = world.robot();
  for (size_t i = 0; i < r.legs.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const double off = offset_[3 * i + k];
      const double t = target_[3 * i + k];
      ctrl[r.legs[i].actuator[k]] = off == 0.0 ? t : t + off;
    }
    if (release_[i] != 0 && adhesion_ != nullptr) adhesion_->RequestReleaseLeg(static_cast<int>(i));
  }
  ApplyStiffness(world);
  ++ticks_;
}

// A servo's kp changes only when its scale does: a manoeuvre (sim/transition_effect.h) sets
// the servos it drives itself while the scale holds.
void ControllerEffect::ApplyStiffness(World& world) {
  for (size_t j = 0; j < kp_scale_.size(); ++j) {
    const double s = kp_scale_[j];
    if (s == kp_applied_[j]) continue;
    if (std::isnan(s)) {
      throw std::invalid_argument("controller command: kp_scale[" + std::to_string(j) +
                                  "] is NaN");
    }
    const double f = std::clamp(s, 0.0, 1.0);
    if (!scalable_[j] && f != 1.0) {
      throw std::invalid_argument(
          std::string("controller command: kp_scale: actuator '") +
          mj_id2name(world.model(), mjOBJ_ACTUATOR, actuator_[j]) +
          "' is not a position servo (gain kp, bias -kp q): its stiffness cannot be scaled");
    }
    SetServoKp(world.model(), actuator_[j], kp_own_[j] * f);
    kp_applied_[j] = s;
  }
}

// Back to the servos' own kp at a run's start (a later run reuses the model copy).
void ControllerEffect::RestoreStiffness(World& world) {
  for (size_t j = 0; j < kp_scale_.size(); ++j) {
    if (kp_applied_[j] != 1.0) SetServoKp(world.model(), actuator_[j], kp_own_[j]);
    kp_scale_[j] = kp_applied_[j] = 1.0;
  }
}

void ControllerEffect::Summarise(const World&, nlohmann::json* summary) const {
  for (const auto& c : chain_) c->Summarise(summary);
}

}  // namespace climbsim::sim
