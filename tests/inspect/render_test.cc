// `climbsim render`: stills of the requested size in which the robot is seen (its pixels differ
// from the same view without it), pads coloured by bonded fraction, a video with the expected
// frame count, PNG frames, clear errors, and a run directory left exactly as it was.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <regex>

#include "inspect/inspect.h"
#include "sim/sim.h"
#include "tests/inspect/inspect_test_util.h"

namespace {

using climbsim::testing::CopyRun;
using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsim;
using climbsim::testing::SharedRun;
using climbsim::testing::Source;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;
namespace fs = std::filesystem;

std::string GeckoWall() { return SharedRun("gecko_wall", Source("examples/gecko_wall.yaml")); }

// Width and height from a PNG's IHDR chunk (bytes 16..23, big-endian).
std::pair<int, int> PngSize(const std::string& png) {
  EXPECT_EQ(png.substr(0, 8), "\x89PNG\r\n\x1a\n");
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  auto be32 = [&](size_t at) {
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v = v << 8 | static_cast<uint8_t>(png[at + i]);
    return static_cast<int>(v);
  };
  return {be32(16), be32(20)};
}

// RGB pixels of a PNG, decoded by ffmpeg.
std::string Pixels(const std::string& png) {
  const std::string raw = png + ".rgb";
  const std::string cmd =
      "ffmpeg -nostdin -loglevel error -y -i " + png + " -f rawvideo -pix_fmt rgb24 " + raw;
  EXPECT_EQ(std::system(cmd.c_str()), 0);
  return ReadFile(raw);
}

// A copy of the run whose robot is drawn fully transparent (every rgba alpha 0 in a copy of
// the robot file): the same camera, the same scene, no robot.
std::string RunWithoutRobot(const std::string& run) {
  const std::string dir = CopyRun(run, "invisible_robot");
  // model.xml holds the robot file expanded between climbsim's begin and end comments.
  std::string model = ReadFile(dir + "/model.xml");
  const size_t begin = model.find("gecko.xml -->");
  const size_t end = model.find("<!-- climbsim: end of", begin);
  EXPECT_NE(begin, std::string::npos);
  EXPECT_NE(end, std::string::npos);
  const std::string robot =
      std::regex_replace(model.substr(begin, end - begin),
                         std::regex(R"(rgba="([-0-9.e]+ [-0-9.e]+ [-0-9.e]+) 1")"),
                         R"(rgba="$1 0")");
  model.replace(begin, end - begin, robot);
  WriteFile(dir + "/model.xml", model);
  return dir;
}

TEST(Render, StillHasTheSizeAskedAndShowsTheRobot) {
  const std::string run = GeckoWall();
  const std::string still = TempDir() + "/still.png", empty = TempDir() + "/no_robot.png";
  auto r = RunClimbsim("render " + run + " --at 5 --out " + still +
                       " --width 320 --height 240 --quality reduced");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(PngSize(ReadFile(still)), std::make_pair(320, 240));
  r = RunClimbsim("render " + RunWithoutRobot(run) + " --at 5 --out " + empty +
                  " --width 320 --height 240 --quality reduced");
  ASSERT_EQ(r.code, 0) << r.err;

  const std::string a = Pixels(still), b = Pixels(empty);
  ASSERT_EQ(a.size(), 320u * 240u * 3u);
  ASSERT_EQ(b.size(), a.size());
  int differ = 0, differ_centre = 0, green_pads = 0, green_pads_empty = 0;
  for (int y = 0; y < 240; ++y) {
    for (int x = 0; x < 320; ++x) {
      const size_t i = 3 * (static_cast<size_t>(y) * 320 + x);
      int d = 0;
      for (int c = 0; c < 3; ++c) {
        d = std::max(d, std::abs(static_cast<uint8_t>(a[i + c]) - static_cast<uint8_t>(b[i + c])));
      }
      if (d > 30) {
        ++differ;
        if (std::abs(x - 160) < 20 && std::abs(y - 120) < 20) ++differ_centre;
      }
      // A bonded pad: (0.1, 0.8, 0.2) lit; nothing in the scene is that green.
      auto green = [&](const std::string& p) {
        const int r = static_cast<uint8_t>(p[i]), g = static_cast<uint8_t>(p[i + 1]),
                  bl = static_cast<uint8_t>(p[i + 2]);
        return g > 140 && r < 110 && bl < 120 && g - r > 80;
      };
      green_pads += green(a);
      green_pads_empty += green(b);
    }
  }
  const int total = 320 * 240;
  // The robot covers a few percent of the frame, centred (the camera looks at the base).
  EXPECT_GT(differ, total / 100) << differ;
  EXPECT_LT(differ, total / 2) << differ;
  EXPECT_GT(differ_centre, 40 * 40 / 4) << differ_centre;
  // At t = 5 s on the wall at least two pads hold, drawn green.
  EXPECT_GT(green_pads, 20);
  EXPECT_EQ(green_pads_empty, 0);
}

TEST(Render, FiveSecondVideoAt640x480Reduced) {
  const std::string run = GeckoWall();
  const std::string video = TempDir() + "/video.mp4";
  const auto start = std::chrono::steady_clock::now();
  const auto r = RunClimbsim("render " + run + " --out " + video +
                             " --from 2 --to 7 --width 640 --height 480 --fps 30 --quality "
                             "reduced --quiet");
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(r.code, 0) << r.err;
  RecordProperty("render_seconds_5s_640x480_reduced", std::to_string(seconds));
  std::printf("5 s video, 640x480, reduced quality: %.2f s wall time\n", seconds);
  const std::string probe = TempDir() + "/probe.txt";
  const std::string cmd =
      "ffprobe -v error -select_streams v:0 -count_frames -show_entries "
      "stream=codec_name,width,height,nb_read_frames -of csv=p=0 " +
      video + " >" + probe;
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  // 2 s .. 7 s at 30 frames/s, both ends included.
  EXPECT_EQ(ReadFile(probe), "h264,640,480,151\n");
}

TEST(Render, FramesFolderHoldsOnePngPerFrame) {
  const std::string dir = TempDir() + "/frames";
  const auto r = RunClimbsim("render " + GeckoWall() + " --frames " + dir +
                             " --from 1 --to 1.5 --fps 10 --width 160 "
                             "--height 120 --quality reduced --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename());
  std::sort(names.begin(), names.end());
  // The frames folder is a run folder: its marker first (docs/run-folders.md), then the frames.
  ASSERT_EQ(names.size(), 7u);
  EXPECT_EQ(names.front(), ".climbsim-run");
  names.erase(names.begin());
  EXPECT_EQ(names.front(), "frame_00000.png");
  EXPECT_EQ(names.back(), "frame_00005.png");
  EXPECT_EQ(PngSize(ReadFile(dir + "/frame_00003.png")), std::make_pair(160, 120));
}

TEST(Render, RenderingLeavesTheRunDirectoryAsItWas) {
  const std::string dir = CopyRun(GeckoWall(), "untouched");
  std::map<std::string, std::string> before;
  for (const auto& e : fs::directory_iterator(dir)) before[e.path()] = ReadFile(e.path());
  ASSERT_EQ(RunClimbsim("render " + dir + " --at 3 --out " + TempDir() +
                        "/untouched.png --width 64 --height 48 --quality reduced --quiet")
                .code,
            0);
  std::map<std::string, std::string> after;
  for (const auto& e : fs::directory_iterator(dir)) after[e.path()] = ReadFile(e.path());
  EXPECT_TRUE(before == after);
}

TEST(Render, BadRequestsAreInputErrors) {
  const std::string run = GeckoWall();
  auto r = RunClimbsim("render " + run + " --at 99 --out " + TempDir() + "/x.png");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "climbsim render: --at: must be inside the recording (0 .. 20 s), got 99\n");
  r = RunClimbsim("render " + run + " --out " + TempDir() + "/x.mp4 --width 641");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err,
            "climbsim render: --width: a video needs an even width and height (H.264, 4:2:0), got "
            "641x480\n");
  r = RunClimbsim("render " + run);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("give one of --out VIDEO.mp4, --frames DIR or --at T --out STILL.png"),
            std::string::npos);
  const std::string no_traj = CopyRun(run, "render_no_traj");
  fs::remove(no_traj + "/trajectory.csv");
  r = RunClimbsim("render " + no_traj + " --at 1 --out " + TempDir() + "/x.png");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(
      r.err.rfind(no_traj + "/trajectory.csv: missing file: the run recorded no trajectory", 0), 0u)
      << r.err;
}

// Where the base is in a frame, in pixels from the top left, seen by `c` (a pinhole with the
// vertical field of view fovy over `height` pixels, square pixels).
Eigen::Vector2d ImageOf(const climbsim::inspect::CameraPose& c, const Eigen::Vector3d& p, int width,
                        int height) {
  const Eigen::Vector3d v = p - c.pos, right = c.forward.cross(c.up);
  const double depth = v.dot(c.forward);
  const double f_px = 0.5 * height / std::tan(0.5 * c.fovy_deg * M_PI / 180.0);
  return {0.5 * width + f_px * v.dot(right) / depth, 0.5 * height - f_px * v.dot(c.up) / depth};
}

// The base's recorded position at the row nearest t.
Eigen::Vector3d BaseAt(const climbsim::inspect::Run& run, double t) {
  const auto& tr = *run.trajectory;
  size_t best = 0;
  for (size_t r = 0; r < tr.rows(); ++r) {
    if (std::abs(tr.at(r, 0) - t) < std::abs(tr.at(best, 0) - t)) best = r;
  }
  return {tr.at(best, 1), tr.at(best, 2), tr.at(best, 3)};
}

// A video of a climb must show the climbing: the fixed camera (a video's default) stays where
// it is while the body crosses the image, and frames the whole climb; the follow camera moves
// and keeps the body in the middle; a camera of the model is taken by name.
TEST(Render, FixedCameraStaysWhileTheBodyCrossesTheImage) {
  namespace inspect = climbsim::inspect;
  const inspect::Run run = inspect::LoadRun(GeckoWall());
  inspect::RenderOptions o;
  o.width = 160;
  o.height = 120;
  o.fps = 0.5;
  o.quality = inspect::Quality::kReduced;
  const std::vector<double> times = inspect::FrameTimes(run, o);  // 0, 2, ..., 20 s
  const inspect::RenderStats fixed = inspect::RenderFrames(run, o, TempDir() + "/cam_fixed");
  EXPECT_EQ(fixed.camera, "fixed");
  ASSERT_EQ(fixed.cameras.size(), times.size());
  double top = o.height, bottom = 0;
  for (size_t k = 0; k < times.size(); ++k) {
    EXPECT_EQ(fixed.cameras[k].pos, fixed.cameras[0].pos) << times[k];
    EXPECT_EQ(fixed.cameras[k].forward, fixed.cameras[0].forward) << times[k];
    EXPECT_EQ(fixed.cameras[k].up, fixed.cameras[0].up) << times[k];
    const Eigen::Vector2d px = ImageOf(fixed.cameras[k], BaseAt(run, times[k]), o.width, o.height);
    EXPECT_GT(px.x(), 0);
    EXPECT_LT(px.x(), o.width);
    top = std::min(top, px.y());
    bottom = std::max(bottom, px.y());
  }
  EXPECT_GE(top, 0);
  EXPECT_LE(bottom, o.height);
  // The gecko climbs the wall: up the image by a good part of its height.
  EXPECT_LT(ImageOf(fixed.cameras.back(), BaseAt(run, times.back()), o.width, o.height).y(),
            ImageOf(fixed.cameras[0], BaseAt(run, times[0]), o.width, o.height).y());
  EXPECT_GT(bottom - top, 0.2 * o.height);

  o.camera = "follow";
  const inspect::RenderStats follow = inspect::RenderFrames(run, o, TempDir() + "/cam_follow");
  EXPECT_NE(follow.cameras.back().pos, follow.cameras.front().pos);
  for (size_t k = 0; k < times.size(); ++k) {
    const Eigen::Vector2d px = ImageOf(follow.cameras[k], BaseAt(run, times[k]), o.width, o.height);
    EXPECT_NEAR(px.y(), 0.5 * o.height, 0.1 * o.height) << times[k];
  }
  // A still follows by default.
  inspect::RenderOptions still;
  still.width = 64;
  still.height = 48;
  still.quality = inspect::Quality::kReduced;
  EXPECT_EQ(inspect::RenderStill(run, still, 5.0, TempDir() + "/cam_still.png").camera, "follow");
}

TEST(Render, CameraByNameFromTheModelOrAnErrorListingThem) {
  const std::string run = GeckoWall();
  auto r = RunClimbsim("render " + run + " --at 5 --out " + TempDir() +
                       "/cam_named.png --width 64 --height 48 --quality reduced --camera "
                       "scene_top");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("scene_top camera"), std::string::npos) << r.out;
  r = RunClimbsim("render " + run + " --at 5 --out " + TempDir() + "/cam_bad.png --camera drone");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err,
            "climbsim render: --camera: 'drone' is not follow, fixed or a camera of the model "
            "(scene_overview, scene_top)\n");
}

// The camera's up is −gravity of the run: the scenario's, rotated for an incline exactly as
// the simulation rotated it.
TEST(Render, CameraUpFollowsTheRunsGravity) {
  const std::string wall = GeckoWall();
  const Eigen::Vector3d g = climbsim::inspect::RunGravity(climbsim::inspect::LoadRun(wall));
  EXPECT_EQ(g, Eigen::Vector3d(-9.81, 0, 0));

  const std::string scenario = TempDir() + "/incline.yaml";
  WriteFile(scenario, "robot: gecko\nscene: {name: incline, incline_deg: 60}\nduration_s: 0.05\n");
  const std::string dir = TempDir() + "/incline_run";
  ASSERT_EQ(RunClimbsim("simulate " + scenario + " --out " + dir + " --quiet").code, 0);
  const climbsim::sim::Scenario s = climbsim::sim::LoadScenario(scenario);
  const auto compiled = climbsim::sim::CompileScenario(s);
  const climbsim::sim::World world(*compiled, s);
  EXPECT_EQ(climbsim::inspect::RunGravity(climbsim::inspect::LoadRun(dir)), world.gravity());
  // The rotation happened (incline.xml writes its gravity to 6 digits: |g| = 9.81 to 1e-7).
  EXPECT_NEAR(world.gravity().x(), -9.81 * std::sin(M_PI / 3), 1e-5);
}

}  // namespace
