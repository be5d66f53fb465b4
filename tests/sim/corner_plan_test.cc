// The kinematics behind the surface transitions: each leg's chain (robot/leg_chain.h) puts the
// ankle and turns the pad exactly as MuJoCo does, its inverse kinematics and tilt reach what
// they aim at, and the corner plan (transition/corner_plan.h) takes the robots with actuated ankles
// round each corner in a dry run (no dynamics): every foot reachable with margin, three pads
// down at every step.
#include "transition/corner_plan.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include "sim/sim.h"

namespace climbsim::sim {
namespace {

std::unique_ptr<CompiledModel> Compile(const std::string& robot, const std::string& scene) {
  const std::string yaml = "robot: " + robot + "\nscene: " + scene + "\nduration_s: 1\n";
  const Scenario s = ParseScenario(YAML::Load(yaml), std::string(CLIMBSIM_SOURCE_DIR) + "/x.yaml");
  return CompileScenario(s);
}

class LegChainTest : public testing::TestWithParam<std::string> {};

// Random joint angles and tilts: the chain's ankle and pad orientation are MuJoCo's, its
// Jacobian the finite difference, its IK reaches the ankle it came from and its tilt turns
// the pad's face normal onto a normal the tilt axis can reach.
TEST_P(LegChainTest, MatchesMujocoKinematics) {
  const auto compiled = Compile(GetParam(), "floor");
  const mjModel* m = compiled->model();
  const RobotInfo& robot = compiled->robot();
  mjData* d = mj_makeData(m);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (size_t leg = 0; leg < robot.legs.size(); ++leg) {
    const LegChain c(m, robot, static_cast<int>(leg));
    const LegInfo& info = robot.legs[leg];
    EXPECT_EQ(c.has_tilt(), info.tilt_joint >= 0);
    for (int trial = 0; trial < 20; ++trial) {
      LegChain::Q q;
      for (int k = 0; k < 3; ++k) q[k] = c.lo()[k] + (c.hi()[k] - c.lo()[k]) * u(rng);
      const double tilt = c.has_tilt() ? c.tilt_lo() + (c.tilt_hi() - c.tilt_lo()) * u(rng) : 0;
      mju_copy(d->qpos, m->qpos0, m->nq);
      for (int k = 0; k < 3; ++k) d->qpos[info.qpos_adr[k]] = q[k];
      if (c.has_tilt()) d->qpos[info.tilt_qpos_adr] = tilt;
      mj_kinematics(m, d);
      const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rb(
          d->xmat + 9 * robot.base_body);
      const Eigen::Map<const Eigen::Vector3d> pb(d->xpos + 3 * robot.base_body);
      const Eigen::Map<const Eigen::Vector3d> site(d->site_xpos + 3 * info.ankle_site);
      const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rp(
          d->xmat + 9 * info.pad_body);
      Eigen::Matrix3d pad_rot, jac;
      const Eigen::Vector3d ankle = c.Ankle(q, tilt, &pad_rot, &jac);
      EXPECT_LT((ankle - rb.transpose() * (site - pb)).norm(), 1e-12);
      EXPECT_LT((pad_rot - rb.transpose() * rp).norm(), 1e-12);
      for (int k = 0; k < 3; ++k) {
        LegChain::Q qp = q;
        qp[k] += 1e-7;
        EXPECT_LT(((c.Ankle(qp, tilt) - ankle) / 1e-7 - jac.col(k)).norm(), 1e-5);
      }
      LegChain::Q guess = q;  // warm-started, as a controller uses it
      for (int k = 0; k < 3; ++k) {
        guess[k] = std::clamp(guess[k] + 0.2 * (u(rng) - 0.5), c.lo()[k], c.hi()[k]);
      }
      EXPECT_LT(c.Solve(ankle, &guess, 50), 1e-6) << "leg " << leg << " trial " << trial;
      if (c.has_tilt()) {
        const Eigen::Vector3d n = pad_rot.col(2);  // a normal this tilt reaches exactly
        double left = 1;
        EXPECT_NEAR(c.Tilt(q, n, &left), tilt, 1e-9);
        EXPECT_LT(left, 1e-6);
      }
    }
  }
  mj_deleteData(d);
}

// OutOfReach is a bound: no joint angles in or out of range put the ankle out of reach of
// the hip, and a target just past the furthest ankle found is out of reach, one just inside
// it is not; a solve towards an out-of-reach target ends further than the tolerance from it.
TEST_P(LegChainTest, OutOfReachBoundsEveryAnkle) {
  const auto compiled = Compile(GetParam(), "floor");
  const RobotInfo& robot = compiled->robot();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-M_PI, M_PI);
  for (size_t leg = 0; leg < robot.legs.size(); ++leg) {
    const LegChain c(compiled->model(), robot, static_cast<int>(leg));
    double furthest = 0.0;
    Eigen::Vector3d far_dir = Eigen::Vector3d::UnitX();
    for (int k = 0; k < 20000; ++k) {
      const LegChain::Q q = {u(rng), u(rng), u(rng)};  // any angles, past the limits too
      const Eigen::Vector3d a = c.Ankle(q, 0.0);
      EXPECT_FALSE(c.OutOfReach(a, 0.0)) << "leg " << leg;
      if ((a - c.hip()).norm() > furthest) {
        furthest = (a - c.hip()).norm();
        far_dir = (a - c.hip()).normalized();
      }
    }
    // The bound is the straight leg: the samples come within 1 mm of it.
    EXPECT_TRUE(c.OutOfReach(c.hip() + (furthest + 0.001) * far_dir, 0.0)) << "leg " << leg;
    const Eigen::Vector3d target = c.hip() + (furthest + 0.01) * far_dir;
    ASSERT_TRUE(c.OutOfReach(target, 0.002));
    LegChain::Q q = {0, 0, 0};
    EXPECT_GT(c.Solve(target, &q), 0.002) << "leg " << leg;
  }
}

// The reach map never rejects an ankle the joints' ranges allow (nor a target within the
// tolerance of one), and what it rejects inside the reach sphere no solve reaches.
TEST_P(LegChainTest, ReachMapIsConservativeAndPrunes) {
  const auto compiled = Compile(GetParam(), "floor");
  const RobotInfo& robot = compiled->robot();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (size_t leg = 0; leg < robot.legs.size(); ++leg) {
    const LegChain c(compiled->model(), robot, static_cast<int>(leg));
    const auto in_range = [&] {
      LegChain::Q q{};
      for (int k = 0; k < 3; ++k) q[k] = c.lo()[k] + u(rng) * (c.hi()[k] - c.lo()[k]);
      return q;
    };
    for (int k = 0; k < 20000; ++k) {
      const Eigen::Vector3d a = c.Ankle(in_range(), 0.0);
      ASSERT_FALSE(c.Unreachable(a, 0.0)) << "leg " << leg;
      const Eigen::Vector3d off = Eigen::Vector3d(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
      ASSERT_FALSE(c.Unreachable(a + 0.0024 * off.normalized(), LegChain::kMapTolM)) << "leg " << leg;
    }
    // Points in the reach sphere: the map rejects some; none of those is solved to 2 mm from
    // five warm starts.
    int inside = 0, pruned = 0;
    const double r = (c.neutral_ankle() - c.hip()).norm() * 1.5;
    for (int k = 0; k < 3000; ++k) {
      const Eigen::Vector3d x = c.hip() + r * Eigen::Vector3d(2 * u(rng) - 1, 2 * u(rng) - 1, 2 * u(rng) - 1);
      if (c.OutOfReach(x, 0.002)) continue;
      ++inside;
      if (!c.Unreachable(x, 0.002)) continue;
      ++pruned;
      for (int w = 0; w < 5; ++w) {
        LegChain::Q q = in_range();
        ASSERT_GT(c.Solve(x, &q), 0.002) << "leg " << leg << " point " << x.transpose();
      }
    }
    EXPECT_GT(pruned, inside / 5) << "leg " << leg << ": " << pruned << " of " << inside;
  }
}

// Solve remembers its first and last forward pass by q (a stance leg following the body, a
// search from one warm start). A remembered pass must be the pass: the same sequence of solves
// on a chain that remembers and on one whose memory is evicted before each solve (by a solve
// from elsewhere) ends at the same q, distance and pad orientation, bit for bit.
TEST_P(LegChainTest, RememberedPassesChangeNoBit) {
  const auto compiled = Compile(GetParam(), "floor");
  const RobotInfo& robot = compiled->robot();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (size_t leg = 0; leg < robot.legs.size(); ++leg) {
    const LegChain remembers(compiled->model(), robot, static_cast<int>(leg));
    const LegChain evicted = remembers;
    LegChain::Q q1{}, q2{}, other{};
    for (int k = 0; k < 3; ++k) other[k] = 0.5 * (remembers.lo()[k] + remembers.hi()[k]) + 0.1;
    for (int step = 0; step < 400; ++step) {
      // Mostly small moves of the target (a tracking stance leg), now and then a jump, and
      // now and then several targets from one warm start (a search).
      const Eigen::Vector3d target =
          remembers.neutral_ankle() +
          (step % 50 == 0 ? 0.02 : 0.003) * Eigen::Vector3d(u(rng), u(rng), u(rng));
      const LegChain::Q start = q1;
      Eigen::Matrix3d rot1, rot2;
      const double e1 = remembers.Solve(target, &q1, LegChain::kSolveIterations, &rot1);
      LegChain::Q scratch = other;
      evicted.Solve(remembers.neutral_ankle(), &scratch);  // its memory now holds other passes
      q2 = start;
      const double e2 = evicted.Solve(target, &q2, LegChain::kSolveIterations, &rot2);
      ASSERT_EQ(q1, q2) << "leg " << leg << " step " << step;
      ASSERT_EQ(e1, e2) << "leg " << leg << " step " << step;
      ASSERT_TRUE(rot1 == rot2) << "leg " << leg << " step " << step;
      if (step % 7 == 3) q1 = start;  // the next solve starts from the same warm start
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Robots, LegChainTest,
                         testing::Values("gecko", "spider", "gecko_ankle", "spider_ankle"));

BodyPose StandingPose(double x, double height) {
  BodyPose p;
  p.p = Eigen::Vector3d(x, 0, height);
  return p;
}

// A dry run round each corner: the body gets 5 cm along the new surface.
struct DryCase {
  const char* robot;
  bool inner;
  double start_x;
};

class CornerDryRun : public testing::TestWithParam<DryCase> {};

TEST_P(CornerDryRun, TakesTheCorner) {
  const DryCase dc = GetParam();
  const auto compiled = Compile(dc.robot, "floor");
  TransitionParams params;
  CornerPlan plan(compiled->model(), compiled->robot(), params);
  // The corner at x = 0.3 on the plane z = 0; inner: a wall ahead; outer: the plane ends there.
  plan.SetCorner(Eigen::Vector3d(0.3, 0, 0), Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(),
                 dc.inner);
  const BodyPose start = StandingPose(dc.start_x, plan.height_m());
  std::string log;
  int steps = 0;
  const double sigma = plan.DryRun(start, 0.05, &log, &steps);
  std::printf("%s", log.c_str());
  EXPECT_GE(sigma, M_PI / 2 + 0.05) << log;
}

INSTANTIATE_TEST_SUITE_P(Corners, CornerDryRun,
                         testing::Values(DryCase{"gecko_ankle", true, 0.236},
                                         DryCase{"gecko_ankle", false, 0.22},
                                         DryCase{"spider_ankle", true, 0.17}),
                         [](const testing::TestParamInfo<DryCase>& i) {
                           return std::string(i.param.robot) + (i.param.inner ? "_inner" : "_outer");
                         });

}  // namespace
}  // namespace climbsim::sim
