// One sticky pad in MuJoCo (adhesion/sticky_pad.h, adhesion_system.h), on a block: the
// attach conditions one by one, weld switching without a jump, build-up, release, the detach
// causes, holding under a ceiling, and MuJoCo's adhesion actuator under the same ceiling.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "adhesion/adhesion.h"
#include "tests/adhesion/mujoco_rig.h"

namespace climbsim::adhesion {
namespace {

using testing::BlockRig;
using testing::BlockSpec;
using testing::kG;

constexpr double kCapacityN = 10e3 * 0.025 * 0.025;  // σ_T·A of the 25 mm pad: 6.25 N

// A flat block whose face starts `gap_m` above the floor, at rest.
BlockSpec Dropped(double gap_m) {
  BlockSpec s;
  s.pos = {0, 0, 0.001 + gap_m};
  return s;
}

const PadEvent& RejectionOf(BlockRig& rig) {
  const PadEvent* e = rig.events().First(PadEventKind::kAttachRejected);
  if (e == nullptr) {
    ADD_FAILURE() << "no attach_rejected event";
    static const PadEvent none;
    return none;
  }
  return *e;
}

// All four conditions hold for a flat block set down gently (0.2 mm drop, 0.06 m/s, flat,
// 4 contacts, preload m·g = 0.49 N): it attaches at once, with initial_fraction bonded.
TEST(PadAttach, AllConditionsHoldAttaches) {
  BlockRig rig(Dropped(0.0002));
  rig.Run(0.05);
  EXPECT_TRUE(rig.pad().attached());
  EXPECT_EQ(rig.pad().counts().attach, 1);
  EXPECT_EQ(rig.pad().counts().attach_rejected, 0);
  const auto kinds = rig.events().Kinds();
  ASSERT_GE(kinds.size(), 2u);
  EXPECT_EQ(kinds[0], "touchdown");
  EXPECT_EQ(kinds[1], "attach");
  EXPECT_NEAR(rig.events().events[1].bonded_fraction, 77.0 / 256, 1e-12)
      << "round(0.3 * 256) bonds at attach";
}

// Dropped from 10 mm the block lands at sqrt(2 g h) = 0.443 m/s > 0.25: rejected at
// touchdown with the speed as cause (measured one step before the contact force acts, so
// within 2 %). Everything else holds (flat, 4 contacts, a large impact preload).
TEST(PadAttach, TooFastAloneRejectsWithApproachSpeed) {
  BlockRig rig(Dropped(0.010));
  rig.Run(0.2);
  EXPECT_FALSE(rig.pad().attached());
  const PadEvent& e = RejectionOf(rig);
  EXPECT_EQ(e.cause, PadCause::kApproachSpeed);
  EXPECT_NEAR(e.cause_value, std::sqrt(2 * kG * 0.010), 0.02 * std::sqrt(2 * kG * 0.010));
  EXPECT_EQ(rig.pad().counts().rejected_approach_speed, 1);
  EXPECT_EQ(rig.pad().counts().attach, 0) << "no attach later in the same touch";
}

// Tilted 30° about x (max 20°), set down on its edge at low speed, min_contacts 1 so that the
// edge's 2 contacts suffice: rejected for the angle alone, value 30° (the angle at touchdown;
// the ankle-less block starts to flatten only after the contact).
TEST(PadAttach, TooSteepAloneRejectsWithApproachAngle) {
  BlockSpec s;
  const double tilt = 30 * M_PI / 180;
  s.quat = Eigen::Quaterniond(Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitX()));
  // Lowest corner 0.2 mm above the floor.
  s.pos = {0, 0, 0.0125 * std::sin(tilt) + 0.001 * std::cos(tilt) + 0.0002};
  s.pad.attach.min_contacts = 1;
  BlockRig rig(s);
  rig.Run(0.2);
  EXPECT_FALSE(rig.pad().attached());
  const PadEvent& e = RejectionOf(rig);
  EXPECT_EQ(e.cause, PadCause::kApproachAngle);
  EXPECT_NEAR(e.cause_value, 30.0, 0.5);
}

// min_contacts 5 against box-on-plane's 4: rejected after attach_window_s (0.1 s) with the
// count as cause.
TEST(PadAttach, TooFewContactsAloneRejectsWithContactsAfterTheWindow) {
  BlockSpec s = Dropped(0.0002);
  s.pad.attach.min_contacts = 5;
  BlockRig rig(s);
  rig.Run(0.3);
  EXPECT_FALSE(rig.pad().attached());
  const PadEvent& e = RejectionOf(rig);
  EXPECT_EQ(e.cause, PadCause::kContacts);
  EXPECT_EQ(e.cause_value, 4);
  const PadEvent* touchdown = rig.events().First(PadEventKind::kTouchdown);
  ASSERT_NE(touchdown, nullptr);
  EXPECT_NEAR(e.time_s - touchdown->time_s, 0.1, 1.5e-3) << "rejected when the window closes";
}

// min_preload 2 N against the block's weight 0.49 N: rejected after the window with the
// preload (= m·g once settled, 2 %) as cause.
TEST(PadAttach, TooLittlePreloadAloneRejectsWithPreload) {
  BlockSpec s = Dropped(0.0002);
  s.pad.attach.min_preload_n = 2.0;
  BlockRig rig(s);
  rig.Run(0.3);
  EXPECT_FALSE(rig.pad().attached());
  const PadEvent& e = RejectionOf(rig);
  EXPECT_EQ(e.cause, PadCause::kPreload);
  EXPECT_NEAR(e.cause_value, 0.05 * kG, 0.02 * 0.05 * kG);
}

// The conditions are checked in a fixed order and the first failure is the cause: too fast
// AND too few contacts AND too little preload reports the speed.
TEST(PadAttach, FirstFailingConditionInOrderIsTheCause) {
  BlockSpec s = Dropped(0.010);
  s.pad.attach.min_contacts = 5;
  s.pad.attach.min_preload_n = 100;
  BlockRig rig(s);
  rig.Run(0.2);
  EXPECT_EQ(RejectionOf(rig).cause, PadCause::kApproachSpeed);
}

// After a rejection the pad stays an ordinary contact until it has left the surface: a block
// rejected for its landing speed rests on the floor with every other condition met, and does
// not attach; lifted 0.3 mm and set down again (0.08 m/s), it touches down anew and attaches.
TEST(PadAttach, RejectedPadAttachesOnlyAfterLeavingTheSurface) {
  BlockRig rig(Dropped(0.010));
  rig.Run(0.3);
  ASSERT_EQ(rig.pad().counts().rejected_approach_speed, 1);
  rig.Run(0.5);
  EXPECT_FALSE(rig.pad().attached());
  EXPECT_EQ(rig.pad().counts().touchdown, 1);
  EXPECT_GE(rig.pad().sense().contacts, 3) << "resting on the floor all along";

  mjData* d = rig.d();
  d->qpos[2] = 0.001 + 0.0003;
  for (int i = 0; i < 6; ++i) d->qvel[i] = 0.0;
  rig.Run(0.2);
  EXPECT_EQ(rig.pad().counts().touchdown, 2);
  EXPECT_TRUE(rig.pad().attached());
}

// Switching a weld on writes it from the current poses: a block set to an arbitrary pose
// (turned 0.7 rad about (1, 2, 3), 5 cm up, at rest, after 30 steps so that xpos is stale)
// and welded there moves < 1e-4 m and < 1e-3 rad over the next 100 steps under gravity
// (issue 3); measured: the weld's sag under the 50 g block.
TEST(Weld, SwitchingOnAtAnArbitraryPoseDoesNotMoveThePad) {
  BlockSpec s;
  s.pos = {0, 0, 0.3};  // falling, far from the floor
  s.pad.contact.partial_contact = false;  // in the air no cell touches: bond the whole face
  BlockRig rig(s);
  rig.Run(0.03);
  // The arbitrary pose, set directly: xpos still describes the old one.
  mjData* d = rig.d();
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  const double pose[7] = {0.013, -0.021, 0.05, q.w(), q.x(), q.y(), q.z()};
  for (int i = 0; i < 7; ++i) d->qpos[i] = pose[i];
  for (int i = 0; i < 6; ++i) d->qvel[i] = 0.0;
  bool kinematics_current = false;
  const int surface = mj_name2id(rig.m(), mjOBJ_GEOM, "surface");
  ASSERT_TRUE(rig.pad().ForceAttach(rig.m(), d, d->time, surface, 1.0, PadCause::kForced,
                                    &kinematics_current, nullptr));
  EXPECT_TRUE(kinematics_current) << "the attach must bring the poses up to date";
  const PadFrame before = FaceFrame(d, rig.pad().geometry());
  double worst_m = 0, worst_rad = 0;
  for (int i = 0; i < 100; ++i) {
    rig.Step();
    mj_kinematics(rig.m(), d);
    const PadFrame now = FaceFrame(d, rig.pad().geometry());
    worst_m = std::max(worst_m, (now.pos - before.pos).norm());
    worst_rad = std::max(
        worst_rad, Eigen::AngleAxisd(Eigen::Matrix3d(before.rot.transpose() * now.rot)).angle());
  }
  EXPECT_TRUE(rig.pad().attached());
  EXPECT_LT(worst_m, 1e-4);
  EXPECT_LT(worst_rad, 1e-3);
  RecordProperty("weld_jump_m", std::to_string(worst_m));
  RecordProperty("weld_jump_rad", std::to_string(worst_rad));
  std::printf("weld switched on at an arbitrary pose: pad moved %.3g m, %.3g rad in 100 steps\n",
              worst_m, worst_rad);
}

// The weld's wrench is the one the constraint applies: a block welded to the world with an
// off-centre mass (its centre of mass 2 cm up and 3 cm aside, tilted, gravity with a
// sideways part) is held by a weld force −M·g and a couple that cancels gravity's moment about
// the weld point, to 1e-9 (statics, independent of MuJoCo's sensors).
TEST(Weld, WrenchBalancesGravityOnAWeldedBlock) {
  PadSpec pad{"block", {}};
  pad.params.bonds.sigma_t_pa = 1e8;  // holds whatever
  const AdhesionMjcfText add = AdhesionMjcf({pad}, {0.002, 1.0});
  const std::string xml =
      "<mujoco><option gravity=\"0 -3 -9.81\"/><worldbody>"
      "<geom name=\"surface\" type=\"plane\" size=\"1 1 .1\"/>"
      "<body name=\"block\" pos=\"0.1 0.2 0.001\" euler=\"0.3 0.2 0.5\"><freejoint/>"
      "<geom name=\"block\" type=\"box\" size=\".0125 .0125 .001\" mass=\"0.1\"/>"
      "<geom type=\"sphere\" size=\"0.005\" pos=\"0.03 0.01 0.02\" mass=\"0.2\" "
      "contype=\"0\" conaffinity=\"0\"/></body></worldbody><equality>" +
      add.equality + "</equality></mujoco>";
  std::string error;
  mjModel* m = common::CompileMjcfString(xml, &error);
  ASSERT_NE(m, nullptr) << error;
  mjData* d = mj_makeData(m);
  AdhesionSystemParams sys;
  sys.pads = {pad};
  sys.start_attached = true;
  sys.start_gap_m = 0.05;  // tilted: its face is well off the plane
  AdhesionSystem system(m, sys);
  system.Reset(m, d, nullptr);
  ASSERT_TRUE(system.pad(0).attached());
  for (int i = 0; i < 2000; ++i) {
    system.BeforeStep(m, d, nullptr);
    mj_step(m, d);
    system.AfterStep(m, d, nullptr);
  }
  ASSERT_TRUE(system.pad(0).attached());
  WeldWrench w;
  ASSERT_TRUE(ReadWeldWrench(m, d, 0, &w));
  const Eigen::Vector3d g(m->opt.gravity[0], m->opt.gravity[1], m->opt.gravity[2]);
  const double mass = m->body_subtreemass[1];
  const Eigen::Vector3d com(d->xipos + 3), face = FaceFrame(d, system.pad(0).geometry()).pos;
  EXPECT_LT((w.force_n + mass * g).norm(), 1e-9);
  EXPECT_LT((w.torque_nm + (com - face).cross(mass * g)).norm(), 1e-9);
  EXPECT_GT(w.torque_nm.norm(), 0.01) << "a real couple";
  mj_deleteData(d);
  mj_deleteModel(m);
}

// While pressed (F_n ≤ 0) the bonded fraction grows as f ← 1 − (1 − f)·exp(−Δt/τ) each step:
// 100 steps after attaching with 0.3 and τ = 0.1 s the target is 1 − 0.7/e = 0.7425 exactly,
// and the grid holds round(f·256) bonds.
TEST(PadBuildup, GrowsTowardsFullWhilePressed) {
  BlockRig rig(Dropped(0.0002));
  while (!rig.pad().attached()) rig.Step();
  for (int i = 0; i < 100; ++i) rig.Step();
  const double expected = 1.0 - 0.7 * std::exp(-1.0);
  EXPECT_NEAR(rig.pad().buildup_target(), expected, 1e-12);
  EXPECT_NEAR(rig.pad().bonded_fraction(), expected, 0.5 / 256 + 1e-12);
}

// Under a ceiling the pad is pulled (F_n = m·g > 0): a pad attached with half its bonds does
// not grow.
TEST(PadBuildup, DoesNotGrowWhilePulled) {
  BlockSpec s;
  s.gravity = {0, 0, kG};  // away from the surface
  s.mass_kg = 0.2 * kCapacityN / kG;
  BlockRig rig(s);
  mj_forward(rig.m(), rig.d());
  bool current = true;
  const int surface = mj_name2id(rig.m(), mjOBJ_GEOM, "surface");
  ASSERT_TRUE(rig.pad().ForceAttach(rig.m(), rig.d(), 0.0, surface, 0.5, PadCause::kForced,
                                    &current, nullptr));
  rig.Run(0.5);
  ASSERT_TRUE(rig.pad().attached());
  EXPECT_NEAR(rig.pad().load().fn_n, s.mass_kg * kG, 1e-3 * s.mass_kg * kG);
  EXPECT_EQ(rig.pad().bonded_fraction(), 0.5);
}

// A wait for a support pad (SupportBuilt) ends at the fraction of what the pad touches, or
// once torn bonds leave it nothing to grow; not while it still grows.
TEST(PadBuildup, ASupportIsBuiltAtTheFractionOrWhenNothingIsLeftToGrow) {
  EXPECT_FALSE(SupportBuilt(0.84, 1.0, 1.0, 0.85));
  EXPECT_TRUE(SupportBuilt(0.85, 1.0, 1.0, 0.85));
  EXPECT_TRUE(SupportBuilt(0.51, 0.6, 0.6, 0.85));   // over an edge: 0.85 of the touched 0.6
  EXPECT_FALSE(SupportBuilt(0.50, 0.6, 0.6, 0.85));
  EXPECT_FALSE(SupportBuilt(0.80, 1.0, 0.824, 0.85));  // torn, still growing
  EXPECT_TRUE(SupportBuilt(0.824, 1.0, 0.824, 0.85));  // torn, all it can
}

// Release: weld off at once, event detach/released, and no re-attach while the pad still
// rests on the surface (it must leave it first).
TEST(PadDetach, ReleaseLetsGoAndWaitsForLiftOff) {
  BlockRig rig(Dropped(0.0002));
  rig.Run(0.2);
  ASSERT_TRUE(rig.pad().attached());
  ASSERT_TRUE(rig.system().Release(0, rig.m(), rig.d(), &rig.events()));
  EXPECT_FALSE(rig.pad().attached());
  EXPECT_FALSE(WeldActive(rig.m(), rig.d(), /*eq=*/0));
  EXPECT_EQ(rig.events().events.back().kind, PadEventKind::kDetach);
  EXPECT_EQ(rig.events().events.back().cause, PadCause::kReleased);
  EXPECT_GT(rig.events().events.back().bonded_fraction, 0.85) << "the fraction it let go with";
  EXPECT_FALSE(rig.system().Release(0, rig.m(), rig.d(), nullptr)) << "not attached any more";
  rig.Run(0.5);
  EXPECT_FALSE(rig.pad().attached());
  EXPECT_EQ(rig.pad().counts().attach, 1);
  EXPECT_EQ(rig.pad().counts().detach_released, 1);
  EXPECT_NE(rig.m()->geom_contype[rig.pad().geometry().geom], 0) << "collides again";
}

// release_contact_delay_s: a released pad collides again only after the delay, in whole steps
// (10 ms at 1 ms steps: the geom's contype is 0 through 9 more steps and back at the 10th);
// without a delay at once.
TEST(PadDetach, AReleasedPadCollidesAgainAfterTheReleaseContactDelay) {
  for (double delay : {0.0, 0.01}) {
    SCOPED_TRACE(::testing::Message() << "delay " << delay);
    BlockSpec spec = Dropped(0.0002);
    spec.pad.release_contact_delay_s = delay;
    BlockRig rig(spec);
    rig.Run(0.2);
    ASSERT_TRUE(rig.pad().attached());
    const int geom = rig.pad().geometry().geom;
    ASSERT_TRUE(rig.system().Release(0, rig.m(), rig.d(), &rig.events()));
    int steps_without = 0;
    while (rig.m()->geom_contype[geom] == 0 && steps_without < 100) {
      rig.Step();
      ++steps_without;
    }
    EXPECT_EQ(steps_without, delay == 0.0 ? 0 : 10);
    EXPECT_FALSE(rig.pad().attached());
  }
}

// A disengaged pad (an active-release foot with its toe held peeled) touches without a
// touchdown or an attach; engaged again while it rests on the floor, that touch is a new
// episode, judged then: the block, at rest, attaches.
TEST(PadDetach, DisengagedPadTouchesWithoutAttachingUntilEngaged) {
  BlockRig rig(Dropped(0.0002));
  rig.pad().SetDisengaged(true);
  rig.Run(0.3);
  EXPECT_FALSE(rig.pad().attached());
  EXPECT_GT(rig.pad().sense().contacts, 0) << "it rests on the floor";
  EXPECT_EQ(rig.pad().counts().touchdown, 0);
  EXPECT_TRUE(rig.events().events.empty());
  rig.pad().SetDisengaged(false);
  rig.Run(0.05);
  EXPECT_TRUE(rig.pad().attached());
  EXPECT_EQ(rig.pad().counts().touchdown, 1);
  EXPECT_EQ(rig.pad().counts().attach, 1);
}

// A block of mass m hanging from one fully bonded pad under a ceiling (gravity pulls it off,
// a uniform normal load m·g): it holds for 10 s when m·g is 5 % below σ_T·A and lets go
// within 1 s (in fact in the first step, all at once: overload) when it is 5 % above.
TEST(PadCeiling, HoldsFivePercentBelowCapacityAndLetsGoFivePercentAbove) {
  for (double factor : {0.95, 1.05}) {
    BlockSpec s;
    s.gravity = {0, 0, kG};
    s.mass_kg = factor * kCapacityN / kG;
    s.start_attached = true;
    BlockRig rig(s);
    ASSERT_TRUE(rig.pad().attached());
    double let_go_s = -1;
    for (int i = 0; i < 10000 && let_go_s < 0; ++i) {
      rig.Step();
      if (!rig.pad().attached()) let_go_s = rig.d()->time;
    }
    if (factor < 1) {
      EXPECT_LT(let_go_s, 0) << "let go at " << let_go_s << " s";
      EXPECT_NEAR(rig.BlockPos().z(), 0.001, 1e-4) << "hangs where it was";
    } else {
      EXPECT_GT(let_go_s, 0);
      EXPECT_LT(let_go_s, 1.0);
      EXPECT_EQ(rig.events().events.back().cause, PadCause::kOverload);
      std::printf("m*g = 1.05 sigma_T*A: let go after %.3f s\n", let_go_s);
    }
  }
}

// MuJoCo's adhesion actuator under the same ceiling holds iff gain·ctrl > m·g: with
// gain·ctrl 2 % above m·g the block stays (moves < 0.1 mm in 10 s), 2 % below it falls away
// (> 5 mm within 1 s) and the pad detaches with cause contact_lost. ctrl 0.5 and gain 2·(...)
// show that the product counts.
TEST(PadCeiling, MujocoActuatorHoldsIffGainTimesCtrlExceedsWeight) {
  const double mass = 0.5 * kCapacityN / kG;
  for (double factor : {1.02, 0.98}) {
    BlockSpec s;
    s.gravity = {0, 0, kG};
    s.mass_kg = mass;
    s.start_attached = true;
    s.pad.model = AdhesionModel::kMujoco;
    s.pad.actuator_ctrl = 0.5;
    s.pad.actuator_gain_n = factor * mass * kG / 0.5;
    BlockRig rig(s);
    ASSERT_TRUE(rig.pad().attached());
    rig.Run(0.05);  // the actuator pulls the block into its contact
    const double z0 = rig.BlockPos().z();
    double gone_s = -1;
    for (int i = 0; i < 10000 && gone_s < 0; ++i) {
      rig.Step();
      mj_kinematics(rig.m(), rig.d());
      if (rig.BlockPos().z() - z0 > 0.005) gone_s = rig.d()->time;
    }
    if (factor > 1) {
      EXPECT_LT(gone_s, 0);
      EXPECT_NEAR(rig.BlockPos().z(), z0, 1e-4);
      EXPECT_TRUE(rig.pad().attached());
    } else {
      EXPECT_GT(gone_s, 0);
      EXPECT_LT(gone_s, 1.0);
      EXPECT_FALSE(rig.pad().attached());
      EXPECT_EQ(rig.pad().counts().detach_contact_lost, 1);
    }
  }
}

// The pad frame read from the box is the contract's L_pad_face: the −z face's centroid with
// the geom's axes (here a block turned and offset in its body).
TEST(PadGeometryTest, FaceFrameIsTheBoxsMinusZFace) {
  BlockRig rig(Dropped(0.0));
  const PadGeometry& g = rig.pad().geometry();
  EXPECT_DOUBLE_EQ(g.width_m, 0.025);
  EXPECT_DOUBLE_EQ(g.length_m, 0.025);
  EXPECT_NEAR((g.face_pos_body - Eigen::Vector3d(0, 0, -0.001)).norm(), 0, 1e-15);
  mj_forward(rig.m(), rig.d());
  const PadFrame f = FaceFrame(rig.d(), g);
  EXPECT_NEAR(f.pos.z(), 0.0, 1e-15);
}

}  // namespace
}  // namespace climbsim::adhesion
