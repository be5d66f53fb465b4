#include "sim/reflex_effect.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace climbsim::sim {
namespace {

constexpr reflex::LegEventType kEventTypes[] = {
    reflex::LegEventType::kPreloadStart, reflex::LegEventType::kPreloadEnd,
    reflex::LegEventType::kSearchStart,  reflex::LegEventType::kSearchEnd,
    reflex::LegEventType::kPeel,         reflex::LegEventType::kPeelEnd,
    reflex::LegEventType::kRegrip,       reflex::LegEventType::kGtoHold,
    reflex::LegEventType::kSpindle,      reflex::LegEventType::kGtoUnload};

// A position servo's stiffness: force = gain·ctrl + bias1·q + bias2·q̇ with gain = kp,
// bias1 = −kp.
void SetKp(mjModel* m, int actuator, double kp) {
  m->actuator_gainprm[actuator * mjNGAIN] = kp;
  m->actuator_biasprm[actuator * mjNBIAS + 1] = -kp;
}

}  // namespace

ReflexEffect::ReflexEffect(const Scenario& scenario, const ReflexParams& params, const World& world,
                           const CpgEffect& cpg, AdhesionEffect* adhesion,
                           std::vector<int> event_pad)
    : params_(params),
      adhesion_(adhesion),
      support_(cpg.support()),
      event_pad_(std::move(event_pad)) {
  const double dt = cpg.control_period_s();
  period_steps_ = static_cast<int>(std::lround(dt / world.model()->opt.timestep));
  const reflex::LegReflexParams leg = params.Leg();
  try {
    reflex::Validate(leg, dt, "reflex");
  } catch (const std::invalid_argument& e) {
    // The module names the field ("reflex.peel.ramp_s must be ..."): point at that key.
    const std::string msg = e.what();
    std::string key = msg.substr(0, msg.find(' '));
    if (key.rfind("reflex.spindle.joints", 0) == 0) key = "reflex.spindle";
    throw ScenarioError(scenario, key, msg.substr(msg.find(' ') + 1));
  }
  const mjModel* m = world.model();
  for (size_t i = 0; i < world.robot().legs.size(); ++i) {
    legs_.emplace_back(leg, dt);
    const LegInfo& info = world.robot().legs[i];
    std::array<int, 3> a{};
    std::array<double, 3> kp{};
    for (int k = 0; k < 3; ++k) {
      a[k] = info.actuator[k];
      kp[k] = m->actuator_gainprm[a[k] * mjNGAIN];
      // Only a position servo (gain kp, bias −kp·q) can have its stiffness scaled.
      if (m->actuator_biastype[a[k]] != mjBIAS_AFFINE ||
          m->actuator_biasprm[a[k] * mjNBIAS + 1] != -kp[k]) {
        if (leg.compliance.enabled || leg.gto.enabled) {
          throw ScenarioError(scenario, "reflex.compliance",
                              std::string("actuator '") + mj_id2name(m, mjOBJ_ACTUATOR, a[k]) +
                                  "' is not a position servo (gain kp, bias -kp q): its "
                                  "stiffness cannot be scheduled");
        }
      }
    }
    actuator_.push_back(a);
    kp_.push_back(kp);
  }
  counts_.assign(legs_.size(), {});
}

void ReflexEffect::Reset(World& world, RunContext& ctx) {
  for (size_t i = 0; i < legs_.size(); ++i) {
    for (int k = 0; k < 3; ++k) SetKp(world.model(), actuator_[i][k], kp_[i][k]);
  }
  for (auto& l : legs_) l.Reset();
  for (auto& c : counts_) c.fill(0);
  for (LegSignals& s : *ctx.legs) {
    s.offset_rad = {0, 0, 0};
    s.kp_fraction = {1, 1, 1};
    s.hold_stance = s.hold_phase = false;
  }
  ctx.hold_all_stance = false;
}

void ReflexEffect::Suspend(World& world, RunContext& ctx) {
  for (size_t i = 0; i < legs_.size(); ++i) {
    for (int k = 0; k < 3; ++k) SetKp(world.model(), actuator_[i][k], kp_[i][k]);
    if (adhesion_ != nullptr) adhesion_->SetPeelingLeg(static_cast<int>(i), false);
  }
  for (LegSignals& s : *ctx.legs) {
    s.offset_rad = {0, 0, 0};
    s.kp_fraction = {1, 1, 1};
    s.hold_stance = s.hold_phase = false;
  }
  ctx.hold_all_stance = false;
}

void ReflexEffect::BeforeStep(World& world, RunContext& ctx) {
  if (ctx.step % period_steps_ != 0) return;
  const mjData* d = world.data();
  std::vector<LegSignals>& signals = *ctx.legs;
  bool hold_all = false;
  for (size_t i = 0; i < legs_.size(); ++i) {
    LegSignals& s = signals[i];
    const LegInfo& info = world.robot().legs[i];
    reflex::LegSensing in;
    in.stance = s.stance;
    in.phase_progress = s.progress;
    in.touching = s.touching;
    in.attached = s.attached;
    in.bonded_fraction = s.bonded_fraction;
    in.normal_load_n = s.normal_load_n;
    in.preload_n = s.preload_n;
    in.bonds_lost = s.bonds_lost;
    s.bonds_lost = false;  // consumed
    for (int k = 0; k < 3; ++k) {
      // Stretch: the joint against the CPG's own target (reflex offsets left out, so the
      // spindle does not chase its own output).
      in.stretch_rad[k] = d->qpos[info.qpos_adr[k]] - s.cpg_target_rad[k];
      in.stretch_velocity_rad_per_s[k] = d->qvel[info.dof_adr[k]];
    }
    in.partner_attached = true;
    in.utilisation = s.utilisation;
    in.support_utilisation = 0.0;
    for (int j : support_[i]) {
      in.partner_attached &= signals[j].attached;
      in.support_utilisation = std::max(in.support_utilisation, signals[j].utilisation);
    }

    const reflex::LegReflexOutput out = legs_[i].Update(in);
    for (int k = 0; k < 3; ++k) {
      s.offset_rad[k] = out.target_offset_rad[k];
      s.kp_fraction[k] = out.kp_fraction[k];
      SetKp(world.model(), actuator_[i][k], kp_[i][k] * out.kp_fraction[k]);
    }
    s.hold_stance = out.hold_stance;
    s.hold_phase = out.hold_phase;
    // While the peel pulls (phase held), a let-go is the peel it meant.
    if (adhesion_ != nullptr) adhesion_->SetPeelingLeg(static_cast<int>(i), out.hold_phase);
    hold_all |= out.hold_others;

    for (const reflex::LegEvent& e : out.events) {
      Event row;
      row.time_s = ctx.time_s;
      row.pad = event_pad_[i];
      // EventName/ReasonName return views of string literals: safe to keep as const char*.
      row.kind = reflex::EventName(e.type).data();
      row.cause = reflex::ReasonName(e.reason).data();
      row.bonded_fraction = s.bonded_fraction;
      row.load[0] = s.normal_load_n;
      ctx.events->Add(row);
      ++counts_[i][static_cast<int>(e.type)];
      if (e.type == reflex::LegEventType::kPeelEnd &&
          e.reason == reflex::LegEventReason::kTimeLimit && params_.release_failed_peel &&
          adhesion_ != nullptr) {
        adhesion_->RequestReleaseLeg(static_cast<int>(i));
      }
    }
  }
  ctx.hold_all_stance = hold_all;
}

void ReflexEffect::Summarise(const World& world, nlohmann::json* summary) const {
  nlohmann::json legs = nlohmann::json::object();
  for (size_t i = 0; i < legs_.size(); ++i) {
    nlohmann::json c = nlohmann::json::object();
    for (reflex::LegEventType t : kEventTypes) {
      c[std::string(reflex::EventName(t))] = counts_[i][static_cast<int>(t)];
    }
    legs[world.robot().legs[i].name] = c;
  }
  (*summary)["reflex"] = {{"legs", legs}};
}

}  // namespace climbsim::sim
