// A pad that touches the surface edge-on or at a grazing angle must not attach: the approach
// angle is judged at touchdown (adhesion/sticky_pad.h, condition 2, max 20° by default) and a
// rejected touch stays rejected until the pad has left the surface. Nothing in it may produce
// a NaN or energy. Tilts of 45° and 80° onto an edge, 90° (edge-on: the side face down) and a
// corner first; the pad either held at its tilt (a slide joint) or free to tip over.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "tests/adhesion/mujoco_rig.h"
#include "tests/hard/hard_util.h"

namespace climbsim::adhesion {
namespace {

using climbsim::testing::StateFinite;
using climbsim::testing::WarningsRaised;
using testing::BlockRig;
using testing::BlockSpec;

constexpr double kDegToRad = M_PI / 180.0;

// Mechanical energy of the free block (J): m·g·z + translational + rotational kinetic energy
// (free joint: qvel[3..5] is the angular velocity in the body frame, the principal frame of
// a box). The potential of the soft contacts' penetration is not counted: the block can only
// lose energy to the contacts' damping, never gain it.
double BlockEnergyJ(const mjModel* m, const mjData* d, int body) {
  const double mass = m->body_mass[body];
  const Eigen::Vector3d g(m->opt.gravity[0], m->opt.gravity[1], m->opt.gravity[2]);
  const Eigen::Vector3d pos(d->qpos[0], d->qpos[1], d->qpos[2]);
  const Eigen::Vector3d v(d->qvel[0], d->qvel[1], d->qvel[2]);
  double rot = 0;
  for (int k = 0; k < 3; ++k) {
    rot += m->body_inertia[3 * body + k] * d->qvel[3 + k] * d->qvel[3 + k];
  }
  return -mass * g.dot(pos) + 0.5 * mass * v.squaredNorm() + 0.5 * rot;
}

struct Touch {
  const char* name;
  Eigen::Quaterniond quat;
};

// Lowest z of the pad box (half sizes 12.5, 12.5, 1 mm) turned by r, relative to its centre.
double LowestCornerZ(const Eigen::Matrix3d& r) {
  double lowest = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d c((corner & 1 ? 1 : -1) * 0.0125, (corner & 2 ? 1 : -1) * 0.0125,
                            (corner & 4 ? 1 : -1) * 0.001);
    lowest = std::min(lowest, (r * c).z());
  }
  return lowest;
}

// The pad's orientation for each case. Each test starts the lowest point of the box 0.2 mm
// above the plane: it lands at sqrt(2·g·0.2 mm) = 0.06 m/s, well under the 0.25 m/s limit, so
// the angle is the only approach condition that fails.
std::vector<Touch> Touches() {
  using Eigen::AngleAxisd;
  using Eigen::Vector3d;
  return {
      {"tilted 45 deg onto an edge",
       Eigen::Quaterniond(AngleAxisd(45 * kDegToRad, Vector3d::UnitX()))},
      {"grazing, 80 deg onto an edge",
       Eigen::Quaterniond(AngleAxisd(80 * kDegToRad, Vector3d::UnitX()))},
      {"edge-on, 90 deg: the side face down",
       Eigen::Quaterniond(AngleAxisd(90 * kDegToRad, Vector3d::UnitX()))},
      {"corner first: 30 deg about x, then 30 deg about y",
       Eigen::Quaterniond(AngleAxisd(30 * kDegToRad, Vector3d::UnitY()) *
                          AngleAxisd(30 * kDegToRad, Vector3d::UnitX()))},
  };
}

// A pad body that can only move along the surface normal (a slide joint; the box geom is
// turned in its body, which the pad frame follows), held at its tilt, set down under gravity: its
// edge (or corner, or side face) rests on the plane with the block's weight as preload for the
// whole second, at an approach speed of 0.06 m/s. Every condition but the angle could be met; the
// angle is judged at touchdown and rejects the touch at once. One touch episode, one rejection, no
// attach, ever.
TEST(HardGrazingTouch, EdgeOnAndGrazingPadsHeldAtTheirTiltNeverAttach) {
  for (const Touch& t : Touches()) {
    SCOPED_TRACE(t.name);
    const Eigen::Matrix3d r = t.quat.toRotationMatrix();
    const double z0 = -LowestCornerZ(r) + 0.0002;
    const double tilt_deg = std::acos(std::clamp(r(2, 2), -1.0, 1.0)) / kDegToRad;
    StickyPadParams params;
    params.attach.min_contacts = 1;  // an edge gives 2 contacts, a corner 1: let them count
    PadSpec pad{"block", params};
    const AdhesionMjcfText add = AdhesionMjcf({pad}, {0.002, 1.0});
    std::ostringstream x;
    x.precision(17);
    x << "<mujoco><option timestep=\"0.001\" cone=\"elliptic\" impratio=\"10\"/><worldbody>"
      << "<geom name=\"surface\" type=\"plane\" size=\"1 1 0.1\"/>"
      << "<body name=\"block\" pos=\"0 0 " << z0 << "\">"
      << "<joint name=\"drop\" type=\"slide\" axis=\"0 0 1\"/>"  // world z: the body is not turned
      << "<geom name=\"block\" type=\"box\" size=\"0.0125 0.0125 0.001\" mass=\"0.05\" quat=\""
      << t.quat.w() << " " << t.quat.x() << " " << t.quat.y() << " " << t.quat.z()
      << "\" priority=\"1\" friction=\"1 0.005 0.0001\" solref=\"0.015 1\"/></body>"
      << "</worldbody><equality>" << add.equality << "</equality></mujoco>";
    std::string error;
    mjModel* m = common::CompileMjcfString(x.str(), &error);
    ASSERT_NE(m, nullptr) << error;
    mjData* d = mj_makeData(m);
    AdhesionSystemParams sys;
    sys.pads = {pad};
    sys.surfaces = {"surface"};
    AdhesionSystem system(m, sys);
    testing::EventRecorder events;
    mj_resetData(m, d);
    system.Reset(m, d, &events);
    const StickyPad& p = system.pad(0);
    // Energy m·g·z + m·v²/2 of the one degree of freedom: only lost.
    const auto energy = [&] { return 0.05 * 9.81 * d->qpos[0] + 0.025 * d->qvel[0] * d->qvel[0]; };
    const double e0 = energy();
    double e_max = e0, max_speed = 0;
    bool finite = true;
    for (int i = 0; i < 1000; ++i) {
      system.BeforeStep(m, d, &events);
      mj_step(m, d);
      system.AfterStep(m, d, &events);
      finite = finite && StateFinite(m, d);
      e_max = std::max(e_max, energy());
      max_speed = std::max(max_speed, std::abs(d->qvel[0]));
      ASSERT_FALSE(p.attached()) << "attached at step " << i;
    }
    EXPECT_TRUE(finite);
    EXPECT_EQ(WarningsRaised(d), "");
    EXPECT_EQ(p.counts().attach, 0);
    EXPECT_EQ(p.counts().touchdown, 1) << "one touch: it rests on the plane from then on";
    EXPECT_GE(p.sense().contacts, 1) << "still touching at the end";
    EXPECT_NEAR(p.sense().preload_n, 0.05 * 9.81, 0.01 * 0.05 * 9.81) << "carries its weight";
    ASSERT_EQ(p.counts().attach_rejected, 1);
    const PadEvent* e = events.First(PadEventKind::kAttachRejected);
    ASSERT_NE(e, nullptr);
    EXPECT_EQ(e->cause, PadCause::kApproachAngle);
    EXPECT_NEAR(e->cause_value, tilt_deg, 1e-6) << "held at its tilt: the angle is exact";
    EXPECT_EQ(e->time_s, events.First(PadEventKind::kTouchdown)->time_s) << "at touchdown";
    // Landing speed sqrt(2·g·0.2 mm) = 0.063 m/s is the most it can have; 1e-6 J is 0.1 % of
    // the 0.1 mJ the fall releases.
    EXPECT_LT(max_speed, 0.07);
    EXPECT_LE(e_max, e0 + 1e-6);
    std::printf(
        "%s, slide joint: rejected at touchdown for %.3f deg, %d contacts, preload %.3f "
        "N\n",
        t.name, e->cause_value, p.sense().contacts, p.sense().preload_n);
    mj_deleteData(d);
    mj_deleteModel(m);
  }
}

// The same touches by a free block: it lands on its edge or corner, is rejected for the angle
// at once, then tips over (and may bounce off the plane and touch down again, a new episode
// judged on its own). Whatever it does, the state stays finite and it never gains energy.
TEST(HardGrazingTouch, FreeBlockLandingOnAnEdgeIsRejectedThenTipsOverFinitely) {
  for (const Touch& t : Touches()) {
    SCOPED_TRACE(t.name);
    BlockSpec s;
    s.quat = t.quat;
    const Eigen::Matrix3d r = t.quat.toRotationMatrix();
    s.pos = {0, 0, -LowestCornerZ(r) + 0.0002};
    const double tilt_deg = std::acos(std::clamp(r(2, 2), -1.0, 1.0)) / kDegToRad;
    BlockRig rig(s);
    const mjModel* m = rig.m();
    const mjData* d = rig.d();
    const int body = rig.block_body();
    const double e0 = BlockEnergyJ(m, d, body);
    double e_max = e0;
    bool finite = true;
    for (int i = 0; i < 1000; ++i) {
      rig.Step();
      finite = finite && StateFinite(m, d);
      e_max = std::max(e_max, BlockEnergyJ(m, d, body));
    }
    EXPECT_TRUE(finite);
    EXPECT_EQ(WarningsRaised(d), "");
    ASSERT_GE(rig.events().events.size(), 2u);
    EXPECT_EQ(rig.events().events[0].kind, PadEventKind::kTouchdown);
    EXPECT_EQ(rig.events().events[1].kind, PadEventKind::kAttachRejected);
    EXPECT_EQ(rig.events().events[1].cause, PadCause::kApproachAngle);
    EXPECT_NEAR(rig.events().events[1].cause_value, tilt_deg, 1.0)
        << "one step of rotation after the contact appeared";
    // Nothing injects energy: 1e-6 J is 0.2 % of what the 50 g block loses tipping over.
    EXPECT_LE(e_max, e0 + 1e-6);
    std::printf(
        "%s, free block: rejected at %.2f deg (tilt %.2f); %ld touchdowns, %ld "
        "rejections, %ld attaches; energy %.4g J -> %.4g J (max %.4g)\n",
        t.name, rig.events().events[1].cause_value, tilt_deg, rig.pad().counts().touchdown,
        rig.pad().counts().attach_rejected, rig.pad().counts().attach, e0, BlockEnergyJ(m, d, body),
        e_max);
  }
}

}  // namespace
}  // namespace climbsim::adhesion
