#include "sim/transition_effect.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace climbsim::sim {
namespace {

constexpr double kStanceTurn = CornerPlan::kStanceTurn;
// A foot pressed onto its surface that has not attached after this long is lifted and placed
// again (the pad must leave the surface before it can attach again: adhesion/sticky_pad.h).
constexpr double kAttachWait = 0.35;
// How often (σ) a leg waiting in the air looks for a foothold again.
constexpr double kIdleCheck = 0.02;
// A peel that has not let go after peel_max_s pulls the other way, then sideways: this many
// tries in all.
constexpr int kPeelAttempts = 3;
// A peel pulls along the other pads' load when it has at least kPeelLoad (N) along the peeling
// pad's surface, else along their normals when their sum has at least kPeelAlong there.
constexpr double kPeelLoad = 0.2;
constexpr double kPeelAlong = 0.5;
// The probe for an edge (a front foot that found no surface): the body crouches over
// kProbeCrouchS, the foot goes kProbeBelow past the old surface's plane (beyond the pad's half
// width) and then back towards the body at kProbeSpeed for at most kProbeBack.
constexpr double kProbeCrouchS = 1.0;
constexpr double kProbeBelow = 0.006;
constexpr double kProbeSpeed = 0.02;
constexpr double kProbeBack = 0.06;
// The body's sag correction: its largest shift and turn.
constexpr double kTrackMaxM = 0.015;
constexpr double kTrackMaxRad = 0.15;
// The sag correction is a slow integral (track_s, about a second): updated every 10 ms, so that
// a stance leg's target, and its solve, change once a period while another leg steps.
constexpr double kTrackPeriodS = 0.01;
// The share of a swing spent lifting the foot straight off the surface it leaves.
constexpr double kLiftShare = 0.3;
// A pad with this many contact points with a surface lies flat on it.
constexpr int kFlatContacts = 3;
// A foot closer than this to where the gait wants it is not stepped there (m).
constexpr double kHandBackTolerance = 0.004;

CornerPlan MakePlan(const Scenario& scenario, const TransitionParams& params, const World& world) {
  try {
    return CornerPlan(world.model(), world.robot(), params);
  } catch (const std::invalid_argument& e) {
    throw ScenarioError(scenario, "transition", e.what());
  }
}

}  // namespace

TransitionEffect::TransitionEffect(const Scenario& scenario, const TransitionParams& params,
                                   const World& world, AdhesionEffect* adhesion,
                                   const CpgEffect* cpg, double period_s,
                                   std::vector<int> event_pad)
    : params_(params),
      adhesion_(adhesion),
      dt_(period_s),
      event_pad_(std::move(event_pad)),
      plan_(MakePlan(scenario, params, world)),
      cpg_(cpg) {
  track_every_ = std::max(1, static_cast<int>(std::lround(kTrackPeriodS / period_s)));
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
    const LegChain& c = plan_.chains()[i];
    if (!c.has_tilt()) {
      throw ScenarioError(scenario, "transition",
                          "the robot has no ankle tilt servo '" + robot.legs[i].name +
                              "_ankle_tilt': a pad must turn to face the new surface (robot "
                              "gecko_ankle or spider_ankle, mjcf/README.md)");
    }
    if (adhesion_->pad_of_leg(static_cast<int>(i)) < 0) {
      throw ScenarioError(scenario, "transition",
                          "every leg's pad must be sticky (adhesion.pads): " + robot.legs[i].name);
    }
    if (c.hip().x() > 1e-6) front_.push_back(static_cast<int>(i));
  }
  feet_.resize(robot.legs.size());
  attached_.assign(robot.legs.size(), 0);
  resume_theta_.assign(robot.legs.size(), 0.0);
  handed_.assign(robot.legs.size(), 0);
  air_since_.assign(robot.legs.size(), -1.0);
  for (const LegInfo& l : robot.legs) {
    std::array<double, 3> kp{};
    for (int k = 0; k < 3; ++k) kp[k] = ServoKp(world.model(), l.actuator[k]);
    kp_.push_back(kp);
  }
}

void TransitionEffect::Reset(World&, RunContext&) {
  mode_ = Mode::kWatching;
  for (Foot& f : feet_) f = Foot{};
  std::fill(attached_.begin(), attached_.end(), 0);
  step_leg_ = -1;
  step_ = StepPhase::kNone;
  sigma_ = idle_check_ = 0.0;
  trigger_time_s_ = end_time_s_ = fail_time_s_ = -1.0;
  trigger_leg_ = trigger_geom_ = fail_leg_ = -1;
  fail_why_ = "";
  last_old_detach_s_ = first_new_attach_s_ = -1.0;
  last_old_leg_ = first_new_leg_ = -1;
  steps_ = 0;
  resume_pending_ = false;
  std::fill(air_since_.begin(), air_since_.end(), -1.0);
  probe_leg_ = -1;
  track_tick_ = 0;
}

BodyPose TransitionEffect::ActualPose(const World& world) const {
  const double* q = world.data()->qpos + world.robot().root_qpos_adr;
  BodyPose p;
  p.p = Eigen::Vector3d(q[0], q[1], q[2]);
  p.r = Eigen::Quaterniond(q[3], q[4], q[5], q[6]).normalized().toRotationMatrix();
  return p;
}

bool TransitionEffect::OldSurface(const World& world, const std::vector<LegSignals>& legs,
                                  Eigen::Vector3d* n0, Eigen::Vector3d* p0) const {
  // The surface the robot stands on: the attached pads' faces.
  n0->setZero();
  p0->setZero();
  int attached = 0;
  for (size_t j = 0; j < legs.size(); ++j) {
    if (!legs[j].attached) continue;
    const adhesion::PadFrame f = adhesion::FaceFrame(
        world.data(), adhesion_->pad(adhesion_->pad_of_leg(static_cast<int>(j))).geometry());
    *n0 += f.rot.col(2);
    *p0 += f.pos;
    ++attached;
  }
  if (attached == 0) return false;
  n0->normalize();
  *p0 /= attached;
  return true;
}

bool TransitionEffect::Corner(World& world, RunContext& ctx, int leg) {
  const std::vector<LegSignals>& legs = *ctx.legs;
  const adhesion::ContactSense& sense = adhesion_->pad(adhesion_->pad_of_leg(leg)).sense();
  if (sense.contacts <= 0) return false;
  Eigen::Vector3d n0, p0;
  if (!OldSurface(world, legs, &n0, &p0)) return false;
  const Eigen::Vector3d& n1 = sense.surface_normal;
  if (n1.dot(n0) > std::cos(params_.trigger_angle_deg * M_PI / 180)) return false;
  const Eigen::Vector3d along = n1 - n1.dot(n0) * n0;
  if (along.norm() < 0.5) return false;  // not a corner across the way (a step, a side wall)
  // Inner when the new surface faces the robot, outer when it faces the way it goes.
  const BodyPose base = ActualPose(world);
  const bool inner = along.dot(base.r.col(0)) < 0;
  const Eigen::Vector3d t0 = (inner ? -along : along).normalized();
  // The corner's point in the body's plane of travel: on the old surface and the new one.
  const Eigen::Vector3d origin =
      base.p + t0.dot(sense.contact_pos - base.p) * t0 + n0.dot(p0 - base.p) * n0;
  plan_.SetCorner(origin, n0, t0, inner);
  trigger_geom_ = sense.surface_geom;
  Trigger(world, ctx, leg);
  return true;
}

bool TransitionEffect::Watch(World& world, RunContext& ctx) {
  const std::vector<LegSignals>& legs = *ctx.legs;
  for (int i : front_) {
    // A front pad touching a surface with another normal: a corner ahead.
    if (!legs[i].attached && legs[i].touching && Corner(world, ctx, i)) return true;
    // A front foot that has found no surface for lost_s: the surface ended (an edge ahead).
    if (legs[i].attached || legs[i].touching || air_since_[i] < 0) {
      air_since_[i] = ctx.time_s;
    } else if (ctx.time_s - air_since_[i] > params_.lost_s) {
      StartProbe(world, ctx, i);
      return true;
    }
  }
  return false;
}

void TransitionEffect::StartProbe(World& world, RunContext& ctx, int leg) {
  Eigen::Vector3d n0, p0;
  if (!OldSurface(world, *ctx.legs, &n0, &p0)) return;
  cmd_ = ActualPose(world);
  up_ = world.gravity().norm() > 0 ? Eigen::Vector3d(-world.gravity().normalized())
                                   : Eigen::Vector3d::UnitZ();
  HoldFeet(world, ctx);
  probe_start_ = cmd_;
  probe_n0_ = n0;
  probe_p0_ = p0;
  const Eigen::Vector3d x = cmd_.r.col(0);
  probe_fwd_ = (x - x.dot(n0) * n0).normalized();
  probe_leg_ = leg;
  probe_phase_ = 0;
  probe_t0_ = ctx.time_s;
  mode_ = Mode::kProbe;
  trigger_time_s_ = ctx.time_s;
  trigger_leg_ = leg;
  Log(ctx, leg, "transition_probe", "lost_ground");
  Update(world, ctx);
}

void TransitionEffect::ProbeTick(World& world, RunContext& ctx) {
  const int i = probe_leg_;
  Foot& f = feet_[i];
  const LegChain& c = plan_.chains()[i];
  const double t = ctx.time_s;
  const double post = c.post_m();
  // 1. The body crouches by crouch_m on the stance feet, so that the probing foot reaches
  //    below the edge.
  if (probe_phase_ == 0) {
    const double u = SmoothStep((t - probe_t0_) / kProbeCrouchS);
    BodyPose pose = probe_start_;
    pose.p -= u * params_.crouch_m * probe_n0_;
    for (size_t j = 0; j < feet_.size(); ++j) {
      if (!feet_[j].stance) continue;
      if (plan_.Margin(static_cast<int>(j), Corrected(pose), StanceTarget(static_cast<int>(j)),
                       feet_[j].normal_w, &feet_[j].q, &feet_[j].tilt, kStanceTurn) < 0) {
        Fail(ctx, static_cast<int>(j), "no_crouch");
        return;
      }
    }
    cmd_ = pose;
    if (u >= 1.0) {
      probe_phase_ = 1;
      probe_t0_ = t;
      const adhesion::PadFrame pf =
          adhesion::FaceFrame(world.data(), adhesion_->pad(adhesion_->pad_of_leg(i)).geometry());
      from_face_ = pf.pos;
      from_normal_ = pf.rot.col(2);
    }
    return;
  }
  // 2. The probing foot turns its pad to face back and goes down past the old surface's plane,
  //    where the foot is along the way; 3. then back towards the body until it touches.
  const double level = (from_face_ - probe_p0_).dot(probe_n0_);
  const Eigen::Vector3d above = from_face_ + (params_.lift_m - level) * probe_n0_;
  const Eigen::Vector3d below =
      from_face_ - (level + plan_.pad_half_m() + kProbeBelow) * probe_n0_;
  Eigen::Vector3d face, normal;
  if (probe_phase_ == 1) {
    const double u = std::clamp((t - probe_t0_) / params_.swing_s, 0.0, 1.0);
    const double s = SmoothStep(u);
    face = s < 0.5 ? from_face_ + 2 * s * (above - from_face_)
                   : above + (2 * s - 1) * (below - above);
    normal = Slerp(from_normal_, probe_fwd_, std::min(1.0, 2 * s));
    if (u >= 1.0) probe_phase_ = 2, probe_t0_ = t;
    if ((*ctx.legs)[i].touching) {  // the old surface goes on after all
      Fail(ctx, i, "no_edge");
      return;
    }
  } else {
    const double back = std::min(kProbeBack, kProbeSpeed * (t - probe_t0_));
    face = below - back * probe_fwd_;
    normal = probe_fwd_;
    if ((*ctx.legs)[i].touching) {
      if (!Corner(world, ctx, i)) Fail(ctx, i, "no_edge");
      return;
    }
    if (back >= kProbeBack) {
      Fail(ctx, i, "no_edge");
      return;
    }
  }
  plan_.Margin(i, cmd_, face + post * normal, normal, &f.q, &f.tilt, kStanceTurn);
}

void TransitionEffect::HoldFeet(World& world, RunContext& ctx) {
  corr_p_.setZero();
  corr_w_.setZero();
  corr_r_ = Exp(corr_w_);
  const mjData* d = world.data();
  const std::vector<LegSignals>& legs = *ctx.legs;
  for (size_t i = 0; i < feet_.size(); ++i) {
    const LegInfo& info = world.robot().legs[i];
    Foot& f = feet_[i];
    f = Foot{};
    // Hold what the gait commanded last.
    for (int k = 0; k < 3; ++k) f.q[k] = d->ctrl[info.actuator[k]];
    f.tilt = d->ctrl[info.tilt_actuator];
    f.stance = legs[i].attached;
    const adhesion::PadFrame face = adhesion::FaceFrame(
        d, adhesion_->pad(adhesion_->pad_of_leg(static_cast<int>(i))).geometry());
    f.normal_w = face.rot.col(2);
    f.surface = 0;
    f.ankle_w = cmd_.p + cmd_.r * plan_.chains()[i].Ankle(f.q, 0.0);
    attached_[i] = legs[i].attached ? 1 : 0;
  }
}

void TransitionEffect::Trigger(World& world, RunContext& ctx, int leg) {
  cmd_ = ActualPose(world);
  up_ = world.gravity().norm() > 0 ? Eigen::Vector3d(-world.gravity().normalized())
                                   : Eigen::Vector3d::UnitZ();
  HoldFeet(world, ctx);
  for (Foot& f : feet_) {
    if (!f.stance) f.normal_w = plan_.normal(0);
    f.surface = f.stance && plan_.SurfaceOf(f.normal_w) == 1 ? 1 : 0;
  }
  mode_ = Mode::kSettle;
  if (trigger_time_s_ < 0) trigger_time_s_ = ctx.time_s;
  if (trigger_leg_ < 0) trigger_leg_ = leg;
  Log(ctx, leg, "transition_start", plan_.inner() ? "inner" : "outer");
  Update(world, ctx);
}

Eigen::Vector3d TransitionEffect::StanceTarget(int i) const { return feet_[i].ankle_w; }

int TransitionEffect::StanceCount() const {
  int n = 0;
  for (const Foot& f : feet_) n += f.stance ? 1 : 0;
  return n;
}

bool TransitionEffect::SupportsHold(int except, const std::vector<LegSignals>& legs) const {
  for (size_t i = 0; i < feet_.size(); ++i) {
    if (static_cast<int>(i) == except || feet_[i].idle) continue;
    if (!feet_[i].stance || !legs[i].attached) return false;
    if (legs[i].bonded_fraction < params_.support_bond_fraction) return false;
  }
  return true;
}

void TransitionEffect::StartStep(World& world, RunContext& ctx, int leg, const Foothold& to,
                                 bool peel) {
  step_leg_ = leg;
  to_ = to;
  attempts_ = 0;
  step_t0_ = ctx.time_s;
  touch_since_ = -1.0;
  ++steps_;
  Foot& f = feet_[leg];
  f.stance = false;
  // Peel: the pull's reaction on the body goes to the other pads. It should relieve them: the
  // pull points along the load they carry (the weight, mostly), projected on this pad's
  // surface. Without such a load there: along the sum of their normals, so that the reaction
  // presses them into their surfaces; when they all stand on this pad's surface, back along
  // it, against the body's heading.
  const Eigen::Vector3d x = cmd_.r.col(0);
  Eigen::Vector3d back = -(x - x.dot(f.normal_w) * f.normal_w).normalized();
  Eigen::Vector3d load = Eigen::Vector3d::Zero(), normals = Eigen::Vector3d::Zero();
  for (size_t j = 0; j < feet_.size(); ++j) {
    if (static_cast<int>(j) == leg || !feet_[j].stance) continue;
    normals += feet_[j].normal_w;
    const adhesion::StickyPad& pad = adhesion_->pad(adhesion_->pad_of_leg(static_cast<int>(j)));
    if (!pad.attached()) continue;
    const adhesion::PadFrame pf = adhesion::FaceFrame(world.data(), pad.geometry());
    const adhesion::PadLoad& l = pad.load();
    load += pf.rot * Eigen::Vector3d(l.fx_n, l.fy_n, l.fn_n);
  }
  load -= load.dot(f.normal_w) * f.normal_w;
  normals -= normals.dot(f.normal_w) * f.normal_w;
  const bool by_load = params_.peel_toward == "load";
  if (by_load && load.norm() > kPeelLoad) {
    back = load.normalized();
  } else if (params_.peel_toward != "back" && normals.norm() > kPeelAlong) {
    back = normals.normalized();
  }
  peel_dir_ = params_.peel_back_m * back;
  Log(ctx, leg, "transition_step", to.surface < 0 ? "idle" : peel ? "peel" : "place");
  if (peel) {
    step_ = StepPhase::kPeel;
    peel_from_.setZero();
    peel_attempts_ = 0;
    adhesion_->SetPeelingLeg(leg, true);
  } else {
    BeginSwing(world, ctx.time_s);
  }
}

void TransitionEffect::BeginSwing(World& world, double t) {
  const int i = step_leg_;
  Foot& f = feet_[i];
  // From the pad's face as it is now.
  const adhesion::PadFrame face =
      adhesion::FaceFrame(world.data(), adhesion_->pad(adhesion_->pad_of_leg(i)).geometry());
  from_face_ = face.pos;
  from_normal_ = face.rot.col(2);
  if (to_.surface < 0) {
    // Into the air: lifted off its surface, then held there in the body's frame.
    to_.face = from_face_ + (params_.lift_m + 0.01) * from_normal_;
    to_.normal = from_normal_;
    f.idle = true;
    f.ankle_w = cmd_.r.transpose() *
                (to_.face + plan_.chains()[i].post_m() * to_.normal - cmd_.p);
  }
  use_via_ = !plan_.inner() && to_.surface >= 0 && to_.surface != f.surface;
  if (use_via_) {
    // Round the edge: out along the bisector of the two normals, at the target's side.
    const double lateral = (to_.face - plan_.origin()).dot(plan_.lateral());
    via_ = plan_.origin() + lateral * plan_.lateral() +
           (1.5 * plan_.pad_half_m() + params_.lift_m) * (plan_.normal(0) + plan_.normal(1)).normalized();
  }
  step_ = StepPhase::kSwing;
  step_t0_ = t;
  swing_q_ = f.q;
}

void TransitionEffect::AdvanceStep(World& world, RunContext& ctx) {
  const int i = step_leg_;
  Foot& f = feet_[i];
  const LegChain& c = plan_.chains()[i];
  const double t = ctx.time_s;
  const bool attached = (*ctx.legs)[i].attached;
  const bool touching = (*ctx.legs)[i].touching;
  if (step_ == StepPhase::kPeel) {
    const double u = SmoothStep((t - step_t0_) / params_.peel_ramp_s);
    const Eigen::Vector3d pull = peel_from_ + u * (peel_dir_ - peel_from_);
    plan_.Margin(i, Corrected(cmd_), f.ankle_w + pull + u * params_.peel_lift_m * f.normal_w,
                 f.normal_w, &f.q, &f.tilt, kStanceTurn);
    // The tilt servo turns the pad the way the pull does, as far as its torque goes: the bonds
    // see that much more peel moment and the leg pulls less. The pull along d at the top of
    // the post turns the pad about n × d.
    const adhesion::PadFrame pf =
        adhesion::FaceFrame(world.data(), adhesion_->pad(adhesion_->pad_of_leg(i)).geometry());
    const double turn = f.normal_w.cross(peel_dir_).dot(pf.rot.col(1)) >= 0 ? 1.0 : -1.0;
    f.tilt = std::clamp(f.tilt + turn * u * params_.peel_tilt_rad, c.tilt_lo(), c.tilt_hi());
    if (!attached) {
      adhesion_->SetPeelingLeg(i, false);
      BeginSwing(world, t);
    } else if (t - step_t0_ > params_.peel_max_s) {
      // Not let go: pull the other way, then sideways (from where the pull is now).
      if (++peel_attempts_ >= kPeelAttempts) {
        adhesion_->SetPeelingLeg(i, false);
        Fail(ctx, i, "peel_time_limit");
        return;
      }
      peel_from_ = pull;
      const double side = c.hip().y() > 0 ? -1.0 : 1.0;
      const Eigen::Vector3d y = cmd_.r.col(1);
      const Eigen::Vector3d in = side * (y - y.dot(f.normal_w) * f.normal_w).normalized();
      peel_dir_ = peel_attempts_ == 1 ? Eigen::Vector3d(-peel_dir_)
                                      : Eigen::Vector3d(peel_dir_.norm() * in);
      step_t0_ = t;
    }
    return;
  }
  if (step_ == StepPhase::kSwing && attached) {
    // The pad stuck again on its way (it fell back onto the surface it left): peel it again.
    if (++attempts_ >= params_.max_place_attempts) {
      Fail(ctx, i, "stuck_again");
      return;
    }
    const BodyPose stance = Corrected(cmd_);
    f.ankle_w = stance.p + stance.r * c.Ankle(f.q, 0.0);
    step_ = StepPhase::kPeel;
    step_t0_ = t;
    peel_from_.setZero();
    adhesion_->SetPeelingLeg(i, true);
    return;
  }
  const Eigen::Vector3d w2 = to_.face + to_.approach_m * to_.normal;
  Eigen::Vector3d face = w2, normal = to_.normal;
  if (step_ == StepPhase::kSwing) {
    const double u = std::clamp((t - step_t0_) / params_.swing_s, 0.0, 1.0);
    // Lift, then move: first straight off the surface it leaves (a peeled pad that falls back
    // onto it sticks again), then along the polyline through the lifted point (and round the
    // edge) to above the target; an idle leg only lifts.
    const Eigen::Vector3d w0 = from_face_ + params_.lift_m * from_normal_;
    if (u < kLiftShare || to_.surface < 0) {
      face = from_face_ + SmoothStep(u / (to_.surface < 0 ? 1.0 : kLiftShare)) *
                              ((to_.surface < 0 ? to_.face : w0) - from_face_);
    } else {
      const int n = use_via_ ? 3 : 2;
      const std::array<Eigen::Vector3d, 3> pts{w0, use_via_ ? via_ : w2, w2};
      double len[2] = {0, 0}, total = 0;
      for (int k = 0; k + 1 < n; ++k) total += len[k] = (pts[k + 1] - pts[k]).norm();
      double along = SmoothStep((u - kLiftShare) / (1 - kLiftShare)) * total;
      face = pts[n - 1];
      for (int k = 0; k + 1 < n; ++k) {
        if (along <= len[k] || k + 2 == n) {
          const double a = len[k] > 0 ? std::min(1.0, along / len[k]) : 1.0;
          face = pts[k] + a * (pts[k + 1] - pts[k]);
          break;
        }
        along -= len[k];
      }
    }
    normal = Slerp(from_normal_, to_.normal, std::min(1.0, 1.4 * SmoothStep(u)));
    // The leg's joints head for the ones the plan landed it with (its kinematics has more than
    // one branch; the warm start picks the planned one).
    if (to_.margin >= 0 && to_.surface >= 0) {
      const double w = SmoothStep(u);
      for (int k = 0; k < 3; ++k) f.q[k] = (1 - w) * swing_q_[k] + w * to_.q[k];
    }
    if (u >= 1.0) {
      if (to_.surface < 0) {  // up in the air: wait there
        step_leg_ = -1;
        step_ = StepPhase::kNone;
        return;
      }
      step_ = StepPhase::kPlace;
      step_t0_ = t;
      touch_since_ = -1.0;
      place_d_ = 0.0;
    }
  } else if (step_ == StepPhase::kPlace) {
    // Lowered along the normal until it sticks, at most place_depth_m into the surface (deeper
    // at each new attempt, in case the surface lies further than planned).
    const double depth = to_.approach_m + params_.place_depth_m * (1 + 0.5 * attempts_);
    // Lowered until it touches, then pressed until its pad lies flat on the surface (a pad
    // that lands on an edge is pressed over onto its face: the passive ankle gives) and no
    // harder than place_force_n (the press pushes the body off the other pads).
    // Flat: the pad touches with its face (the contacts of a box on a plane: 4; an edge: 2).
    const bool flat = adhesion_->pad(adhesion_->pad_of_leg(i)).sense().contacts >= kFlatContacts;
    if (!(touching && flat && (*ctx.legs)[i].preload_n >= params_.place_force_n)) {
      place_d_ = std::min(depth, place_d_ + params_.place_speed_mps * dt_);
    }
    const double d = place_d_;
    face = w2 - d * to_.normal;
    if (attached) {
      // Stuck: a stance foot from now on, held where it is for the commanded body.
      const LegInfo& info = world.robot().legs[i];
      LegChain::Q q;
      for (int k = 0; k < 3; ++k) q[k] = world.data()->qpos[info.qpos_adr[k]];
      f.stance = true;
      f.idle = false;
      f.surface = to_.surface;
      f.normal_w = to_.normal;
      // Along the surface where the joints put it for the commanded body; across it, the
      // planned press (the sag of the body would otherwise add up in the stance targets).
      const BodyPose stance = Corrected(cmd_);
      f.ankle_w = stance.p + stance.r * c.Ankle(q, 0.0);
      const Eigen::Vector3d on = plan_.origin() + (c.post_m() - params_.press_m) * to_.normal;
      f.ankle_w -= (f.ankle_w - on).dot(to_.normal) * to_.normal;
      plan_.Margin(i, Corrected(cmd_), f.ankle_w, f.normal_w, &f.q, &f.tilt, kStanceTurn);
      step_leg_ = -1;
      step_ = StepPhase::kNone;
      return;
    }
    if (touching && touch_since_ < 0) touch_since_ = t;
    const bool rejected = touch_since_ >= 0 && t - touch_since_ > kAttachWait;
    const bool nothing = touch_since_ < 0 && d >= depth && t - step_t0_ > depth / params_.place_speed_mps + kAttachWait;
    if (rejected || nothing) {
      if (++attempts_ >= params_.max_place_attempts) {
        Fail(ctx, i, "place_attempts");
        return;
      }
      step_ = StepPhase::kRetry;
      step_t0_ = t;
      from_face_ = face;  // back up from where it got to
    }
  } else if (step_ == StepPhase::kRetry) {
    const double u = SmoothStep((t - step_t0_) / 0.25);
    face = from_face_ + u * (w2 - from_face_);
    if (u >= 1.0) {
      step_ = StepPhase::kPlace;
      step_t0_ = t;
      touch_since_ = -1.0;
      place_d_ = 0.0;
    }
  }
  // Through the commanded body, as the stance legs' targets and the plan's margins are: the
  // foot lands where the plan has it in the leg's joints, whatever the body's sag.
  plan_.Margin(i, cmd_, face + c.post_m() * normal, normal, &f.q, &f.tilt, kStanceTurn);
}

bool TransitionEffect::ReplaceLost(World& world, RunContext& ctx) {
  const std::vector<LegSignals>& legs = *ctx.legs;
  for (size_t i = 0; i < feet_.size(); ++i) {
    if (!feet_[i].stance || legs[i].attached) continue;
    const Foothold h = plan_.Next(static_cast<int>(i), sigma_, cmd_, feet_[i].q, false);
    if (h.margin < 0) {
      Fail(ctx, static_cast<int>(i), "no_foothold");
    } else {
      StartStep(world, ctx, static_cast<int>(i), h, false);
    }
    return true;
  }
  return false;
}

void TransitionEffect::HandBackTick(World& world, RunContext& ctx) {
  const std::vector<LegSignals>& legs = *ctx.legs;
  if (ReplaceLost(world, ctx)) return;
  // First the body rises to its standing height over the new surface, the feet where they are.
  if (raise_t0_ < 0) {
    raise_t0_ = ctx.time_s;
    raise_from_ = cmd_;
    raise_m_ = plan_.height_m() - plan_.Standoff(cmd_);
  }
  const double u = SmoothStep((ctx.time_s - raise_t0_) /
                              std::max(0.2, std::abs(raise_m_) / params_.body_speed_mps));
  if (u < 1.0 || !raised_) {
    BodyPose pose = raise_from_;
    pose.p += u * raise_m_ * plan_.normal(1);
    std::array<LegChain::Q, 8> q{};
    std::array<double, 8> tilt{};
    for (size_t i = 0; i < feet_.size() && i < q.size(); ++i) {
      q[i] = feet_[i].q;
      if (plan_.Margin(static_cast<int>(i), Corrected(pose), StanceTarget(static_cast<int>(i)),
                       feet_[i].normal_w, &q[i], &tilt[i], kStanceTurn) < 0) {
        Fail(ctx, static_cast<int>(i), "no_standing_height");
        return;
      }
    }
    cmd_ = pose;
    for (size_t i = 0; i < feet_.size() && i < q.size(); ++i) {
      feet_[i].q = q[i], feet_[i].tilt = tilt[i];
    }
    raised_ = u >= 1.0;
    return;
  }
  // Then each foot, one at a time, to where the gait has it at the moment it goes on from.
  for (size_t i = 0; i < feet_.size(); ++i) {
    const LegChain& c = plan_.chains()[i];
    double dx = 0.0, dz = 0.0;
    cpg_->FootAt(static_cast<int>(i), resume_theta_[i], &dx, &dz);
    const Eigen::Vector3d neutral_face = c.neutral_ankle() - c.post_m() * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d n = plan_.normal(1);
    Eigen::Vector3d face = cmd_.p + cmd_.r * (neutral_face + Eigen::Vector3d(dx, 0, 0));
    face -= (face - plan_.origin()).dot(n) * n;
    const Foot& f = feet_[i];
    const Eigen::Vector3d now = f.ankle_w - (c.post_m() - params_.press_m) * f.normal_w;
    const Eigen::Vector3d off = now - face;
    // Each foot steps once; one already there (along the surface) stays.
    if (handed_[i] || (off - off.dot(n) * n).norm() < kHandBackTolerance) continue;
    if (!SupportsHold(static_cast<int>(i), legs)) return;
    handed_[i] = 1;
    Foothold h;
    h.face = face;
    h.normal = n;
    h.surface = 1;
    h.q = feet_[i].q;
    h.approach_m = params_.lift_m;
    double tilt = 0.0;
    h.margin = std::max(0.0, plan_.Margin(static_cast<int>(i), cmd_,
                                          plan_.StanceAnkle(static_cast<int>(i), face, n), n,
                                          &h.q, &tilt, kStanceTurn));
    StartStep(world, ctx, static_cast<int>(i), h, true);
    return;
  }
  // Every foot where the gait wants it: the gait goes on.
  resume_pending_ = true;
  mode_ = Mode::kWatching;
  RestoreKp(world);
  Log(ctx, trigger_leg_, "transition_gait", "");
}

void TransitionEffect::RunTick(World& world, RunContext& ctx) {
  const std::vector<LegSignals>& legs = *ctx.legs;
  const size_t n = feet_.size();
  if (ReplaceLost(world, ctx)) return;
  if (params_.then == "gait" && end_time_s_ >= 0 && sigma_ >= plan_.Settled()) {
    cpg_->ResumePhases(resume_theta_);
    mode_ = Mode::kHandBack;
    raise_t0_ = -1.0;
    raised_ = false;
    std::fill(handed_.begin(), handed_.end(), 0);
    HandBackTick(world, ctx);
    return;
  }
  // A leg waiting in the air lands as soon as it has a foothold.
  if (sigma_ >= idle_check_) {
    idle_check_ = sigma_ + kIdleCheck;
    for (size_t i = 0; i < n; ++i) {
      if (!feet_[i].idle || !SupportsHold(static_cast<int>(i), legs) ||
          StanceCount() < kMinStance) {
        continue;
      }
      const Foothold h = plan_.Next(static_cast<int>(i), sigma_, cmd_, feet_[i].q, false);
      if (h.margin < 0) continue;
      StartStep(world, ctx, static_cast<int>(i), h, false);
      return;
    }
  }
  // The body goes on while every stance leg keeps its margin.
  const double next = sigma_ + plan_.Rate(sigma_) * dt_;
  const BodyPose pose = plan_.Pose(next);
  double worst = 1e9;
  int worst_leg = -1;
  std::array<LegChain::Q, 8> q{};
  std::array<double, 8> tilt{}, err{};
  const BodyPose corrected = Corrected(pose);
  for (size_t i = 0; i < n && i < q.size(); ++i) {
    if (!feet_[i].stance) continue;
    q[i] = feet_[i].q;
    const double m =
        plan_.Margin(static_cast<int>(i), corrected, StanceTarget(static_cast<int>(i)),
                     feet_[i].normal_w, &q[i], &tilt[i], kStanceTurn, nullptr, &err[i]);
    if (m < worst) worst = m, worst_leg = static_cast<int>(i);
  }
  if (worst >= params_.margin_rad) {
    sigma_ = next;
    cmd_ = pose;
    for (size_t i = 0; i < n && i < q.size(); ++i) {
      if (!feet_[i].stance) continue;
      feet_[i].q = q[i], feet_[i].tilt = tilt[i];
      // The stance targets below solve the same: they skip it.
      Remember(static_cast<int>(i), corrected, StanceTarget(static_cast<int>(i)), err[i]);
    }
    return;
  }
  // The leg that stops the body steps, once every other pad holds (and enough stand).
  if (!SupportsHold(worst_leg, legs) || StanceCount() - 1 < kMinStance) return;
  const Foothold h = plan_.Next(worst_leg, sigma_, cmd_, feet_[worst_leg].q, false);
  if (h.margin >= 0) {
    StartStep(world, ctx, worst_leg, h, true);
  } else if (StanceCount() - 1 >= kMinStance) {
    Foothold air;
    air.surface = -1;
    StartStep(world, ctx, worst_leg, air, true);
  } else {
    Fail(ctx, worst_leg, "no_foothold");
  }
}

void TransitionEffect::Update(World& world, RunContext& ctx) {
  const std::vector<LegSignals>& legs = *ctx.legs;
  // Bookkeeping: the last pad off the old surface and the first onto the new one.
  for (size_t i = 0; i < legs.size(); ++i) {
    const bool now = legs[i].attached;
    if (now == (attached_[i] != 0)) continue;
    attached_[i] = now ? 1 : 0;
    if (!now && feet_[i].surface == 0) {
      last_old_detach_s_ = ctx.time_s;
      last_old_leg_ = static_cast<int>(i);
    }
    if (now && first_new_attach_s_ < 0) {
      const adhesion::PadFrame f = adhesion::FaceFrame(
          world.data(), adhesion_->pad(adhesion_->pad_of_leg(static_cast<int>(i))).geometry());
      if (plan_.SurfaceOf(f.rot.col(2)) == 1) {
        first_new_attach_s_ = ctx.time_s;
        first_new_leg_ = static_cast<int>(i);
      }
    }
  }
  if (mode_ != Mode::kFailed && params_.track_s > 0 && ++track_tick_ >= track_every_) {
    track_tick_ = 0;
    TrackBody(world);
  }
  if (mode_ != Mode::kFailed) {
    if (step_leg_ >= 0) {
      AdvanceStep(world, ctx);
    } else if (mode_ == Mode::kSettle) {
      int loose = -1;
      for (size_t i = 0; i < feet_.size() && loose < 0; ++i) {
        if (!feet_[i].stance) loose = static_cast<int>(i);
      }
      if (loose < 0) {
        sigma_ = plan_.Start(cmd_);
        idle_check_ = sigma_;
        mode_ = Mode::kRun;
      } else {
        Foothold h = plan_.Next(loose, 0.0, cmd_, feet_[loose].q, true);
        if (h.margin < 0) h = plan_.Next(loose, CornerPlan::kHere, cmd_, feet_[loose].q, false);
        if (h.margin < 0) {
          Fail(ctx, loose, "no_foothold");
        } else {
          StartStep(world, ctx, loose, h, false);
        }
      }
    } else if (mode_ == Mode::kProbe) {
      ProbeTick(world, ctx);
    } else if (mode_ == Mode::kHandBack) {
      HandBackTick(world, ctx);
    } else {
      RunTick(world, ctx);
    }
  }
  // The stance legs carry the body to the commanded pose (with the sag correction).
  if (mode_ != Mode::kWatching && mode_ != Mode::kFailed) {
    const BodyPose stance = Corrected(cmd_);
    for (size_t i = 0; i < feet_.size(); ++i) {
      const Foot& f = feet_[i];
      if (!f.stance || static_cast<int>(i) == step_leg_) continue;
      HoldLeg(static_cast<int>(i), stance);
    }
  }
  // Idle legs hold their place in the body's frame.
  for (size_t i = 0; i < feet_.size(); ++i) {
    const Foot& f = feet_[i];
    if (!f.idle || static_cast<int>(i) == step_leg_) continue;
    HoldLeg(static_cast<int>(i), BodyPose{});
  }
  if (mode_ == Mode::kWatching) return;  // handed back: the gait writes the targets
  if (end_time_s_ < 0 && mode_ == Mode::kRun && step_leg_ < 0) {
    bool all_new = true;
    for (const Foot& f : feet_) all_new &= f.stance && f.surface == 1;
    if (all_new) {
      end_time_s_ = ctx.time_s;
      Log(ctx, first_new_leg_ >= 0 ? first_new_leg_ : 0, "transition_end", "");
    }
  }
  WriteTargets(world);
}

void TransitionEffect::HoldLeg(int i, const BodyPose& pose) {
  Foot& f = feet_[i];
  const Eigen::Vector3d target = f.stance ? StanceTarget(i) : f.ankle_w;
  if (f.held && f.held_q == f.q && f.held_tilt == f.tilt && f.held_target == target &&
      f.held_normal == f.normal_w && f.held_pose.p == pose.p && f.held_pose.r == pose.r) {
    return;
  }
  double err = 1.0;
  if (f.stance) {
    plan_.Margin(i, pose, target, f.normal_w, &f.q, &f.tilt, kStanceTurn, nullptr, &err);
  } else {
    err = plan_.chains()[i].Solve(target, &f.q);
  }
  Remember(i, pose, target, err);
}

void TransitionEffect::Remember(int i, const BodyPose& pose, const Eigen::Vector3d& target,
                                double err_m) {
  Foot& f = feet_[i];
  f.held = err_m < LegChain::kSolvedM;
  f.held_pose = pose, f.held_target = target, f.held_normal = f.normal_w, f.held_q = f.q;
  f.held_tilt = f.tilt;
}

BodyPose TransitionEffect::Corrected(const BodyPose& pose) const {
  BodyPose p = pose;
  p.p += corr_p_;
  p.r = p.r * corr_r_;
  return p;
}

void TransitionEffect::TrackBody(const World& world) {
  // The body sags on its compliant servos under its weight: an integral correction moves the
  // stance legs' targets until the body is where the plan commands it (so that a foot lands,
  // in its joints, where the plan expects).
  const BodyPose actual = ActualPose(world);
  const double k = track_every_ * dt_ / params_.track_s;
  corr_p_ += k * (cmd_.p - actual.p);
  corr_w_ += k * RotationLog(actual.r.transpose() * cmd_.r);
  if (corr_p_.norm() > kTrackMaxM) corr_p_ *= kTrackMaxM / corr_p_.norm();
  if (corr_w_.norm() > kTrackMaxRad) corr_w_ *= kTrackMaxRad / corr_w_.norm();
  corr_r_ = Exp(corr_w_);
}

void TransitionEffect::RestoreKp(World& world) const {
  mjModel* m = world.model();
  const RobotInfo& r = world.robot();
  for (size_t i = 0; i < feet_.size(); ++i) {
    for (int k = 0; k < 3; ++k) SetServoKp(m, r.legs[i].actuator[k], kp_[i][k]);
  }
}

void TransitionEffect::Fail(RunContext& ctx, int leg, const char* why) {
  mode_ = Mode::kFailed;
  fail_time_s_ = ctx.time_s;
  fail_leg_ = leg;
  fail_why_ = why;
  Log(ctx, leg, "transition_failed", why);
}

void TransitionEffect::Log(RunContext& ctx, int leg, const char* kind, const char* cause) const {
  if (ctx.events == nullptr) return;
  Event e;
  e.time_s = ctx.time_s;
  e.pad = event_pad_[leg];
  e.kind = kind;
  e.cause = cause;
  ctx.events->Add(e);
}

void TransitionEffect::WriteTargets(World& world) const {
  double* ctrl = world.data()->ctrl;
  const RobotInfo& r = world.robot();
  mjModel* m = world.model();
  for (size_t i = 0; i < feet_.size(); ++i) {
    for (int k = 0; k < 3; ++k) ctrl[r.legs[i].actuator[k]] = feet_[i].q[k];
    ctrl[r.legs[i].tilt_actuator] = feet_[i].tilt;
    if (params_.unload_gain > 0) {
      // Stance legs only: the leg that peels must pull.
      const double u = static_cast<int>(i) == step_leg_
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
  const auto pad = [&](int i) {
    return i >= 0 ? nlohmann::json(legs[i].name + "_pad") : nlohmann::json();
  };
  const auto time = [](double t) { return t >= 0 ? nlohmann::json(t) : nlohmann::json(); };
  nlohmann::json j;
  j["triggered"] = trigger_time_s_ >= 0;
  j["trigger_time_s"] = time(trigger_time_s_);
  j["trigger_pad"] = pad(trigger_leg_);
  const char* geom =
      trigger_geom_ >= 0 ? mj_id2name(world.model(), mjOBJ_GEOM, trigger_geom_) : nullptr;
  j["new_surface"] = geom != nullptr ? nlohmann::json(geom) : nlohmann::json();
  j["corner"] = trigger_time_s_ < 0 ? nlohmann::json()
                                    : nlohmann::json(plan_.inner() ? "inner" : "outer");
  j["last_old_surface_detach_s"] = time(last_old_detach_s_);
  j["last_old_surface_pad"] = pad(last_old_leg_);
  j["first_new_surface_attach_s"] = time(first_new_attach_s_);
  j["first_new_surface_pad"] = pad(first_new_leg_);
  j["all_on_new_surface_s"] = time(end_time_s_);
  j["steps"] = steps_;
  j["failed"] = mode_ == Mode::kFailed;
  if (mode_ == Mode::kFailed) {
    j["failure"] = fail_why_;
    j["failure_time_s"] = fail_time_s_;
    j["failure_pad"] = pad(fail_leg_);
  }
  (*summary)["transition"] = j;
}

}  // namespace climbsim::sim
