// Partial contact (adhesion/pad_touch.h): a pad bonds only where its face touches the surface.
// The touched set against known geometry (a step, a tilt, a hollow, a stand-off), the bond
// grid's touching set, and pull-offs in the MuJoCo rig against closed forms: a pad over a
// step edge holds the touched share of σ_T·A, a pad over a hollow its rim's share, a flat pad
// exactly what it held without partial contact; a landing on too little of a step rejected by
// its touched share, and a foam-backed face judged by that share on a rock summit.
//
// Error budget of the rig's pull-offs: the ramp rises by σ_T·A·Δt/ramp_time_s per step
// (5·10⁻⁴ of σ_T·A) and the recorded force is the first step's that lets go; 2·10⁻³ of σ_T·A
// covers it and the weld's lag (pulloff_rig_test.cc). Where the step edge does not fall
// between two columns the grid's error is one column of cells (σ_T·A/N_x).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "adhesion/adhesion.h"
#include "common/common.h"

namespace climbsim::adhesion {
namespace {

constexpr double kPad = 0.025;      // pad side (m), as the rig's
constexpr int kGrid = 16;           // cells per side
constexpr double kSigmaT = 10e3;    // Pa
constexpr double kDrop = 0.005;     // depth of the lower level (m)
constexpr double kRampTol = 2e-3;   // of σ_T·A: the ramp step and the weld's lag

double CellCentre(int i) { return ((i + 0.5) / kGrid - 0.5) * kPad; }

// One box geom given by its x and y extents, top at z = 0.
std::string Box(double x0, double x1, double y0, double y1) {
  std::ostringstream s;
  s.precision(17);
  s << "      <geom type=\"box\" pos=\"" << 0.5 * (x0 + x1) << " " << 0.5 * (y0 + y1) << " "
    << -0.5 * kDrop << "\" size=\"" << 0.5 * (x1 - x0) << " " << 0.5 * (y1 - y0) << " "
    << 0.5 * kDrop << "\"/>\n";
  return s.str();
}
std::string LowerLevel() {
  std::ostringstream s;
  s << "      <geom type=\"plane\" pos=\"0 0 " << -kDrop << "\" size=\"1 1 0.1\"/>\n";
  return s.str();
}
// A step: the upper level (top z = 0) for x < edge, the lower one kDrop below elsewhere.
std::string Step(double edge_m) { return Box(-0.05, edge_m, -0.05, 0.05) + LowerLevel(); }
// A square hollow of side `side_m` centred at the origin in a level top at z = 0.
std::string Hollow(double side_m) {
  const double h = 0.5 * side_m;
  return Box(-0.05, -h, -0.05, 0.05) + Box(h, 0.05, -0.05, 0.05) + Box(-h, h, h, 0.05) +
         Box(-h, h, -0.05, -h) + LowerLevel();
}

// A compiled world of `surface` geoms (in a body "surface") and a pad box of kPad × kPad ×
// 2 mm whose face centre sits at `face_pos`, turned by `quat`; the probe of that pad.
class ProbeWorld {
 public:
  ProbeWorld(const std::string& surface, const Eigen::Vector3d& face_pos,
             const Eigen::Quaterniond& quat = Eigen::Quaterniond::Identity(),
             const std::string& others = "") {
    const Eigen::Vector3d centre = face_pos + quat * Eigen::Vector3d(0, 0, 0.001);
    std::ostringstream x;
    x.precision(17);
    x << "<mujoco>\n  <worldbody>\n    <body name=\"surface\">\n"
      << surface << "    </body>\n" << others << "    <body name=\"pad\" pos=\""
      << centre.transpose() << "\" quat=\"" << quat.w() << " " << quat.x() << " " << quat.y()
      << " " << quat.z() << "\">\n      <freejoint/>\n      <geom type=\"box\" size=\""
      << 0.5 * kPad << " " << 0.5 * kPad << " 0.001\"/>\n    </body>\n  </worldbody>\n</mujoco>\n";
    std::string error;
    m_ = common::CompileMjcfString(x.str(), &error);
    if (m_ == nullptr) throw std::runtime_error(error);
    d_ = mj_makeData(m_);
    mj_kinematics(m_, d_);  // the geoms' poses are all the probe reads
    const int surface_body = mj_name2id(m_, mjOBJ_BODY, "surface");
    sticks_to_.assign(m_->ngeom, 0);
    for (int g = 0; g < m_->ngeom; ++g) sticks_to_[g] = m_->geom_bodyid[g] == surface_body;
    geometry_ = ReadPadGeometry(m_, mj_name2id(m_, mjOBJ_BODY, "pad"));
    probe_ = std::make_unique<TouchProbe>(m_, geometry_, kGrid, kGrid);
  }
  ~ProbeWorld() {
    mj_deleteData(d_);
    mj_deleteModel(m_);
  }
  // The touching set; its count in *count.
  std::vector<uint8_t> Measure(double gap_m, double standoff_limit_m, int* count,
                               double pressed_m = 0.0) {
    std::vector<uint8_t> touching(kGrid * kGrid, 2);
    *count = probe_->Measure(m_, d_, sticks_to_, gap_m, standoff_limit_m, pressed_m, touching);
    return touching;
  }
  // The same, seated on the rest plane (pressed through the centre).
  std::vector<uint8_t> MeasureSeated(double gap_m, int* count) {
    std::vector<uint8_t> touching(kGrid * kGrid, 2);
    *count = probe_->MeasureSeated(m_, d_, sticks_to_, gap_m, 0.0, 0.0, touching);
    return touching;
  }
  const TouchProbe& probe() const { return *probe_; }

 private:
  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  std::vector<uint8_t> sticks_to_;
  PadGeometry geometry_;
  std::unique_ptr<TouchProbe> probe_;
};

// Over a step edge that cuts a column, exactly the cells whose centre lies on the upper level
// touch, with gap 0 there and kDrop beyond; a non-surface geom under the pad is not seen.
TEST(TouchProbe, StepEdgeTouchesExactlyTheCellsOnTheUpperLevel) {
  const double edge = 0.3 * kPad / kGrid;  // 0.3 of a cell right of the centre line
  const std::string not_surface =
      "    <body name=\"other\">\n      <geom type=\"box\" pos=\"0.01 0 -0.001\" "
      "size=\"0.003 0.003 0.001\"/>\n    </body>\n";
  ProbeWorld w(Step(edge), Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity(), not_surface);
  int count = 0;
  const std::vector<uint8_t> t = w.Measure(0.5e-3, 0.0, &count);
  int expected = 0;
  for (int iy = 0; iy < kGrid; ++iy) {
    for (int ix = 0; ix < kGrid; ++ix) {
      const int i = iy * kGrid + ix;
      const bool upper = CellCentre(ix) < edge;
      expected += upper;
      EXPECT_EQ(t[i], upper ? 1 : 0) << ix << ", " << iy;
      EXPECT_NEAR(w.probe().gap_m(i), upper ? 0.0 : kDrop, 1e-12) << ix << ", " << iy;
    }
  }
  EXPECT_EQ(count, expected);
  EXPECT_EQ(expected, kGrid * kGrid / 2);  // the cut column's centre lies beyond the edge
}

// A pad tilted by α about its y axis, its face centre at height z0 over a plane: cell i's ray
// along −n meets the plane at gap_i = (z0 + x_i·sin α)/cos α. With the stand-off limited to 0
// the cells with gap_i ≤ δ + contact_gap_m touch (δ: how far the soft contact let it sink),
// the rest not; pressed in deeper, more of the raised side counts.
TEST(TouchProbe, TiltedPadTouchesWhereItsGapIsWithinTheTolerance) {
  const double alpha = 3.0 * M_PI / 180.0;
  const Eigen::Quaterniond q(Eigen::AngleAxisd(-alpha, Eigen::Vector3d::UnitY()));  // +x up
  const double tol = 0.4e-3;
  const double lowest = -CellCentre(0) * std::sin(alpha);  // z0 with the lowest cell at gap 0
  int previous = 0;
  for (const auto& [z0, pressed] : {std::pair{lowest, 0.0}, std::pair{lowest - 0.3e-3, 0.3e-3}}) {
    ProbeWorld w(LowerLevel(), Eigen::Vector3d(0, 0, z0 - kDrop), q);
    int count = 0;
    const std::vector<uint8_t> t = w.Measure(tol, 0.0, &count, pressed);
    const double deepest = -(z0 + CellCentre(0) * std::sin(alpha)) / std::cos(alpha);
    const double sink = std::max(pressed, deepest);  // δ: the contacts' or the deepest cell's
    int expected = 0;
    for (int iy = 0; iy < kGrid; ++iy) {
      for (int ix = 0; ix < kGrid; ++ix) {
        const double gap = (z0 + CellCentre(ix) * std::sin(alpha)) / std::cos(alpha);
        const bool touches = gap <= sink + tol;
        ASSERT_GT(std::abs(gap - sink - tol), 1e-6) << "a cell on the boundary tests rounding";
        EXPECT_NEAR(w.probe().gap_m(iy * kGrid + ix), gap, 1e-12);
        EXPECT_EQ(t[iy * kGrid + ix], touches ? 1 : 0) << ix;
        expected += touches;
      }
    }
    EXPECT_EQ(count, expected);
    EXPECT_GT(count, previous);
    EXPECT_LT(count, kGrid * kGrid);
    previous = count;
  }
}

// A pad 0.5 mm above a plane (as the robots start): every cell touches with a stand-off of
// 1 mm (start_gap_m), none with none (a pad that attached by its contacts) and contact_gap_m
// below 0.5 mm; nothing touches over no surface at all.
TEST(TouchProbe, StandOffWidensTheGapThatTouches) {
  ProbeWorld w(LowerLevel(), Eigen::Vector3d(0, 0, 0.5e-3 - kDrop));
  int count = 0;
  w.Measure(0.3e-3, 1e-3, &count);
  EXPECT_EQ(count, kGrid * kGrid);
  w.Measure(0.3e-3, 0.0, &count);
  EXPECT_EQ(count, 0);
  w.Measure(0.6e-3, 0.0, &count);
  EXPECT_EQ(count, kGrid * kGrid);
  ProbeWorld far(LowerLevel(), Eigen::Vector3d(0, 0, 0.05));
  far.Measure(0.5e-3, 0.0, &count);
  EXPECT_EQ(count, 0);
}

// A pad that landed tilted by 10° on the corners of its −x edge, seated (pressed through its
// centre onto its rest plane): on a plane every cell touches, however far the tilt lifts the
// +x edge (4 mm); with a step edge two cells right of the centre it rests flat on the upper
// level: exactly the cells over it touch.
TEST(TouchProbe, SeatedPadTouchesWhatTheSurfaceOffersNotWhatTheTiltLeaves) {
  const double alpha = 10.0 * M_PI / 180.0;
  const Eigen::Quaterniond q(Eigen::AngleAxisd(-alpha, Eigen::Vector3d::UnitY()));  // +x up
  const double lift = 0.5 * kPad * std::sin(alpha);  // the face centre's height
  int count = 0;
  ProbeWorld plane(LowerLevel(), Eigen::Vector3d(0, 0, lift - kDrop), q);
  plane.Measure(0.5e-3, 0.0, &count);
  EXPECT_LT(count, kGrid * kGrid / 4) << "unseated, the lifted side does not touch";
  plane.MeasureSeated(0.5e-3, &count);
  EXPECT_EQ(count, kGrid * kGrid);

  const double edge = 2.0 * kPad / kGrid;
  ProbeWorld step(Step(edge), Eigen::Vector3d(0, 0, lift), q);
  const std::vector<uint8_t> t = step.MeasureSeated(0.5e-3, &count);
  EXPECT_EQ(count, kGrid * 10);  // the columns whose centre lies left of the edge
  for (int i = 0; i < kGrid * kGrid; ++i) EXPECT_EQ(t[i], i % kGrid < 10 ? 1 : 0) << i;
}

// A flat pad whose centre lies over the lower level, two cells beyond a step edge, pressed
// through its centre: it tips onto the edge and its far side, and rests bridging them. The rest
// plane runs from column 5 (the last on the upper level) to column 15 on the lower one, kDrop
// lower: slope kDrop / (10 pitches) = 0.32, so the neighbouring columns stand 0.5 mm off it and,
// with a 0.3 mm gap, only those two columns touch.
TEST(TouchProbe, SeatedPadOverTheLowerSideOfAStepBridgesEdgeAndFarSide) {
  ProbeWorld step(Step(-2.0 * kPad / kGrid), Eigen::Vector3d::Zero());
  int count = 0;
  const std::vector<uint8_t> t = step.MeasureSeated(0.3e-3, &count);
  EXPECT_EQ(count, 2 * kGrid);
  for (int i = 0; i < kGrid * kGrid; ++i) {
    EXPECT_EQ(t[i], i % kGrid == 5 || i % kGrid == 15 ? 1 : 0) << i;
  }
}

// RestPlane against closed forms on a 16×16 grid of pitch h: gaps g = k·|x| (a valley whose
// bottom falls between two columns) rest on those columns, a = k·h/2; gaps g = −k·x² (a
// ridge-free trough seen from above: the surface curving towards the pad at both ends) rest on
// the two end columns, a = −k·x_max²; a surface under only the +x half leaves the centre
// outside: false.
TEST(RestPlane, LowerHullFacetUnderTheCentre) {
  const double h = kPad / kGrid, k = 0.1;
  std::vector<double> x(kGrid * kGrid), y(x.size()), g(x.size());
  for (int i = 0; i < kGrid * kGrid; ++i) x[i] = CellCentre(i % kGrid), y[i] = CellCentre(i / kGrid);
  double p[3];
  for (size_t i = 0; i < g.size(); ++i) g[i] = k * std::abs(x[i]);
  ASSERT_TRUE(RestPlane(x, y, g, kGrid, kGrid, p));
  EXPECT_NEAR(p[0], 0.5 * k * h, 1e-15);
  EXPECT_NEAR(p[1], 0.0, 1e-12);
  EXPECT_NEAR(p[2], 0.0, 1e-12);
  for (size_t i = 0; i < g.size(); ++i) g[i] = -k * x[i] * x[i];
  ASSERT_TRUE(RestPlane(x, y, g, kGrid, kGrid, p));
  const double x_max = CellCentre(kGrid - 1);
  EXPECT_NEAR(p[0], -k * x_max * x_max, 1e-15);
  EXPECT_NEAR(p[1], 0.0, 1e-12);
  EXPECT_NEAR(p[2], 0.0, 1e-12);
  for (size_t i = 0; i < g.size(); ++i) g[i] = x[i] < 0 ? TouchProbe::kNoSurface : 0.0;
  EXPECT_FALSE(RestPlane(x, y, g, kGrid, kGrid, p));
}

// The rim's cells of a pad centred over a square hollow: those whose centre lies outside it.
int RimCells(double side_m) {
  int k = 0;
  for (int iy = 0; iy < kGrid; ++iy) {
    for (int ix = 0; ix < kGrid; ++ix) {
      k += std::abs(CellCentre(ix)) > 0.5 * side_m || std::abs(CellCentre(iy)) > 0.5 * side_m;
    }
  }
  return k;
}

TEST(TouchProbe, HollowLeavesOnlyTheRimTouching) {
  const double side = 0.015;
  ProbeWorld w(Hollow(side), Eigen::Vector3d::Zero());
  int count = 0;
  const std::vector<uint8_t> t = w.Measure(0.5e-3, 0.0, &count);
  EXPECT_EQ(count, RimCells(side));
  EXPECT_EQ(count, kGrid * kGrid - 10 * 10);  // 10 centres a side lie within ±7.5 mm
  for (int iy = 0; iy < kGrid; ++iy) {
    for (int ix = 0; ix < kGrid; ++ix) {
      const bool rim =
          std::abs(CellCentre(ix)) > 0.5 * side || std::abs(CellCentre(iy)) > 0.5 * side;
      EXPECT_EQ(t[iy * kGrid + ix], rim ? 1 : 0) << ix << ", " << iy;
    }
  }
}

// The grid bonds only touching cells (BondAll, BondFraction of |T|, Grow), keeps the mask
// across Release, and with every cell touching bonds exactly what a grid without a mask bonds.
TEST(PartialContactGrid, BondsOnlyTouchingCellsAndAllTouchingIsUnchanged) {
  const PadParams p{.width_m = 0.02, .length_m = 0.02, .grid_x = 8, .grid_y = 8};
  BondGrid grid(p);
  std::vector<uint8_t> left(64, 0);
  for (int i = 0; i < 64; ++i) left[i] = grid.ix_of(i) < 4;
  grid.SetTouching(left);
  EXPECT_EQ(grid.touching_count(), 32);
  grid.BondAll();
  EXPECT_EQ(grid.bonded_count(), 32);
  grid.BondFraction(0.5);
  EXPECT_EQ(grid.bonded_count(), 16);
  for (int i = 0; i < 64; ++i) EXPECT_TRUE(!grid.bonded(i) || left[i]) << i;
  EXPECT_EQ(grid.Grow(1.0), 16);
  EXPECT_EQ(grid.bonded_count(), 32);
  EXPECT_DOUBLE_EQ(grid.bonded_fraction(), 0.5) << "cells that do not touch count as not bonded";
  grid.Release();
  EXPECT_EQ(grid.touching_count(), 32);
  EXPECT_THROW(grid.SetTouching(std::vector<uint8_t>(63, 1)), std::invalid_argument);

  BondGrid plain(p), masked(p);
  masked.SetTouching(std::vector<uint8_t>(64, 1));
  for (double f : {0.0, 0.3, 0.55, 1.0}) {
    plain.BondFraction(f);
    masked.BondFraction(f);
    plain.Grow(f + 0.2);
    masked.Grow(f + 0.2);
    for (int i = 0; i < 64; ++i) ASSERT_EQ(plain.state(i), masked.state(i)) << f << " " << i;
  }
}

PulloffRigParams SurfaceRig(const std::string& surface, double pull_x_m, bool partial = true) {
  PulloffRigParams p;
  p.pad.width_m = p.pad.length_m = kPad;
  p.pad.grid_x = p.pad.grid_y = kGrid;
  p.surface_mjcf = surface;
  p.pull_point_m = {pull_x_m, 0.0};
  p.contact.partial_contact = partial;
  return p;
}

// A pad over a step edge, pulled straight off through the centroid of the cells that touch:
// they let go together at σ_T times their area. Edge between two columns: exactly half the
// full pad's pull-off; edge through a column: the touched face's share, (e + b/2)/b of σ_T·A,
// within one column of cells (the cells whose centre lies on the step).
TEST(PartialContactPulloff, PadOverAStepEdgeHoldsTheTouchedShare) {
  const double capacity = kSigmaT * kPad * kPad;
  PulloffRig full(AdhesionModel::kBonds, SurfaceRig("", 0.0));
  const PulloffRun f = full.Run(0.0);
  ASSERT_TRUE(f.detached);
  EXPECT_NEAR(f.force_n, capacity, kRampTol * capacity);

  PulloffRig half(AdhesionModel::kBonds, SurfaceRig(Step(0.0), -0.25 * kPad));
  const PulloffRun h = half.Run(0.0);
  ASSERT_TRUE(h.detached);
  EXPECT_NEAR(h.force_n / f.force_n, 0.5, kRampTol);
  EXPECT_STREQ(h.cause, PadCauseName(PadCause::kOverload)) << "uniform: all at once";

  for (double edge : {0.3 * kPad / kGrid, -2.6 * kPad / kGrid}) {
    const double touched = (edge + 0.5 * kPad) / kPad;  // share of the face on the step
    int columns = 0;
    double centroid = 0.0;
    for (int ix = 0; ix < kGrid && CellCentre(ix) < edge; ++ix, ++columns) {
      centroid += CellCentre(ix);
    }
    centroid /= columns;
    PulloffRig cut(AdhesionModel::kBonds, SurfaceRig(Step(edge), centroid));
    const PulloffRun c = cut.Run(0.0);
    ASSERT_TRUE(c.detached);
    EXPECT_NEAR(c.force_n, capacity * columns / kGrid, kRampTol * capacity) << edge;
    EXPECT_NEAR(c.force_n, touched * capacity, capacity / kGrid) << edge;
  }
}

// Pulled through the pad's own centre, the half pad on the step carries a moment about its
// bonded centroid (lever b/4): the column at the edge, b/4 − Δx/2 from that centroid, is the
// most tensioned and breaks first, at F₁ = σ_T·A_B / (1 + (b/4)(b/4 − Δx/2)·A_B/I_y) (I_y of
// the bonded cells' centres about their centroid): well below σ_T·A_B.
TEST(PartialContactPulloff, HalfPadPulledThroughThePadCentrePeelsFromTheEdge) {
  PulloffRig rig(AdhesionModel::kBonds, SurfaceRig(Step(0.0), 0.0));
  const PulloffRun r = rig.Run(0.0);
  ASSERT_TRUE(r.detached);
  ASSERT_FALSE(r.sequence.empty());
  const double da = kPad * kPad / (kGrid * kGrid);
  const double area = 0.5 * kPad * kPad;
  double i_y = 0.0;
  for (int ix = 0; ix < kGrid / 2; ++ix) {
    i_y += kGrid * da * std::pow(CellCentre(ix) + 0.25 * kPad, 2);
  }
  const double lever = 0.25 * kPad, edge_offset = 0.25 * kPad - 0.5 * kPad / kGrid;
  const double f1 = kSigmaT * area / (1.0 + lever * edge_offset * area / i_y);
  EXPECT_NEAR(r.sequence_force_n.front(), f1, kRampTol * kSigmaT * kPad * kPad);
  EXPECT_NEAR(r.sequence.front().x_m, CellCentre(kGrid / 2 - 1), 1e-12) << "the edge column";
  EXPECT_GE(r.force_n, r.sequence_force_n.front());
  EXPECT_LT(r.force_n, 0.75 * kSigmaT * area);
}

// A pad centred over a hollow touches only its rim: a pull straight off its centre (the rim is
// symmetric) lets go at k/N of σ_T·A, k the rim's cells.
TEST(PartialContactPulloff, PadOverAHollowHoldsTheRimsShare) {
  const double side = 0.015;
  PulloffRig rig(AdhesionModel::kBonds, SurfaceRig(Hollow(side), 0.0));
  const PulloffRun r = rig.Run(0.0);
  ASSERT_TRUE(r.detached);
  const double share = static_cast<double>(RimCells(side)) / (kGrid * kGrid);
  EXPECT_NEAR(r.force_n, share * kSigmaT * kPad * kPad, kRampTol * kSigmaT * kPad * kPad);
  EXPECT_LT(share, 0.65);
}

// On a flat surface partial contact changes nothing: the same pull-off and the same broken
// bonds in the same order, bit for bit, with and without it, straight off and at angles.
TEST(PartialContactPulloff, FlatPadIsBitForBitUnchanged) {
  PulloffRig on(AdhesionModel::kBonds, SurfaceRig("", 0.0, true));
  PulloffRig off(AdhesionModel::kBonds, SurfaceRig("", 0.0, false));
  for (double deg : {0.0, 45.0, 90.0, 150.0}) {
    const PulloffRun a = on.Run(deg * M_PI / 180.0);
    const PulloffRun b = off.Run(deg * M_PI / 180.0);
    EXPECT_EQ(a.force_n, b.force_n) << deg;
    EXPECT_EQ(a.steps, b.steps) << deg;
    ASSERT_EQ(a.sequence.size(), b.sequence.size()) << deg;
    for (size_t k = 0; k < a.sequence.size(); ++k) {
      EXPECT_EQ(a.sequence[k].x_m, b.sequence[k].x_m);
      EXPECT_EQ(a.sequence[k].y_m, b.sequence[k].y_m);
    }
  }
}

// Attach condition 5 on a landing: a pad on a vertical slide (it cannot tip) is let down onto a
// step edge under gravity. Over the upper level it touches (edge + b/2)/b of its face and bonds
// exactly those cells; with its centre over the lower level it bridges the edge and the far
// side (a seated pad, "SeatedPadOverTheLowerSideOfAStepBridgesEdgeAndFarSide"), touches less
// than min_contact_share and is rejected with cause contact_share, once, at the end of the
// attach window; without the condition it attaches with that share bonded. Conditions 1-4
// hold in each: 0.1 m/s, square, 4 contacts, its own weight.
struct Landing {
  std::vector<PadEvent> events;
  double bonded_fraction = 0.0;
  bool attached = false;
};
Landing LandOn(const std::string& surface, double min_contact_share, double conform_m) {
  struct Sink : PadEventSink {
    void OnPadEvent(int, const PadEvent& e) override { events.push_back(e); }
    std::vector<PadEvent> events;
  } sink;
  PadSpec spec;
  spec.body = "pad";
  spec.params.bonds.grid_x = spec.params.bonds.grid_y = kGrid;
  spec.params.attach.initial_fraction = 1.0;
  spec.params.contact.min_contact_share = min_contact_share;
  spec.params.contact.contact_gap_m += conform_m;  // as the simulator sets up a foam
  spec.params.conform_m = conform_m;
  const AdhesionMjcfText weld = AdhesionMjcf({spec}, kDefaultWeldSolref);
  std::ostringstream x;
  x << "<mujoco>\n  <option timestep=\"0.001\"/>\n  <worldbody>\n    <body name=\"surface\">\n"
    << surface << "    </body>\n    <body name=\"pad\" pos=\"0 0 0.0015\">\n"
    << "      <joint name=\"drop\" type=\"slide\" axis=\"0 0 1\"/>\n"
    << "      <geom type=\"box\" size=\"" << 0.5 * kPad << " " << 0.5 * kPad
    << " 0.001\" mass=\"0.005\"/>\n    </body>\n  </worldbody>\n  <equality>\n"
    << weld.equality << "  </equality>\n  <actuator>\n" << weld.actuator
    << "  </actuator>\n</mujoco>\n";
  std::string error;
  mjModel* m = common::CompileMjcfString(x.str(), &error);
  if (m == nullptr) throw std::runtime_error(error);
  mjData* d = mj_makeData(m);
  AdhesionSystemParams params;
  params.pads = {spec};
  params.surfaces = {"surface"};
  AdhesionSystem system(m, params);
  system.Reset(m, d, &sink);
  for (int k = 0; k < 300; ++k) {  // 0.3 s: the fall (~20 ms) and the attach window (0.1 s)
    system.BeforeStep(m, d, &sink);
    mj_step(m, d);
    system.AfterStep(m, d, &sink);
  }
  Landing l{sink.events, system.pad(0).bonded_fraction(), system.pad(0).attached()};
  mj_deleteData(d);
  mj_deleteModel(m);
  return l;
}

Landing LandOnStep(double edge_m, double min_contact_share = 0.5) {
  return LandOn(Step(edge_m), min_contact_share, 0.0);
}

TEST(PartialContactLanding, PadLandingOnTooLittleOfAStepIsRejectedByItsContactShare) {
  const double cell = kPad / kGrid;
  const Landing over = LandOnStep(4 * cell);  // 12 of 16 columns on the upper level
  ASSERT_TRUE(over.attached);
  ASSERT_EQ(over.events.size(), 2u);
  EXPECT_EQ(over.events[0].kind, PadEventKind::kTouchdown);
  EXPECT_EQ(over.events[1].kind, PadEventKind::kAttach);
  EXPECT_NEAR(over.bonded_fraction, 12.0 / kGrid, 1e-12);

  const Landing off = LandOnStep(-4 * cell);  // the centre over the lower level
  EXPECT_FALSE(off.attached);
  ASSERT_EQ(off.events.size(), 2u);
  EXPECT_EQ(off.events[0].kind, PadEventKind::kTouchdown);
  EXPECT_EQ(off.events[1].kind, PadEventKind::kAttachRejected);
  EXPECT_EQ(off.events[1].cause, PadCause::kContactShare);
  EXPECT_LT(off.events[1].cause_value, 0.5);
  EXPECT_NEAR(off.events[1].time_s - off.events[0].time_s, 0.1, 0.0015) << "the window";

  // Without condition 5 the same landing attaches, bonding only the share it touches.
  const Landing any = LandOnStep(-4 * cell, 0.0);
  ASSERT_TRUE(any.attached);
  EXPECT_NEAR(any.bonded_fraction, off.events[1].cause_value, 1e-12);
}

// Rock under a foam-backed pad: one summit (an ellipsoid of 1 mm radius under the pad's centre,
// its top at z = 0) over a plane `floor_m` below it. The rigid box rests on the summit with fewer
// than 3 contacts: condition 3 rejects it (cause contacts) at the end of the attach window,
// however close the plane. A face that conforms 1 mm further (conform_m, contact_gap_m 0.5 →
// 1.5 mm) is judged by its touched share instead when the window ends without the contacts:
// over a plane 1 mm down every cell reaches the surface, and the pad attaches then with all of
// them bonded, on the same contacts.
std::string Summit(double floor_m) {
  std::ostringstream s;
  s << "      <geom type=\"ellipsoid\" size=\"0.001 0.001 0.001\" pos=\"0 0 -0.001\"/>\n"
    << "      <geom type=\"plane\" pos=\"0 0 " << -floor_m << "\" size=\"1 1 0.1\"/>\n";
  return s.str();
}

TEST(PartialContactLanding, AConformingFaceIsSeatedByItsTouchedShareNotItsContactCount) {
  const Landing rigid = LandOn(Summit(0.001), 0.5, 0.0);
  EXPECT_FALSE(rigid.attached);
  ASSERT_EQ(rigid.events.size(), 2u);
  EXPECT_EQ(rigid.events[1].kind, PadEventKind::kAttachRejected);
  EXPECT_EQ(rigid.events[1].cause, PadCause::kContacts);
  EXPECT_GE(rigid.events[1].cause_value, 1.0);
  EXPECT_LT(rigid.events[1].cause_value, 3.0);
  EXPECT_NEAR(rigid.events[1].time_s - rigid.events[0].time_s, 0.1, 0.0015) << "the window";

  const Landing foam = LandOn(Summit(0.001), 0.5, 0.001);
  ASSERT_TRUE(foam.attached);
  ASSERT_EQ(foam.events.size(), 2u);
  EXPECT_EQ(foam.events[0].kind, PadEventKind::kTouchdown);
  EXPECT_EQ(foam.events[1].kind, PadEventKind::kAttach);
  EXPECT_NEAR(foam.events[1].time_s - foam.events[0].time_s, 0.1, 0.0015) << "the window";
  EXPECT_EQ(foam.bonded_fraction, 1.0) << "every cell within 1.5 mm of the surface";
}

}  // namespace
}  // namespace climbsim::adhesion
