#include "adhesion/pulloff_rig.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "adhesion/weld.h"
#include "common/common.h"

namespace climbsim::adhesion {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr const char* kBlockName = "pulloff_block";
constexpr const char* kSurfaceName = "pulloff_surface";
constexpr double kPadThicknessM = 0.002;

void Require(bool ok, const std::string& message) {
  if (!ok) throw std::invalid_argument(message);
}

// The plane z = 0, or the given geoms in one static body.
std::string SurfaceXml(const std::string& geoms) {
  if (geoms.empty()) {
    return std::string("    <geom name=\"") + kSurfaceName + "\" type=\"plane\" size=\"1 1 0.1\"/>\n";
  }
  return std::string("    <body name=\"") + kSurfaceName + "\">\n" + geoms + "\n    </body>\n";
}

std::string BlockXml(AdhesionModel model, const PulloffRigParams& p, double gain_n) {
  std::ostringstream x;
  x.precision(17);
  const double half_t = 0.5 * kPadThicknessM;
  x << "<mujoco model=\"pulloff\">\n"
    << "  <option timestep=\"" << p.timestep_s << "\" gravity=\"0 0 0\" cone=\"elliptic\""
    << " impratio=\"10\" noslip_iterations=\""
    << (model == AdhesionModel::kMujoco ? p.noslip_iterations : 0) << "\"/>\n"
    << "  <worldbody>\n"
    << SurfaceXml(p.surface_mjcf)
    << "    <body name=\"" << kBlockName << "\" pos=\"0 0 " << half_t << "\">\n"
    << "      <freejoint/>\n"
    << "      <geom name=\"" << kBlockName << "\" type=\"box\" size=\"" << 0.5 * p.pad.width_m
    << " " << 0.5 * p.pad.length_m << " " << half_t << "\" mass=\"" << p.block_mass_kg
    << "\" priority=\"1\" friction=\"" << p.friction << " 0.005 0.0001\" solref=\""
    << p.contact_solref[0] << " " << p.contact_solref[1] << "\"/>\n"
    << "    </body>\n"
    << "  </worldbody>\n";
  PadSpec spec;
  spec.body = kBlockName;
  spec.params.model = model;
  spec.params.actuator_gain_n = gain_n;
  const AdhesionMjcfText add = AdhesionMjcf({spec}, p.weld_solref);
  if (!add.equality.empty()) x << "  <equality>\n" << add.equality << "  </equality>\n";
  if (!add.actuator.empty()) x << "  <actuator>\n" << add.actuator << "  </actuator>\n";
  x << "</mujoco>\n";
  return x.str();
}

// The pad-face corners of the block in the world.
std::array<Eigen::Vector3d, 4> Corners(const mjData* d, const PadGeometry& g) {
  const PadFrame f = FaceFrame(d, g);
  std::array<Eigen::Vector3d, 4> c;
  int k = 0;
  for (double sx : {-0.5, 0.5}) {
    for (double sy : {-0.5, 0.5}) {
      c[k++] = f.pos + f.rot * Eigen::Vector3d(sx * g.width_m, sy * g.length_m, 0.0);
    }
  }
  return c;
}

// kBonds: the bonds this step broke, in the run's sequence (rounds counted over the run).
void RecordBondsLost(const StickyPad& pad, double force, int* total_rounds, PulloffRun* run) {
  const auto broken = pad.grid().last_broken();
  if (broken.empty() || !pad.bonds_lost_this_step()) return;
  ++run->steps_losing_bonds;
  int rounds = 0;
  for (const BrokenBond& b : broken) {
    run->sequence.push_back(
        {pad.grid().bond_x_m(b.index), pad.grid().bond_y_m(b.index), *total_rounds + b.round});
    run->sequence_force_n.push_back(force);
    rounds = std::max(rounds, b.round);
  }
  *total_rounds += rounds;
}

// kMujoco: the pad has let go once a corner moved slip_m from where it started; how it
// moved names the cause ("tip", "lift", "slide"). nullptr while it holds.
const char* SlipCause(const std::array<Eigen::Vector3d, 4>& corners0,
                      const std::array<Eigen::Vector3d, 4>& c, double slip_m) {
  double worst = 0.0, normal = 0.0, spread = 0.0;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d move = c[i] - corners0[i];
    worst = std::max(worst, move.norm());
    normal += move.z() / 4.0;
  }
  for (int i = 0; i < 4; ++i)
    spread = std::max(spread, std::abs((c[i] - corners0[i]).z() - normal));
  if (!(worst >= slip_m)) return nullptr;
  return spread > 0.25 * worst ? "tip" : normal > 0.5 * worst ? "lift" : "slide";
}

}  // namespace

// Records the detach cause and the broken bonds.
class PulloffRig::Sink final : public PadEventSink {
 public:
  explicit Sink(PadEventSink* observer = nullptr) : observer_(observer) {}
  void OnPadEvent(int pad, const PadEvent& e) override {
    if (e.kind == PadEventKind::kDetach) cause = e.cause;
    if (observer_ != nullptr) observer_->OnPadEvent(pad, e);
  }
  PadCause cause = PadCause::kNone;

 private:
  PadEventSink* observer_;
};

void ValidatePulloffRigParams(const PulloffRigParams& p) {
  ValidatePadParams(p.pad);
  auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  Require(std::isfinite(p.arm_m) && p.arm_m >= 0, "arm_m must be >= 0");
  Require(std::isfinite(p.pull_point_m[0]) && std::isfinite(p.pull_point_m[1]),
          "pull_point_m must be finite");
  Require(p.contact.contact_gap_m >= 0 && p.contact.contact_gap_m <= 0.01,
          "contact_gap_m must be in [0, 0.01]");
  Require(std::isfinite(p.azimuth_rad), "azimuth must be finite");
  Require(positive(p.ramp_time_s), "ramp_time_s must be > 0");
  Require(positive(p.timestep_s) && p.timestep_s <= 0.01, "timestep_s must be in (0, 0.01]");
  Require(positive(p.block_mass_kg), "block_mass_kg must be > 0");
  Require(std::isfinite(p.max_force_factor) && p.max_force_factor > 1,
          "max_force_factor must be > 1");
  Require(std::isfinite(p.gain_n) && p.gain_n >= 0, "gain_n must be >= 0 (0: sigma_T*A)");
  Require(positive(p.friction), "friction must be > 0");
  Require(positive(p.slip_m), "slip_m must be > 0");
  Require(std::isfinite(p.settle_time_s) && p.settle_time_s >= 0, "settle_time_s must be >= 0");
  Require(std::isfinite(p.reach_m) && p.reach_m >= 0, "reach_m must be >= 0");
  Require(positive(p.weld_solref[0]) && positive(p.weld_solref[1]), "weld_solref must be > 0");
  Require(positive(p.contact_solref[0]) && positive(p.contact_solref[1]),
          "contact_solref must be > 0");
  Require(p.noslip_iterations >= 0, "noslip_iterations must be >= 0");
}

double PulloffRig::gain_n() const { return params_.gain_n > 0 ? params_.gain_n : capacity_n(); }

PulloffRig::PulloffRig(AdhesionModel model, const PulloffRigParams& params)
    : model_type_(model), params_(params) {
  ValidatePulloffRigParams(params_);
  xml_ = BlockXml(model, params_, gain_n());
  std::string error;
  model_ = common::CompileMjcfString(xml_, &error);
  Require(model_ != nullptr, "pull-off model: " + error);
  data_ = mj_makeData(model_);
  block_ = mj_name2id(model_, mjOBJ_BODY, kBlockName);
  surface_geom_ = mj_name2id(model_, mjOBJ_GEOM, kSurfaceName);
  if (surface_geom_ < 0) {
    const int body = mj_name2id(model_, mjOBJ_BODY, kSurfaceName);
    Require(body >= 0 && model_->body_geomnum[body] > 0, "pull-off model: surface_mjcf has no geom");
    surface_geom_ = model_->body_geomadr[body];
  }

  AdhesionSystemParams sys;
  PadSpec spec;
  spec.body = kBlockName;
  spec.params.model = model;
  spec.params.bonds = params_.pad;
  spec.params.actuator_gain_n = gain_n();
  spec.params.actuator_ctrl = 1.0;
  spec.params.contact = params_.contact;
  sys.pads.push_back(spec);
  sys.surfaces = {kSurfaceName};
  sys.reach_m = params_.reach_m;
  system_ = std::make_unique<AdhesionSystem>(model_, sys);
}

PulloffRig::~PulloffRig() {
  if (data_ != nullptr) mj_deleteData(data_);
  if (model_ != nullptr) mj_deleteModel(model_);
}

void PulloffRig::Start(PadEventSink* sink) {
  mjModel* m = model_;
  mjData* d = data_;
  mj_resetData(m, d);
  system_->Reset(m, d, sink);
  mj_forward(m, d);
  bool kinematics_current = true;
  system_->pad(0).ForceAttach(m, d, d->time, surface_geom_, 1.0, PadCause::kForced,
                              &kinematics_current, sink);
  // kMujoco: let the actuator pull the block into its resting penetration first.
  if (model_type_ == AdhesionModel::kMujoco) {
    const long settle_steps = std::lround(params_.settle_time_s / m->opt.timestep);
    for (long k = 0; k < settle_steps; ++k) Step(Eigen::Vector3d::UnitZ(), 0.0, sink);
  }
  mj_forward(m, d);
}

void PulloffRig::Step(const Eigen::Vector3d& u, double force_n, PadEventSink* sink) {
  mjModel* m = model_;
  mjData* d = data_;
  // The pull at L above the face centroid, as a force and its moment about the centre of mass.
  const PadFrame face = FaceFrame(d, system_->pad(0).geometry());
  const Eigen::Vector3d point = face.pos + params_.arm_m * face.rot.col(2) +
                                params_.pull_point_m[0] * face.rot.col(0) +
                                params_.pull_point_m[1] * face.rot.col(1);
  const Eigen::Vector3d com(d->xipos[3 * block_], d->xipos[3 * block_ + 1],
                            d->xipos[3 * block_ + 2]);
  const Eigen::Vector3d f = force_n * u;
  const Eigen::Vector3d t = (point - com).cross(f);
  for (int i = 0; i < 3; ++i) {
    d->xfrc_applied[6 * block_ + i] = f[i];
    d->xfrc_applied[6 * block_ + 3 + i] = t[i];
  }
  system_->BeforeStep(m, d, sink);
  mj_step(m, d);
  system_->AfterStep(m, d, sink);
}

Eigen::Vector3d PulloffRig::Direction(double angle_rad) const {
  return {std::sin(angle_rad) * std::cos(params_.azimuth_rad),
          std::sin(angle_rad) * std::sin(params_.azimuth_rad), std::cos(angle_rad)};
}

const StickyPad& PulloffRig::Hold(double angle_rad, double force_n, double duration_s) {
  Require(std::isfinite(angle_rad) && std::isfinite(force_n) && std::isfinite(duration_s),
          "Hold: angle, force and duration must be finite");
  Sink sink;
  Start(&sink);
  const Eigen::Vector3d u = Direction(angle_rad);
  const long steps = std::lround(duration_s / model_->opt.timestep);
  for (long k = 0; k < steps; ++k) Step(u, force_n, &sink);
  return system_->pad(0);
}

PulloffRun PulloffRig::Run(double angle_rad, PadEventSink* observer) {
  Require(std::isfinite(angle_rad), "angle must be finite");
  mjModel* m = model_;
  mjData* d = data_;
  Sink sink(observer);
  Start(&sink);
  StickyPad& pad = system_->pad(0);
  PulloffRun run;
  const std::array<Eigen::Vector3d, 4> corners0 = Corners(d, pad.geometry());

  const Eigen::Vector3d u = Direction(angle_rad);
  const double dt = m->opt.timestep;
  const double rate = capacity_n() / params_.ramp_time_s;
  const long max_steps = std::lround(params_.max_force_factor * params_.ramp_time_s / dt) + 1;
  int total_rounds = 0;
  for (long k = 0; k < max_steps; ++k) {
    const double force = rate * (k + 1) * dt;
    Step(u, force, &sink);
    ++run.steps;

    if (model_type_ == AdhesionModel::kBonds) {
      RecordBondsLost(pad, force, &total_rounds, &run);
      if (!pad.attached()) {
        run.detached = true;
        run.cause = PadCauseName(sink.cause);
      }
    } else if (!pad.attached()) {
      run.detached = true;
      run.cause = PadCauseName(PadCause::kContactLost);
    } else {
      mj_kinematics(m, d);
      const char* slip = SlipCause(corners0, Corners(d, pad.geometry()), params_.slip_m);
      if (slip != nullptr) {
        run.detached = true;
        run.cause = slip;
      }
    }
    if (run.detached) {
      run.force_n = force;
      run.time_s = d->time;
      break;
    }
  }
  if (!run.detached) {
    run.force_n = kInf;
    run.time_s = d->time;
  }
  for (int i = 0; i < 6; ++i) d->xfrc_applied[6 * block_ + i] = 0.0;
  return run;
}

double MujocoPulloffClosedForm(double gain_n, double friction, double width_m, double arm_m,
                               double angle_rad) {
  const double s = std::sin(angle_rad), c = std::cos(angle_rad);
  double best = kInf;
  const double tip = arm_m * s + 0.5 * width_m * c;
  if (tip > 1e-12 * width_m) best = std::min(best, gain_n * 0.5 * width_m / tip);
  const double slide = s + friction * c;
  if (slide > 1e-12) best = std::min(best, friction * gain_n / slide);
  return best;
}

}  // namespace climbsim::adhesion
