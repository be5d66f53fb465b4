// `climbsim pulloff` and the adhesion examples as a user meets them: the sweep writes
// pulloff.csv with both models and the quasi-static columns and draws both models on one
// plot; bad options exit 2 with a message; the help ends with an example that runs; every
// adhesion example runs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "sim/sim.h"
#include "tests/common/test_util.h"

namespace {

using climbsim::testing::CliResult;
using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsim;
using climbsim::testing::SplitCsv;
using climbsim::testing::TempDir;

// 0°, 30°, ..., 180° for both models: the bond model in MuJoCo within 0.3 % of the
// quasi-static column (one ramp step plus the weld's lag), and a PNG that draws both.
TEST(PulloffCli, SweepWritesBothModelsAndThePlot) {
  const std::string dir = TempDir() + "/pulloff";
  const CliResult r = RunClimbsim("pulloff --out " + dir + " --step-deg 30 --grid 8");
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream csv(ReadFile(dir + "/pulloff.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line,
            "angle_deg,force_n,cause,bond_loss_steps,mujoco_force_n,mujoco_cause,quasi_static_n,"
            "closed_form_n,mujoco_closed_form_n,capacity_n");
  int rows = 0;
  while (std::getline(csv, line)) {
    const auto c = SplitCsv(line);
    ASSERT_EQ(c.size(), 10u) << line;
    EXPECT_EQ(std::stod(c[0]), 30.0 * rows);
    const double bonds = std::stod(c[1]), quasi = std::stod(c[6]);
    if (std::isfinite(quasi)) {
      EXPECT_NEAR(bonds, quasi, 3e-3 * quasi) << line;
    }
    EXPECT_FALSE(c[4].empty()) << "the actuator model ran: " << line;
    ++rows;
  }
  EXPECT_EQ(rows, 7);
  const std::string png = ReadFile(dir + "/pulloff.png");
  ASSERT_GT(png.size(), 1000u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  const std::string gp = ReadFile(dir + "/pulloff.gp");
  EXPECT_NE(gp.find("bond model in MuJoCo"), std::string::npos);
  EXPECT_NE(gp.find("MuJoCo adhesion actuator"), std::string::npos);
  EXPECT_NE(r.out.find("outputs " + dir + "/{pulloff.csv,pulloff.gp,pulloff.png}"),
            std::string::npos);
}

TEST(PulloffCli, BadOptionsExitTwoWithAMessage) {
  CliResult r = RunClimbsim("pulloff --out " + TempDir() + "/x --from-deg 90 --to-deg 10");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--from-deg: must be <= --to-deg"), std::string::npos) << r.err;
  r = RunClimbsim("pulloff --out " + TempDir() + "/x --sigma-t-pa -5");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--sigma-t-pa"), std::string::npos) << r.err;
  r = RunClimbsim("pulloff --out " + TempDir() + "/x --model velcro");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--model"), std::string::npos) << r.err;
  EXPECT_EQ(RunClimbsim("pulloff").code, 2) << "--out is required";
}

TEST(PulloffCli, HelpEndsWithAnExampleThatRuns) {
  const CliResult help = RunClimbsim("pulloff --help");
  EXPECT_EQ(help.code, 0);
  const size_t at = help.out.rfind("Example:\n  climbsim ");
  ASSERT_NE(at, std::string::npos) << help.out;
  std::string example = help.out.substr(at + std::string("Example:\n  climbsim ").size());
  example = example.substr(0, example.find('\n'));
  // Run it into the temporary folder, faster (fewer angles), with its own options kept.
  const size_t out = example.find("--out runs/pulloff");
  ASSERT_NE(out, std::string::npos) << example;
  example.replace(out, std::string("--out runs/pulloff").size(),
                  "--out " + TempDir() + "/example --step-deg 45");
  const CliResult r = RunClimbsim(example);
  EXPECT_EQ(r.code, 0) << example << "\n" << r.err;
}

// Every adhesion example runs, holds on (no fall) and stays stable.
TEST(AdhesionExamples, RunAndHold) {
  for (const char* file : {"examples/gecko_wall_hold.yaml", "examples/gecko_ceiling_mujoco.yaml"}) {
    const climbsim::sim::Scenario s = climbsim::sim::LoadScenario(climbsim::testing::Source(file));
    auto model = climbsim::sim::CompileScenario(s);
    climbsim::sim::Simulation sim(s, *model);
    const climbsim::sim::RunResult r = sim.Run();
    EXPECT_TRUE(r.stable) << file << ": " << r.failure;
    EXPECT_FALSE(r.fell) << file;
  }
}

}  // namespace
