// Climbing control (issue: climbing gaits; issue 12: spindle and GTO on): the bundled wall and
// ceiling examples climb and hang as documented, the gecko walks from the floor onto the wall round
// a fillet, the climbing reflexes recover from a push that the same gait without them does not
// survive, and every climbing reflex is logged on the leg that fired it. Body lengths are those of
// mjcf/README.md: gecko 0.10 m, spider 0.16 m.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "sim/sim.h"
#include "tests/common/run_scenario.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::RunScenario;
using climbsim::testing::Source;
using climbsim::testing::WriteFile;

// The example's text with extra YAML appended (a push, a reflex switched off).
Scenario ExampleWith(const std::string& example, const std::string& name,
                     const std::string& replace_from = "", const std::string& replace_to = "",
                     const std::string& append = "") {
  std::string text = climbsim::testing::ReadFile(Source(example));
  if (!replace_from.empty()) {
    const size_t at = text.find(replace_from);
    EXPECT_NE(at, std::string::npos) << replace_from;
    text.replace(at, replace_from.size(), replace_to);
  }
  return LoadScenario(WriteFile(name, text + append));
}

// The climbing examples run with the spindle and GTO reflexes on (issue 12).
void ExpectSpindleAndGtoOn(const Scenario& s) {
  ASSERT_TRUE(s.reflex.has_value());
  EXPECT_TRUE(s.reflex->spindle.enabled);
  EXPECT_TRUE(s.reflex->gto.enabled);
}

TEST(Climb, GeckoClimbsThreeBodyLengthsUpAWallIn20s) {
  const Scenario s = LoadScenario(Source("examples/gecko_wall.yaml"));
  ExpectSpindleAndGtoOn(s);
  const RunResult r = RunScenario(s);
  ASSERT_TRUE(r.stable) << r.failure;
  EXPECT_FALSE(r.fell) << r.fall_time_s;
  EXPECT_GE(r.distance_m, 3 * 0.10);
  EXPECT_GE(r.distance_m, 0.34);  // issue 12: with spindle and GTO on
}

TEST(Climb, SpiderClimbsTwoBodyLengthsUpAWallIn20s) {
  const Scenario s = LoadScenario(Source("examples/spider_wall.yaml"));
  ExpectSpindleAndGtoOn(s);
  const RunResult r = RunScenario(s);
  ASSERT_TRUE(r.stable) << r.failure;
  EXPECT_FALSE(r.fell) << r.fall_time_s;
  EXPECT_GE(r.distance_m, 2 * 0.16);
  EXPECT_GE(r.distance_m, 0.46);  // issue 12: with spindle and GTO on
}

// GTO's load channel on a welded pad (load_attached, Ekeberg and Pearson's rule and Geyer and
// Herr's press as they were): on a wall the front pads hang loaded all the time, so the loaded
// legs press their welded feet and hold stance, and the gecko falls. The default leaves
// attached pads to the support and unload channels (utilisation) and climbs.
TEST(Climb, LoadChannelOnWeldedPadsLosesTheWall) {
  const Scenario base = ExampleWith("examples/gecko_wall.yaml", "load_hold.yaml",
                                    "duration_s: 20", "duration_s: 4");
  Scenario welded = base;
  welded.reflex->gto.load_attached = true;
  const RunResult free = RunScenario(base);
  const RunResult lost = RunScenario(welded);
  EXPECT_FALSE(free.fell);
  EXPECT_GT(free.distance_m, 0.05);
  EXPECT_TRUE(lost.fell);
}

TEST(Climb, GeckoWalksUnderTheCeilingFor20sWithoutFalling) {
  const Scenario s = LoadScenario(Source("examples/gecko_ceiling.yaml"));
  ASSERT_EQ(s.duration_s, 20.0);
  ExpectSpindleAndGtoOn(s);
  const RunResult r = RunScenario(s);
  ASSERT_TRUE(r.stable) << r.failure;
  EXPECT_FALSE(r.fell) << r.fall_time_s;
  EXPECT_GT(r.distance_m, 0.02);  // walking, not only hanging
}

// Without the reflex block the wall gait cannot even lift its feet: a swing drags its pad
// along instead of peeling it, and the robot falls within a second.
TEST(Climb, WithoutReflexesTheWallGaitFalls) {
  std::string text = climbsim::testing::ReadFile(Source("examples/gecko_wall.yaml"));
  text = text.substr(0, text.find("reflex:\n")) +
         text.substr(text.find("optimise:\n"));  // reflex block dropped
  const RunResult r = RunScenario(LoadScenario(WriteFile("noreflex2.yaml", text)));
  EXPECT_TRUE(r.fell);
  EXPECT_LT(r.fall_time_s, 1.0);
}

// The push: 0.6 N sideways on the right front tibia for 0.3 s (0.18 N s) at t = 3 s, while
// that leg is in stance. GTO unload softens the leg as its pad's utilisation passes 0.8, the
// other pads take the load, and the pad loses no bond (before the closed-chain GTO it lost a
// row and the re-grip reflex saved it). The same gait and push with re-grip and GTO off
// falls: the crack runs on through the pad and the robot peels off the wall.
const char* kPush =
    "perturbations:\n  - {time_s: 3.0, body: RF_tibia, impulse_ns: [0, 0.18, 0], duration_s: "
    "0.3}\n";

TEST(Climb, ReflexesSurviveAPushThatTheGaitWithoutThemDoesNot) {
  const Scenario with = ExampleWith("examples/gecko_wall.yaml", "push_on.yaml", "", "", kPush);
  Scenario without = ExampleWith("examples/gecko_wall.yaml", "push_off.yaml",
                                 "    posture: {enabled: true}\n",
                                 "    enabled: false\n    posture: {enabled: true}\n", kPush);
  without.reflex->regrip.enabled = false;
  std::string events;
  const RunResult on = RunScenario(with, &events);
  const RunResult off = RunScenario(without);
  EXPECT_FALSE(on.fell) << on.fall_time_s;
  EXPECT_GE(on.distance_m, 3 * 0.10);
  EXPECT_NE(events.find("RF_pad,gto_unload"), std::string::npos);
  EXPECT_TRUE(off.fell);
  EXPECT_LT(off.distance_m, on.distance_m - 0.1);
}

// GTO alone (re-grip off) on the same push and seed: the pushed pad passes utilisation 0.8, its
// leg yields (gto_unload) and the legs that would lift wait (gto_hold, support): the gecko
// climbs on. With GTO off as well it falls (the test above).
TEST(Climb, GtoUnloadAndSupportSurviveThePushWithoutRegrip) {
  Scenario s = ExampleWith("examples/gecko_wall.yaml", "push_gto.yaml", "", "", kPush);
  s.reflex->regrip.enabled = false;
  std::string events;
  const RunResult r = RunScenario(s, &events);
  EXPECT_FALSE(r.fell) << r.fall_time_s;
  EXPECT_GE(r.distance_m, 3 * 0.10);
  EXPECT_NE(events.find("RF_pad,gto_unload"), std::string::npos);
  EXPECT_NE(events.find("gto_hold,support"), std::string::npos);
}

using Row = climbsim::testing::EventRow;
using climbsim::testing::ParseEvents;

// The first row after (or at) index i of `event` on `pad`, or nullptr.
const Row* Next(const std::vector<Row>& rows, size_t i, const std::string& pad,
                const std::string& event) {
  for (; i < rows.size(); ++i) {
    if (rows[i].pad == pad && rows[i].event == event) return &rows[i];
  }
  return nullptr;
}

// Each climbing reflex is logged on the leg that fired it, which the adhesion events of that
// same pad confirm: a peel is followed by that pad's detach (cause peel) within the peel's
// time limit; a preload starts at that pad's touchdown; a search ends when that pad touches;
// a re-grip fires in the control period in which that pad lost bonds.
TEST(Climb, EveryClimbingReflexIsLoggedOnTheLegThatFiredIt) {
  std::string wall_events, ceiling_events;
  // The push and a few failing pads (10 % of the attachments) make sure re-grips happen: with
  // load sharing the push alone no longer costs a bond.
  RunScenario(ExampleWith("examples/gecko_wall.yaml", "push_log.yaml", "adhesion:\n",
                          "adhesion:\n  pad_failure_probability: 0.1\n", kPush),
              &wall_events);
  RunScenario(LoadScenario(Source("examples/gecko_ceiling.yaml")), &ceiling_events);
  int seen[4] = {0, 0, 0, 0};  // peel, preload, search, regrip
  for (const std::string& csv : {wall_events, ceiling_events}) {
    const std::vector<Row> rows = ParseEvents(csv);
    for (size_t i = 0; i < rows.size(); ++i) {
      const Row& r = rows[i];
      if (r.event == "peel") {
        ++seen[0];
        const Row* detach = Next(rows, i, r.pad, "detach");
        ASSERT_NE(detach, nullptr) << r.pad << " " << r.t;
        const Row* end = Next(rows, i, r.pad, "peel_end");
        ASSERT_NE(end, nullptr);
        if (end->cause == "detached") {
          EXPECT_EQ(detach->cause, "peel") << r.pad << " " << r.t;
          EXPECT_LE(detach->t - r.t, 0.6 + 1e-9) << r.pad;  // peel.max_duration_s
        }
      } else if (r.event == "preload_start" && r.cause == "touchdown") {
        ++seen[1];
        // The reflex sees the touchdown at its next control tick: within 20 ms here.
        bool touched = false;
        for (size_t j = 0; j < i; ++j) {
          touched |= rows[j].pad == r.pad && rows[j].event == "touchdown" && r.t - rows[j].t < 0.02;
        }
        EXPECT_TRUE(touched) << r.pad << " " << r.t;
      } else if (r.event == "search_end" && r.cause == "found") {
        ++seen[2];
        bool touched = false;
        for (size_t j = 0; j < rows.size(); ++j) {
          touched |= rows[j].pad == r.pad && rows[j].event == "touchdown" &&
                     std::abs(r.t - rows[j].t) < 0.02;
        }
        EXPECT_TRUE(touched) << r.pad << " " << r.t;
      } else if (r.event == "regrip" && r.cause == "touchdown") {
        // A landing that did not attach: a touchdown of this pad earlier, no attach since.
        bool touched = false, attached = false;
        for (size_t j = 0; j < i; ++j) {
          if (rows[j].pad != r.pad) continue;
          if (rows[j].event == "touchdown") touched = true, attached = false;
          if (rows[j].event == "attach") attached = true;
        }
        EXPECT_TRUE(touched && !attached) << r.pad << " " << r.t;
      } else if (r.event == "regrip") {
        ++seen[3];
        bool lost = false;
        for (size_t j = 0; j < i + 1; ++j) {
          lost |= rows[j].pad == r.pad && rows[j].event == "bonds_lost" && r.t - rows[j].t < 0.002;
        }
        EXPECT_TRUE(lost) << r.pad << " " << r.t;
      }
    }
  }
  for (int k = 0; k < 4; ++k) EXPECT_GT(seen[k], 0) << "reflex " << k << " never fired";
}

// Floor to wall round a fillet of radius 0.20 m (docs/climbing.md, "Floor to wall"). The base
// starts at z = 0.055 on the floor; the fillet meets the wall at z = 0.20. Measured: the first
// front pad attaches to the wall at 40.1 s, the last hind pad at 50.5 s, and at 60 s the base
// is at z = 0.363 m, pitched up 89°, every pad on the wall (0.551 m along the L). The bounds:
// the base at least 0.10 m above the fillet's top (so the robot climbs the wall itself, not the
// bend), standing within 10° of vertical, and each pad's last attach on the wall geom.
TEST(Climb, GeckoWalksFromTheFloorOntoTheWallRoundAFillet) {
  const Scenario s = LoadScenario(Source("examples/gecko_floor_to_wall_fillet.yaml"));
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  const RunResult r = sim.Run();
  ASSERT_TRUE(r.stable) << r.failure;
  EXPECT_FALSE(r.fell) << r.fall_time_s;
  EXPECT_GE(r.distance_m, 0.5);
  const mjData* d = sim.world().data();
  const double* root = d->qpos + sim.world().robot().root_qpos_adr;
  EXPECT_GE(root[2], 0.20 + 0.10) << "base z";
  // Pitch: the body's forward axis against the horizontal, sin = its z component.
  const double q0 = root[3], q1 = root[4], q2 = root[5], q3 = root[6];
  const double forward_z = 2 * (q1 * q3 - q0 * q2);
  EXPECT_GE(forward_z, std::sin(80.0 * M_PI / 180.0));
  const std::vector<Row> rows = ParseEvents(sim.EventsCsv());
  for (const char* pad : {"LF_pad", "RF_pad", "LH_pad", "RH_pad"}) {
    const Row* last = nullptr;
    for (const Row& row : rows) {
      if (row.pad == pad && row.event == "attach") last = &row;
    }
    ASSERT_NE(last, nullptr) << pad;
    EXPECT_EQ(last->surface, "wall") << pad;
    EXPECT_LT(last->t, 60.0) << pad;
  }
}

// The fall monitor calls a base turned more than fall.turn_over_deg (default 90°) from its
// start normal turned over. A floor-to-wall climb does that on purpose once the body passes
// vertical: with the default the same run is flagged fallen while it climbs on, which is why
// the example sets 135°.
TEST(Climb, FloorToWallPastVerticalIsATurnOverAtTheDefaultAngle) {
  Scenario s = ExampleWith("examples/gecko_floor_to_wall_fillet.yaml", "f2w_turn.yaml",
                           "turn_over_deg: 135", "turn_over_deg: 90");
  s.fall.stop = false;  // simulate on past the "fall" to see the climb go on
  const RunResult r = RunScenario(s);
  ASSERT_TRUE(r.stable) << r.failure;
  EXPECT_TRUE(r.fell);
  EXPECT_GT(r.fall_time_s, 40.0);       // near the wall, not on the floor
  EXPECT_GE(r.distance_at_end_m, 0.5);  // and it went on climbing
}

// Under the ceiling a re-placed foot can come down on nothing (the body sags while a pad is
// gone): it then searches, as after a short swing, and the walk goes on. Without that search
// RF hung in the air from 12.9 s and the gait stood to the end (0.074 m).
TEST(Climb, UnderTheCeilingARePlacedFootThatFindsNothingSearchesAndTheWalkGoesOn) {
  std::string events;
  const RunResult r = RunScenario(LoadScenario(Source("examples/gecko_ceiling.yaml")), &events);
  ASSERT_TRUE(r.stable) << r.failure;
  EXPECT_FALSE(r.fell);
  EXPECT_GE(r.distance_m, 0.08);
  const std::vector<Row> rows = ParseEvents(events);
  int searched_after_replace = 0;
  for (size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].event != "regrip" || rows[i].cause != "touchdown") continue;
    // The re-place lasts regrip.replace_s (0.25 s); its search starts at the next tick.
    const Row* search = Next(rows, i, rows[i].pad, "search_start");
    if (search == nullptr || search->t - rows[i].t > 0.25 + 0.002) continue;
    ++searched_after_replace;
    const Row* attach = Next(rows, i, rows[i].pad, "attach");
    ASSERT_NE(attach, nullptr) << rows[i].pad << " " << rows[i].t;  // found the ceiling again
  }
  EXPECT_GE(searched_after_replace, 1);
}

}  // namespace
}  // namespace climbsim::sim
