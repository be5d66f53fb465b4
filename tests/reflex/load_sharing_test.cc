// LoadSharing (reflex.h): internal forces among attached pads that drive down the soft maximum
// of their utilisations. Checked against what defines it: every request is internal (Σλ = 0,
// Σr×λ = 0 over the attached pads), the first-order change of the soft maximum is exactly
// −dt·K·[S − U_S]₊, the leak, the cap and the rate limit, and the closed form of two pads.
// Tolerances: the projection solves G·Gᵀ with a ridge of 10⁻¹² of its trace, so identities hold
// to 10⁻⁸ of the quantities' size or better (forces of 0.01–1 N here; the condition of G·Gᵀ
// amplifies the ridge).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <stdexcept>

#include "reflex/reflex.h"

namespace climbsim::reflex {
namespace {

constexpr double kSharingDt = 0.001;

LoadSharingParams SharingParams() {
  LoadSharingParams p;
  p.gain_per_s = 20.0;
  p.threshold = 0.5;
  p.leak_s = 0.5;
  p.softmax_beta = 20.0;
  p.max_force_n = 1.0;
  p.max_rate_n_per_s = 1e6;  // out of the way unless a test sets it
  return p;
}

double SoftMax(const std::vector<SharingLeg>& legs, double beta) {
  double m = -1e300, sum = 0.0;
  for (const auto& l : legs) {
    if (l.active) m = std::max(m, l.utilisation);
  }
  for (const auto& l : legs) {
    if (l.active) sum += std::exp(beta * (l.utilisation - m));
  }
  return m + std::log(sum) / beta;
}

// Σλ and Σ r×λ over the active legs (about the origin: internal forces have zero net wrench
// about every point).
void ExpectInternal(const std::vector<SharingLeg>& legs,
                    const std::array<Eigen::Vector3d, kMaxSharingLegs>& lambda, double tol) {
  Eigen::Vector3d f = Eigen::Vector3d::Zero(), m = Eigen::Vector3d::Zero();
  double size = 1.0;  // relative to the largest request (tol is a relative tolerance)
  for (size_t i = 0; i < legs.size(); ++i) size = std::max(size, lambda[i].norm());
  tol *= size;
  for (size_t i = 0; i < legs.size(); ++i) {
    if (!legs[i].active) {
      EXPECT_EQ(lambda[i], Eigen::Vector3d::Zero()) << i;
      continue;
    }
    f += lambda[i];
    m += legs[i].position_m.cross(lambda[i]);
  }
  EXPECT_LT(f.norm(), tol);
  EXPECT_LT(m.norm(), tol);
}

std::vector<SharingLeg> RandomLegs(std::mt19937* rng, int n) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<SharingLeg> legs(n);
  for (auto& l : legs) {
    l.active = true;
    l.position_m = Eigen::Vector3d(0.1 * unit(*rng), 0.1 * unit(*rng), 0.0);  // a wall: z = 0
    l.utilisation = 0.6 + 0.3 * unit(*rng);
    l.gradient_per_n = Eigen::Vector3d(unit(*rng), unit(*rng), unit(*rng));
  }
  return legs;
}

// Two pads: the only internal force is a pull or push along the line between them. Pad A is
// near its limit with ∇U along +x (the line), B has margin: A's force along +x drops by what
// B's rises, and S falls at exactly K·[S − U_S] to first order.
TEST(ReflexLoadSharing, TwoPadsTradeLoadAlongTheLineBetweenThem) {
  LoadSharing sharing(SharingParams(), kSharingDt);
  std::vector<SharingLeg> legs(2);
  legs[0] = {true, {0.05, 0.02, 0.0}, 0.9, {1.0, 0.5, 0.2}};
  legs[1] = {true, {-0.05, 0.02, 0.0}, 0.2, {1.0, -0.3, 0.4}};
  const auto& lambda = sharing.Update(legs.data(), 2);
  EXPECT_LT(lambda[0].x(), 0.0);
  EXPECT_NEAR(lambda[0].y(), 0.0, 1e-10 * lambda[0].norm());
  EXPECT_NEAR(lambda[0].z(), 0.0, 1e-10 * lambda[0].norm());
  EXPECT_LT((lambda[1] + lambda[0]).norm(), 1e-10 * lambda[0].norm());
  // First order: Σ w_i ∇U_i · λ_i = −dt·K·(S − U_S).
  const double s = SoftMax(legs, 20.0);
  EXPECT_DOUBLE_EQ(sharing.soft_max(), s);
  const double w0 = 1.0 / (1.0 + std::exp(20.0 * (0.2 - 0.9)));
  const double dS = w0 * legs[0].gradient_per_n.dot(lambda[0]) +
                    (1 - w0) * legs[1].gradient_per_n.dot(lambda[1]);
  EXPECT_NEAR(dS, -kSharingDt * 20.0 * (s - 0.5), 1e-10 * std::abs(dS));
}

TEST(ReflexLoadSharing, RequestsStayInternalAndLowerTheSoftMaximumAtTheSetRate) {
  std::mt19937 rng(2026);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 2 + trial % 5;
    std::vector<SharingLeg> legs = RandomLegs(&rng, n);
    if (trial % 4 == 3) legs[0].active = false;
    LoadSharingParams p = SharingParams();
    p.max_force_n = 1e9;  // the cap (tested below) would scale the step
    LoadSharing sharing(p, kSharingDt);
    std::array<Eigen::Vector3d, kMaxSharingLegs> before;
    for (Eigen::Vector3d& b : before) b.setZero();
    for (int k = 0; k < 5; ++k) {
      const auto& lambda = sharing.Update(legs.data(), n);
      ExpectInternal(legs, lambda, 1e-8);
      // The change over this period: the leak of what was there, plus the step.
      double dS = 0.0;
      const double s = sharing.soft_max();
      double sum = 0.0, m = -1e300;
      for (const auto& l : legs) {
        if (l.active) m = std::max(m, l.utilisation);
      }
      for (const auto& l : legs) {
        if (l.active) sum += std::exp(20.0 * (l.utilisation - m));
      }
      for (int i = 0; i < n; ++i) {
        if (!legs[i].active) continue;
        const double w = std::exp(20.0 * (legs[i].utilisation - m)) / sum;
        dS += w * legs[i].gradient_per_n.dot(lambda[i] - (1 - kSharingDt / 0.5) * before[i]);
      }
      const int active = n - (trial % 4 == 3 ? 1 : 0);
      if (active >= 2) {
        EXPECT_NEAR(dS, -kSharingDt * 20.0 * std::max(0.0, s - 0.5),
                    1e-8 * std::max(1.0, std::abs(dS)))
            << trial << " " << k;
      }
      before = lambda;
    }
  }
}

// Below the threshold only the leak acts: λ shrinks by 1 − dt/τ a period.
TEST(ReflexLoadSharing, BelowTheThresholdTheRequestLeaks) {
  LoadSharing sharing(SharingParams(), kSharingDt);
  std::vector<SharingLeg> legs(3);
  legs[0] = {true, {0.05, 0.05, 0.0}, 0.95, {1.0, 0.0, 0.3}};
  legs[1] = {true, {0.05, -0.05, 0.0}, 0.3, {1.0, 0.0, 0.3}};
  legs[2] = {true, {-0.05, 0.0, 0.0}, 0.3, {1.0, 0.0, -0.3}};
  for (int k = 0; k < 10; ++k) sharing.Update(legs.data(), 3);
  const auto before = sharing.Update(legs.data(), 3);
  ASSERT_GT(before[0].norm(), 0.0);
  for (auto& l : legs) l.utilisation = 0.1;
  const auto& after = sharing.Update(legs.data(), 3);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT((after[i] - (1 - kSharingDt / 0.5) * before[i]).norm(), 1e-10 * before[i].norm())
        << i;
  }
}

// The cap scales every request alike (so they stay internal); the rate limit bounds a step.
TEST(ReflexLoadSharing, CapAndRateLimit) {
  std::mt19937 rng(5);
  std::vector<SharingLeg> legs = RandomLegs(&rng, 4);
  for (auto& l : legs) l.utilisation = 3.0;  // far above: large steps
  LoadSharingParams p = SharingParams();
  p.gain_per_s = 1e4;
  p.max_force_n = 0.2;
  LoadSharing capped(p, kSharingDt);
  for (int k = 0; k < 50; ++k) {
    const auto& lambda = capped.Update(legs.data(), 4);
    double largest = 0.0;
    for (int i = 0; i < 4; ++i) largest = std::max(largest, lambda[i].norm());
    EXPECT_LE(largest, 0.2 + 1e-15);
    ExpectInternal(legs, lambda, 1e-8);
  }
  p.max_force_n = 100.0;
  p.max_rate_n_per_s = 2.0;  // 2 mN a period at 1 ms
  LoadSharing limited(p, kSharingDt);
  const auto first = limited.Update(legs.data(), 4);
  double largest = 0.0;
  for (int i = 0; i < 4; ++i) largest = std::max(largest, first[i].norm());
  EXPECT_NEAR(largest, 0.002, 1e-15);
}

// Fewer than two attached pads: no internal force exists. A pad that lets go takes its share
// of λ with it: what remains is internal on the pads still attached.
TEST(ReflexLoadSharing, NoInternalForceWithOnePadAndReprojectionWhenAPadLetsGo) {
  std::mt19937 rng(9);
  std::vector<SharingLeg> legs = RandomLegs(&rng, 4);
  LoadSharing sharing(SharingParams(), kSharingDt);
  for (int k = 0; k < 20; ++k) sharing.Update(legs.data(), 4);
  legs[1].active = false;
  ExpectInternal(legs, sharing.Update(legs.data(), 4), 1e-8);
  legs[0].active = legs[2].active = false;
  const auto& one = sharing.Update(legs.data(), 4);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(one[i], Eigen::Vector3d::Zero()) << i;
  EXPECT_EQ(sharing.soft_max(), 0.0);
}

TEST(ReflexLoadSharing, OffAtZeroGainAndRejectsBadParams) {
  LoadSharingParams p = SharingParams();
  p.gain_per_s = 0.0;
  LoadSharing off(p, kSharingDt);
  std::mt19937 rng(1);
  std::vector<SharingLeg> legs = RandomLegs(&rng, 4);
  for (int k = 0; k < 5; ++k) {
    const auto& lambda = off.Update(legs.data(), 4);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(lambda[i], Eigen::Vector3d::Zero());
  }
  p = SharingParams();
  p.leak_s = 0.0;
  EXPECT_THROW(LoadSharing(p, kSharingDt), std::invalid_argument);
  p = SharingParams();
  p.softmax_beta = -1.0;
  try {
    Validate(p, kSharingDt, "reflex.gto.share");
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "reflex.gto.share.softmax_beta must be > 0, got -1");
  }
}


// Force tracking: λ moves by K·dt·P·e each period. With K·dt = 1 an internal error is met in
// one period exactly (two pads on the x axis: equal and opposite x forces), a non-internal
// one (the same force on both) not at all, and the result is internal.
TEST(ReflexLoadSharing, ForceTrackingMeetsTheInternalPartOfTheErrorAtItsRate) {
  LoadSharingParams p = SharingParams();
  p.mode = SharingMode::kForceTracking;
  p.gain_per_s = 1.0 / kSharingDt;
  p.leak_s = 1e9;  // no leak
  std::vector<SharingLeg> legs(2);
  legs[0].position_m = Eigen::Vector3d(0.05, 0.0, 0.0);
  legs[1].position_m = Eigen::Vector3d(-0.05, 0.0, 0.0);
  for (auto& l : legs) l.active = true;
  legs[0].force_error_n = Eigen::Vector3d(0.3, 0.2, 0.0);   // internal part: (+0.3, 0, 0),
  legs[1].force_error_n = Eigen::Vector3d(-0.3, 0.2, 0.0);  // the y parts move the body
  LoadSharing sharing(p, kSharingDt);
  const auto& lambda = sharing.Update(legs.data(), 2);
  EXPECT_NEAR(lambda[0].x(), 0.3, 1e-9);
  EXPECT_NEAR(lambda[1].x(), -0.3, 1e-9);
  EXPECT_NEAR(lambda[0].y(), 0.0, 1e-9);
  EXPECT_NEAR(lambda[1].y(), 0.0, 1e-9);
  ExpectInternal(legs, lambda, 1e-8);

  // At half the rate, half the way; errors that are met (zero) leave λ where it is.
  p.gain_per_s = 0.5 / kSharingDt;
  LoadSharing half(p, kSharingDt);
  EXPECT_NEAR(half.Update(legs.data(), 2)[0].x(), 0.15, 1e-9);
  for (auto& l : legs) l.force_error_n.setZero();
  EXPECT_NEAR(half.Update(legs.data(), 2)[0].x(), 0.15, 1e-9);
}

// Force tracking does not project λ again when a pad lets go: the forces it set are in
// balance already, and a re-projection would move the other pads' requests (the utilisation
// mode does re-project, and there the third pad's request changes).
TEST(ReflexLoadSharing, ForceTrackingKeepsTheOthersRequestsWhenAPadLetsGo) {
  for (SharingMode mode : {SharingMode::kForceTracking, SharingMode::kUtilisation}) {
    LoadSharingParams p = SharingParams();
    p.mode = mode;
    p.gain_per_s = mode == SharingMode::kForceTracking ? 1.0 / kSharingDt : 200.0;
    p.threshold = 0.0;
    p.leak_s = 1e9;
    std::vector<SharingLeg> legs(3);
    legs[0].position_m = Eigen::Vector3d(0.05, 0.03, 0.0);
    legs[1].position_m = Eigen::Vector3d(-0.05, 0.03, 0.0);
    legs[2].position_m = Eigen::Vector3d(0.0, -0.04, 0.0);
    const Eigen::Vector3d e[3] = {{0.2, 0.1, 0.0}, {-0.1, 0.05, 0.0}, {-0.1, -0.15, 0.0}};
    for (int i = 0; i < 3; ++i) {
      legs[i].active = true;
      legs[i].force_error_n = e[i];
      legs[i].utilisation = 0.5 + 0.1 * i;
      legs[i].gradient_per_n = e[i];
    }
    LoadSharing sharing(p, kSharingDt);
    const std::array<Eigen::Vector3d, kMaxSharingLegs> before = sharing.Update(legs.data(), 3);
    ASSERT_GT(before[2].norm(), 1e-3);
    legs[0].active = false;  // lets go
    for (auto& l : legs) l.force_error_n.setZero();
    for (auto& l : legs) l.gradient_per_n.setZero();  // no new descent step
    const auto& after = sharing.Update(legs.data(), 3);
    EXPECT_EQ(after[0], Eigen::Vector3d::Zero());
    if (mode == SharingMode::kForceTracking) {  // unchanged but for the leak (10⁻¹²)
      EXPECT_LT((after[1] - before[1]).norm(), 1e-12);
      EXPECT_LT((after[2] - before[2]).norm(), 1e-12);
    } else {
      EXPECT_GT((after[2] - before[2]).norm(), 1e-4);  // projected onto the two pads left
      ExpectInternal(legs, after, 1e-8);
    }
  }
}

// GripShearTargets, common direction (a wall): each sharing pad's target is its need plus an
// equal share of what all the tracked pads carry beyond their needs; a pad being let go keeps
// its keep and gives the rest away; the targets' sum over the sharing pads plus what the pad
// being let go keeps is the total carried (nothing lost or made).
TEST(ReflexGripShearTargets, CommonDirectionSharesTheScalarSurplusEqually) {
  std::array<GripShare, 4> pads{};
  const double shear[4] = {1.2, 0.3, 0.9, 0.5}, keep[4] = {0.4, 0.1, 0.2, 0.25};
  for (int i = 0; i < 4; ++i) {
    pads[i] = {true, i != 3, Eigen::Vector3d(-1, 0, 0), shear[i], keep[i]};
  }
  std::array<double, 4> target{-7, -7, -7, -7};
  ASSERT_EQ(GripShearTargets(pads.data(), 4, /*common_direction=*/true, target.data()), 3);
  const double rest = (1.2 + 0.3 + 0.9 + 0.5) - (0.4 + 0.1 + 0.2) - 0.25;  // 1.95
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(target[i], keep[i] + rest / 3, 1e-15) << i;
  EXPECT_EQ(target[3], -7);  // being let go: untouched
  EXPECT_NEAR(target[0] + target[1] + target[2] + keep[3], 1.2 + 0.3 + 0.9 + 0.5, 1e-14);
}

// Different directions (pads opposed in pairs under a ceiling): two pads squeezing each other
// carry no net force, so each is driven to its own keep, whatever the squeeze; the scalar sum
// would call the squeeze load and leave them on target. A net force F is shared as g_i·F/n.
TEST(ReflexGripShearTargets, OpposedPadsShareOnlyTheNetForce) {
  const Eigen::Vector3d gx(1, 0, 0);
  for (double squeeze : {0.5, 2.0, 6.0}) {
    std::array<GripShare, 2> pads{};
    pads[0] = {true, true, gx, squeeze, 0.3};
    pads[1] = {true, true, -gx, squeeze, 0.7};
    std::array<double, 2> target{};
    ASSERT_EQ(GripShearTargets(pads.data(), 2, false, target.data()), 2);
    // Written out: Σ(F_t,j − k_j)·g_j = (squeeze − 0.3)·x − (squeeze − 0.7)·x = 0.4·x.
    EXPECT_NEAR(target[0], 0.3 + 0.4 / 2, 1e-12) << squeeze;
    EXPECT_NEAR(target[1], 0.7 - 0.4 / 2, 1e-12) << squeeze;
    // The scalar sum: the squeeze counts as load.
    ASSERT_EQ(GripShearTargets(pads.data(), 2, true, target.data()), 2);
    EXPECT_NEAR(target[0], 0.3 + (2 * squeeze - 1.0) / 2, 1e-12);
  }
  // Three pads at 120 degrees with a net force along one of them.
  std::array<GripShare, 3> pads{};
  const Eigen::Vector3d g[3] = {{1, 0, 0}, {-0.5, std::sqrt(0.75), 0}, {-0.5, -std::sqrt(0.75), 0}};
  for (int i = 0; i < 3; ++i) pads[i] = {true, true, g[i], 1.0 + (i == 0 ? 0.9 : 0.0), 0.1};
  std::array<double, 3> target{};
  ASSERT_EQ(GripShearTargets(pads.data(), 3, false, target.data()), 3);
  // Σ(F_t − k)·g = 0.9·g_0 + 0.9·(g_0 + g_1 + g_2) = 0.9·g_0: pad 0 takes 0.3, the others
  // −0.15 each, about their keep.
  EXPECT_NEAR(target[0], 0.1 + 0.9 / 3, 1e-12);
  EXPECT_NEAR(target[1], 0.1 - 0.45 / 3, 1e-12);
  EXPECT_NEAR(target[2], 0.1 - 0.45 / 3, 1e-12);
}

// Inactive pads count for nothing; with no sharing pad nothing is written.
TEST(ReflexGripShearTargets, InactivePadsAndNoSharingPad) {
  std::array<GripShare, 3> pads{};
  pads[0] = {false, true, Eigen::Vector3d(-1, 0, 0), 5.0, 0.0};
  pads[1] = {true, false, Eigen::Vector3d(-1, 0, 0), 1.0, 0.2};
  pads[2] = {true, false, Eigen::Vector3d(-1, 0, 0), 1.0, 0.2};
  std::array<double, 3> target{-1, -1, -1};
  EXPECT_EQ(GripShearTargets(pads.data(), 3, true, target.data()), 0);
  EXPECT_EQ(target, (std::array<double, 3>{-1, -1, -1}));
  pads[2].shares = true;
  ASSERT_EQ(GripShearTargets(pads.data(), 3, true, target.data()), 1);
  EXPECT_NEAR(target[2], 0.2 + (1.0 + 1.0 - 0.2 - 0.2), 1e-15);  // pad 0's 5 N not counted
  EXPECT_EQ(target[0], -1);
}

}  // namespace
}  // namespace climbsim::reflex
