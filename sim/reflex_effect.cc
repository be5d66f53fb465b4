#include "sim/reflex_effect.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>

namespace climbsim::sim {
namespace {

constexpr reflex::LegEventType kEventTypes[] = {
    reflex::LegEventType::kPreloadStart, reflex::LegEventType::kPreloadEnd,
    reflex::LegEventType::kSearchStart,  reflex::LegEventType::kSearchEnd,
    reflex::LegEventType::kPeel,         reflex::LegEventType::kPeelEnd,
    reflex::LegEventType::kRegrip,       reflex::LegEventType::kGtoHold,
    reflex::LegEventType::kSpindle,      reflex::LegEventType::kGtoUnload};

// The reflex block's checks, each at its key in the scenario file.
class BlockChecker : public Checker {
 public:
  explicit BlockChecker(const Scenario& scenario) : scenario_(scenario) {}
  [[noreturn]] void Fail(std::string_view key, const std::string& message) const override {
    throw ScenarioError(scenario_, "reflex." + std::string(key), message);
  }
  bool Has(std::string_view) const override { return true; }

 private:
  const Scenario& scenario_;
};

}  // namespace

ReflexEffect::ReflexEffect(const Scenario& scenario, const ReflexParams& params, const World& world,
                           const CpgEffect& cpg, AdhesionEffect* adhesion,
                           std::vector<int> event_pad)
    : params_(params),
      adhesion_(adhesion),
      cpg_(&cpg),
      support_(cpg.support()),
      push_hold_(static_cast<int>(world.robot().legs.size()), params.spindle.max_hold_s,
                 cpg.control_period_s()),
      event_pad_(std::move(event_pad)) {
  const double dt = cpg.control_period_s();
  period_steps_ = static_cast<int>(std::lround(dt / world.model()->opt.timestep));
  CheckScenario(scenario, world, cpg, dt);
  BuildLegs(world, dt);
  supported_.assign(legs_.size(), {});
  for (size_t j = 0; j < support_.size(); ++j) {
    for (int i : support_[j]) supported_[i].push_back(static_cast<int>(j));
  }
  waited_on_.assign(legs_.size(), 0);
  if (SharingOn()) BuildSharing(world, dt);
  if (params.PostureOn()) {
    posture_.emplace(params.gto.posture, dt);
    weight_n_ = world.robot().mass_kg * world.gravity().norm();
  }
  if (params.landing.settle_s > 0.0) {
    landing_.assign(legs_.size(), LandingState{});
    jacp_.assign(3 * world.model()->nv, 0.0);
  }
  if (params.tail) tail_.emplace(*params.tail, world, dt, event_pad_.back(), adhesion);
}

bool ReflexEffect::SharingOn() const {
  return params_.gto.enabled && params_.gto.share.gain_per_s > 0.0 && adhesion_ != nullptr;
}

// The reader checked every key's range; what is left needs the control period, the model or
// the other blocks. Raises ScenarioError at the key, in the order the wiring meets them.
void ReflexEffect::CheckScenario(const Scenario& scenario, const World& world,
                                 const CpgEffect& cpg, double dt) const {
  params_.CheckControlPeriod(dt, BlockChecker(scenario));
  CheckServos(scenario, world);
  const int legs = static_cast<int>(world.robot().legs.size());
  const reflex::LoadSharingParams& share = params_.gto.share;
  if (SharingOn()) {
    if (legs > reflex::kMaxSharingLegs) {
      throw ScenarioError(scenario, "reflex.gto.share",
                          "load sharing takes at most " +
                              std::to_string(reflex::kMaxSharingLegs) + " legs");
    }
    if (share.mode == reflex::SharingMode::kForceTracking) {
      RequireFrictionalPads(scenario, legs, "reflex.gto.share.mode",
                            "force_tracking steers directional pads");
    }
  }
  // Checked on the keys, not on whether tracking runs: with spindle and GTO off (bench
  // robustness's second column) the same file must still load.
  if (share.min_grip_n > 0.0 && share.mode != reflex::SharingMode::kForceTracking) {
    throw ScenarioError(scenario, "reflex.gto.share.min_grip_n",
                        "acts only with reflex.gto.share.mode: force_tracking");
  }
  if (params_.PostureOn()) {
    if (adhesion_ == nullptr) {
      throw ScenarioError(scenario, "reflex.gto.posture.enabled",
                          "needs the adhesion block (the pull of the attached pads)");
    }
    if (!cpg.foot_space()) {
      throw ScenarioError(scenario, "reflex.gto.posture.enabled",
                          "needs a foot-space gait (cpg.stride_m): the crouch moves the feet "
                          "along the body's normal");
    }
  }
  if (params_.tail && !world.robot().tail.present()) {
    throw ScenarioError(scenario, "reflex.tail",
                        "needs a robot with a tail (robot.tail: a joint and servo 'tail_pitch')");
  }
  if (params_.tail && params_.tail->yaw_rad > 0.0 && world.robot().tail.yaw_actuator < 0) {
    throw ScenarioError(scenario, "reflex.tail.yaw_rad",
                        "needs a tail with a yaw servo (robot.tail.yaw: true)");
  }
  if (params_.landing.settle_s > 0.0) {
    if (adhesion_ == nullptr) {
      throw ScenarioError(scenario, "reflex.landing",
                          "needs the adhesion block (pads that attach)");
    }
    if (params_.landing.drag_n > 0.0) {
      RequireFrictionalPads(scenario, legs, "reflex.landing.drag_n",
                            "the drag follows each pad's gripping direction");
    }
  }
}

// Stiffness scheduling (compliance, GTO unloading) scales a position servo's kp: only a
// servo with gain kp and bias −kp·q can have it.
void ReflexEffect::CheckServos(const Scenario& scenario, const World& world) const {
  if (!params_.compliance.enabled && !params_.gto.enabled) return;
  const mjModel* m = world.model();
  for (const LegInfo& info : world.robot().legs) {
    for (int k = 0; k < 3; ++k) {
      const int a = info.actuator[k];
      if (m->actuator_biastype[a] != mjBIAS_AFFINE ||
          m->actuator_biasprm[a * mjNBIAS + 1] != -ServoKp(m, a)) {
        throw ScenarioError(scenario, "reflex.compliance",
                            std::string("actuator '") + mj_id2name(m, mjOBJ_ACTUATOR, a) +
                                "' is not a position servo (gain kp, bias -kp q): its "
                                "stiffness cannot be scheduled");
      }
    }
  }
}

// One LegReflex per leg (peel.against_grip signs each leg's peel by its pad), its servos and
// their kp as compiled.
void ReflexEffect::BuildLegs(const World& world, double dt) {
  const reflex::LegReflexParams leg = params_.Leg();
  const mjModel* m = world.model();
  for (size_t i = 0; i < world.robot().legs.size(); ++i) {
    reflex::LegReflexParams own = leg;
    if (params_.peel.against_grip && adhesion_ != nullptr) {
      // The release of a directional pad unloads its gripping shear: the foot moves against
      // the pad's gripping direction (pad x runs along the heading on the bundled robots).
      const int pad = adhesion_->pad_of_leg(static_cast<int>(i));
      if (pad >= 0 && adhesion_->pad(pad).params().law == adhesion::PadLaw::kFrictional) {
        const double grip_x = adhesion_->pad(pad).params().frictional.grip_x;
        own.peel.hip_yaw_rad =
            grip_x > 0 ? -std::abs(leg.peel.hip_yaw_rad) : std::abs(leg.peel.hip_yaw_rad);
      }
    }
    legs_.emplace_back(own, dt);
    const LegInfo& info = world.robot().legs[i];
    std::array<int, 3> a{};
    std::array<double, 3> kp{};
    for (int k = 0; k < 3; ++k) {
      a[k] = info.actuator[k];
      kp[k] = ServoKp(m, a[k]);
    }
    actuator_.push_back(a);
    kp_.push_back(kp);
  }
  counts_.assign(legs_.size(), {});
}

// The load sharing, run every share_every_ control periods, and its buffers (sized once);
// with force tracking, whether every pad grips along one direction in its own frame.
void ReflexEffect::BuildSharing(const World& world, double dt) {
  share_every_ = std::max(1, static_cast<int>(std::lround(params_.gto.share.period_s / dt)));
  sharing_.emplace(params_.gto.share, dt * share_every_);
  sharing_in_.resize(legs_.size());
  share_offset_.assign(legs_.size(), {0.0, 0.0, 0.0});
  unload_.assign(legs_.size(), false);
  jacp_.assign(3 * world.model()->nv, 0.0);
  if (sharing_->params().mode != reflex::SharingMode::kForceTracking) return;
  tracking_.resize(legs_.size());
  grip_share_.resize(legs_.size());
  grip_target_.assign(legs_.size(), 0.0);
  const auto law = [&](int leg) -> const adhesion::FrictionalLaw& {
    return adhesion_->pad(adhesion_->pad_of_leg(leg)).frictional_law();
  };
  for (size_t i = 1; i < legs_.size(); ++i) {
    const adhesion::FrictionalLaw& other = law(static_cast<int>(i));
    common_grip_ = common_grip_ && other.grip_x() == law(0).grip_x() &&
                   other.grip_y() == law(0).grip_y();
  }
}

void ReflexEffect::RequireFrictionalPads(const Scenario& scenario, int legs, const std::string& key,
                                         const std::string& why) const {
  for (int i = 0; i < legs; ++i) {
    const int pad = adhesion_ != nullptr ? adhesion_->pad_of_leg(i) : -1;
    if (pad < 0 || adhesion_->pad(pad).params().law != adhesion::PadLaw::kFrictional) {
      throw ScenarioError(scenario, key,
                          "needs adhesion.law: frictional on every leg's pad (" + why + ")");
    }
  }
}

bool ReflexEffect::UtilisationGradientWorld(const World& world, int leg,
                                            Eigen::Vector3d* grad) const {
  const int pad = adhesion_->pad_of_leg(leg);
  Eigen::Matrix<double, 5, 1> g;
  if (pad < 0 || !adhesion_->pad(pad).UtilisationGradient(&g, adhesion_->peak_bond(pad))) {
    return false;
  }
  const mjData* d = world.data();
  const LegInfo& info = world.robot().legs[leg];
  // The pad frame (x, y, n: columns of the face site's rotation) and the lever from the face
  // centroid to the ankle: the pad's load is (F·n, F·x, F·y, (r×F)·x, (r×F)·y) for the force F
  // the leg puts on it at the ankle, so ∂U/∂F = U_n n + U_x x + U_y y + U_mx x×r + U_my y×r.
  const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rot(
      d->site_xmat + 9 * info.pad_face_site);
  const Eigen::Vector3d x = rot.col(0), y = rot.col(1), n = rot.col(2);
  const Eigen::Vector3d r = Eigen::Map<const Eigen::Vector3d>(d->site_xpos + 3 * info.ankle_site) -
                            Eigen::Map<const Eigen::Vector3d>(d->site_xpos + 3 * info.pad_face_site);
  *grad = g[0] * n + g[1] * x + g[2] * y + g[3] * x.cross(r) + g[4] * y.cross(r);
  return grad->allFinite();
}

void ReflexEffect::ShareLoad(World& world, std::vector<LegSignals>& signals) {
  const mjModel* m = world.model();
  const mjData* d = world.data();
  for (size_t i = 0; i < legs_.size(); ++i) {
    const LegSignals& s = signals[i];
    reflex::SharingLeg& in = sharing_in_[i];
    const int ankle = world.robot().legs[i].ankle_site;
    // A leg shares while its pad is attached in stance and no peel holds its phase, or while
    // an active-release peel asks the others to take its pad's load (bias 1).
    const bool unloading = s.attached && unload_[i];
    in.active = s.attached && ((s.stance && !s.hold_phase) || unloading) &&
                UtilisationGradientWorld(world, static_cast<int>(i), &in.gradient_per_n);
    in.bias = 0.0;
    if (in.active && unloading) {
      // The pad to be let go: drive the force on it to zero (|F| in N stands for its
      // utilisation, its direction for the gradient), ahead of every other pad (bias 1).
      const adhesion::StickyPad& pad = adhesion_->pad(adhesion_->pad_of_leg(static_cast<int>(i)));
      const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rot(
          d->site_xmat + 9 * world.robot().legs[i].pad_face_site);
      const Eigen::Vector3d f =
          rot * Eigen::Vector3d(pad.load().fx_n, pad.load().fy_n, pad.load().fn_n);
      in.utilisation = f.norm();
      in.gradient_per_n = f.norm() > 0.0 ? Eigen::Vector3d(f / f.norm()) : Eigen::Vector3d::Zero();
      in.bias = 1.0;
    }
    in.position_m = Eigen::Map<const Eigen::Vector3d>(d->site_xpos + 3 * ankle);
    if (in.bias == 0.0) in.utilisation = s.utilisation;
  }
  if (!tracking_.empty()) TrackingErrors(world);
  const auto& lambda = sharing_->Update(sharing_in_.data(), static_cast<int>(legs_.size()));
  for (size_t i = 0; i < legs_.size(); ++i) {
    share_offset_[i] = {0.0, 0.0, 0.0};
    if (!sharing_in_[i].active || lambda[i].isZero()) continue;
    // τ = Jᵀ·F for the force F the leg puts on its pad; a position servo's torque changes by
    // kp·Δq while its joint is held.
    const LegInfo& info = world.robot().legs[i];
    mj_jacSite(m, d, jacp_.data(), nullptr, info.ankle_site);
    for (int k = 0; k < 3; ++k) {
      const int dof = info.dof_adr[k];
      const Eigen::Vector3d column(jacp_[dof], jacp_[m->nv + dof], jacp_[2 * m->nv + dof]);
      share_offset_[i][k] = column.dot(lambda[i]) / kp_[i][k];
    }
  }
}

Eigen::Vector3d ReflexEffect::GripDirectionWorld(const World& world, int leg) const {
  const adhesion::FrictionalLaw& law = adhesion_->pad(adhesion_->pad_of_leg(leg)).frictional_law();
  const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rot(
      world.data()->site_xmat + 9 * world.robot().legs[leg].pad_face_site);
  return rot * Eigen::Vector3d(law.grip_x(), law.grip_y(), 0.0);
}

void ReflexEffect::TrackingErrors(const World& world) {
  // Each directional pad's force (what its leg puts on it) in the world: its gripping
  // direction g, its normal n (+ off the surface), its gripping shear F_t = f·g and pull F_n,
  // and the least gripping shear that holds that pull (FrictionalLaw::LeastGripShear).
  const mjData* d = world.data();
  const reflex::LoadSharingParams& share = params_.gto.share;
  for (size_t i = 0; i < legs_.size(); ++i) {
    reflex::SharingLeg& in = sharing_in_[i];
    TrackedPad& t = tracking_[i];
    reflex::GripShare& g = grip_share_[i];
    in.force_error_n.setZero();
    g.active = in.active;
    if (!in.active) continue;
    const adhesion::StickyPad& pad = adhesion_->pad(adhesion_->pad_of_leg(static_cast<int>(i)));
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rot(
        d->site_xmat + 9 * world.robot().legs[i].pad_face_site);
    t.grip = GripDirectionWorld(world, static_cast<int>(i));
    t.normal = rot.col(2);
    t.mu = pad.frictional_law().params().friction_mu;
    t.force = rot * Eigen::Vector3d(pad.load().fx_n, pad.load().fy_n, pad.load().fn_n);
    t.shear = t.force.dot(t.grip);
    t.pull = pad.load().fn_n;
    t.need = pad.frictional_law().LeastGripShear(t.pull, share.friction_credit);
    // min_grip_n: the least grasp, also of a pad being let go until it goes (its opposed
    // partners' shear leans on it).
    if (share.min_grip_n > 0.0) t.need = std::max(t.need, share.min_grip_n);
    g.shares = in.bias == 0.0;
    g.grip = t.grip;
    g.shear_n = t.shear;
    // A pad being let go keeps only what its pull needs (plus kReleaseShearN) and gives the
    // rest away.
    if (!g.shares) t.need = std::max(t.need, 0.0) + kReleaseShearN;
    g.keep_n = g.shares ? t.need : std::min(t.shear, t.need);
  }
  // Each sharing pad's target: its need plus an equal share of the rest (reflex/load_sharing.h).
  reflex::GripShearTargets(grip_share_.data(), static_cast<int>(legs_.size()), common_grip_,
                           grip_target_.data());
  for (size_t i = 0; i < legs_.size(); ++i) {
    reflex::SharingLeg& in = sharing_in_[i];
    const TrackedPad& t = tracking_[i];
    if (!in.active) continue;
    if (in.bias != 0.0) {
      // To no load: no pull (but kept pressed while its shear is reversed, which only friction
      // holds), gripping shear down to its need (up to kReleaseShearN if reversed), no lateral.
      const Eigen::Vector3d lateral = t.force - t.pull * t.normal - t.shear * t.grip;
      const bool reversed = t.shear < 0.0;
      const double pull_target =
          reversed ? kReleasePressFactor * t.shear / std::max(t.mu, 1e-3) : 0.0;
      const double shear_target = reversed ? kReleaseShearN : std::min(t.shear, t.need);
      in.force_error_n = (pull_target - t.pull) * t.normal + (shear_target - t.shear) * t.grip -
                         lateral;
    } else {
      // Lateral shear left free (moving down-wall shear between the left and right pads takes
      // a yaw couple of lateral forces).
      in.force_error_n = (grip_target_[i] - t.shear) * t.grip;
    }
  }
}

void ReflexEffect::Land(World& world, std::vector<LegSignals>& signals) {
  const reflex::LandingParams& p = params_.landing;
  const mjModel* m = world.model();
  const mjData* d = world.data();
  const double period_s = period_steps_ * m->opt.timestep;
  const double keep = std::exp(-period_s / p.settle_s);
  for (size_t i = 0; i < legs_.size(); ++i) {
    LegSignals& s = signals[i];
    LandingState& l = landing_[i];
    const LegInfo& info = world.robot().legs[i];
    if (s.attached && !l.attached) {
      // The servo error now becomes part of the target; the drag is a force along the pad's
      // gripping direction through the servos' stiffness, Δq = Kp⁻¹·Jᵀ·f.
      Eigen::Vector3d f = Eigen::Vector3d::Zero();
      if (p.drag_n > 0.0) {
        f = p.drag_n * GripDirectionWorld(world, static_cast<int>(i));
        mj_jacSite(m, d, jacp_.data(), nullptr, info.ankle_site);
      }
      for (int k = 0; k < 3; ++k) {
        l.offset_rad[k] = d->qpos[info.qpos_adr[k]] - (s.cpg_target_rad[k] + s.offset_rad[k]);
        if (!f.isZero()) {
          const int dof = info.dof_adr[k];
          const Eigen::Vector3d column(jacp_[dof], jacp_[m->nv + dof], jacp_[2 * m->nv + dof]);
          l.offset_rad[k] += column.dot(f) / kp_[i][k];
        }
      }
    }
    l.attached = s.attached;
    for (int k = 0; k < 3; ++k) {
      if (!s.attached) l.offset_rad[k] = 0.0;
      l.offset_rad[k] *= keep;
      s.offset_rad[k] += l.offset_rad[k];
    }
  }
}

void ReflexEffect::Reset(World& world, RunContext& ctx) {
  for (size_t i = 0; i < legs_.size(); ++i) {
    for (int k = 0; k < 3; ++k) SetServoKp(world.model(), actuator_[i][k], kp_[i][k]);
  }
  for (auto& l : legs_) l.Reset();
  if (sharing_) {
    sharing_->Reset();
    for (auto& o : share_offset_) o = {0.0, 0.0, 0.0};
    std::fill(unload_.begin(), unload_.end(), false);
  }
  for (auto& c : counts_) c.fill(0);
  std::fill(landing_.begin(), landing_.end(), LandingState{});
  if (posture_) posture_->Reset();
  if (tail_) tail_->Reset(world);
  push_hold_.Reset();
  ctx.crouch_m = 0.0;
  for (LegSignals& s : *ctx.legs) {
    s.offset_rad = {0, 0, 0};
    s.kp_fraction = {1, 1, 1};
    s.hold_stance = s.hold_phase = false;
  }
  ctx.hold_all_stance = false;
}

void ReflexEffect::Suspend(World& world, RunContext& ctx) {
  for (size_t i = 0; i < legs_.size(); ++i) {
    for (int k = 0; k < 3; ++k) SetServoKp(world.model(), actuator_[i][k], kp_[i][k]);
    if (adhesion_ != nullptr) adhesion_->SetPeelingLeg(static_cast<int>(i), false);
  }
  for (LegSignals& s : *ctx.legs) {
    s.offset_rad = {0, 0, 0};
    s.kp_fraction = {1, 1, 1};
    s.hold_stance = s.hold_phase = false;
  }
  ctx.hold_all_stance = false;
  // Stands up again: the other controller places the feet from the body it finds.
  if (posture_) posture_->Reset();
  push_hold_.Reset();
  ctx.crouch_m = 0.0;
}

// Leg i's sensing from its signals (bonds_lost is consumed) and the joints' stretch; the
// support legs give the partner and support inputs.
reflex::LegSensing ReflexEffect::SenseLeg(const World& world, std::vector<LegSignals>& signals,
                                          size_t i) const {
  const mjData* d = world.data();
  LegSignals& s = signals[i];
  const LegInfo& info = world.robot().legs[i];
  reflex::LegSensing in;
  in.stance = s.stance;
  in.phase_progress = s.progress;
  in.touching = s.touching;
  in.attached = s.attached;
  // The bonded share of what touches (as cpg.support_bond_fraction counts it): a pad on rock
  // that has bonded all it touches is not pressed further. Exactly 1 on a flat surface.
  in.bonded_fraction =
      s.touched_fraction > 0.0 ? s.bonded_fraction / s.touched_fraction : s.bonded_fraction;
  in.touched_fraction = s.touched_fraction;
  in.refusal = s.refusal;
  in.normal_load_n = s.normal_load_n;
  in.preload_n = s.preload_n;
  in.load_n = s.load_n;
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
  in.waited_on = waited_on_[i] != 0;
  in.bond_awaited = static_cast<int>(i) == cpg_->awaited_bond_leg();
  return in;
}

// Legs whose pad the gait waits for, from every leg's last period, so that the order in which
// the legs are updated does not matter: a peel waits for it (peel.wait_for_support), or, with
// search.again_when_stood, the gait has stood still for longer than the leg's whole search (a
// partner holding stance for a foot whose search ran out waits for good: the foot stands in
// stance and so never swings).
void ReflexEffect::MarkWaitedOn(const std::vector<LegSignals>& signals, double time_s) {
  const double held_s = cpg_->held_since_s() < 0.0 ? 0.0 : time_s - cpg_->held_since_s();
  for (size_t i = 0; i < legs_.size(); ++i) {
    waited_on_[i] = 0;
    if (signals[i].attached) continue;
    const reflex::SearchParams& search = legs_[i].params().search;
    if (search.again_when_stood && held_s > search.max_attempts * search.attempt_duration_s) {
      waited_on_[i] = 1;
    }
    for (int j : supported_[i]) {
      if (signals[j].hold_phase && legs_[j].params().peel.wait_for_support) waited_on_[i] = 1;
    }
  }
}

// Leg i's answer into its signals (its servos' stiffness among them) and its pad's release and
// peel state.
void ReflexEffect::ApplyLeg(LegSignals& s, size_t i, const reflex::LegReflexOutput& out) {
  for (int k = 0; k < 3; ++k) {
    s.offset_rad[k] = out.target_offset_rad[k];
    // The stiffness goes out through the controller's command (Command::kp_scale), which
    // the pipeline applies to the servo (sim/controller.h).
    s.kp_fraction[k] = out.kp_fraction[k];
  }
  s.hold_stance = out.hold_stance;
  s.hold_phase = out.hold_phase;
  if (sharing_) unload_[i] = out.unload_pad;
  if (adhesion_ != nullptr) {
    if (out.release_pad) adhesion_->RequestReleaseLeg(static_cast<int>(i));
    adhesion_->SetDisengagedLeg(static_cast<int>(i), out.disengage_pad);
  }
  // While the peel pulls (phase held), a let-go is the peel it meant.
  if (adhesion_ != nullptr) adhesion_->SetPeelingLeg(static_cast<int>(i), out.hold_phase);
}

// One events.csv row per event of leg i, counted; with release_failed_peel a peel out of time
// lets its pad go.
void ReflexEffect::LogEvents(RunContext& ctx, const LegSignals& s, size_t i,
                             const reflex::LegReflexOutput& out) {
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

// The robot-level channels after every leg's reflexes: load sharing, landing, posture.
void ReflexEffect::RobotChannels(World& world, RunContext& ctx) {
  std::vector<LegSignals>& signals = *ctx.legs;
  if (sharing_) {
    // The law runs every share_every_ control periods; its offsets hold in between (a leg
    // whose pad let go drops its own at once).
    if ((ctx.step / period_steps_) % share_every_ == 0) ShareLoad(world, signals);
    for (size_t i = 0; i < legs_.size(); ++i) {
      if (!signals[i].attached) share_offset_[i] = {0.0, 0.0, 0.0};
      for (int k = 0; k < 3; ++k) signals[i].offset_rad[k] += share_offset_[i][k];
    }
  }
  if (!landing_.empty()) Land(world, signals);
  if (posture_) {
    // The pull of the pads that carry the robot: not of one its own leg peels.
    double pull_n = 0.0;
    for (size_t i = 0; i < legs_.size(); ++i) {
      const LegSignals& s = signals[i];
      if (s.attached && !legs_[i].state().peeling) pull_n += std::max(0.0, s.normal_load_n);
    }
    ctx.crouch_m = posture_->Update(pull_n / weight_n_);
  }
}

void ReflexEffect::BeforeStep(World& world, RunContext& ctx) {
  if (ctx.step % period_steps_ != 0) return;
  std::vector<LegSignals>& signals = *ctx.legs;
  bool regrip = false;
  MarkWaitedOn(signals, ctx.time_s);
  for (size_t i = 0; i < legs_.size(); ++i) {
    const reflex::LegReflexOutput out = legs_[i].Update(SenseLeg(world, signals, i));
    ApplyLeg(signals[i], i, out);
    regrip |= out.regrip_hold;
    push_hold_.SetLeg(static_cast<int>(i), out.pushed,
                      signals[i].stance && signals[i].attached);
    LogEvents(ctx, signals[i], i, out);
  }
  RobotChannels(world, ctx);
  if (tail_) tail_->Update(world, ctx, legs_);
  const bool pushed = push_hold_.Update();
  ctx.hold_all_stance = regrip || pushed;
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
  if (tail_) {
    (*summary)["reflex"]["tail"] = {{"presses", tail_->presses()},
                                    {"max_pitch_rad", tail_->max_pitch_rad()}};
  }
}

}  // namespace climbsim::sim
