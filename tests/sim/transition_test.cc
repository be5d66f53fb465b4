// Surface transitions at sharp corners (issue 17, docs/climbing.md, "Sharp corners"): the shipped
// examples take each corner and go on along the new surface; the last pad leaves the old
// surface only when the front pads hold the new one; a robot without the ankle option is
// refused with the key's place; the step loop through a transition allocates nothing.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <sstream>

#include "sim/sim.h"
#include "tests/common/alloc_counter.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::Source;
using climbsim::testing::WriteFile;

using Row = climbsim::testing::EventRow;
using climbsim::testing::ParseEvents;

// What each corner example must do (issue 17, "Done when").
struct CornerCase {
  std::string example;
  std::string old_surface, new_surface, corner;
  std::vector<std::string> front, hind;  // pads
  Eigen::Vector3d along;                 // travel on the new surface (world)
  double min_after_m;                    // base travel along it after the last pad landed
  double max_all_on_s;                   // every pad on the new surface by then
};
void PrintTo(const CornerCase& c, std::ostream* os) { *os << c.example; }

struct CornerRun {
  RunResult result;
  nlohmann::json transition;
  std::vector<Row> events;
  std::vector<std::pair<double, Eigen::Vector3d>> base;  // (t, base position), ~200 samples
};

CornerRun RunCorner(const Scenario& s) {
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  CornerRun run;
  const auto sample = [&](double) {
    const mjData* d = sim.world().data();
    const double* p = d->qpos + sim.world().robot().root_qpos_adr;
    run.base.emplace_back(d->time, Eigen::Vector3d(p[0], p[1], p[2]));
  };
  sample(0);
  run.result = sim.Run(sample);
  run.transition = sim.Summary()["transition"];
  run.events = ParseEvents(sim.EventsCsv());
  return run;
}

// Each example runs once per test program (both tests below read the same run).
const CornerRun& ExampleRun(const std::string& example) {
  static std::map<std::string, CornerRun> runs;
  auto it = runs.find(example);
  if (it == runs.end()) it = runs.emplace(example, RunCorner(LoadScenario(Source(example)))).first;
  return it->second;
}

// The base position at the first sample at or after t.
Eigen::Vector3d BaseAt(const CornerRun& run, double t) {
  for (const auto& [time, pos] : run.base) {
    if (time >= t) return pos;
  }
  return run.base.back().second;
}

class CornerExample : public ::testing::TestWithParam<CornerCase> {};

// The example runs as shipped (spindle and GTO on), senses its corner with a front pad, has
// every pad on the new surface within the bound and the whole run (60 s) without a fall, and
// then goes on along the new surface. The summary's first and last pads are the events'.
TEST_P(CornerExample, TakesTheCornerAndGoesOnAlongTheNewSurface) {
  const CornerCase& c = GetParam();
  const Scenario s = LoadScenario(Source(c.example));
  ASSERT_TRUE(s.reflex.has_value());
  EXPECT_TRUE(s.reflex->spindle.enabled);
  EXPECT_TRUE(s.reflex->gto.enabled);
  ASSERT_TRUE(s.transition.has_value());
  EXPECT_LE(s.duration_s, 60.0);
  const CornerRun& run = ExampleRun(c.example);
  ASSERT_TRUE(run.result.stable) << run.result.failure;
  EXPECT_FALSE(run.result.fell) << run.result.fall_time_s;
  const nlohmann::json& tr = run.transition;
  ASSERT_TRUE(tr.is_object());
  ASSERT_TRUE(tr["triggered"].get<bool>());
  EXPECT_FALSE(tr["failed"].get<bool>()) << tr.dump();
  EXPECT_EQ(tr["corner"], c.corner);
  EXPECT_EQ(tr["new_surface"], c.new_surface);
  const std::string trigger = tr["trigger_pad"];
  EXPECT_TRUE(std::count(c.front.begin(), c.front.end(), trigger)) << trigger;
  const double all_on = tr["all_on_new_surface_s"];
  EXPECT_GT(all_on, tr["trigger_time_s"].get<double>());
  EXPECT_LE(all_on, c.max_all_on_s);

  // After the last pad landed, the base goes on along the new surface.
  const Eigen::Vector3d after = run.base.back().second - BaseAt(run, all_on);
  EXPECT_GE(c.along.dot(after), c.min_after_m) << "base moved " << after.transpose();

  // The summary's first and last pads are the events': the first attach on the new surface
  // and the last detach from the old one.
  const Row* first_new = nullptr;
  const Row* last_old = nullptr;
  for (const Row& row : run.events) {
    if (row.event == "attach" && row.surface == c.new_surface && first_new == nullptr) {
      first_new = &row;
    }
    if (row.event == "detach" && row.surface == c.old_surface && row.t <= all_on) last_old = &row;
  }
  ASSERT_NE(first_new, nullptr);
  ASSERT_NE(last_old, nullptr);
  EXPECT_EQ(tr["first_new_surface_pad"], first_new->pad);
  EXPECT_NEAR(tr["first_new_surface_attach_s"].get<double>(), first_new->t, 1e-6);  // csv: 1 us
  EXPECT_EQ(tr["last_old_surface_pad"], last_old->pad);
  EXPECT_NEAR(tr["last_old_surface_detach_s"].get<double>(), last_old->t, 1e-6);
  EXPECT_TRUE(std::count(c.front.begin(), c.front.end(), first_new->pad)) << first_new->pad;
  EXPECT_TRUE(std::count(c.hind.begin(), c.hind.end(), last_old->pad)) << last_old->pad;
  EXPECT_LT(first_new->t, last_old->t);
}

// The manoeuvre's order, replayed from the events: the front pads hold the new surface
// before the last pad lets go of the old one, and from the trigger to the last landing at
// least three pads stay attached whenever a planned step lifts one (the planner's
// kMinStance): no planned step leaves the robot on two feet.
TEST_P(CornerExample, HindPadsLeaveTheOldSurfaceOnlyWhenTheFrontPadsHold) {
  const CornerCase& c = GetParam();
  const CornerRun& run = ExampleRun(c.example);
  ASSERT_FALSE(run.result.fell);
  const double trigger = run.transition["trigger_time_s"];
  const double last_old = run.transition["last_old_surface_detach_s"];
  std::map<std::string, std::string> on;  // pad -> surface it is attached to ("" = free)
  bool checked_last = false;
  int steps = 0;
  for (const Row& row : run.events) {
    if (row.event == "attach") on[row.pad] = row.surface;
    if (row.event == "detach") on[row.pad] = "";
    if (row.t < trigger) continue;
    if (row.event == "transition_step" && row.cause == "peel") {
      ++steps;
      int attached = 0;
      for (const auto& [pad, surface] : on) attached += !surface.empty();
      EXPECT_GE(attached, 3) << row.pad << " at " << row.t;
    }
    if (row.event == "detach" && std::abs(row.t - last_old) < 1e-6 && !checked_last) {
      checked_last = true;
      for (const std::string& pad : c.front) {
        EXPECT_EQ(on[pad], c.new_surface) << pad << " when " << row.pad << " let go";
      }
    }
  }
  EXPECT_TRUE(checked_last);
  EXPECT_GE(steps, static_cast<int>(c.front.size() + c.hind.size()));
}

const std::vector<std::string> kGeckoFront = {"LF_pad", "RF_pad"};
const std::vector<std::string> kGeckoHind = {"LH_pad", "RH_pad"};

// Measured (docs/climbing.md, "Sharp corners"): every pad on the new surface at 25.7 s (floor
// to wall), 25.8 s (wall to ceiling), 37.2 s (over the outer corner), 38.2 s (spider); the
// base then goes 0.273, 0.265, 0.169 and 0.132 m on along it by 60 s.
INSTANTIATE_TEST_SUITE_P(
    Examples, CornerExample,
    ::testing::Values(CornerCase{"examples/gecko_floor_to_wall.yaml", "floor", "wall", "inner",
                                 kGeckoFront, kGeckoHind, Eigen::Vector3d(0, 0, 1), 0.20, 45.0},
                      CornerCase{"examples/gecko_wall_to_ceiling.yaml", "wall", "ceiling", "inner",
                                 kGeckoFront, kGeckoHind, Eigen::Vector3d(0, 0, 1), 0.10, 45.0},
                      CornerCase{"examples/gecko_wall_to_top.yaml", "wall", "top", "outer",
                                 kGeckoFront, kGeckoHind, Eigen::Vector3d(0, 0, -1), 0.10, 50.0},
                      CornerCase{"examples/spider_floor_to_wall.yaml",
                                 "floor",
                                 "wall",
                                 "inner",
                                 {"L1_pad", "R1_pad"},
                                 {"L3_pad", "R3_pad"},
                                 Eigen::Vector3d(0, 0, 1),
                                 0.08,
                                 50.0}),
    [](const ::testing::TestParamInfo<CornerCase>& info) {
      std::string name = info.param.example.substr(9);  // past "examples/"
      name = name.substr(0, name.find('.'));
      return name;
    });

// `climbsim simulate` on an example with its first `from` replaced by `to`, written as
// <name>.yaml and run into <name>/ (the edit must find its text).
climbsim::testing::CliResult SimulateEdited(const std::string& example, const std::string& from,
                                           const std::string& to, const std::string& name) {
  std::string text = climbsim::testing::ReadFile(Source(example));
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  const std::string file = WriteFile(name + ".yaml", text);
  return climbsim::testing::RunClimbsim("simulate " + file + " --out " +
                                        climbsim::testing::TempDir() + "/" + name);
}

// The transition needs the ankle option (a servo that turns each pad): the plain gecko is
// refused at load with the file, the line and the key, exit code 2.
TEST(CornerInput, APlainRobotIsRefusedWithTheKeysPlace) {
  const auto r = SimulateEdited("examples/gecko_floor_to_wall.yaml", "robot: gecko_ankle",
                                "robot: gecko", "plain_corner");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("plain_corner.yaml:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("transition"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("ankle"), std::string::npos) << r.err;
}

// A bad value of a transition key is refused with its place, like every key.
TEST(CornerInput, AnUnknownHandBackIsRefused) {
  const auto r = SimulateEdited("examples/gecko_wall_to_top.yaml", "transition:\n",
                                "transition:\n  then: jump\n", "bad_then");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("bad_then.yaml:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("then"), std::string::npos) << r.err;
}

// Nothing allocates in the step loop through a transition: the floor-to-wall example from
// just before its trigger through the first steps of the manoeuvre (peel, swing, place).
TEST(CornerAllocation, TheManoeuvreAllocatesNothing) {
  const Scenario s = LoadScenario(Source("examples/gecko_floor_to_wall.yaml"));
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  const double dt = model->model()->opt.timestep;
  const long before = std::lround(15.0 / dt);  // trigger at 15.3 s (docs)
  for (long i = 0; i < before; ++i) ASSERT_TRUE(sim.Step());
  bool ok = true;
  const auto counts = climbsim::testing::CountAllocations([&] {
    for (int i = 0; i < 4000; ++i) ok &= sim.Step();  // to 19 s: trigger, two steps
  });
  EXPECT_TRUE(ok);
  EXPECT_EQ(counts.news, 0);
  EXPECT_EQ(counts.mallocs, 0);
  EXPECT_TRUE(sim.Summary()["transition"]["triggered"].get<bool>());
}

}  // namespace
}  // namespace climbsim::sim
