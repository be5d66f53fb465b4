// 1,000 attach/detach cycles of one pad (adhesion/sticky_pad.h): a block is set down on the
// plane, attaches under the normal conditions, is let go (every other cycle by
// RequestRelease, the others by a pull that breaks every bond), lifted and set down again.
// Nothing may accumulate: the weld is written fresh from the current poses at each attach
// (its residual is zero then, whatever happened before), the sag under the block's weight is
// the same in every cycle, the contact count stays that of a box on a plane, and after the
// first cycle nothing allocates. Its own executable: tests/common/alloc_counter replaces the
// global allocation functions.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "tests/adhesion/mujoco_rig.h"
#include "tests/common/alloc_counter.h"
#include "tests/hard/hard_util.h"

namespace climbsim::adhesion {
namespace {

using climbsim::testing::CountAllocations;
using climbsim::testing::StateFinite;
using climbsim::testing::WarningsRaised;
using climbsim::testing::WeldPositionResidualM;
using testing::BlockRig;
using testing::BlockSpec;

// Counts events without allocating.
class CountingSink final : public PadEventSink {
 public:
  void OnPadEvent(int, const PadEvent& e) override {
    ++count[static_cast<int>(e.kind)];
    if (e.kind == PadEventKind::kDetach) last_detach_cause = e.cause;
    if (e.kind == PadEventKind::kAttachRejected) last_rejection = e.cause;
  }
  long count[5] = {};
  PadCause last_detach_cause = PadCause::kNone;
  PadCause last_rejection = PadCause::kNone;
};

// The weld's residual from its eq_data and the current poses (docs/mujoco.md):
// position (x1 + R1·d[3:6]) − (x2 + R2·d[0:3]), orientation vec(q2⁻¹·q1·d[6:10]).
struct Residual {
  double pos_m, rot;
};
Residual WeldResidualNow(const mjModel* m, const mjData* d, int eq) {
  const mjtNum* data = m->eq_data + eq * mjNEQDATA;
  const int b1 = m->eq_obj1id[eq], b2 = m->eq_obj2id[eq];
  mjtNum p1[3], p2[3];
  mju_rotVecMat(p1, data + 3, d->xmat + 9 * b1);
  mju_addTo3(p1, d->xpos + 3 * b1);
  mju_rotVecMat(p2, data, d->xmat + 9 * b2);
  mju_addTo3(p2, d->xpos + 3 * b2);
  mjtNum q2_inv[4], q21[4], q[4];
  mju_negQuat(q2_inv, d->xquat + 4 * b2);
  mju_mulQuat(q21, q2_inv, d->xquat + 4 * b1);
  mju_mulQuat(q, q21, data + 6);
  return {Eigen::Vector3d(p1[0] - p2[0], p1[1] - p2[1], p1[2] - p2[2]).norm(),
          Eigen::Vector3d(q[1], q[2], q[3]).norm()};
}

struct CycleStats {
  int steps_to_attach = 0;
  double residual_at_attach_m = 0, residual_at_attach_rot = 0;
  double sag_before_detach_m = 0;  // efc_pos of the weld, the last step before letting go
  int max_ncon = 0;
  bool finite = true;
  bool ok = true;  // attached and detached as intended
};

class Cycler {
 public:
  Cycler() : rig_(Spec()) {
    eq_ = 0;  // the rig's one weld
    body_ = rig_.block_body();
    capacity_n_ = rig_.pad().params().bonds.sigma_t_pa * 0.025 * 0.025;
  }
  static BlockSpec Spec() {
    BlockSpec s;
    s.pos = {0, 0, 0.001};  // resting on the plane
    return s;
  }

  // One step with a hook between the attach decision and mj_step.
  void Step(CycleStats* st, bool* attached_now) {
    mjModel* m = rig_.m();
    mjData* d = rig_.d();
    const bool was = rig_.pad().attached();
    rig_.system().BeforeStep(m, d, &sink_);
    if (!was && rig_.pad().attached()) {
      // Just attached: the attach ran mj_kinematics, so xpos/xquat are the current poses.
      const Residual r = WeldResidualNow(m, d, eq_);
      st->residual_at_attach_m = r.pos_m;
      st->residual_at_attach_rot = r.rot;
      *attached_now = true;
    }
    mj_step(m, d);
    rig_.system().AfterStep(m, d, &sink_);
    st->max_ncon = std::max(st->max_ncon, d->ncon);
    st->finite = st->finite && StateFinite(m, d);
  }

  // Lift 0.3 mm, at rest, keeping x, y and orientation; set down; attach; hold 50 ms; let go.
  CycleStats Cycle(bool by_pull) {
    CycleStats st;
    mjModel* m = rig_.m();
    mjData* d = rig_.d();
    d->qpos[2] += 0.0003;
    for (int i = 0; i < 6; ++i) d->qvel[i] = 0.0;
    bool attached_now = false;
    while (!attached_now && st.steps_to_attach < 300) {
      Step(&st, &attached_now);
      ++st.steps_to_attach;
    }
    if (!attached_now) {
      st.ok = false;
      return st;
    }
    for (int i = 0; i < 50; ++i) Step(&st, &attached_now);
    st.sag_before_detach_m = WeldPositionResidualM(m, d, eq_);
    if (!rig_.pad().attached()) {
      st.ok = false;
      return st;
    }
    if (by_pull) {
      // Twice σ_T·A straight off: every bond over its threshold in the step the weld carries
      // it (overload).
      d->xfrc_applied[6 * body_ + 2] = 2.0 * capacity_n_;
      Step(&st, &attached_now);
      d->xfrc_applied[6 * body_ + 2] = 0.0;
      st.ok = !rig_.pad().attached() && sink_.last_detach_cause == PadCause::kOverload;
    } else {
      rig_.system().Release(0, m, d, &sink_);
      st.ok = !rig_.pad().attached() && sink_.last_detach_cause == PadCause::kReleased;
    }
    // The soft weld lets the pulled block rise a little in the step it breaks (it leaves at
    // 0.025 m/s and would hop, land and attach on its own): the puller holds it still.
    for (int i = 0; i < 6; ++i) d->qvel[i] = 0.0;
    for (int i = 0; i < 50; ++i) Step(&st, &attached_now);
    return st;
  }

  BlockRig& rig() { return rig_; }
  const CountingSink& sink() const { return sink_; }

 private:
  BlockRig rig_;
  CountingSink sink_;
  int eq_ = 0, body_ = 0;
  double capacity_n_ = 0;
};

TEST(HardCycles, ThousandAttachDetachCyclesDriftNothingAndAllocateNothing) {
  Cycler c;
  // The rig starts it resting: let it attach once normally and go, as cycle 0.
  std::vector<CycleStats> stats;
  stats.reserve(1000);
  stats.push_back(c.Cycle(false));
  ASSERT_TRUE(stats[0].ok);
  const auto allocations = CountAllocations([&] {
    for (int k = 1; k < 1000; ++k) stats.push_back(c.Cycle(k % 2 == 1));
  });
  // Nothing allocates after the first cycle (operator new, and malloc when countable).
  EXPECT_EQ(allocations.news, 0);
  EXPECT_EQ(allocations.mallocs, 0);

  double worst_attach_m = 0, worst_attach_rot = 0, sag_min = 1, sag_max = 0;
  int worst_ncon = 0, max_steps_to_attach = 0;
  int failed = 0;
  bool finite = true;
  for (const CycleStats& s : stats) {
    failed += !s.ok;
    finite = finite && s.finite;
    worst_attach_m = std::max(worst_attach_m, s.residual_at_attach_m);
    worst_attach_rot = std::max(worst_attach_rot, s.residual_at_attach_rot);
    sag_min = std::min(sag_min, s.sag_before_detach_m);
    sag_max = std::max(sag_max, s.sag_before_detach_m);
    worst_ncon = std::max(worst_ncon, s.max_ncon);
    max_steps_to_attach = std::max(max_steps_to_attach, s.steps_to_attach);
  }
  EXPECT_EQ(failed, 0) << "cycles that did not attach and let go as intended";
  EXPECT_TRUE(finite);
  EXPECT_EQ(WarningsRaised(c.rig().d()), "");
  const CountingSink& sink = c.sink();
  EXPECT_EQ(sink.count[static_cast<int>(PadEventKind::kAttach)], 1000);
  EXPECT_EQ(sink.count[static_cast<int>(PadEventKind::kDetach)], 1000);
  EXPECT_EQ(sink.count[static_cast<int>(PadEventKind::kAttachRejected)], 0);
  EXPECT_EQ(c.rig().pad().counts().detach_released, 500);
  EXPECT_EQ(c.rig().pad().counts().detach_overload, 500);
  // The weld written fresh at every attach: zero residual to rounding (the poses are ~1e-3 m,
  // so 1e-15 m is a few ulps), in every one of the 1000 cycles.
  EXPECT_LT(worst_attach_m, 1e-15);
  EXPECT_LT(worst_attach_rot, 1e-15);
  // The sag under the 50 g block after 50 ms attached is the same physics in every cycle; a
  // weld that carried anything over from earlier cycles would spread it. Measured: 4.372e-6 m
  // in every cycle, spread 7e-13 m; 1e-9 m bounds it.
  EXPECT_LT(sag_max - sag_min, 1e-9);
  EXPECT_GT(sag_min, 0);
  // A box on a plane has at most 4 contacts; welded, the pad collides with nothing.
  EXPECT_LE(worst_ncon, 4);
  std::printf("block at (%.3g, %.3g, %.6g) m after the cycles\n", c.rig().d()->qpos[0],
              c.rig().d()->qpos[1], c.rig().d()->qpos[2]);
  std::printf(
      "1000 cycles: attach within %d steps, residual at attach %.3g m / %.3g, sag "
      "%.17g..%.17g m, max ncon %d, allocations after cycle 0: %ld new, %ld malloc\n",
      max_steps_to_attach, worst_attach_m, worst_attach_rot, sag_min, sag_max, worst_ncon,
      allocations.news, allocations.mallocs);
}

}  // namespace
}  // namespace climbsim::adhesion
