#include "sim/transition_effect.h"

#include <Eigen/Geometry>
#include <string>
#include <utility>

#include "reflex/reflex.h"

namespace climbsim::sim {
namespace {

// The corner plan for the world's robot; a leg it cannot plan for is reported at the
// transition key.
CornerPlan PlanFor(const Scenario& scenario, const TransitionParams& params, const World& world) {
  const std::string problem = CornerPlan::Problem(world.model(), world.robot());
  if (!problem.empty()) throw ScenarioError(scenario, "transition", problem);
  return CornerPlan(world.model(), world.robot(), params);
}

}  // namespace

// The manoeuvre's senses and commands over one control tick: this run's world, the adhesion
// effect, the gait and the event log.
class TransitionEffect::Io final : public ManoeuvreIo {
 public:
  Io(TransitionEffect& effect, World& world, RunContext& ctx)
      : effect_(effect), world_(world), ctx_(ctx) {}

  BodyPose BasePose() const override {
    const double* q = world_.data()->qpos + world_.robot().root_qpos_adr;
    BodyPose p;
    p.p = Eigen::Vector3d(q[0], q[1], q[2]);
    p.r = Eigen::Quaterniond(q[3], q[4], q[5], q[6]).normalized().toRotationMatrix();
    return p;
  }
  adhesion::PadFrame PadFace(int leg) const override {
    return adhesion::FaceFrame(world_.data(), Pad(leg).geometry());
  }
  const adhesion::ContactSense& PadContact(int leg) const override { return Pad(leg).sense(); }
  bool PadHolds(int leg) const override { return Pad(leg).attached(); }
  Eigen::Vector3d PadLoad(int leg) const override {
    const adhesion::PadLoad& l = Pad(leg).load();
    return Eigen::Vector3d(l.fx_n, l.fy_n, l.fn_n);
  }
  LegChain::Q Joints(int leg) const override {
    const LegInfo& info = world_.robot().legs[leg];
    LegChain::Q q;
    for (int k = 0; k < 3; ++k) q[k] = world_.data()->qpos[info.qpos_adr[k]];
    return q;
  }
  void Commanded(int leg, LegChain::Q* q, double* tilt) const override {
    const LegInfo& info = world_.robot().legs[leg];
    const mjData* d = world_.data();
    for (int k = 0; k < 3; ++k) (*q)[k] = d->ctrl[info.actuator[k]];
    *tilt = d->ctrl[info.tilt_actuator];
  }
  void SetPeeling(int leg, bool peeling) override {
    effect_.adhesion_->SetPeelingLeg(leg, peeling);
  }
  void GaitFoot(int leg, double theta_rad, double* dx, double* dz) const override {
    effect_.cpg_->FootAt(leg, theta_rad, dx, dz);
  }
  void GaitResumePhases(std::span<double> theta_rad) const override {
    effect_.cpg_->ResumePhases(theta_rad);
  }
  void RestoreKp() override { effect_.RestoreKp(world_); }
  void WriteTargets() override { effect_.WriteTargets(world_); }
  void Log(int leg, const char* kind, const char* cause) override {
    if (ctx_.events == nullptr) return;
    Event e;
    e.time_s = ctx_.time_s;
    e.pad = effect_.event_pad_[leg];
    e.kind = kind;
    e.cause = cause;
    ctx_.events->Add(e);
  }

 private:
  const adhesion::StickyPad& Pad(int leg) const {
    return effect_.adhesion_->pad(effect_.adhesion_->pad_of_leg(leg));
  }

  TransitionEffect& effect_;
  World& world_;
  RunContext& ctx_;
};

TransitionEffect::TransitionEffect(const Scenario& scenario, const TransitionParams& params,
                                   const World& world, AdhesionEffect* adhesion,
                                   const CpgEffect* cpg, double period_s,
                                   std::vector<int> event_pad)
    : params_(params),
      adhesion_(adhesion),
      cpg_(cpg),
      event_pad_(std::move(event_pad)),
      manoeuvre_(PlanFor(scenario, params, world), params, period_s, params.then == "gait") {
  if (params_.then == "gait" && (cpg_ == nullptr || !cpg_->foot_space())) {
    throw ScenarioError(scenario, "transition.then",
                        "gait: the feet are handed back to the CPG's foot-space gait, which needs "
                        "cpg.stride_m");
  }
  if (adhesion_ == nullptr) {
    throw ScenarioError(scenario, "transition",
                        "needs the adhesion block: it senses what the pads touch and hold");
  }
  const RobotInfo& robot = world.robot();
  for (size_t i = 0; i < robot.legs.size(); ++i) {
    if (!manoeuvre_.plan().chains()[i].has_tilt()) {
      throw ScenarioError(scenario, "transition",
                          "the robot has no ankle tilt servo '" + robot.legs[i].name +
                              "_ankle_tilt': a pad must turn to face the new surface (robot "
                              "gecko_ankle or spider_ankle, mjcf/README.md)");
    }
    if (adhesion_->pad_of_leg(static_cast<int>(i)) < 0) {
      throw ScenarioError(scenario, "transition",
                          "every leg's pad must be sticky (adhesion.pads): " + robot.legs[i].name);
    }
  }
  for (const LegInfo& l : robot.legs) {
    std::array<double, 3> kp{};
    for (int k = 0; k < 3; ++k) kp[k] = ServoKp(world.model(), l.actuator[k]);
    kp_.push_back(kp);
  }
}

void TransitionEffect::Reset(World&, RunContext&) { manoeuvre_.Reset(); }

void TransitionEffect::SensePads(const RunContext& ctx) {
  const std::vector<LegSignals>& legs = *ctx.legs;
  std::vector<PadSignals>& pads = manoeuvre_.pads();
  for (size_t i = 0; i < pads.size(); ++i) {
    pads[i] = {legs[i].touching, legs[i].attached, legs[i].bonded_fraction,
               legs[i].touched_fraction, legs[i].preload_n, legs[i].bondable_fraction};
  }
}

bool TransitionEffect::Watch(World& world, RunContext& ctx) {
  SensePads(ctx);
  Io io(*this, world, ctx);
  return manoeuvre_.Watch(io, ctx.time_s);
}

void TransitionEffect::Update(World& world, RunContext& ctx) {
  SensePads(ctx);
  Io io(*this, world, ctx);
  manoeuvre_.Update(io, ctx.time_s);
}

void TransitionEffect::RestoreKp(World& world) const {
  mjModel* m = world.model();
  const RobotInfo& r = world.robot();
  for (size_t i = 0; i < kp_.size(); ++i) {
    for (int k = 0; k < 3; ++k) SetServoKp(m, r.legs[i].actuator[k], kp_[i][k]);
  }
}

void TransitionEffect::WriteTargets(World& world) const {
  double* ctrl = world.data()->ctrl;
  const RobotInfo& r = world.robot();
  mjModel* m = world.model();
  const std::vector<Foot>& feet = manoeuvre_.feet();
  for (size_t i = 0; i < feet.size(); ++i) {
    for (int k = 0; k < 3; ++k) ctrl[r.legs[i].actuator[k]] = feet[i].q[k];
    ctrl[r.legs[i].tilt_actuator] = feet[i].tilt;
    if (params_.unload_gain > 0) {
      // Stance legs only: the leg that peels must pull.
      const double u = static_cast<int>(i) == manoeuvre_.step_leg()
                           ? 0.0
                           : adhesion_->utilisation(adhesion_->pad_of_leg(static_cast<int>(i)));
      // The reflexes' GTO unload law on the utilisation as it is (no delay), kp at least 20 %.
      const double f = reflex::GtoUnloadKpFraction(
          reflex::GtoLaw(u, params_.unload_gain, params_.unload_threshold), 0.2);
      for (int k = 0; k < 3; ++k) SetServoKp(m, r.legs[i].actuator[k], kp_[i][k] * f);
    }
  }
}

void TransitionEffect::Summarise(const World& world, nlohmann::json* summary) const {
  const auto& legs = world.robot().legs;
  const ManoeuvreReport& report = manoeuvre_.report();
  const auto pad = [&](int i) {
    return i >= 0 ? nlohmann::json(legs[i].name + "_pad") : nlohmann::json();
  };
  const auto time = [](double t) { return t >= 0 ? nlohmann::json(t) : nlohmann::json(); };
  nlohmann::json j;
  j["triggered"] = report.trigger_time_s >= 0;
  j["trigger_time_s"] = time(report.trigger_time_s);
  j["trigger_pad"] = pad(report.trigger_leg);
  const char* geom = report.trigger_geom >= 0
                         ? mj_id2name(world.model(), mjOBJ_GEOM, report.trigger_geom)
                         : nullptr;
  j["new_surface"] = geom != nullptr ? nlohmann::json(geom) : nlohmann::json();
  j["corner"] = report.trigger_time_s < 0
                    ? nlohmann::json()
                    : nlohmann::json(manoeuvre_.plan().inner() ? "inner" : "outer");
  j["last_old_surface_detach_s"] = time(report.last_old_detach_s);
  j["last_old_surface_pad"] = pad(report.last_old_leg);
  j["first_new_surface_attach_s"] = time(report.first_new_attach_s);
  j["first_new_surface_pad"] = pad(report.first_new_leg);
  j["all_on_new_surface_s"] = time(report.end_time_s);
  j["steps"] = report.steps;
  j["failed"] = manoeuvre_.failed();
  if (manoeuvre_.failed()) {
    j["failure"] = report.fail_why;
    j["failure_time_s"] = report.fail_time_s;
    j["failure_pad"] = pad(report.fail_leg);
  }
  (*summary)["transition"] = j;
}

}  // namespace climbsim::sim
