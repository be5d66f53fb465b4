#include "sim/tail_driver.h"

#include <algorithm>
#include <cmath>

namespace climbsim::sim {
namespace {

// The legs whose hip (the leg's first body, a child of the base) stands within 5 mm of the
// foremost: the gecko's LF and RF, the spider's front pair.
std::vector<int> FrontLegs(const mjModel* m, const RobotInfo& robot) {
  std::vector<double> x;
  for (const LegInfo& l : robot.legs) x.push_back(m->body_pos[3 * m->jnt_bodyid[l.joint[0]]]);
  const double front_x = x.empty() ? 0.0 : *std::max_element(x.begin(), x.end());
  std::vector<int> front;
  for (size_t i = 0; i < x.size(); ++i) {
    if (x[i] > front_x - 0.005) front.push_back(static_cast<int>(i));
  }
  return front;
}

// Each leg's side: its hip's y on the body.
std::vector<int> Sides(const mjModel* m, const RobotInfo& robot, const std::vector<int>& legs) {
  std::vector<int> side;
  for (int i : legs) {
    side.push_back(m->body_pos[3 * m->jnt_bodyid[robot.legs[i].joint[0]] + 1] >= 0 ? 1 : -1);
  }
  return side;
}

// The base's rotation from its root quaternion (qpos, so it holds before mj_forward has run).
Eigen::Matrix3d BaseRotation(const World& world) {
  double r[9];
  mju_quat2Mat(r, world.data()->qpos + world.robot().root_qpos_adr + 3);
  return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(r);
}

}  // namespace

TailDriver::TailDriver(const reflex::TailReflexParams& params, const World& world, double dt_s,
                       int event_pad, AdhesionEffect* adhesion)
    : reflex_(params, dt_s),
      actuator_(world.robot().tail.pitch_actuator),
      yaw_actuator_(world.robot().tail.yaw_actuator),
      event_pad_(event_pad),
      adhesion_(adhesion),
      tail_pad_(adhesion != nullptr && world.robot().tail.pad_body >= 0
                    ? adhesion->system().FindPad(world.robot().tail.pad_body)
                    : -1),
      front_(FrontLegs(world.model(), world.robot())),
      front_side_(Sides(world.model(), world.robot(), front_)),
      was_attached_(front_.size(), false) {}

void TailDriver::Reset(World& world) {
  reflex_.Reset();
  normal_ = BaseRotation(world).col(2);
  std::fill(was_attached_.begin(), was_attached_.end(), false);
  world.data()->ctrl[actuator_] = reflex_.params().rest_rad;
  if (yaw_actuator_ >= 0) world.data()->ctrl[yaw_actuator_] = 0.0;
  presses_ = 0;
  max_pitch_rad_ = 0.0;
  DriveTailPad(false);  // a tip that started attached lets go at once
}

void TailDriver::DriveTailPad(bool pressing) {
  if (tail_pad_ < 0) return;
  if (!pressing && adhesion_->pad(tail_pad_).attached()) adhesion_->RequestRelease(tail_pad_);
  adhesion_->SetDisengaged(tail_pad_, !pressing);
}

// The nose's turn away from the surface: the base's x axis along the starting normal.
double TailDriver::PitchRad(const World& world) const {
  const double along = BaseRotation(world).col(0).dot(normal_);
  return std::asin(std::clamp(along, -1.0, 1.0));
}

void TailDriver::Update(World& world, RunContext& ctx, const std::vector<reflex::LegReflex>& legs) {
  const std::vector<LegSignals>& signals = *ctx.legs;
  reflex::TailSensing in;
  for (size_t k = 0; k < front_.size(); ++k) {
    const LegSignals& s = signals[front_[k]];
    // A pad lost in stance while its leg is not peeling it: a failure, not a release.
    if (was_attached_[k] && !s.attached && s.stance && !legs[front_[k]].state().peeling) {
      in.front_pad_lost = true;
      in.lost_side = front_side_[k];
    }
    was_attached_[k] = s.attached;
  }
  in.pitch_rad = PitchRad(world);
  max_pitch_rad_ = std::max(max_pitch_rad_, in.pitch_rad);
  const reflex::TailOutput out = reflex_.Update(in);
  DriveTailPad(reflex_.pressing());
  world.data()->ctrl[actuator_] = out.command_rad;
  // tail_yaw turns about the base's z: + swings the tip (behind the body) towards −y.
  if (yaw_actuator_ >= 0) world.data()->ctrl[yaw_actuator_] = -out.yaw_command_rad;
  if (out.event == reflex::TailEventType::kNone) return;
  Event row;
  row.time_s = ctx.time_s;
  row.pad = event_pad_;
  row.kind = reflex::TailEventName(out.event).data();  // views of string literals
  row.cause = reflex::TailTriggerName(out.trigger).data();
  row.cause_value = in.pitch_rad;  // the pitch that triggered it, undelayed
  row.has_cause_value = out.trigger == reflex::TailTrigger::kPitch;
  ctx.events->Add(row);
  if (out.event == reflex::TailEventType::kPress) ++presses_;
}

}  // namespace climbsim::sim
