// What sweep and optimise do when something goes wrong: bad input met only when a point's
// simulation is built is refused before any run (exit code 2, no signal, no folder left); a
// checkpoint that cannot be written stops the run with the file named (exit code 1), the
// previous checkpoint intact; a resumed run never reports a best it did not compute.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "optimise/checkpoint.h"
#include "experiments/experiments.h"
#include "tests/common/test_util.h"

namespace {

namespace fs = std::filesystem;
using climbsim::testing::CliResult;
using climbsim::testing::Has;
using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsimArgs;
using climbsim::testing::Source;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

// Files in `dir` whose name holds `part` (staging folders, temporary files).
int CountNamed(const std::string& dir, const std::string& part) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir)) n += Has(e.path().filename().string(), part);
  return n;
}

// The floor's step is 1 ms: 1.5 ms and 2.5 ms are no whole multiple, which only the
// simulation (it knows the scene's step) can tell. A worker's exception used to abort.
TEST(SweepFailure, APointTheSimulationRefusesIsBadInputBeforeAnyRun) {
  const std::string out = TempDir() + "/sweep_bad_period";
  const CliResult r = RunClimbsimArgs({"sweep", Source("examples/gecko_floor.yaml"), "--key",
                                       "cpg.control_period_s", "--from", "0.0015", "--to", "0.0025",
                                       "--step", "0.001", "--out", out});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_TRUE(Has(r.err, "cpg.control_period_s = 0.0015 gives an invalid scenario")) << r.err;
  EXPECT_TRUE(Has(r.err, "whole multiple")) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(CountNamed(TempDir(), ".sweep_bad_period.climbsim-new"), 0);
}

// A valid point first: it is not run (the refusal comes first), and the error is the lowest
// bad point's whatever the threads.
TEST(SweepFailure, TheLowestBadPointIsNamedForAnyThreadCount) {
  std::string first;
  for (const char* threads : {"1", "4"}) {
    const std::string out = TempDir() + "/sweep_bad_" + threads;
    const CliResult r = RunClimbsimArgs(
        {"sweep", Source("examples/gecko_floor.yaml"), "--key", "cpg.control_period_s", "--from",
         "0.001", "--to", "0.0025", "--step", "0.0005", "--threads", threads, "--out", out});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_TRUE(Has(r.err, "cpg.control_period_s = 0.0015 gives")) << r.err;
    EXPECT_FALSE(fs::exists(out));
    if (first.empty()) first = r.err;
    EXPECT_EQ(r.err, first);
  }
}

const char* kScenario =
    "robot: gecko\nscene: floor\nduration_s: 0.5\n"
    "cpg:\n  gait: trot\n  frequency_hz: 1.0\n  stride_rad: [0.35, 0.0, 0.0]\n"
    "  lift_rad: [0.0, 0.4, 0.3]\n"
    "outputs:\n  trajectory_rate_hz: 0\n"
    "optimise:\n  parameters:\n"
    "    - {key: cpg.frequency_hz, start: 1.0, min: 0.5, max: 2.5}\n"
    "    - {key: \"cpg.stride_rad[0]\", start: 0.35, min: 0.1, max: 0.45}\n"
    "  algorithm: LN_SBPLX\n  max_evaluations: 8\n  starts: 1\n";

CliResult Optimise(const std::string& scenario, const std::string& out, bool resume,
                   long file_size_limit_bytes = 0) {
  std::vector<std::string> args{"optimise", scenario, "--out", out, "--threads", "2", "--quiet"};
  if (resume) args.push_back("--resume");
  return RunClimbsimArgs(args, "", file_size_limit_bytes);
}

int Evaluations(const nlohmann::json& checkpoint) {
  int n = 0;
  for (const auto& s : checkpoint["starts"]) n += static_cast<int>(s.size());
  return n;
}

// RLIMIT_FSIZE of 2000 bytes: scenario.yaml (about 1.4 kB) fits, the checkpoint outgrows it
// after five or six evaluations (about 330 bytes each): the write fails with EFBIG, as on a
// full disk, inside a rollout worker. It used to reach std::terminate (SIGABRT).
TEST(OptimiseFailure, ACheckpointThatCannotBeWrittenStopsTheRunAndKeepsThePreviousOne) {
  const std::string scenario = WriteFile("disk_full.yaml", kScenario);
  const std::string full = TempDir() + "/disk_full_reference", out = TempDir() + "/disk_full";
  ASSERT_EQ(Optimise(scenario, full, false).code, 0);
  const CliResult r = Optimise(scenario, out, false, 2000);
  EXPECT_EQ(r.code, 1) << r.err;  // a failed run, not a signal (-1)
  EXPECT_TRUE(Has(r.err, out + "/checkpoint.json")) << r.err;
  const nlohmann::json kept = nlohmann::json::parse(ReadFile(out + "/checkpoint.json"));
  EXPECT_GE(Evaluations(kept), 1);
  EXPECT_LT(Evaluations(kept), 8);
  EXPECT_EQ(CountNamed(out, ".tmp."), 0);
  EXPECT_FALSE(fs::exists(out + "/best.yaml"));
  // The kept checkpoint is whole: the run resumes from it to the uninterrupted run's end.
  const CliResult resumed = Optimise(scenario, out, true);
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  EXPECT_EQ(ReadFile(out + "/best.yaml"), ReadFile(full + "/best.yaml"));
}

// The checkpoint's checksum as climbsim computes it, as a forger would recompute it.
std::string Checksum(const nlohmann::json& checkpoint) {
  return climbsim::optimise::CheckpointChecksum(checkpoint["fingerprint"].get<std::string>(),
                                                checkpoint["starts"]);
}

// An edited checkpoint with its checksum recomputed passes the checksum; the resumed run
// recomputes the best it would report and refuses the forged value.
TEST(OptimiseFailure, AForgedBestInACheckpointIsNeverReported) {
  const std::string scenario = WriteFile("forged.yaml", kScenario);
  const std::string out = TempDir() + "/forged";
  ASSERT_EQ(Optimise(scenario, out, false).code, 0);
  const std::string best = ReadFile(out + "/best.yaml");
  // An honest resume (every evaluation replayed) recomputes its best to the same bits.
  const CliResult honest = Optimise(scenario, out, true);
  ASSERT_EQ(honest.code, 0) << honest.err;
  EXPECT_EQ(ReadFile(out + "/best.yaml"), best);

  nlohmann::json j = nlohmann::json::parse(ReadFile(out + "/checkpoint.json"));
  j["starts"][0][3]["objective"] = -5.0;
  j["starts"][0][3]["nominal"]["total"] = -5.0;
  j["starts"][0][3]["nominal"]["speed_mps"] = 5.0;
  j["checksum"] = Checksum(j);
  WriteFile(out + "/checkpoint.json", j.dump() + "\n");
  const CliResult forged = Optimise(scenario, out, true);
  EXPECT_EQ(forged.code, 2) << forged.err;
  EXPECT_TRUE(Has(forged.err, "checkpoint.json: starts[0][3].objective: ")) << forged.err;
  EXPECT_TRUE(Has(forged.err, "J = -5,")) << forged.err;
  const nlohmann::json summary = nlohmann::json::parse(ReadFile(out + "/summary.json"));
  EXPECT_NE(summary["best_objective"].get<double>(), -5.0);
  EXPECT_EQ(ReadFile(out + "/best.yaml"), best);
}

}  // namespace
