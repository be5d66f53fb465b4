// The corner manoeuvre (CornerManoeuvre, manoeuvre.h): the watch for a corner, the probe of
// its edge, the body's advance, the hand-back to the gait and the run's bookkeeping. The
// one-foot step (peel, swing, place, land) is in manoeuvre_step.cc.
#include "transition/manoeuvre.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <utility>

#include "adhesion/adhesion.h"

namespace climbsim::sim {
namespace {

constexpr double kStanceTurn = CornerPlan::kStanceTurn;
// How often (σ) a leg waiting in the air looks for a foothold again.
constexpr double kIdleCheck = 0.02;
// The sag correction is a slow integral (track_s, about a second): updated every 10 ms, so that
// a stance leg's target, and its solve, change once a period while another leg steps.
constexpr double kTrackPeriodS = 0.01;
// A foot closer than this to where the gait wants it is not stepped there (m).
constexpr double kHandBackTolerance = 0.004;

}  // namespace

CornerManoeuvre::CornerManoeuvre(CornerPlan plan, const TransitionParams& params,
                                 double period_s, bool hand_back)
    : plan_(std::move(plan)), params_(params), dt_(period_s), hand_back_(hand_back) {
  track_every_ = std::max(1, static_cast<int>(std::lround(kTrackPeriodS / period_s)));
  const size_t n = plan_.chains().size();
  for (size_t i = 0; i < n; ++i) {
    if (plan_.chains()[i].hip().x() > 1e-6) front_.push_back(static_cast<int>(i));
  }
  pads_.resize(n);
  feet_.resize(n);
  attached_.assign(n, 0);
  resume_theta_.assign(n, 0.0);
  handed_.assign(n, 0);
  air_since_.assign(n, -1.0);
}

void CornerManoeuvre::Reset() {
  mode_ = Mode::kWatching;
  for (Foot& f : feet_) f = Foot{};
  std::fill(attached_.begin(), attached_.end(), 0);
  step_leg_ = -1;
  step_ = StepPhase::kNone;
  sigma_ = idle_check_ = 0.0;
  report_ = ManoeuvreReport{};
  resume_pending_ = false;
  std::fill(air_since_.begin(), air_since_.end(), -1.0);
  probe_.leg = -1;
  track_tick_ = 0;
}

bool CornerManoeuvre::OldSurface(const ManoeuvreIo& io, Eigen::Vector3d* n0,
                                 Eigen::Vector3d* p0) const {
  // The surface the robot stands on: the attached pads' faces.
  n0->setZero();
  p0->setZero();
  int attached = 0;
  for (size_t j = 0; j < pads_.size(); ++j) {
    if (!pads_[j].attached) continue;
    const adhesion::PadFrame f = io.PadFace(static_cast<int>(j));
    *n0 += f.rot.col(2);
    *p0 += f.pos;
    ++attached;
  }
  if (attached == 0) return false;
  n0->normalize();
  *p0 /= attached;
  return true;
}

bool CornerManoeuvre::Corner(ManoeuvreIo& io, double t, int leg) {
  const adhesion::ContactSense& sense = io.PadContact(leg);
  if (sense.contacts <= 0) return false;
  Eigen::Vector3d n0, p0;
  if (!OldSurface(io, &n0, &p0)) return false;
  const Eigen::Vector3d& n1 = sense.surface_normal;
  if (n1.dot(n0) > std::cos(params_.trigger_angle_deg * M_PI / 180)) return false;
  const Eigen::Vector3d along = n1 - n1.dot(n0) * n0;
  if (along.norm() < 0.5) return false;  // not a corner across the way (a step, a side wall)
  // Inner when the new surface faces the robot, outer when it faces the way it goes.
  const BodyPose base = io.BasePose();
  const bool inner = along.dot(base.r.col(0)) < 0;
  const Eigen::Vector3d t0 = (inner ? -along : along).normalized();
  // The corner's point in the body's plane of travel: on the old surface and the new one.
  const Eigen::Vector3d origin =
      base.p + t0.dot(sense.contact_pos - base.p) * t0 + n0.dot(p0 - base.p) * n0;
  plan_.SetCorner(origin, n0, t0, inner);
  report_.trigger_geom = sense.surface_geom;
  Trigger(io, t, leg);
  return true;
}

bool CornerManoeuvre::Watch(ManoeuvreIo& io, double t) {
  for (int i : front_) {
    const PadSignals& pad = pads_[i];
    // A front pad touching a surface with another normal: a corner ahead.
    if (!pad.attached && pad.touching && Corner(io, t, i)) return true;
    // A front foot that has found no surface for lost_s: the surface ended (an edge ahead).
    if (pad.attached || pad.touching || air_since_[i] < 0) {
      air_since_[i] = t;
    } else if (t - air_since_[i] > params_.lost_s) {
      StartProbe(io, t, i);
      return true;
    }
  }
  return false;
}

void CornerManoeuvre::StartProbe(ManoeuvreIo& io, double t, int leg) {
  Eigen::Vector3d n0, p0;
  if (!OldSurface(io, &n0, &p0)) return;
  HoldFeet(io, io.BasePose());
  probe_.start = cmd_;
  probe_.n0 = n0;
  probe_.p0 = p0;
  const Eigen::Vector3d x = cmd_.r.col(0);
  probe_.fwd = (x - x.dot(n0) * n0).normalized();
  probe_.leg = leg;
  probe_.phase = 0;
  probe_.t0 = t;
  mode_ = Mode::kProbe;
  report_.trigger_time_s = t;
  report_.trigger_leg = leg;
  io.Log(leg, "transition_probe", "lost_ground");
  Update(io, t);
}

void CornerManoeuvre::ProbeCrouch(ManoeuvreIo& io, double t) {
  // The body crouches by crouch_m on the stance feet, so that the probing foot reaches below
  // the edge.
  const double u = SmoothStep((t - probe_.t0) / Probe::kCrouchS);
  BodyPose pose = probe_.start;
  pose.p -= u * params_.crouch_m * probe_.n0;
  for (size_t j = 0; j < feet_.size(); ++j) {
    Foot& f = feet_[j];
    if (!f.stance) continue;
    if (plan_.Margin(static_cast<int>(j), sag_.Apply(pose), f.ankle_w, f.normal_w, &f.q, &f.tilt,
                     kStanceTurn) < 0) {
      Fail(io, t, static_cast<int>(j), "no_crouch");
      return;
    }
  }
  cmd_ = pose;
  if (u >= 1.0) {
    probe_.phase = 1;
    probe_.t0 = t;
    const adhesion::PadFrame pf = io.PadFace(probe_.leg);
    probe_.from_face = pf.pos;
    probe_.from_normal = pf.rot.col(2);
  }
}

void CornerManoeuvre::ProbeTick(ManoeuvreIo& io, double t) {
  if (probe_.phase == 0) {
    ProbeCrouch(io, t);
    return;
  }
  // The probing foot turns its pad to face back and goes down past the old surface's plane,
  // where the foot is along the way (phase 1); then back towards the body until it touches.
  const int i = probe_.leg;
  Foot& f = feet_[i];
  const Eigen::Vector3d below = probe_.Below(plan_.pad_half_m());
  Eigen::Vector3d face, normal;
  if (probe_.phase == 1) {
    const double u = std::clamp((t - probe_.t0) / params_.swing_s, 0.0, 1.0);
    probe_.Down(u, params_.lift_m, below, &face, &normal);
    if (u >= 1.0) probe_.phase = 2, probe_.t0 = t;
    if (pads_[i].touching) {  // the old surface goes on after all
      Fail(io, t, i, "no_edge");
      return;
    }
  } else {
    const double back = std::min(Probe::kBackM, Probe::kSpeedMps * (t - probe_.t0));
    face = below - back * probe_.fwd;
    normal = probe_.fwd;
    if (pads_[i].touching) {
      if (!Corner(io, t, i)) Fail(io, t, i, "no_edge");
      return;
    }
    if (back >= Probe::kBackM) {
      Fail(io, t, i, "no_edge");
      return;
    }
  }
  plan_.Margin(i, cmd_, face + plan_.chains()[i].post_m() * normal, normal, &f.q, &f.tilt,
               kStanceTurn);
}

void CornerManoeuvre::HoldFeet(const ManoeuvreIo& io, const BodyPose& pose) {
  cmd_ = pose;
  sag_.Clear();
  for (size_t i = 0; i < feet_.size(); ++i) {
    Foot& f = feet_[i];
    f = Foot{};
    // Hold what the gait commanded last.
    io.Commanded(static_cast<int>(i), &f.q, &f.tilt);
    f.stance = pads_[i].attached;
    const adhesion::PadFrame face = io.PadFace(static_cast<int>(i));
    f.normal_w = face.rot.col(2);
    f.surface = 0;
    f.ankle_w = cmd_.p + cmd_.r * plan_.chains()[i].Ankle(f.q, 0.0);
    attached_[i] = pads_[i].attached ? 1 : 0;
  }
}

void CornerManoeuvre::Trigger(ManoeuvreIo& io, double t, int leg) {
  HoldFeet(io, io.BasePose());
  for (Foot& f : feet_) {
    if (!f.stance) f.normal_w = plan_.normal(0);
    f.surface = f.stance && plan_.SurfaceOf(f.normal_w) == 1 ? 1 : 0;
  }
  mode_ = Mode::kSettle;
  if (report_.trigger_time_s < 0) report_.trigger_time_s = t;
  if (report_.trigger_leg < 0) report_.trigger_leg = leg;
  io.Log(leg, "transition_start", plan_.inner() ? "inner" : "outer");
  Update(io, t);
}

int CornerManoeuvre::StanceCount() const {
  int n = 0;
  for (const Foot& f : feet_) n += f.stance ? 1 : 0;
  return n;
}

bool CornerManoeuvre::SupportsHold(int except) const {
  for (size_t i = 0; i < feet_.size(); ++i) {
    if (static_cast<int>(i) == except || feet_[i].idle) continue;
    if (!feet_[i].stance || !pads_[i].attached) return false;
    if (!adhesion::SupportBuilt(pads_[i].bonded_fraction, pads_[i].touched_fraction,
                                pads_[i].bondable_fraction, params_.support_bond_fraction)) {
      return false;
    }
  }
  return true;
}

void CornerManoeuvre::HandBackTick(ManoeuvreIo& io, double t) {
  if (ReplaceLost(io, t)) return;
  // First the body rises to its standing height over the new surface, the feet where they
  // are; then each foot, one at a time, to where the gait has it at the moment it goes on from.
  if (RaiseTick(io, t) || HandBackStep(io, t)) return;
  // Every foot where the gait wants it: the gait goes on.
  resume_pending_ = true;
  mode_ = Mode::kWatching;
  io.RestoreKp();
  io.Log(report_.trigger_leg, "transition_gait", "");
}

bool CornerManoeuvre::RaiseTick(ManoeuvreIo& io, double t) {
  if (raise_t0_ < 0) {
    raise_t0_ = t;
    raise_from_ = cmd_;
    raise_m_ = plan_.height_m() - plan_.Standoff(cmd_);
  }
  const double u =
      SmoothStep((t - raise_t0_) / std::max(0.2, std::abs(raise_m_) / params_.body_speed_mps));
  if (u >= 1.0 && raised_) return false;
  BodyPose pose = raise_from_;
  pose.p += u * raise_m_ * plan_.normal(1);
  std::array<LegChain::Q, 8> q{};
  std::array<double, 8> tilt{};
  for (size_t i = 0; i < feet_.size() && i < q.size(); ++i) {
    q[i] = feet_[i].q;
    if (plan_.Margin(static_cast<int>(i), sag_.Apply(pose), feet_[i].ankle_w, feet_[i].normal_w,
                     &q[i], &tilt[i], kStanceTurn) < 0) {
      Fail(io, t, static_cast<int>(i), "no_standing_height");
      return true;
    }
  }
  cmd_ = pose;
  for (size_t i = 0; i < feet_.size() && i < q.size(); ++i) {
    feet_[i].q = q[i], feet_[i].tilt = tilt[i];
  }
  raised_ = u >= 1.0;
  return true;
}

bool CornerManoeuvre::HandBackStep(ManoeuvreIo& io, double t) {
  for (size_t i = 0; i < feet_.size(); ++i) {
    const LegChain& c = plan_.chains()[i];
    double dx = 0.0, dz = 0.0;
    io.GaitFoot(static_cast<int>(i), resume_theta_[i], &dx, &dz);
    const Eigen::Vector3d neutral_face = c.neutral_ankle() - c.post_m() * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d n = plan_.normal(1);
    Eigen::Vector3d face = cmd_.p + cmd_.r * (neutral_face + Eigen::Vector3d(dx, 0, 0));
    face -= (face - plan_.origin()).dot(n) * n;
    const Foot& f = feet_[i];
    const Eigen::Vector3d now = f.ankle_w - (c.post_m() - params_.press_m) * f.normal_w;
    const Eigen::Vector3d off = now - face;
    // Each foot steps once; one already there (along the surface) stays.
    if (handed_[i] || (off - off.dot(n) * n).norm() < kHandBackTolerance) continue;
    if (!SupportsHold(static_cast<int>(i))) return true;
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
    StartStep(io, t, static_cast<int>(i), h, true);
    return true;
  }
  return false;
}

bool CornerManoeuvre::LandIdle(ManoeuvreIo& io, double t) {
  if (sigma_ < idle_check_) return false;
  idle_check_ = sigma_ + kIdleCheck;
  for (size_t i = 0; i < feet_.size(); ++i) {
    if (!feet_[i].idle || !SupportsHold(static_cast<int>(i)) || StanceCount() < kMinStance) {
      continue;
    }
    const Foothold h = plan_.Next(static_cast<int>(i), sigma_, cmd_, feet_[i].q, false);
    if (h.margin < 0) continue;
    StartStep(io, t, static_cast<int>(i), h, false);
    return true;
  }
  return false;
}

int CornerManoeuvre::AdvanceBody() {
  const size_t n = feet_.size();
  const double next = sigma_ + plan_.Rate(sigma_) * dt_;
  const BodyPose pose = plan_.Pose(next);
  double worst = 1e9;
  int worst_leg = -1;
  std::array<LegChain::Q, 8> q{};
  std::array<double, 8> tilt{}, err{};
  const BodyPose corrected = sag_.Apply(pose);
  for (size_t i = 0; i < n && i < q.size(); ++i) {
    if (!feet_[i].stance) continue;
    q[i] = feet_[i].q;
    const double m = plan_.Margin(static_cast<int>(i), corrected, feet_[i].ankle_w,
                                  feet_[i].normal_w, &q[i], &tilt[i], kStanceTurn, nullptr,
                                  &err[i]);
    if (m < worst) worst = m, worst_leg = static_cast<int>(i);
  }
  if (worst < params_.margin_rad) return worst_leg;
  sigma_ = next;
  cmd_ = pose;
  for (size_t i = 0; i < n && i < q.size(); ++i) {
    if (!feet_[i].stance) continue;
    feet_[i].q = q[i], feet_[i].tilt = tilt[i];
    // The stance targets below solve the same: they skip it.
    feet_[i].Remember(corrected, feet_[i].ankle_w, err[i]);
  }
  return -1;
}

void CornerManoeuvre::StepWorst(ManoeuvreIo& io, double t, int worst_leg) {
  if (!SupportsHold(worst_leg) || StanceCount() - 1 < kMinStance) return;
  const Foothold h = plan_.Next(worst_leg, sigma_, cmd_, feet_[worst_leg].q, false);
  if (h.margin >= 0) {
    StartStep(io, t, worst_leg, h, true);
  } else if (StanceCount() - 1 >= kMinStance) {
    Foothold air;
    air.surface = -1;
    StartStep(io, t, worst_leg, air, true);
  } else {
    Fail(io, t, worst_leg, "no_foothold");
  }
}

void CornerManoeuvre::RunTick(ManoeuvreIo& io, double t) {
  if (ReplaceLost(io, t)) return;
  if (hand_back_ && report_.end_time_s >= 0 && sigma_ >= plan_.Settled()) {
    io.GaitResumePhases(resume_theta_);
    mode_ = Mode::kHandBack;
    raise_t0_ = -1.0;
    raised_ = false;
    std::fill(handed_.begin(), handed_.end(), 0);
    HandBackTick(io, t);
    return;
  }
  // A leg waiting in the air lands as soon as it has a foothold.
  if (LandIdle(io, t)) return;
  // The body goes on while every stance leg keeps its margin; the leg that stops it steps,
  // once every other pad holds (and enough stand).
  const int worst_leg = AdvanceBody();
  if (worst_leg >= 0) StepWorst(io, t, worst_leg);
}

void CornerManoeuvre::SettleTick(ManoeuvreIo& io, double t) {
  int loose = -1;
  for (size_t i = 0; i < feet_.size() && loose < 0; ++i) {
    if (!feet_[i].stance) loose = static_cast<int>(i);
  }
  if (loose < 0) {
    sigma_ = plan_.Start(cmd_);
    idle_check_ = sigma_;
    mode_ = Mode::kRun;
    return;
  }
  Foothold h = plan_.Next(loose, 0.0, cmd_, feet_[loose].q, true);
  if (h.margin < 0) h = plan_.Next(loose, CornerPlan::kHere, cmd_, feet_[loose].q, false);
  if (h.margin < 0) {
    Fail(io, t, loose, "no_foothold");
  } else {
    StartStep(io, t, loose, h, false);
  }
}

void CornerManoeuvre::Bookkeep(const ManoeuvreIo& io, double t) {
  for (size_t i = 0; i < pads_.size(); ++i) {
    const bool now = pads_[i].attached;
    if (now == (attached_[i] != 0)) continue;
    attached_[i] = now ? 1 : 0;
    if (!now && feet_[i].surface == 0) {
      report_.last_old_detach_s = t;
      report_.last_old_leg = static_cast<int>(i);
    }
    if (now && report_.first_new_attach_s < 0) {
      const adhesion::PadFrame f = io.PadFace(static_cast<int>(i));
      if (plan_.SurfaceOf(f.rot.col(2)) == 1) {
        report_.first_new_attach_s = t;
        report_.first_new_leg = static_cast<int>(i);
      }
    }
  }
}

void CornerManoeuvre::Update(ManoeuvreIo& io, double t) {
  Bookkeep(io, t);
  if (mode_ != Mode::kFailed && params_.track_s > 0 && ++track_tick_ >= track_every_) {
    track_tick_ = 0;
    TrackBody(io);
  }
  if (mode_ != Mode::kFailed) {
    if (step_leg_ >= 0) {
      AdvanceStep(io, t);
    } else if (mode_ == Mode::kSettle) {
      SettleTick(io, t);
    } else if (mode_ == Mode::kProbe) {
      ProbeTick(io, t);
    } else if (mode_ == Mode::kHandBack) {
      HandBackTick(io, t);
    } else {
      RunTick(io, t);
    }
  }
  HoldLegs();
  if (mode_ == Mode::kWatching) return;  // handed back: the gait writes the targets
  if (report_.end_time_s < 0 && mode_ == Mode::kRun && step_leg_ < 0) {
    bool all_new = true;
    for (const Foot& f : feet_) all_new &= f.stance && f.surface == 1;
    if (all_new) {
      report_.end_time_s = t;
      const int leg = report_.first_new_leg >= 0 ? report_.first_new_leg : 0;
      io.Log(leg, "transition_end", "");
    }
  }
  io.WriteTargets();
}

void CornerManoeuvre::HoldLegs() {
  // The stance legs carry the body to the commanded pose (with the sag correction).
  if (mode_ != Mode::kWatching && mode_ != Mode::kFailed) {
    const BodyPose stance = sag_.Apply(cmd_);
    for (size_t i = 0; i < feet_.size(); ++i) {
      if (!feet_[i].stance || static_cast<int>(i) == step_leg_) continue;
      HoldLeg(static_cast<int>(i), stance);
    }
  }
  // Idle legs hold their place in the body's frame.
  for (size_t i = 0; i < feet_.size(); ++i) {
    if (!feet_[i].idle || static_cast<int>(i) == step_leg_) continue;
    HoldLeg(static_cast<int>(i), BodyPose{});
  }
}

void CornerManoeuvre::HoldLeg(int i, const BodyPose& pose) {
  Foot& f = feet_[i];
  const Eigen::Vector3d target = f.ankle_w;  // stance: for the body; idle: in its frame
  if (f.Holds(pose, target)) return;
  double err = 1.0;
  if (f.stance) {
    plan_.Margin(i, pose, target, f.normal_w, &f.q, &f.tilt, kStanceTurn, nullptr, &err);
  } else {
    err = plan_.chains()[i].Solve(target, &f.q);
  }
  f.Remember(pose, target, err);
}

void CornerManoeuvre::TrackBody(const ManoeuvreIo& io) {
  const double k = track_every_ * dt_ / params_.track_s;
  sag_.Track(cmd_, io.BasePose(), k);
}

void CornerManoeuvre::Fail(ManoeuvreIo& io, double t, int leg, const char* why) {
  mode_ = Mode::kFailed;
  report_.fail_time_s = t;
  report_.fail_leg = leg;
  report_.fail_why = why;
  io.Log(leg, "transition_failed", why);
}

}  // namespace climbsim::sim
