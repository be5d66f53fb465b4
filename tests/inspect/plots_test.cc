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

}  // namespace
