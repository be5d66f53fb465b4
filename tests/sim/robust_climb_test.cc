// Issue 12's loads: the climbers with active-release feet (mjcf/gecko_active.xml,
// spider_active.xml; reflex.peel.active_release) carry a payload of their own mass up the
// wall, which the same gaits on leg-peeled pads cannot; load sharing (reflex.gto.share) is
// what makes a pad's release gentle and lets the leg-peel spider carry 0.1 kg. Each claim is a
// comparison on the same scenario with one thing changed, or a bound on a 20 s climb.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "sim/sim.h"
#include "tests/common/scenario_error.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::Source;

struct Outcome {
  RunResult result;
  double robot_mass_kg = 0.0;
  std::string events;
};

// The example, with `edit` applied to the parsed scenario.
template <class Edit>
Outcome RunExample(const std::string& example, Edit edit) {
  Scenario s = LoadScenario(Source(example));
  edit(&s);
  auto model = CompileScenario(s);
  Simulation sim(s, *model);
  Outcome o;
  o.result = sim.Run();
  o.robot_mass_kg = model->robot().mass_kg;
  o.events = sim.EventsCsv();
  return o;
}

Outcome RunExample(const std::string& example) {
  return RunExample(example, [](Scenario*) {});
}

// The robot's own mass, as compiled (the payload of the test).
double OwnMass(const std::string& example) {
  const Scenario s = LoadScenario(Source(example));
  return CompileScenario(s)->robot().mass_kg;
}

TEST(RobustClimb, ActiveReleaseExamplesClimbWithSpindleAndGtoOn) {
  for (const auto& [example, at_least_m] :
       std::vector<std::pair<std::string, double>>{{"examples/gecko_wall_active.yaml", 0.40},
                                                   {"examples/spider_wall_active.yaml", 0.50}}) {
    const Scenario s = LoadScenario(Source(example));
    ASSERT_TRUE(s.reflex.has_value());
    EXPECT_TRUE(s.reflex->spindle.enabled && s.reflex->gto.enabled);
    EXPECT_TRUE(s.reflex->peel.active_release);
    const Outcome o = RunExample(example);
    ASSERT_TRUE(o.result.stable) << example << ": " << o.result.failure;
    EXPECT_FALSE(o.result.fell) << example;
    EXPECT_GE(o.result.distance_m, at_least_m) << example;
  }
}

// `example` carries its own mass (as compiled: `mass_kg`) 0.2 m up the wall in 20 s without a
// fall, and `peeled` (the same gait on leg-peeled pads) with `peeled_payload_kg` falls.
void ExpectCarriesItsOwnMass(const std::string& example, double mass_kg, const std::string& peeled,
                             double peeled_payload_kg) {
  const double mass = OwnMass(example);
  EXPECT_NEAR(mass, mass_kg, 1e-4) << example;
  const Outcome o = RunExample(example, [&](Scenario* s) { s->payload_kg = mass; });
  ASSERT_TRUE(o.result.stable) << example << ": " << o.result.failure;
  EXPECT_FALSE(o.result.fell) << example << " fell at " << o.result.fall_time_s;
  EXPECT_GE(o.result.distance_m, 0.2) << example;
  const Outcome p = RunExample(peeled, [&](Scenario* s) { s->payload_kg = peeled_payload_kg; });
  EXPECT_TRUE(p.result.fell) << peeled;
}

// The gecko carries its own mass (0.1045 kg); gecko_wall.yaml's gait with its own (0.1025 kg)
// falls: the peel's pull, the pad's whole capacity, snaps onto three pads that already carry
// twice the weight.
TEST(RobustClimb, GeckoCarriesItsOwnMassUpTheWall) {
  ExpectCarriesItsOwnMass("examples/gecko_wall_active.yaml", 0.1045, "examples/gecko_wall.yaml",
                          0.1025);
}

// The spider carries its own mass (0.3602 kg); spider_wall.yaml's gait falls with 0.2 kg.
TEST(RobustClimb, SpiderCarriesItsOwnMassUpTheWall) {
  ExpectCarriesItsOwnMass("examples/spider_wall_active.yaml", 0.3602, "examples/spider_wall.yaml",
                          0.2);
}

// The released pads' loads, from events.csv (detach rows with cause released): |F| in N.
std::vector<double> ReleasedLoads(const std::string& events_csv) {
  std::vector<double> loads;
  std::istringstream in(events_csv);
  std::string line;
  while (std::getline(in, line)) {
    if (line.find(",detach,released,") == std::string::npos) continue;
    std::vector<double> cols;
    std::stringstream row(line);
    std::string cell;
    while (std::getline(row, cell, ',')) cols.push_back(cell.empty() ? 0.0 : std::atof(cell.c_str()));
    // time,pad,event,cause,surface,bonded_fraction,fn,fx,fy,mx,my
    loads.push_back(std::sqrt(cols[6] * cols[6] + cols[7] * cols[7] + cols[8] * cols[8]));
  }
  return loads;
}

// An active release lets a pad go after the other legs have taken its load: with load sharing
// most releases carry at most release_load_n (0.2 N); without it the tendon lets go at the
// time limit, the pad still loaded.
TEST(RobustClimb, ActiveReleaseLetsGoOfAnUnloadedPad) {
  const auto count = [](const std::vector<double>& loads, double at_most) {
    int n = 0;
    for (double l : loads) n += l <= at_most ? 1 : 0;
    return n;
  };
  const Outcome shared = RunExample("examples/gecko_wall_active.yaml");
  const std::vector<double> with = ReleasedLoads(shared.events);
  ASSERT_GE(with.size(), 20u);
  EXPECT_GE(count(with, 0.2), 0.8 * with.size());
  const Outcome alone = RunExample("examples/gecko_wall_active.yaml", [](Scenario* s) {
    s->reflex->gto.share.gain_per_s = 0.0;
  });
  const std::vector<double> without = ReleasedLoads(alone.events);
  ASSERT_GE(without.size(), 10u);
  EXPECT_LE(count(without, 0.2), 0.2 * without.size());
}

// GTO load sharing on the leg-peel spider: with a 0.1 kg payload it climbs; the same run
// without it (share gain 0) falls.
TEST(RobustClimb, LoadSharingCarriesAPayloadTheSpiderDropsWithoutIt) {
  const auto with_payload = [](double gain) {
    return [gain](Scenario* s) {
      s->duration_s = 10;
      s->payload_kg = 0.1;
      s->reflex->gto.share.gain_per_s = gain;
    };
  };
  const Outcome on = RunExample("examples/spider_wall.yaml", with_payload(100.0));
  EXPECT_FALSE(on.result.fell);
  EXPECT_GE(on.result.distance_m, 0.15);
  const Outcome off = RunExample("examples/spider_wall.yaml", with_payload(0.0));
  EXPECT_TRUE(off.result.fell || off.result.distance_m < 0.05) << off.result.distance_m;
}

// The GTO's posture channel (reflex.gto.posture, on in gecko_wall.yaml): the pads' pull lowers
// the body on the wall, by max_crouch_m at the feet (12.5 mm: the pull over weight, ~0.36, asks
// for more),
// and with it the moment the front pads hold. On the same 10 s scenario with 0.03 kg on its
// back (29 % of its mass) the gecko climbs with the posture and falls without it.
TEST(RobustClimb, PostureLowersTheBodyOnTheWallAndCarriesAPayloadTheUprightGaitDrops) {
  const std::string example = "examples/gecko_wall.yaml";
  ASSERT_TRUE(LoadScenario(Source(example)).reflex->gto.posture.enabled);
  const auto run = [&](bool posture, double payload_kg, double* mean_standoff_m) {
    Scenario s = LoadScenario(Source(example));
    s.duration_s = 10.0;
    s.payload_kg = payload_kg;
    s.reflex->gto.posture.enabled = posture;
    auto model = CompileScenario(s);
    Simulation sim(s, *model);
    const RunResult r = sim.Run();
    if (mean_standoff_m != nullptr) {
      // The base's height over the wall (z = 0) in trajectory.csv, from 3 s on (the crouch's
      // lag is 0.3 s).
      std::istringstream csv(sim.TrajectoryCsv());
      std::string line, cell;
      std::getline(csv, line);
      int t_col = -1, z_col = -1, col = 0;
      for (std::istringstream head(line); std::getline(head, cell, ','); ++col) {
        if (cell == "time_s") t_col = col;
        if (cell == "base_z_m") z_col = col;
      }
      double sum = 0.0;
      int n = 0;
      while (std::getline(csv, line)) {
        std::vector<double> v;
        for (std::istringstream row(line); std::getline(row, cell, ',');) v.push_back(std::stod(cell));
        if (v.at(t_col) >= 3.0) sum += v.at(z_col), ++n;
      }
      *mean_standoff_m = n > 0 ? sum / n : 0.0;
    }
    return r;
  };
  double up = 0.0, down = 0.0;
  const RunResult upright = run(false, 0.0, &up);
  const RunResult crouched = run(true, 0.0, &down);
  ASSERT_FALSE(upright.fell);
  ASSERT_FALSE(crouched.fell);
  // 12.5 mm commanded at the feet; the base lowers 8.9 mm (measured), and not at all upright.
  EXPECT_NEAR(up - down, 0.0089, 0.0015) << up << " " << down;
  EXPECT_GE(crouched.distance_m, upright.distance_m - 0.005);   // no slower for it

  const RunResult with = run(true, 0.03, nullptr);
  const RunResult without = run(false, 0.03, nullptr);
  ASSERT_TRUE(with.stable && without.stable);
  EXPECT_FALSE(with.fell) << with.fall_time_s;
  EXPECT_GE(with.distance_m, 0.15);
  EXPECT_TRUE(without.fell);
}

// A run after Simulation::Reset is the fresh run bit for bit, trajectory.csv whole: the feet
// are placed standing, not at the posture's crouch the previous run ended in (which put them
// off the wall and the rerun fell), and the first row's utilisations are 0, not the previous
// run's last (a released bond grid kept its stress field).
TEST(RobustClimb, ARerunAfterResetIsTheFreshRunBitForBit) {
  Scenario s = LoadScenario(Source("examples/gecko_wall.yaml"));
  ASSERT_TRUE(s.reflex->gto.posture.enabled);
  s.duration_s = 3.0;
  auto model = CompileScenario(s);
  Simulation fresh(s, *model);
  const RunResult first = fresh.Run();
  const std::string first_csv = fresh.TrajectoryCsv();
  fresh.Reset();
  const RunResult again = fresh.Run();
  EXPECT_FALSE(again.fell);
  EXPECT_EQ(again.distance_m, first.distance_m);
  EXPECT_EQ(fresh.TrajectoryCsv(), first_csv);
}

// The posture moves the feet along the body's normal: it needs a foot-space gait and pads; a
// file that asks for it otherwise is refused at the key's line, before anything runs.
TEST(RobustClimb, PostureNeedsAFootSpaceGaitAndPads) {
  std::string text = climbsim::testing::ReadFile(Source("examples/gecko_wall.yaml"));
  const size_t at = text.find("  stride_m: 0.03");
  ASSERT_NE(at, std::string::npos);
  std::string joint_space = text;
  joint_space.replace(at, 16, "  stride_rad: [0.35, 0, 0]");
  const std::string e = climbsim::testing::ScenarioErrorOf("posture_joint.yaml", joint_space);
  EXPECT_NE(e.find("posture_joint.yaml:"), std::string::npos) << e;
  EXPECT_NE(e.find("reflex.gto.posture.enabled"), std::string::npos) << e;
  EXPECT_NE(e.find("cpg.stride_m"), std::string::npos) << e;
  EXPECT_EQ(climbsim::testing::ScenarioErrorOf("posture_ok.yaml", text), "");
}

}  // namespace
}  // namespace climbsim::sim
