// A block with one sticky pad (its box geom) and a plane "surface" at z = 0, compiled from
// MJCF text, with an AdhesionSystem and an event recorder: the small MuJoCo worlds of the
// adhesion tests. Gravity, pose, velocity, mass and pad parameters are chosen per test.
#ifndef CLIMBSIM_TESTS_ADHESION_MUJOCO_RIG_H_
#define CLIMBSIM_TESTS_ADHESION_MUJOCO_RIG_H_

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "adhesion/adhesion.h"
#include "common/common.h"

namespace climbsim::adhesion::testing {

inline constexpr double kG = 9.81;  // m/s²: the rig's gravity, straight down by default

struct BlockSpec {
  Eigen::Vector3d gravity{0, 0, -kG};
  double mass_kg = 0.05;
  double half_x_m = 0.0125, half_y_m = 0.0125, half_z_m = 0.001;  // the pad box
  Eigen::Vector3d pos{0, 0, 0.001};                               // body (= box centre) position
  Eigen::Quaterniond quat = Eigen::Quaterniond::Identity();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  // linear, set after Reset
  StickyPadParams pad;
  bool start_attached = false;
  std::string pad_solref = "0.015 1";  // the robots' pads
  int noslip_iterations = 0;
  std::string extra_bodies;  // more <body> elements in the worldbody
};

class EventRecorder final : public PadEventSink {
 public:
  void OnPadEvent(int pad, const PadEvent& e) override {
    (void)pad;
    events.push_back(e);
  }
  std::vector<PadEvent> events;
  std::vector<std::string> Kinds() const {
    std::vector<std::string> k;
    for (const auto& e : events) k.push_back(PadEventName(e.kind));
    return k;
  }
  const PadEvent* First(PadEventKind kind) const {
    for (const auto& e : events) {
      if (e.kind == kind) return &e;
    }
    return nullptr;
  }
};

class BlockRig {
 public:
  explicit BlockRig(const BlockSpec& spec) : spec_(spec) {
    PadSpec pad{"block", spec.pad};
    std::ostringstream x;
    x.precision(17);
    const AdhesionMjcfText add = AdhesionMjcf({pad}, {0.002, 1.0});
    x << "<mujoco>\n  <option timestep=\"0.001\" gravity=\"" << spec.gravity.transpose()
      << "\" cone=\"elliptic\" impratio=\"10\" noslip_iterations=\"" << spec.noslip_iterations
      << "\"/>\n  <worldbody>\n    <geom name=\"surface\" type=\"plane\" size=\"1 1 0.1\"/>\n"
      << "    <body name=\"block\" pos=\"" << spec.pos.transpose() << "\" quat=\"" << spec.quat.w()
      << " " << spec.quat.x() << " " << spec.quat.y() << " " << spec.quat.z()
      << "\">\n      <freejoint/>\n      <geom name=\"block\" type=\"box\" size=\"" << spec.half_x_m
      << " " << spec.half_y_m << " " << spec.half_z_m << "\" mass=\"" << spec.mass_kg
      << "\" priority=\"1\" friction=\"1 0.005 0.0001\" solref=\"" << spec.pad_solref
      << "\"/>\n    </body>\n"
      << spec.extra_bodies << "  </worldbody>\n";
    if (!add.equality.empty()) x << "  <equality>\n" << add.equality << "  </equality>\n";
    if (!add.actuator.empty()) x << "  <actuator>\n" << add.actuator << "  </actuator>\n";
    x << "</mujoco>\n";
    xml_ = x.str();
    std::string error;
    m_ = common::CompileMjcfString(xml_, &error);
    if (m_ == nullptr) throw std::runtime_error(error + "\n" + xml_);
    d_ = mj_makeData(m_);
    AdhesionSystemParams sys;
    sys.pads = {pad};
    sys.surfaces = {"surface"};
    sys.start_attached = spec.start_attached;
    system_ = std::make_unique<AdhesionSystem>(m_, sys);
    Reset();
  }
  ~BlockRig() {
    mj_deleteData(d_);
    mj_deleteModel(m_);
  }

  void Reset() {
    mj_resetData(m_, d_);
    for (int i = 0; i < 3; ++i) d_->qvel[i] = spec_.velocity[i];
    events_.events.clear();
    system_->Reset(m_, d_, &events_);
  }
  void Step() {
    system_->BeforeStep(m_, d_, &events_);
    mj_step(m_, d_);
    system_->AfterStep(m_, d_, &events_);
  }
  void Run(double seconds) {
    const long n = std::lround(seconds / m_->opt.timestep);
    for (long i = 0; i < n; ++i) Step();
  }

  mjModel* m() { return m_; }
  mjData* d() { return d_; }
  StickyPad& pad() { return system_->pad(0); }
  AdhesionSystem& system() { return *system_; }
  EventRecorder& events() { return events_; }
  const std::string& xml() const { return xml_; }
  int block_body() const { return mj_name2id(m_, mjOBJ_BODY, "block"); }
  Eigen::Vector3d BlockPos() const {
    const int b = block_body();
    return {d_->xpos[3 * b], d_->xpos[3 * b + 1], d_->xpos[3 * b + 2]};
  }

 private:
  BlockSpec spec_;
  std::string xml_;
  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  std::unique_ptr<AdhesionSystem> system_;
  EventRecorder events_;
};

}  // namespace climbsim::adhesion::testing

#endif  // CLIMBSIM_TESTS_ADHESION_MUJOCO_RIG_H_
