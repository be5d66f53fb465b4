// The corner manoeuvre's one-foot step (CornerManoeuvre, manoeuvre.h): a stance leg chosen,
// its pad peeled, the swing over to the foothold, the placing, pressing and landing, and a
// lost foot stepped again. The watch, the probe, the body's advance and the hand-back are in
// manoeuvre.cc.
#include "transition/manoeuvre.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace climbsim::sim {
namespace {

// A foot pressed onto its surface that has not attached after this long is lifted and placed
// again (the pad must leave the surface before it can attach again: adhesion/sticky_pad.h).
constexpr double kAttachWait = 0.35;
// A pad with this many contact points with a surface lies flat on it.
constexpr int kFlatContacts = 3;

}  // namespace

void CornerManoeuvre::StartStep(ManoeuvreIo& io, double t, int leg, const Foothold& to,
                                bool peel) {
  step_leg_ = leg;
  to_ = to;
  attempts_ = 0;
  step_t0_ = t;
  touch_since_ = -1.0;
  ++report_.steps;
  feet_[leg].stance = false;
  peel_dir_ = params_.peel_back_m * PeelBack(io, leg);
  io.Log(leg, "transition_step", to.surface < 0 ? "idle" : peel ? "peel" : "place");
  if (peel) {
    step_ = StepPhase::kPeel;
    peel_from_.setZero();
    peel_attempts_ = 0;
    io.SetPeeling(leg, true);
  } else {
    BeginSwing(io, t);
  }
}

Eigen::Vector3d CornerManoeuvre::PeelBack(const ManoeuvreIo& io, int leg) const {
  // The pull's reaction on the body goes to the other pads. It should relieve them: the pull
  // points along the load they carry (the weight, mostly), projected on this pad's surface.
  // Without such a load there: along the sum of their normals, so that the reaction presses
  // them into their surfaces; when they all stand on this pad's surface, back along it,
  // against the body's heading.
  Eigen::Vector3d load = Eigen::Vector3d::Zero(), normals = Eigen::Vector3d::Zero();
  for (size_t j = 0; j < feet_.size(); ++j) {
    if (static_cast<int>(j) == leg || !feet_[j].stance) continue;
    normals += feet_[j].normal_w;
    if (!io.PadHolds(static_cast<int>(j))) continue;
    const adhesion::PadFrame pf = io.PadFace(static_cast<int>(j));
    load += pf.rot * io.PadLoad(static_cast<int>(j));
  }
  return PeelPull(cmd_.r.col(0), feet_[leg].normal_w, load, normals, params_.peel_toward);
}

void CornerManoeuvre::BeginSwing(const ManoeuvreIo& io, double t) {
  const int i = step_leg_;
  Foot& f = feet_[i];
  // From the pad's face as it is now.
  const adhesion::PadFrame face = io.PadFace(i);
  swing_.from_face = face.pos;
  swing_.from_normal = face.rot.col(2);
  if (to_.surface < 0) {
    // Into the air: lifted off its surface, then held there in the body's frame.
    to_.face = swing_.from_face + (params_.lift_m + 0.01) * swing_.from_normal;
    to_.normal = swing_.from_normal;
    f.idle = true;
    f.ankle_w = cmd_.r.transpose() *
                (to_.face + plan_.chains()[i].post_m() * to_.normal - cmd_.p);
  }
  swing_.use_via = !plan_.inner() && to_.surface >= 0 && to_.surface != f.surface;
  if (swing_.use_via) {
    // Round the edge: out along the bisector of the two normals, at the target's side.
    const double lateral = (to_.face - plan_.origin()).dot(plan_.lateral());
    swing_.via = plan_.origin() + lateral * plan_.lateral() +
                 (1.5 * plan_.pad_half_m() + params_.lift_m) *
                     (plan_.normal(0) + plan_.normal(1)).normalized();
  }
  step_ = StepPhase::kSwing;
  step_t0_ = t;
  swing_q_ = f.q;
}

void CornerManoeuvre::PeelTick(ManoeuvreIo& io, double t) {
  const int i = step_leg_;
  Foot& f = feet_[i];
  const LegChain& c = plan_.chains()[i];
  const double u = SmoothStep((t - step_t0_) / params_.peel_ramp_s);
  const Eigen::Vector3d pull = peel_from_ + u * (peel_dir_ - peel_from_);
  plan_.Margin(i, sag_.Apply(cmd_), f.ankle_w + pull + u * params_.peel_lift_m * f.normal_w,
               f.normal_w, &f.q, &f.tilt, CornerPlan::kStanceTurn);
  // The tilt servo turns the pad the way the pull does, as far as its torque goes: the bonds
  // see that much more peel moment and the leg pulls less. The pull along d at the top of
  // the post turns the pad about n × d.
  const adhesion::PadFrame pf = io.PadFace(i);
  const double turn = f.normal_w.cross(peel_dir_).dot(pf.rot.col(1)) >= 0 ? 1.0 : -1.0;
  f.tilt = std::clamp(f.tilt + turn * u * params_.peel_tilt_rad, c.tilt_lo(), c.tilt_hi());
  if (!pads_[i].attached) {
    io.SetPeeling(i, false);
    BeginSwing(io, t);
  } else if (t - step_t0_ > params_.peel_max_s) {
    // Not let go: pull the other way, then sideways (from where the pull is now).
    if (++peel_attempts_ >= kPeelAttempts) {
      io.SetPeeling(i, false);
      Fail(io, t, i, "peel_time_limit");
      return;
    }
    peel_from_ = pull;
    peel_dir_ = RetryPull(peel_dir_, peel_attempts_, c.hip().y(), cmd_.r.col(1), f.normal_w);
    step_t0_ = t;
  }
}

void CornerManoeuvre::StuckAgain(ManoeuvreIo& io, double t) {
  const int i = step_leg_;
  Foot& f = feet_[i];
  if (++attempts_ >= params_.max_place_attempts) {
    Fail(io, t, i, "stuck_again");
    return;
  }
  const BodyPose stance = sag_.Apply(cmd_);
  f.ankle_w = stance.p + stance.r * plan_.chains()[i].Ankle(f.q, 0.0);
  step_ = StepPhase::kPeel;
  step_t0_ = t;
  peel_from_.setZero();
  io.SetPeeling(i, true);
}

void CornerManoeuvre::AdvanceStep(ManoeuvreIo& io, double t) {
  const int i = step_leg_;
  Foot& f = feet_[i];
  if (step_ == StepPhase::kPeel) {
    PeelTick(io, t);
    return;
  }
  if (step_ == StepPhase::kSwing && pads_[i].attached) {
    // The pad stuck again on its way (it fell back onto the surface it left): peel it again.
    StuckAgain(io, t);
    return;
  }
  const Eigen::Vector3d w2 = to_.face + to_.approach_m * to_.normal;
  Eigen::Vector3d face = w2, normal = to_.normal;
  if (step_ == StepPhase::kSwing) {
    const double u = std::clamp((t - step_t0_) / params_.swing_s, 0.0, 1.0);
    face = swing_.Face(u, to_, w2, params_.lift_m);
    normal = Slerp(swing_.from_normal, to_.normal, std::min(1.0, 1.4 * SmoothStep(u)));
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
    if (!PlaceTick(io, t, &face)) return;
  } else if (step_ == StepPhase::kRetry) {
    const double u = SmoothStep((t - step_t0_) / 0.25);
    face = swing_.from_face + u * (w2 - swing_.from_face);
    if (u >= 1.0) {
      step_ = StepPhase::kPlace;
      step_t0_ = t;
      touch_since_ = -1.0;
      place_d_ = 0.0;
    }
  }
  // Through the commanded body, as the stance legs' targets and the plan's margins are: the
  // foot lands where the plan has it in the leg's joints, whatever the body's sag.
  plan_.Margin(i, cmd_, face + plan_.chains()[i].post_m() * normal, normal, &f.q, &f.tilt,
               CornerPlan::kStanceTurn);
}

bool CornerManoeuvre::PlaceTick(ManoeuvreIo& io, double t, Eigen::Vector3d* face) {
  const int i = step_leg_;
  const PadSignals& pad = pads_[i];
  const Eigen::Vector3d w2 = to_.face + to_.approach_m * to_.normal;
  // Lowered along the normal until it sticks, at most place_depth_m into the surface (deeper
  // at each new attempt, in case the surface lies further than planned).
  const double depth = to_.approach_m + params_.place_depth_m * (1 + 0.5 * attempts_);
  // Lowered until it touches, then pressed until its pad lies flat on the surface (a pad
  // that lands on an edge is pressed over onto its face: the passive ankle gives) and no
  // harder than place_force_n (the press pushes the body off the other pads).
  // Flat: the pad touches with its face (the contacts of a box on a plane: 4; an edge: 2).
  const bool flat = io.PadContact(i).contacts >= kFlatContacts;
  if (!(pad.touching && flat && pad.preload_n >= params_.place_force_n)) {
    place_d_ = std::min(depth, place_d_ + params_.place_speed_mps * dt_);
  }
  const double d = place_d_;
  *face = w2 - d * to_.normal;
  if (pad.attached) {
    Landed(io);
    return false;
  }
  if (pad.touching && touch_since_ < 0) touch_since_ = t;
  const bool rejected = touch_since_ >= 0 && t - touch_since_ > kAttachWait;
  const bool nothing = touch_since_ < 0 && d >= depth &&
                       t - step_t0_ > depth / params_.place_speed_mps + kAttachWait;
  if (rejected || nothing) {
    if (++attempts_ >= params_.max_place_attempts) {
      Fail(io, t, i, "place_attempts");
      return false;
    }
    step_ = StepPhase::kRetry;
    step_t0_ = t;
    swing_.from_face = *face;  // back up from where it got to
  }
  return true;
}

void CornerManoeuvre::Landed(const ManoeuvreIo& io) {
  // Stuck: a stance foot from now on, held where it is for the commanded body.
  const int i = step_leg_;
  Foot& f = feet_[i];
  const LegChain& c = plan_.chains()[i];
  const LegChain::Q q = io.Joints(i);
  f.stance = true;
  f.idle = false;
  f.surface = to_.surface;
  f.normal_w = to_.normal;
  // Along the surface where the joints put it for the commanded body; across it, the
  // planned press (the sag of the body would otherwise add up in the stance targets).
  const BodyPose stance = sag_.Apply(cmd_);
  f.ankle_w = stance.p + stance.r * c.Ankle(q, 0.0);
  const Eigen::Vector3d on = plan_.origin() + (c.post_m() - params_.press_m) * to_.normal;
  f.ankle_w -= (f.ankle_w - on).dot(to_.normal) * to_.normal;
  plan_.Margin(i, sag_.Apply(cmd_), f.ankle_w, f.normal_w, &f.q, &f.tilt, CornerPlan::kStanceTurn);
  step_leg_ = -1;
  step_ = StepPhase::kNone;
}

bool CornerManoeuvre::ReplaceLost(ManoeuvreIo& io, double t) {
  for (size_t i = 0; i < feet_.size(); ++i) {
    if (!feet_[i].stance || pads_[i].attached) continue;
    const Foothold h = plan_.Next(static_cast<int>(i), sigma_, cmd_, feet_[i].q, false);
    if (h.margin < 0) {
      Fail(io, t, static_cast<int>(i), "no_foothold");
    } else {
      StartStep(io, t, static_cast<int>(i), h, false);
    }
    return true;
  }
  return false;
}

}  // namespace climbsim::sim
