// `climbsim inspect --plots`: the gait diagram, the per-leg pad plots and the body's path, as
// PNG and SVG next to the run, complete or absent (no temporary files left behind).
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "tests/inspect/inspect_test_util.h"

namespace {

using climbsim::testing::CopyRun;
using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsim;
using climbsim::testing::SharedRun;
using climbsim::testing::Source;
namespace fs = std::filesystem;

std::set<std::string> Files(const std::string& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  return names;
}

void ExpectPlot(const std::string& base) {
  const std::string png = ReadFile(base + ".png"), svg = ReadFile(base + ".svg");
  ASSERT_GT(png.size(), 1000u) << base;
  EXPECT_EQ(png.substr(0, 8), "\x89PNG\r\n\x1a\n") << base;
  EXPECT_NE(svg.find("<svg"), std::string::npos) << base;
  EXPECT_NE(svg.find("</svg>"), std::string::npos) << base;
}

TEST(InspectPlots, WritesGaitPadAndPathPlotsNextToTheRun) {
  const std::string dir =
      CopyRun(SharedRun("gecko_wall", Source("examples/gecko_wall.yaml")), "plots_run");
  const std::set<std::string> before = Files(dir);
  const auto r = RunClimbsim("inspect " + dir + " --plots --from 2 --to 12");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* name : {"gait", "pad_LF", "pad_RF", "pad_LH", "pad_RH", "path"}) {
    ExpectPlot(dir + "/" + name);
    EXPECT_NE(r.out.find(dir + "/" + name + ".png"), std::string::npos) << name;
  }
  std::set<std::string> added;
  for (const auto& f : Files(dir)) {
    if (!before.count(f)) added.insert(f);
  }
  EXPECT_EQ(added.size(), 12u);
  for (const auto& f : added) EXPECT_EQ(f.find(".tmp."), std::string::npos) << f;
  // The gait diagram draws a bar per stance of the window and marks peel detaches.
  const std::string svg = ReadFile(dir + "/gait.svg");
  EXPECT_NE(svg.find("detach: peel"), std::string::npos);
}

TEST(InspectPlots, WithoutATrajectoryThePathIsSkippedAndSaidSo) {
  const std::string dir =
      CopyRun(SharedRun("gecko_wall", Source("examples/gecko_wall.yaml")), "plots_no_traj");
  fs::remove(dir + "/trajectory.csv");
  const auto r = RunClimbsim("inspect " + dir + " --plots");
  ASSERT_EQ(r.code, 0) << r.err;
  ExpectPlot(dir + "/gait");
  ExpectPlot(dir + "/pad_LF");
  EXPECT_FALSE(fs::exists(dir + "/path.png"));
  EXPECT_NE(r.out.find("note: path: the run recorded no trajectory.csv"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("drawn from the events"), std::string::npos) << r.out;
}

// Empty panels are drawn, not refused: a walk without adhesion has no pad events at all, and a
// narrow window of a climb has none either. gnuplot rejects `plot NaN` on an autoscaled axis,
// which once failed `inspect --plots` on the README's own floor run.
TEST(InspectPlots, RunsWithoutPadEventsStillGetEveryPlot) {
  const std::string floor =
      CopyRun(SharedRun("gecko_floor", Source("examples/gecko_floor.yaml")), "plots_floor");
  auto r = RunClimbsim("inspect " + floor + " --plots");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* name : {"gait", "pad_LF", "pad_RF", "pad_LH", "pad_RH", "path"}) {
    ExpectPlot(floor + "/" + name);
  }
  EXPECT_NE(ReadFile(floor + "/pad_LF.svg").find("no pad events in this window"),
            std::string::npos);

  // The first 0.2 s of a climb: the speed (a central difference over 0.5 s) has no point there.
  const std::string wall =
      CopyRun(SharedRun("gecko_wall", Source("examples/gecko_wall.yaml")), "plots_narrow");
  r = RunClimbsim("inspect " + wall + " --plots --from 0 --to 0.2");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* name : {"gait", "pad_LF", "path"}) ExpectPlot(wall + "/" + name);
  EXPECT_NE(ReadFile(wall + "/path.svg").find("it needs 0.25 s of recording either side"),
            std::string::npos);
}

}  // namespace
