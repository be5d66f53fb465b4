// Every verb's --help ends with an example that runs. Each test reads the example from the
// help text and runs it as a user would, made short so that the suite stays fast:
//   - a scenario file of examples/ it names is run from a copy with duration_s set short;
//   - a run folder it reads (runs/NAME) is first made by simulating a short copy of
//     examples/NAME.yaml; everything it writes goes to a temporary folder;
//   - the options that set the amount of work are turned down (replaced where the example
//     gives them, added where it does not), and a verb that writes to a default folder is
//     given one in the temporary folder.
// The command is otherwise the help's own: a verb whose example names a file that does not
// exist, or an option that the verb does not take, fails here with exit code 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/common/test_util.h"

namespace {

namespace fs = std::filesystem;
using climbsim::testing::CliResult;
using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsim;
using climbsim::testing::Source;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;

// A scenario's simulated time in these runs (s): enough for a few steps of every effect.
constexpr const char* kShortDuration = "0.4";

// As a value in VerbCase::less_work: a folder in the temporary folder, for a verb that writes
// to a default folder (runs/...) when the example gives no --out.
constexpr const char* kTempOut = "(temporary folder)";

struct VerbCase {
  std::string verb;                                // as typed: "bench speed"
  std::vector<std::pair<std::string, std::string>> less_work;  // option -> value
};

const std::vector<VerbCase>& Verbs() {
  static const std::vector<VerbCase> verbs = {
      {"simulate", {}},
      {"optimise", {{"--max-evaluations", "2"}, {"--threads", "1"}}},
      {"sweep", {{"--step", "90"}, {"--threads", "1"}}},
      {"bench speed", {{"--duration", "0.2"}, {"--repetitions", "1"}}},
      {"bench accuracy", {{"--duration", "0.1"}}},
      {"bench optimise", {{"--evaluations", "2"}, {"--out", kTempOut}}},
      {"bench robustness", {{"--duration", "0.2"}}},
      {"pulloff", {{"--step-deg", "45"}}},
      {"fit-adhesion", {{"--grid", "4"}}},
      {"inspect", {{"--from", "0.1"}, {"--to", "0.3"}}},
      {"render", {{"--at", "0.2"}, {"--width", "64"}, {"--height", "48"}}},
      {"keys", {}},
      {"model", {}},
  };
  return verbs;
}

// gtest names a failing case by its verb.
void PrintTo(const VerbCase& c, std::ostream* out) { *out << c.verb; }

std::vector<std::string> Split(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> tokens;
  for (std::string t; in >> t;) tokens.push_back(t);
  return tokens;
}

// The first command line of the help's "Example:" / "Examples:" section, without "climbsim".
std::string ExampleOf(const std::string& help) {
  const std::regex section("Examples?:\n  climbsim ([^\n]*)");
  std::smatch m;
  if (!std::regex_search(help, m, section)) return "";
  return m[1].str();
}

// A copy of examples/NAME.yaml with a short duration, in the temporary folder.
std::string ShortScenario(const std::string& example_path) {
  const std::string text = ReadFile(Source(example_path));
  EXPECT_FALSE(text.empty()) << example_path << " is missing or empty";
  const std::string shorter = std::regex_replace(
      text, std::regex("^duration_s:.*$", std::regex::multiline),
      std::string("duration_s: ") + kShortDuration);
  return WriteFile("help_examples/scenarios/" + fs::path(example_path).filename().string(),
                   shorter);
}

// A run folder standing for runs/NAME: a simulation of a short examples/NAME.yaml.
std::string MadeRun(const std::string& runs_path) {
  const std::string name = fs::path(runs_path).filename().string();
  const std::string dir = TempDir() + "/help_examples/runs/" + name;
  if (!fs::exists(dir + "/summary.json")) {
    const CliResult r =
        RunClimbsim("simulate " + ShortScenario("examples/" + name + ".yaml") + " --out " + dir +
                    " --quiet --force");
    EXPECT_EQ(r.code, 0) << "making " << runs_path << ": " << r.err;
  }
  return dir;
}

// The example of `verb` made short (see the file comment).
std::string Shortened(const VerbCase& c, const std::string& example) {
  std::vector<std::string> tokens = Split(example);
  const std::string slug = std::regex_replace(c.verb, std::regex(" "), "_");
  for (size_t i = 0; i < tokens.size(); ++i) {
    std::string& t = tokens[i];
    const bool after_out = i > 0 && tokens[i - 1] == "--out";
    if (after_out) {
      t = TempDir() + "/help_examples/out/" + slug + "/" + fs::path(t).filename().string();
    } else if (t.rfind("examples/", 0) == 0) {
      t = ShortScenario(t);
    } else if (t.rfind("runs/", 0) == 0) {
      t = MadeRun(t);
    }
  }
  for (const auto& [option, given_value] : c.less_work) {
    const std::string value = given_value == kTempOut
                                  ? TempDir() + "/help_examples/out/" + slug + "/default_out"
                                  : given_value;
    bool given = false;
    for (size_t i = 0; i + 1 < tokens.size(); ++i) {
      if (tokens[i] == option) tokens[i + 1] = value, given = true;
    }
    if (!given) tokens.insert(tokens.end(), {option, value});
  }
  std::string line;
  for (const std::string& t : tokens) line += (line.empty() ? "" : " ") + t;
  return line;
}

// The verbs `climbsim --help` (and `climbsim bench --help`) list.
std::set<std::string> ListedVerbs() {
  std::set<std::string> verbs;
  const std::regex row("\n  ([a-z-]+) ");
  for (const std::string parent : {"", "bench "}) {
    const CliResult r = RunClimbsim(parent + "--help");
    EXPECT_EQ(r.code, 0) << parent;
    const size_t at = r.out.find("SUBCOMMANDS:");
    const size_t at2 = r.out.find("Subcommands:");
    const size_t from = at != std::string::npos ? at : at2;
    if (from == std::string::npos) {
      ADD_FAILURE() << "no subcommand list in `climbsim " << parent << "--help`:\n" << r.out;
      continue;
    }
    // The list ends at the first blank line (the example follows).
    std::string list = r.out.substr(from);
    list = list.substr(0, list.find("\n\n"));
    for (std::sregex_iterator it(list.begin(), list.end(), row), end; it != end; ++it) {
      const std::string verb = (*it)[1].str();
      if (parent.empty() && verb == "bench") continue;  // its own verbs are listed below
      verbs.insert(parent + verb);
    }
  }
  return verbs;
}

// The cases below cover every verb the executable has: a new verb needs its case.
TEST(HelpExamples, EveryVerbHasACase) {
  std::set<std::string> cased;
  for (const VerbCase& c : Verbs()) cased.insert(c.verb);
  EXPECT_EQ(ListedVerbs(), cased);
}

// Every example line of a verb's help ("Example:" / "Examples:" to the end), with what comes
// before "climbsim" (mpirun -np 4) and after two blanks (a remark) left out.
std::vector<std::string> ExampleLines(const std::string& help) {
  std::vector<std::string> lines;
  const size_t at = help.find("Example");
  if (at == std::string::npos) return lines;
  std::istringstream in(help.substr(at));
  for (std::string line; std::getline(in, line);) {
    const size_t from = line.find("climbsim ");
    if (line.rfind("  ", 0) != 0 || from == std::string::npos) continue;
    line = line.substr(from);
    lines.push_back(line.substr(0, line.find("   ")));
  }
  return lines;
}

// A user who runs the examples one after another gets every one done: no two write to the
// same --out (the second would be refused, its folder holding the first one's run).
TEST(HelpExamples, EveryExampleWritesToAFolderOfItsOwn) {
  std::map<std::string, std::string> writer;  // --out -> the example that writes it
  for (const VerbCase& c : Verbs()) {
    const CliResult help = RunClimbsim(c.verb + " --help");
    ASSERT_EQ(help.code, 0) << help.err;
    for (const std::string& example : ExampleLines(help.out)) {
      const std::vector<std::string> tokens = Split(example);
      for (size_t i = 0; i + 1 < tokens.size(); ++i) {
        if (tokens[i] != "--out") continue;
        const auto [it, fresh] = writer.emplace(tokens[i + 1], example);
        // The same command shown twice (a parent's help and the verb's) is one run.
        EXPECT_TRUE(fresh || it->second == example) << "two examples write to " << tokens[i + 1]
                                                    << ":\n  " << it->second << "\n  " << example;
      }
    }
  }
  EXPECT_GE(writer.size(), 8u) << "examples found: the parsing above missed some";
}

class HelpExample : public ::testing::TestWithParam<VerbCase> {};

TEST_P(HelpExample, RunsWithExitCodeZero) {
  const VerbCase& c = GetParam();
  const CliResult help = RunClimbsim(c.verb + " --help");
  ASSERT_EQ(help.code, 0) << help.err;
  const std::string example = ExampleOf(help.out);
  ASSERT_FALSE(example.empty()) << "`climbsim " << c.verb << " --help` shows no example:\n"
                                << help.out;
  ASSERT_EQ(example.rfind(c.verb + (c.verb == "keys" ? "" : " "), 0), 0u)
      << "the example of " << c.verb << " runs another verb: " << example;
  const std::string command = Shortened(c, example);
  const CliResult r = RunClimbsim(command);
  EXPECT_EQ(r.code, 0) << "help: climbsim " << example << "\nran: climbsim " << command << "\n"
                       << r.err;
}

INSTANTIATE_TEST_SUITE_P(EveryVerb, HelpExample, ::testing::ValuesIn(Verbs()),
                         [](const ::testing::TestParamInfo<VerbCase>& info) {
                           return std::regex_replace(info.param.verb, std::regex("[ -]"), "_");
                         });

}  // namespace
