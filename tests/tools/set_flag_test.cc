// --set KEY=VALUE on every verb that reads a scenario file. The file below is refused on its
// own (duration_s: 0 is out of range); each verb runs it once --set gives a valid duration,
// which shows the flag reaches the scenario every verb reads. A bad value is refused naming
// the flag, with exit code 2, before anything runs; the run's scenario.yaml holds the value.
#include <gtest/gtest.h>

#include <filesystem>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "tests/common/test_util.h"

namespace {

using climbsim::testing::CliResult;
using climbsim::testing::Has;
using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsimArgs;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

const char* kBroken =
    "robot: gecko\nscene: floor\nduration_s: 0\n"
    "cpg:\n  gait: trot\n  frequency_hz: 1.0\n"
    "outputs:\n  trajectory_rate_hz: 0\n"
    "optimise:\n  parameters:\n    - {key: cpg.frequency_hz, start: 1.0, min: 0.5, max: 1.5}\n";

struct Verb {
  const char* name;
  std::vector<std::string> args;  // after the scenario file; OUT is the verb's own folder
};

void PrintTo(const Verb& v, std::ostream* os) { *os << v.name; }

std::vector<std::string> Args(const Verb& v, const std::string& file, const std::string& out) {
  std::vector<std::string> args;
  std::string word = v.name;
  for (size_t sp; (sp = word.find(' ')) != std::string::npos; word = word.substr(sp + 1)) {
    args.push_back(word.substr(0, sp));
  }
  args.push_back(word);
  args.push_back(file);
  for (const std::string& a : v.args) args.push_back(a == "OUT" ? out : a);
  return args;
}

class SetFlag : public ::testing::TestWithParam<Verb> {};

TEST_P(SetFlag, FixesTheRefusedFileOnEveryVerbThatReadsOne) {
  const Verb& v = GetParam();
  const std::string file = WriteFile("set_flag_broken.yaml", kBroken);
  std::string tag = v.name;
  for (char& c : tag) c = c == ' ' ? '_' : c;
  const std::string out = TempDir() + "/set_flag_" + tag;
  std::filesystem::remove_all(out);
  const CliResult refused = RunClimbsimArgs(Args(v, file, out));
  EXPECT_EQ(refused.code, 2) << refused.err;
  EXPECT_TRUE(Has(refused.err, "duration_s")) << refused.err;
  std::filesystem::remove_all(out);
  std::vector<std::string> args = Args(v, file, out);
  args.insert(args.end(), {"--set", "duration_s=0.05"});
  const CliResult r = RunClimbsimArgs(args);
  EXPECT_EQ(r.code, 0) << r.err;
}

INSTANTIATE_TEST_SUITE_P(
    Verbs, SetFlag,
    ::testing::Values(
        Verb{"simulate", {"--out", "OUT", "--quiet"}},
        Verb{"model", {"--out", "OUT"}},
        Verb{"sweep", {"--key", "cpg.frequency_hz", "--from", "1", "--to", "1.5", "--step", "0.5",
                       "--threads", "1", "--out", "OUT"}},
        Verb{"optimise", {"--out", "OUT", "--max-evaluations", "2", "--threads", "1", "--quiet"}},
        Verb{"bench speed", {"--duration", "0.02", "--repetitions", "1"}},
        Verb{"bench accuracy", {"--duration", "0.02", "--threads", "1", "--out", "OUT"}},
        Verb{"bench optimise", {"--evaluations", "2", "--only", "threads", "--out", "OUT"}},
        Verb{"bench robustness", {"--duration", "0.05", "--seeds", "1", "--phases", "1",
                                  "--families", "payload", "--threads", "1", "--out", "OUT"}}),
    [](const ::testing::TestParamInfo<Verb>& info) {
      std::string n = info.param.name;
      for (char& c : n) c = c == ' ' ? '_' : c;
      return n;
    });

// The value reaches the run, and the run's scenario.yaml records it and the flag; a list
// item is set by its index.
TEST(SetFlagSimulate, TheRunsScenarioYamlHoldsTheValueAndNamesTheFlag) {
  const std::string file = WriteFile("set_flag_broken.yaml", kBroken);
  const std::string out = TempDir() + "/set_flag_recorded";
  std::filesystem::remove_all(out);
  const CliResult r = RunClimbsimArgs({"simulate", file, "--out", out, "--quiet", "--set",
                                       "duration_s=0.05", "--set", "cpg.frequency_hz=0.8",
                                       "--set", "cpg.stride_rad=[0.3, 0, 0]", "--set",
                                       "cpg.stride_rad[1]=0.05"});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string yaml = ReadFile(out + "/scenario.yaml");
  EXPECT_TRUE(Has(yaml, "# with --set cpg.frequency_hz=0.8\n")) << yaml;
  EXPECT_TRUE(Has(yaml, "frequency_hz: 0.8\n")) << yaml;
  EXPECT_TRUE(Has(yaml, "duration_s: 0.05\n")) << yaml;
  EXPECT_TRUE(Has(yaml, "stride_rad: [0.3, 0.05, 0]\n")) << yaml;
}

// Refusals: a value the key does not take, a key the file cannot have, no '='. Each names
// the flag, exit code 2, and no run folder is made.
TEST(SetFlagSimulate, ABadValueOrKeyIsRefusedNamingTheFlag) {
  const std::string file = WriteFile("set_flag_ok.yaml",
                                     "robot: gecko\nscene: floor\nduration_s: 0.05\n"
                                     "cpg: {gait: trot}\n");
  const std::string out = TempDir() + "/set_flag_refused";
  std::filesystem::remove_all(out);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"cpg.frequency_hz=abc", "--set cpg.frequency_hz=abc: cpg.frequency_hz: "},
      {"cpg.frequency_hz=-1", "--set cpg.frequency_hz=-1: cpg.frequency_hz: "},
      {"cpg.frequncy_hz=1", "--set cpg.frequncy_hz=1: cpg.frequncy_hz: "},
      {"cpg.stride_rad[7]=0.1", "--set cpg.stride_rad[7]=0.1: cpg.stride_rad is not in the file"},
      {"cpg..x=1", "--set cpg..x=1: 'cpg..x' is not a dotted key"},
      {"frequency", "--set frequency: give KEY=VALUE"}};
  for (const auto& [set, message] : cases) {
    const CliResult r = RunClimbsimArgs({"simulate", file, "--out", out, "--set", set});
    EXPECT_EQ(r.code, 2) << set << ": " << r.err;
    EXPECT_TRUE(Has(r.err, message)) << set << ": " << r.err;
    EXPECT_FALSE(std::filesystem::exists(out)) << set;
  }
}

}  // namespace
