// Replaying a recorded trajectory offscreen: EGL (surfaceless, Mesa), MuJoCo's mjv/mjr, ffmpeg.
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <mujoco/mujoco.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "common/common.h"
#include "inspect/inspect.h"
#include "sim/sim.h"

namespace climbsim::inspect {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
constexpr const char* kCli = "climbsim render";

// A current OpenGL context without any window: EGL on Mesa's surfaceless platform
// (docs/mujoco.md, "Headless rendering").
class EglContext {
 public:
  EglContext() {
    const auto get_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (get_display == nullptr) Fail("no eglGetPlatformDisplayEXT");
    display_ = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display_ == EGL_NO_DISPLAY || eglInitialize(display_, nullptr, nullptr) != EGL_TRUE) {
      Fail("cannot open the surfaceless display");
    }
    const EGLint attributes[] = {EGL_SURFACE_TYPE,
                                 EGL_PBUFFER_BIT,
                                 EGL_RENDERABLE_TYPE,
                                 EGL_OPENGL_BIT,
                                 EGL_RED_SIZE,
                                 8,
                                 EGL_GREEN_SIZE,
                                 8,
                                 EGL_BLUE_SIZE,
                                 8,
                                 EGL_ALPHA_SIZE,
                                 8,
                                 EGL_DEPTH_SIZE,
                                 24,
                                 EGL_STENCIL_SIZE,
                                 8,
                                 EGL_NONE};
    EGLConfig config;
    EGLint count = 0;
    if (eglChooseConfig(display_, attributes, &config, 1, &count) != EGL_TRUE || count < 1) {
      Fail("no pbuffer-capable OpenGL configuration");
    }
    if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) Fail("cannot bind the OpenGL API");
    context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, nullptr);
    if (context_ == EGL_NO_CONTEXT) Fail("cannot create an OpenGL context");
    if (eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) != EGL_TRUE) {
      Fail("cannot make the context current");
    }
  }
  ~EglContext() {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
    eglTerminate(display_);
  }
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

 private:
  [[noreturn]] void Fail(const char* what) {
    char buf[64];
    std::snprintf(buf, sizeof(buf), " (EGL error 0x%x)", eglGetError());
    if (display_ != EGL_NO_DISPLAY) eglTerminate(display_);
    throw std::runtime_error(
        std::string("headless OpenGL through EGL failed: ") + what + buf +
        "; Mesa's EGL and llvmpipe are needed (libegl-mesa0, libgl1-mesa-dri: scripts/setup.sh)");
  }
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
};

// Pads: red at a trace of bonds to green at full; the pad's own colour when unbonded.
void PadColour(const float* own, double f, float* rgba) {
  if (!(f > 0.0)) {
    std::copy(own, own + 4, rgba);
    return;
  }
  f = std::min(1.0, f);
  const float red[3] = {0.90f, 0.15f, 0.10f}, green[3] = {0.10f, 0.80f, 0.20f};
  for (int i = 0; i < 3; ++i) rgba[i] = static_cast<float>((1 - f) * red[i] + f * green[i]);
  rgba[3] = own[3];
}

// The recorded trajectory replayed on a private model copy, one frame at a time.
class Renderer {
 public:
  Renderer(const Run& run, const RenderOptions& o, std::vector<std::string>* notes)
      : run_(run), o_(o), traj_(*run.trajectory) {
    std::string error;
    model_owner_.reset(common::CompileMjcfString(run.model_xml, &error));
    model_ = model_owner_.get();
    if (model_ == nullptr) {
      throw InputError(run.dir + "/model.xml", 0, 0, "", "MuJoCo cannot load it: " + error);
    }
    data_owner_.reset(mj_makeData(model_));
    data_ = data_owner_.get();
    MapColumns(notes);
    SetCamera(notes);

    // Offscreen buffer of the requested size; reduced quality before the context exists.
    model_->vis.global.offwidth = o.width;
    model_->vis.global.offheight = o.height;
    if (o.quality == Quality::kReduced) model_->vis.quality.offsamples = 0;
    mjv_defaultOption(&option_);
    gl_.Make(model_);
    mjr_setBuffer(mjFB_OFFSCREEN, &context_);
    if (context_.offWidth != o.width || context_.offHeight != o.height) {
      throw std::runtime_error("the OpenGL driver gave an offscreen buffer of " +
                               std::to_string(context_.offWidth) + "x" +
                               std::to_string(context_.offHeight) + " instead of " +
                               std::to_string(o.width) + "x" + std::to_string(o.height));
    }
    if (o.quality == Quality::kReduced) {
      scene_.flags[mjRND_SHADOW] = 0;
      scene_.flags[mjRND_REFLECTION] = 0;
    }
    rgb_.resize(static_cast<size_t>(3) * o.width * o.height);
  }

  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Renders time t; rgb() then holds the frame, rows bottom-up, 3 bytes per pixel.
  void Frame(double t) {
    SetState(t);
    mj_kinematics(model_, data_);
    mj_comPos(model_, data_);
    mj_camlight(model_, data_);
    if (camera_.type == mjCAMERA_FREE) {
      const Eigen::Vector3d look = fixed_ ? fixed_look_ : LookAt(t);
      for (int i = 0; i < 3; ++i) camera_.lookat[i] = look[i];
    }
    mjv_updateScene(model_, data_, &option_, nullptr, &camera_, mjCAT_ALL, &scene_);
    // MuJoCo's free camera keeps world +z up; turn the image so that −gravity is up.
    if (camera_.type == mjCAMERA_FREE) {
      for (mjvGLCamera& c : scene_.camera) {
        for (int i = 0; i < 3; ++i) c.up[i] = static_cast<float>(up_[i]);
      }
    }
    const mjrRect viewport = {0, 0, o_.width, o_.height};
    mjr_render(viewport, &scene_, &context_);
    char label[64];
    std::snprintf(label, sizeof(label), "t = %.2f s", t);
    mjr_overlay(mjFONT_NORMAL, mjGRID_TOPLEFT, viewport, label, nullptr, &context_);
    mjr_readPixels(rgb_.data(), nullptr, viewport, &context_);
  }
  const std::vector<unsigned char>& rgb() const { return rgb_; }
  // The last frame's camera (the two eyes averaged).
  CameraPose pose() const {
    CameraPose p;
    const mjvGLCamera c = mjv_averageCamera(&scene_.camera[0], &scene_.camera[1]);
    for (int i = 0; i < 3; ++i) p.pos[i] = c.pos[i], p.forward[i] = c.forward[i], p.up[i] = c.up[i];
    p.fovy_deg = model_->vis.global.fovy;
    return p;
  }
  const std::string& camera_name() const { return o_.camera; }
  double first_time() const { return traj_.at(0, 0); }
  double last_time() const { return traj_.at(traj_.rows() - 1, 0); }

 private:
  // Which qpos entry (or pad geom) each trajectory column drives.
  void MapColumns(std::vector<std::string>* notes) {
    const mjModel* m = model_;
    const int root = mj_name2id(m, mjOBJ_JOINT, "root");
    if (root < 0 || m->jnt_type[root] != mjJNT_FREE) {
      throw InputError(run_.dir + "/model.xml", 0, 0, "",
                       "the robot has no free joint 'root' (mjcf/README.md, contract)");
    }
    qpos_of_column_.assign(traj_.columns.size(), -1);
    for (int i = 0; i < 7; ++i) qpos_of_column_[1 + i] = m->jnt_qposadr[root] + i;
    std::vector<bool> covered(m->njnt, false);
    covered[root] = true;
    for (size_t c = 8; c < traj_.columns.size(); ++c) {
      const std::string& name = traj_.columns[c];
      for (const char* suffix : {"_rad", "_m"}) {
        const size_t n = std::string_view(suffix).size();
        if (name.size() <= n || name.compare(name.size() - n, n, suffix) != 0) continue;
        const int j = mj_name2id(m, mjOBJ_JOINT, name.substr(0, name.size() - n).c_str());
        if (j >= 0 && (m->jnt_type[j] == mjJNT_HINGE || m->jnt_type[j] == mjJNT_SLIDE)) {
          qpos_of_column_[c] = m->jnt_qposadr[j];
          covered[j] = true;
        }
      }
    }
    std::string missing;
    for (int j = 0; j < m->njnt; ++j) {
      if (covered[j]) continue;
      const char* n = mj_id2name(m, mjOBJ_JOINT, j);
      missing += (missing.empty() ? "" : ", ") + std::string(n ? n : "?");
    }
    if (!missing.empty()) {
      notes->push_back("joints not in trajectory.csv, shown at their reference pose: " + missing);
    }
    for (const std::string& pad : run_.pads) {
      const int g = mj_name2id(m, mjOBJ_GEOM, pad.c_str());
      if (g < 0) continue;
      pad_geom_.push_back(g);
      pad_column_.push_back(traj_.Column(pad + "_bonded_fraction"));
      pad_rgba_.emplace_back(m->geom_rgba + 4 * g, m->geom_rgba + 4 * g + 4);
    }
  }

  // Camera: behind, beside and off the surface (normal +z in every scene), up along −gravity.
  void SetCamera(std::vector<std::string>* notes) {
    std::string note;
    const Eigen::Vector3d g = RunGravity(run_, &note);
    if (!note.empty()) notes->push_back(note);
    const Eigen::Vector3d n(0, 0, 1);
    Eigen::Vector3d along = run_.travel - run_.travel.dot(n) * n;
    along = along.norm() > 1e-9 ? along.normalized() : Eigen::Vector3d::UnitX();
    const Eigen::Vector3d side = n.cross(along);
    const Eigen::Vector3d offset = (-0.45 * along - 0.30 * side + 0.84 * n).normalized();
    const Eigen::Vector3d forward = -offset;
    const Eigen::Vector3d up_wanted = g.norm() > 0 ? Eigen::Vector3d(-g.normalized()) : n;
    up_ = up_wanted - up_wanted.dot(forward) * forward;
    up_ = up_.norm() > 1e-6 ? up_.normalized() : Eigen::Vector3d(n - n.dot(forward) * forward);
    up_.normalize();

    mjv_defaultCamera(&camera_);
    if (o_.camera != "follow" && o_.camera != "fixed") {
      UseModelCamera();
      return;
    }
    camera_.type = mjCAMERA_FREE;
    camera_.azimuth = std::atan2(forward.y(), forward.x()) * 180.0 / M_PI;
    camera_.elevation = std::asin(std::clamp(forward.z(), -1.0, 1.0)) * 180.0 / M_PI;
    camera_.distance = o_.distance_m > 0 ? o_.distance_m : 3.5 * RobotRadius();
    if (o_.camera == "fixed") {
      FrameTheClimb();
      return;
    }
    // Prefix sums of the base position for the ±0.25 s average the camera looks at.
    base_sum_.assign(traj_.rows() + 1, Eigen::Vector3d::Zero());
    for (size_t r = 0; r < traj_.rows(); ++r) {
      base_sum_[r + 1] =
          base_sum_[r] + Eigen::Vector3d(traj_.at(r, 1), traj_.at(r, 2), traj_.at(r, 3));
    }
  }

  // The model's camera o_.camera, or InputError at --camera naming the cameras there are.
  void UseModelCamera() {
    const int id = mj_name2id(model_, mjOBJ_CAMERA, o_.camera.c_str());
    if (id < 0) {
      std::string names;
      for (int c = 0; c < model_->ncam; ++c) {
        const char* n = mj_id2name(model_, mjOBJ_CAMERA, c);
        if (n != nullptr) names += std::string(names.empty() ? "" : ", ") + n;
      }
      throw InputError(kCli, 0, 0, "--camera",
                       "'" + o_.camera + "' is not follow, fixed or a camera of the model (" +
                           (names.empty() ? std::string("it has no named camera") : names) + ")");
    }
    camera_.type = mjCAMERA_FIXED;
    camera_.fixedcamid = id;
  }

  // The fixed view: the centre of the box the base spans over the rendered time, from a
  // distance at which that box's sphere, grown by the robot's radius, fills the narrower
  // field of view.
  void FrameTheClimb() {
    fixed_ = true;
    const double a = std::max(o_.from_s, first_time()), b = std::min(o_.to_s, last_time());
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d hi = -lo;
    for (size_t r = 0; r < traj_.rows(); ++r) {
      const double t = traj_.at(r, 0);
      // Rows inside the span; a span between two rows takes the row at its start.
      if ((t < a || t > b) && !(r == Bracket(a).first && lo.x() > hi.x())) continue;
      const Eigen::Vector3d p(traj_.at(r, 1), traj_.at(r, 2), traj_.at(r, 3));
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    fixed_look_ = 0.5 * (lo + hi);
    if (o_.distance_m > 0) return;
    const double radius = 0.5 * (hi - lo).norm() + RobotRadius();
    const double half_fovy = 0.5 * model_->vis.global.fovy * M_PI / 180.0;
    const double half_fovx = std::atan(std::tan(half_fovy) * o_.width / o_.height);
    camera_.distance = 1.05 * radius / std::sin(std::min(half_fovy, half_fovx));
  }

  // Largest distance of a robot geom's bounding sphere from the base, at the first row.
  double RobotRadius() {
    SetState(first_time());
    mj_kinematics(model_, data_);
    const int base = mj_name2id(model_, mjOBJ_BODY, "base");
    if (base < 0) return 0.1;
    const int root_body = model_->body_rootid[base];
    const Eigen::Map<const Eigen::Vector3d> centre(data_->xpos + 3 * base);
    double r = 0.0;
    for (int g = 0; g < model_->ngeom; ++g) {
      if (model_->body_rootid[model_->geom_bodyid[g]] != root_body) continue;
      const Eigen::Map<const Eigen::Vector3d> p(data_->geom_xpos + 3 * g);
      r = std::max(r, (p - centre).norm() + model_->geom_rbound[g]);
    }
    return r > 0 ? r : 0.1;
  }

  // Rows i, i+1 around t and the weight of row i+1.
  std::pair<size_t, double> Bracket(double t) const {
    const size_t n = traj_.rows();
    if (n == 1 || t <= traj_.at(0, 0)) return {0, 0.0};
    if (t >= traj_.at(n - 1, 0)) return {n - 2, 1.0};
    size_t lo = 0, hi = n - 1;  // time[lo] <= t < time[hi]
    while (hi - lo > 1) {
      const size_t mid = (lo + hi) / 2;
      (traj_.at(mid, 0) <= t ? lo : hi) = mid;
    }
    const double span = traj_.at(hi, 0) - traj_.at(lo, 0);
    return {lo, span > 0 ? (t - traj_.at(lo, 0)) / span : 0.0};
  }

  void SetState(double t) {
    const auto [i, w] = Bracket(t);
    const size_t j = std::min(i + 1, traj_.rows() - 1);
    auto value = [&](size_t c) { return (1 - w) * traj_.at(i, c) + w * traj_.at(j, c); };
    mju_copy(data_->qpos, model_->qpos0, model_->nq);
    for (size_t c = 1; c < traj_.columns.size(); ++c) {
      if (qpos_of_column_[c] >= 0) data_->qpos[qpos_of_column_[c]] = value(c);
    }
    // The base quaternion: blend on the same hemisphere, then normalise.
    double* q = data_->qpos + qpos_of_column_[4];
    double dot = 0.0;
    for (int k = 0; k < 4; ++k) dot += traj_.at(i, 4 + k) * traj_.at(j, 4 + k);
    for (int k = 0; k < 4; ++k) {
      q[k] = (1 - w) * traj_.at(i, 4 + k) + (dot < 0 ? -w : w) * traj_.at(j, 4 + k);
    }
    mju_normalize4(q);
    for (size_t p = 0; p < pad_geom_.size(); ++p) {
      const double f = pad_column_[p] >= 0 ? value(pad_column_[p]) : FractionFromEvents(p, t);
      PadColour(pad_rgba_[p].data(), f, model_->geom_rgba + 4 * pad_geom_[p]);
    }
  }

  // Without a bonded-fraction column: the fraction of the pad's last event at or before t.
  double FractionFromEvents(size_t p, double t) const {
    double f = 0.0;
    for (const EventRow& e : run_.events) {
      if (e.time_s > t) break;
      if (e.pad == run_.pads[p]) f = e.event == "detach" ? 0.0 : e.bonded_fraction;
    }
    return f;
  }

  Eigen::Vector3d LookAt(double t) const {
    const size_t n = traj_.rows();
    auto first_at_or_after = [&](double x) {
      size_t lo = 0, hi = n;
      while (lo < hi) {
        const size_t mid = (lo + hi) / 2;
        (traj_.at(mid, 0) < x ? lo = mid + 1 : hi = mid);
      }
      return lo;
    };
    size_t a = first_at_or_after(t - 0.25), b = first_at_or_after(t + 0.25 + 1e-12);
    if (b <= a) {  // no row inside: the nearest one
      a = std::min(a, n - 1);
      b = a + 1;
    }
    return (base_sum_[b] - base_sum_[a]) / static_cast<double>(b - a);
  }

  struct ModelDeleter {
    void operator()(mjModel* m) const { mj_deleteModel(m); }
  };
  struct DataDeleter {
    void operator()(mjData* d) const { mj_deleteData(d); }
  };
  // MuJoCo's scene and GL context, freed before the EGL context goes (members are destroyed
  // in reverse order).
  struct Gl {
    mjvScene scene{};
    mjrContext context{};
    bool made = false;
    void Make(const mjModel* m) {
      mjv_defaultScene(&scene);
      mjr_defaultContext(&context);
      made = true;
      mjv_makeScene(m, &scene, 4000);
      mjr_makeContext(m, &context, mjFONTSCALE_100);
    }
    ~Gl() {
      if (!made) return;
      mjr_freeContext(&context);
      mjv_freeScene(&scene);
    }
  };

  const Run& run_;
  RenderOptions o_;
  const NumericTable& traj_;
  std::unique_ptr<mjModel, ModelDeleter> model_owner_;
  std::unique_ptr<mjData, DataDeleter> data_owner_;
  mjModel* model_ = nullptr;
  mjData* data_ = nullptr;
  EglContext egl_;  // current before mjr_makeContext, released after mjr_freeContext
  Gl gl_;
  mjrContext& context_ = gl_.context;
  mjvScene& scene_ = gl_.scene;
  mjvOption option_{};
  mjvCamera camera_{};
  bool fixed_ = false;
  Eigen::Vector3d fixed_look_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d up_;
  std::vector<int> qpos_of_column_;
  std::vector<int> pad_geom_, pad_column_;
  std::vector<std::vector<float>> pad_rgba_;
  std::vector<Eigen::Vector3d> base_sum_;
  std::vector<unsigned char> rgb_;
};

// ffmpeg reading raw RGB frames (bottom-up, hence vflip) on its standard input, started from
// an argument vector in `working_dir` (no shell). `output_args` end with the output as
// "file:NAME", a name in `working_dir`: the file protocol whatever the name holds (no URL).
class Encoder {
 public:
  Encoder(const RenderOptions& o, const std::string& working_dir,
          const std::vector<std::string>& output_args) {
    if (common::FindInPath("ffmpeg").empty()) {
      throw std::runtime_error("ffmpeg is not installed (scripts/setup.sh installs it)");
    }
    err_path_ =
        (fs::temp_directory_path() / ("climbsim_ffmpeg_" + std::to_string(::getpid()) + ".err"))
            .string();
    char fps[32];
    std::snprintf(fps, sizeof(fps), "%.9g", o.fps);
    const std::string size = std::to_string(o.width) + "x" + std::to_string(o.height);
    // -nostdin keeps ffmpeg off the terminal; its input is the "-i -" pipe.
    std::vector<std::string> argv = {"ffmpeg",   "-nostdin", "-loglevel", "error", "-y",   "-f",
                                     "rawvideo", "-pix_fmt", "rgb24",     "-s",    size,   "-r",
                                     fps,        "-i",       "-",         "-vf",   "vflip"};
    argv.insert(argv.end(), output_args.begin(), output_args.end());
    const common::ProcessOptions options{
        .working_dir = working_dir, .stderr_path = err_path_, .stdin_pipe = true};
    process_ = std::make_unique<common::Process>(argv, options);
  }
  ~Encoder() {
    process_.reset();
    std::error_code ec;
    fs::remove(err_path_, ec);
  }
  Encoder(const Encoder&) = delete;
  Encoder& operator=(const Encoder&) = delete;

  void Write(const std::vector<unsigned char>& rgb) {
    if (!process_->Write(rgb.data(), rgb.size())) Fail("it stopped reading frames");
  }
  void Finish() {
    const std::string status = process_->Wait();
    if (!status.empty()) Fail(status);
  }

 private:
  [[noreturn]] void Fail(const std::string& status) {
    const std::string waited = process_->Wait();
    std::ifstream in(err_path_);
    std::stringstream e;
    e << in.rdbuf();
    throw std::runtime_error("ffmpeg failed (" + (waited.empty() ? status : waited) +
                             "): " + e.str());
  }
  std::unique_ptr<common::Process> process_;
  std::string err_path_;
};

void CheckOptions(const Run& run, const RenderOptions& o, bool video) {
  if (!run.trajectory) {
    throw InputError(run.dir + "/trajectory.csv", 0, 0, "",
                     "missing file: the run recorded no trajectory (outputs.trajectory_rate_hz: "
                     "0), so there is nothing to replay");
  }
  if (o.width < 16 || o.width > 8192) {
    throw InputError(kCli, 0, 0, "--width",
                     "must be in [16, 8192], got " + std::to_string(o.width));
  }
  if (o.height < 16 || o.height > 8192) {
    throw InputError(kCli, 0, 0, "--height",
                     "must be in [16, 8192], got " + std::to_string(o.height));
  }
  if (video && (o.width % 2 != 0 || o.height % 2 != 0)) {
    throw InputError(kCli, 0, 0, o.width % 2 ? "--width" : "--height",
                     "a video needs an even width and height (H.264, 4:2:0), got " +
                         std::to_string(o.width) + "x" + std::to_string(o.height));
  }
  if (!(o.fps > 0 && o.fps <= 240)) {
    throw InputError(kCli, 0, 0, "--fps", "must be in (0, 240]");
  }
  if (!(o.distance_m >= 0)) throw InputError(kCli, 0, 0, "--distance-m", "must be >= 0");
}

// The options with the default camera filled in (a still follows, a video frames the climb).
RenderOptions WithCamera(RenderOptions o, const char* default_camera) {
  if (o.camera.empty()) o.camera = default_camera;
  return o;
}

void MakeParent(const fs::path& path) {
  if (!path.parent_path().empty()) fs::create_directories(path.parent_path());
}

template <class Body>
RenderStats Timed(Body body) {
  RenderStats stats;
  const Clock::time_point start = Clock::now();
  body(&stats);
  stats.total_s = std::chrono::duration<double>(Clock::now() - start).count();
  return stats;
}

// Renders `times` into the encoder, timing the renderer apart from the encoding.
void RenderInto(Renderer& r, const std::vector<double>& times, Encoder& encoder, RenderStats* stats,
                const std::function<void(double)>& progress) {
  for (size_t k = 0; k < times.size(); ++k) {
    const Clock::time_point start = Clock::now();
    r.Frame(times[k]);
    stats->render_s += std::chrono::duration<double>(Clock::now() - start).count();
    encoder.Write(r.rgb());
    stats->cameras.push_back(r.pose());
    stats->camera = r.camera_name();
    ++stats->frames;
    if (progress) progress(static_cast<double>(k + 1) / times.size());
  }
}

}  // namespace

Eigen::Vector3d RunGravity(const Run& run, std::string* note) {
  try {
    const sim::Scenario scenario = sim::LoadScenario(run.dir + "/scenario.yaml");
    const auto compiled = sim::CompileScenario(scenario);
    const sim::World world(*compiled, scenario);
    return world.gravity();
  } catch (const InputError& e) {
    std::string error;
    mjModel* m = common::CompileMjcfString(run.model_xml, &error);
    if (m == nullptr)
      throw InputError(run.dir + "/model.xml", 0, 0, "", "MuJoCo cannot load it: " + error);
    const Eigen::Vector3d g(m->opt.gravity[0], m->opt.gravity[1], m->opt.gravity[2]);
    mj_deleteModel(m);
    if (note != nullptr) {
      *note =
          std::string("gravity from model.xml (an incline's rotation is not in it): ") + e.what();
    }
    return g;
  }
}

std::vector<double> FrameTimes(const Run& run, const RenderOptions& o) {
  CheckOptions(run, o, false);
  const NumericTable& t = *run.trajectory;
  const double first = t.at(0, 0), last = t.at(t.rows() - 1, 0);
  const double a = std::max(o.from_s, first), b = std::min(o.to_s, last);
  if (!(a <= b)) {
    char buf[160];
    std::snprintf(buf, sizeof(buf), "the span %g .. %g s holds none of the recording (%g .. %g s)",
                  o.from_s, o.to_s, first, last);
    throw InputError(kCli, 0, 0, "--from", buf);
  }
  std::vector<double> times;
  for (long k = 0;; ++k) {
    const double time = a + k / o.fps;
    if (time > b + 1e-9) break;
    times.push_back(std::min(time, b));
  }
  return times;
}

RenderStats RenderStill(const Run& run, const RenderOptions& o, double t_s,
                        const std::string& png_path) {
  CheckOptions(run, o, false);
  const NumericTable& t = *run.trajectory;
  const double first = t.at(0, 0), last = t.at(t.rows() - 1, 0);
  if (!(t_s >= first - 1e-9 && t_s <= last + 1e-9)) {
    char buf[160];
    std::snprintf(buf, sizeof(buf), "must be inside the recording (%g .. %g s), got %g", first,
                  last, t_s);
    throw InputError(kCli, 0, 0, "--at", buf);
  }
  return Timed([&](RenderStats* stats) {
    Renderer r(run, WithCamera(o, "follow"), &stats->notes);
    MakeParent(png_path);
    const std::string tmp = common::TempSiblingPath(png_path);
    {
      Encoder encoder(o, fs::path(tmp).parent_path().string(),
                      {"-frames:v", "1", "-update", "1", "-c:v", "png", "-f", "image2",
                       "file:" + fs::path(tmp).filename().string()});
      RenderInto(r, {t_s}, encoder, stats, {});
      encoder.Finish();
    }
    fs::rename(tmp, png_path);
  });
}

RenderStats RenderVideo(const Run& run, const RenderOptions& o, const std::string& mp4_path,
                        const std::function<void(double)>& progress) {
  CheckOptions(run, o, true);
  const std::vector<double> times = FrameTimes(run, o);
  return Timed([&](RenderStats* stats) {
    Renderer r(run, WithCamera(o, "fixed"), &stats->notes);
    MakeParent(mp4_path);
    const std::string tmp = common::TempSiblingPath(mp4_path);
    try {
      Encoder encoder(
          o, fs::path(tmp).parent_path().string(),
          {"-c:v", "libx264", "-preset", "veryfast", "-crf", "20", "-pix_fmt", "yuv420p",
           "-movflags", "+faststart", "-f", "mp4", "file:" + fs::path(tmp).filename().string()});
      RenderInto(r, times, encoder, stats, progress);
      encoder.Finish();
    } catch (...) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw;
    }
    fs::rename(tmp, mp4_path);
  });
}

RenderStats RenderFrames(const Run& run, const RenderOptions& o, const std::string& out_dir,
                         const std::function<void(double)>& progress) {
  CheckOptions(run, o, false);
  const std::vector<double> times = FrameTimes(run, o);
  return Timed([&](RenderStats* stats) {
    Renderer r(run, WithCamera(o, "fixed"), &stats->notes);
    // ffmpeg writes into a private folder; each finished frame is then renamed into place.
    const fs::path tmp = fs::path(out_dir) / (".tmp." + std::to_string(::getpid()));
    fs::create_directories(tmp);
    try {
      Encoder encoder(o, tmp.string(),
                      {"-start_number", "0", "-c:v", "png", "-f", "image2", "file:frame_%05d.png"});
      RenderInto(r, times, encoder, stats, progress);
      encoder.Finish();
    } catch (...) {
      std::error_code ec;
      fs::remove_all(tmp, ec);
      throw;
    }
    for (const auto& entry : fs::directory_iterator(tmp)) {
      fs::rename(entry.path(), fs::path(out_dir) / entry.path().filename());
    }
    fs::remove(tmp);
  });
}

}  // namespace climbsim::inspect
