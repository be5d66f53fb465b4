// Scenario files: every malformed input is rejected before anything runs, with a message
// that names file:line:col and the key. The messages are compared exactly: they are the
// user interface of a scenario file.
#include <gtest/gtest.h>

#include "cpg/cpg.h"
#include "sim/sim.h"
#include "tests/common/scenario_error.h"
#include "tests/common/test_util.h"

namespace climbsim::sim {
namespace {

using climbsim::testing::WriteFile;

// The error message LoadScenario gives for `text`, or "" when it loads.
std::string ErrorOf(const std::string& name, const std::string& text) {
  return climbsim::testing::ScenarioErrorOf(name, text);
}

const char* kGood = "robot: gecko\nscene: floor\nduration_s: 0.01\n";

TEST(Scenario, MinimalFileLoadsWithDefaults) {
  const Scenario s = LoadScenario(WriteFile("good.yaml", kGood));
  EXPECT_EQ(s.robot, "gecko");
  EXPECT_EQ(s.scene.name, "floor");
  EXPECT_DOUBLE_EQ(s.duration_s, 0.01);
  EXPECT_FALSE(s.physics.timestep_s.has_value());  // absent: the scene's <option>
  EXPECT_FALSE(s.cpg.has_value());  // absent block: effect not constructed
  EXPECT_EQ(ErrorOf("good2.yaml", kGood), "");
}

// The scene files own the physics options; a run records what it used; a key wins.
TEST(Scenario, PhysicsComesFromTheSceneUnlessTheScenarioGivesIt) {
  const auto resolved = [](const std::string& text) {
    const Scenario s = LoadScenario(WriteFile("physics.yaml", text));
    const auto model = CompileScenario(s);
    return Simulation(s, *model).scenario().physics;
  };
  const PhysicsParams floor = resolved(kGood);
  EXPECT_EQ(*floor.timestep_s, 0.001);
  EXPECT_EQ(*floor.integrator, "euler");
  EXPECT_EQ(*floor.cone, "pyramidal");
  EXPECT_EQ(*floor.solver_iterations, 100);
  const PhysicsParams wall = resolved("robot: gecko\nscene: wall\nduration_s: 0.01\n");
  EXPECT_EQ(*wall.integrator, "euler");
  EXPECT_EQ(*wall.cone, "elliptic");
  EXPECT_EQ(*wall.impratio, 10.0);
  const PhysicsParams given = resolved(std::string(kGood) +
                                       "physics:\n  integrator: implicit\n  cone: elliptic\n"
                                       "  timestep_s: 0.0005\n");
  EXPECT_EQ(*given.integrator, "implicit");
  EXPECT_EQ(*given.cone, "elliptic");
  EXPECT_EQ(*given.timestep_s, 0.0005);
  // The resolved file names every option and reads back to the same run.
  const std::string text = ScenarioToYamlText(
      Simulation(LoadScenario(WriteFile("p2.yaml", kGood)),
                 *CompileScenario(LoadScenario(WriteFile("p2.yaml", kGood))))
          .scenario());
  EXPECT_NE(text.find("integrator: euler"), std::string::npos) << text;
  EXPECT_NE(text.find("cone: pyramidal"), std::string::npos) << text;
}

TEST(Scenario, UnknownKeyNamesItsPlaceAndTheKnownKeys) {
  EXPECT_EQ(
      ErrorOf("unknown.yaml", "robot: gecko\nscene: floor\nduration_s: 1\ndurration: 2\n"),
      "unknown.yaml:4:1: durration: unknown key (known here: adhesion, cpg, duration_s, fall, "
      "initial, optimise, outputs, payload_kg, perturbations, physics, reflex, robot, scene, "
      "seed, transition)");
}

TEST(Scenario, UnknownNestedKey) {
  EXPECT_EQ(ErrorOf("nested.yaml",
                    "robot: gecko\nscene: floor\nduration_s: 1\nphysics:\n  timestepp_s: 0.002\n"),
            "nested.yaml:5:3: physics.timestepp_s: unknown key (known here: cone, impratio, "
            "integrator, noslip_iterations, solver_iterations, solver_tolerance, timestep_s)");
}

TEST(Scenario, WrongType) {
  EXPECT_EQ(ErrorOf("type.yaml", "robot: gecko\nscene: floor\nduration_s: ten\n"),
            "type.yaml:3:13: duration_s: expected a number, got 'ten'");
}

TEST(Scenario, NegativeTimeStep) {
  EXPECT_EQ(ErrorOf("dt.yaml", std::string(kGood) + "physics:\n  timestep_s: -0.001\n"),
            "dt.yaml:5:15: physics.timestep_s: must be in (0, 0.05], got -0.001");
}

TEST(Scenario, NotANumber) {
  EXPECT_EQ(ErrorOf("nan.yaml", "robot: gecko\nscene: floor\nduration_s: .nan\n"),
            "nan.yaml:3:13: duration_s: must be finite, got .nan");
}

TEST(Scenario, MissingModelFile) {
  const std::string msg =
      ErrorOf("missing.yaml", "robot: models/nothere.xml\nscene: floor\nduration_s: 1\n");
  EXPECT_EQ(msg, "missing.yaml:1:8: robot: file not found: " + climbsim::testing::TempDir() +
                     "/models/nothere.xml");
}

TEST(Scenario, UnknownBundledScene) {
  EXPECT_EQ(ErrorOf("scene.yaml", "robot: gecko\nscene: moon\nduration_s: 1\n"),
            "scene.yaml:2:8: scene.name: no bundled scene 'moon' (floor, wall, ceiling, "
            "incline, floor_to_wall, floor_to_wall_fillet, wall_to_ceiling, wall_to_top)");
}

TEST(Scenario, BadYamlSyntax) {
  EXPECT_EQ(ErrorOf("syntax.yaml", "robot: gecko\nscene: floor\nduration_s: [1, 2\n"),
            "syntax.yaml:4:1: invalid YAML: end of sequence flow not found");
}

TEST(Scenario, MissingRequiredKey) {
  EXPECT_EQ(ErrorOf("required.yaml", "robot: gecko\nscene: floor\n"),
            "required.yaml:1:1: duration_s: is required");
}

TEST(Scenario, ChoiceOutsideTheList) {
  EXPECT_EQ(ErrorOf("choice.yaml", std::string(kGood) + "physics:\n  integrator: verlet\n"),
            "choice.yaml:5:15: physics.integrator: must be one of euler, rk4, implicit, got "
            "'verlet'");
}

TEST(Scenario, DuplicateKey) {
  EXPECT_EQ(ErrorOf("dup.yaml", "robot: gecko\nscene: floor\nduration_s: 1\nduration_s: 2\n"),
            "dup.yaml:4:1: duration_s: key appears twice");
}

TEST(Scenario, ListOfWrongLength) {
  EXPECT_EQ(ErrorOf("list.yaml", std::string(kGood) + "initial:\n  offset_m: [0, 0]\n"),
            "list.yaml:5:13: initial.offset_m: expected 3 numbers, got 2");
}

TEST(Scenario, MapExpected) {
  EXPECT_EQ(ErrorOf("map.yaml", std::string(kGood) + "physics: 5\n"),
            "map.yaml:4:10: physics: expected a map of keys, got '5'");
}

TEST(Scenario, GaitThatDoesNotFitTheRobot) {
  EXPECT_EQ(ErrorOf("gait.yaml", std::string(kGood) + "cpg:\n  gait: tripod\n"),
            "gait.yaml:5:9: cpg.gait: " + [] {
              try {
                cpg::GaitPreset("tripod", 4);
              } catch (const std::invalid_argument& e) {
                return std::string(e.what());
              }
              return std::string("(no error)");
            }());
}

TEST(Scenario, TwoGaitsAtOnce) {
  EXPECT_EQ(ErrorOf("two.yaml", std::string(kGood) +
                                    "cpg:\n  gait: trot\n  offsets_cycles: [0, 0.5, 0.5, 0]\n"),
            "two.yaml:6:19: cpg.offsets_cycles: give only one of gait, offsets_cycles and "
            "phase_bias_rad");
}

TEST(Scenario, ControlPeriodNotAMultipleOfTheTimeStep) {
  EXPECT_EQ(ErrorOf("period.yaml", std::string(kGood) + "cpg:\n  control_period_s: 0.0015\n"),
            "period.yaml:5:21: cpg.control_period_s: must be a whole multiple of "
            "physics.timestep_s (0.001 s, the scene's)");
}

TEST(Scenario, EmptyFile) {
  EXPECT_EQ(ErrorOf("empty.yaml", ""), "empty.yaml:1:1: file is empty");
}

TEST(Scenario, InclineAngleOutOfRange) {
  EXPECT_EQ(ErrorOf("incline.yaml",
                    "robot: gecko\nscene:\n  name: incline\n  incline_deg: 200\nduration_s: 1\n"),
            "incline.yaml:4:16: scene.incline_deg: must be in [0, 180], got 200");
}

TEST(Scenario, ResolvedScenarioReadsBackToTheSameValues) {
  Scenario s = LoadScenario(WriteFile(
      "resolved.yaml", std::string(kGood) + "cpg:\n  frequency_hz: 0.1\n  gait: trot\n"));
  const std::string text = ScenarioToYamlText(s);
  const Scenario back = LoadScenario(WriteFile("resolved_back.yaml", text));
  EXPECT_EQ(ScenarioToYamlText(back), text);
  ASSERT_TRUE(back.cpg.has_value());
  EXPECT_EQ(back.cpg->frequency_hz, 0.1);  // exact: shortest round-trip text
}

TEST(Scenario, KeyTableInTheDocsIsCurrent) {
  const std::string docs =
      climbsim::testing::ReadFile(climbsim::testing::Source("docs/scenario.md"));
  const std::string begin = "<!-- keys:begin (generated by `climbsim keys`) -->\n";
  const size_t a = docs.find(begin), b = docs.find("<!-- keys:end -->");
  ASSERT_NE(a, std::string::npos);
  ASSERT_NE(b, std::string::npos);
  EXPECT_EQ(docs.substr(a + begin.size(), b - a - begin.size()), ScenarioKeysMarkdown())
      << "docs/scenario.md is out of date: paste the output of `climbsim keys`";
}

}  // namespace
}  // namespace climbsim::sim
