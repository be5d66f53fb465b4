// Malformed and incomplete run directories: each fault gets its own message naming the file
// and, for a bad row, its line (and column), through the library (InputError) and through
// the executable (exit code 2, the message on stderr).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <sstream>
#include <vector>

#include "inspect/inspect.h"
#include "common/common.h"
#include "tests/inspect/inspect_test_util.h"

namespace {

using climbsim::InputError;
using climbsim::testing::CopyRun;
using climbsim::testing::ReadFile;
using climbsim::testing::RunClimbsim;
using climbsim::testing::SharedRun;
using climbsim::testing::Source;
using climbsim::testing::TempDir;
using climbsim::testing::WriteFile;
namespace inspect = climbsim::inspect;

std::string Base() { return SharedRun("gecko_wall", Source("examples/gecko_wall.yaml")); }

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

std::string Join(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l + "\n";
  return s;
}

// LoadRun's message for `dir`; "" when it loads.
std::string LoadError(const std::string& dir) {
  try {
    inspect::LoadRun(dir);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The same fault through the executable: exit 2, the same message.
void ExpectCliError(const std::string& dir, const std::string& message) {
  const auto r = RunClimbsim("inspect " + dir);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_EQ(r.err, message + "\n");
}

TEST(InspectFiles, ARealRunLoads) {
  const inspect::Run run = inspect::LoadRun(Base());
  EXPECT_EQ(run.legs, (std::vector<std::string>{"LF", "RF", "LH", "RH"}));
  EXPECT_EQ(run.duration_s, 20.0);
  ASSERT_TRUE(run.trajectory.has_value());
  EXPECT_GE(run.trajectory->Column("LF_pad_bonded_fraction"), 0);
  EXPECT_GT(run.events.size(), 100u);
  EXPECT_EQ(run.events[1].line, 3);
}

TEST(InspectFiles, MissingEventsCsv) {
  const std::string dir = CopyRun(Base(), "no_events");
  std::filesystem::remove(dir + "/events.csv");
  const std::string want =
      dir + "/events.csv: missing file (the pad events of a run, written by climbsim simulate)";
  EXPECT_EQ(LoadError(dir), want);
  ExpectCliError(dir, want);
}

TEST(InspectFiles, MissingSummaryMeansTheRunDidNotFinish) {
  const std::string dir = CopyRun(Base(), "no_summary");
  std::filesystem::remove(dir + "/summary.json");
  const std::string want = dir +
                           "/summary.json: missing file (written last by climbsim simulate: "
                           "without it the run did not finish)";
  EXPECT_EQ(LoadError(dir), want);
  ExpectCliError(dir, want);
}

TEST(InspectFiles, MissingModel) {
  const std::string dir = CopyRun(Base(), "no_model");
  std::filesystem::remove(dir + "/model.xml");
  EXPECT_EQ(LoadError(dir), dir + "/model.xml: missing file (the composed model of the run)");
}

TEST(InspectFiles, NotARunDirectory) {
  const std::string empty = TempDir() + "/empty_dir";
  std::filesystem::create_directories(empty);
  EXPECT_EQ(LoadError(empty),
            empty +
                "/summary.json: missing file (written last by climbsim simulate: without it the "
                "run did not finish)");
  EXPECT_EQ(LoadError(TempDir() + "/nowhere"), TempDir() + "/nowhere: no such folder");
  ExpectCliError(TempDir() + "/nowhere", TempDir() + "/nowhere: no such folder");
}

TEST(InspectFiles, TruncatedRow) {
  const std::string dir = CopyRun(Base(), "truncated");
  const std::string text = ReadFile(dir + "/events.csv");
  // Cut the file in the middle of line 12, as a killed writer would.
  size_t at = 0;
  for (int i = 0; i < 11; ++i) at = text.find('\n', at) + 1;
  const std::string cut = text.substr(at, 20);
  WriteFile(dir + "/events.csv", text.substr(0, at + 20));
  const std::string present = std::to_string(1 + std::count(cut.begin(), cut.end(), ','));
  const std::string want = dir +
                           "/events.csv:12: truncated row: the file ends inside it, without a "
                           "newline (" +
                           present +
                           " of 11 columns present; was the writer "
                           "stopped?)";
  EXPECT_EQ(LoadError(dir), want);
  ExpectCliError(dir, want);
}

TEST(InspectFiles, WrongColumnCount) {
  const std::string dir = CopyRun(Base(), "wrong_columns");
  auto lines = Lines(ReadFile(dir + "/events.csv"));
  lines[6] = lines[6].substr(0, lines[6].rfind(','));  // line 7 loses its last cell
  WriteFile(dir + "/events.csv", Join(lines));
  const std::string want =
      dir + "/events.csv:7: wrong column count: expected 11 columns as in the header, got 10";
  EXPECT_EQ(LoadError(dir), want);
  ExpectCliError(dir, want);
}

TEST(InspectFiles, EmptyLineIsAWrongColumnCount) {
  const std::string dir = CopyRun(Base(), "empty_line");
  auto lines = Lines(ReadFile(dir + "/events.csv"));
  lines.insert(lines.begin() + 4, "");
  WriteFile(dir + "/events.csv", Join(lines));
  EXPECT_EQ(LoadError(dir), dir +
                                "/events.csv:5: wrong column count: expected 11 columns as in "
                                "the header, got an empty line");
}

TEST(InspectFiles, WrongHeader) {
  const std::string dir = CopyRun(Base(), "wrong_header");
  auto lines = Lines(ReadFile(dir + "/events.csv"));
  lines[0].replace(lines[0].find("fn_n"), 4, "normal");
  WriteFile(dir + "/events.csv", Join(lines));
  const std::string want =
      dir +
      "/events.csv:1: wrong header: expected "
      "'time_s,pad,event,cause,surface,bonded_fraction,fn_n,fx_n,fy_n,mx_nm,my_nm', got "
      "'time_s,pad,event,cause,surface,bonded_fraction,normal,fx_n,fy_n,mx_nm,my_nm'";
  EXPECT_EQ(LoadError(dir), want);
  ExpectCliError(dir, want);
}

TEST(InspectFiles, NotANumberNamesLineColumnAndKey) {
  const std::string dir = CopyRun(Base(), "not_a_number");
  auto lines = Lines(ReadFile(dir + "/events.csv"));
  // Line 10: replace the fn_n cell (7th) with text.
  std::vector<std::string> cells;
  std::stringstream in(lines[9]);
  for (std::string c; std::getline(in, c, ',');) cells.push_back(c);
  cells[6] = "abc";
  int column = 1;
  for (int i = 0; i < 6; ++i) column += static_cast<int>(cells[i].size()) + 1;
  std::string line;
  for (size_t i = 0; i < cells.size(); ++i) line += (i ? "," : "") + cells[i];
  lines[9] = line;
  WriteFile(dir + "/events.csv", Join(lines));
  const std::string want =
      dir + "/events.csv:10:" + std::to_string(column) + ": fn_n: expected a number, got 'abc'";
  EXPECT_EQ(LoadError(dir), want);
  ExpectCliError(dir, want);
}

TEST(InspectFiles, TimeGoingBackwards) {
  const std::string dir = CopyRun(Base(), "backwards");
  auto lines = Lines(ReadFile(dir + "/events.csv"));
  std::swap(lines[10], lines[30]);
  WriteFile(dir + "/events.csv", Join(lines));
  const std::string error = LoadError(dir);
  EXPECT_EQ(error.rfind(dir + "/events.csv:12:1: time_s: time goes backwards: ", 0), 0u) << error;
}

TEST(InspectFiles, UnknownPad) {
  const std::string dir = CopyRun(Base(), "unknown_pad");
  auto lines = Lines(ReadFile(dir + "/events.csv"));
  lines[3].replace(lines[3].find("RF_pad"), 6, "XX_pad");
  WriteFile(dir + "/events.csv", Join(lines));
  EXPECT_EQ(LoadError(dir), dir +
                                "/events.csv:4: pad: 'XX_pad' is not a pad of the robot (LF_pad, "
                                "RF_pad, LH_pad, RH_pad)");
}

TEST(InspectFiles, EmptyEventsFile) {
  const std::string dir = CopyRun(Base(), "empty_events");
  WriteFile(dir + "/events.csv", "");
  EXPECT_EQ(LoadError(dir), dir + "/events.csv: empty file (expected a header line)");
}

TEST(InspectFiles, TrajectoryFaults) {
  const std::string dir = CopyRun(Base(), "bad_trajectory");
  const std::string good = ReadFile(dir + "/trajectory.csv");
  auto lines = Lines(good);

  auto header = lines;
  header[0].replace(0, 6, "t");
  WriteFile(dir + "/trajectory.csv", Join(header));
  EXPECT_EQ(LoadError(dir).rfind(dir + "/trajectory.csv:1: wrong header: column 1 must be "
                                       "'time_s', got 't'",
                                 0),
            0u)
      << LoadError(dir);

  auto nan_row = lines;
  const size_t c1 = nan_row[4].find(','), c2 = nan_row[4].find(',', c1 + 1);
  nan_row[4].replace(c1 + 1, c2 - c1 - 1, "1e");
  WriteFile(dir + "/trajectory.csv", Join(nan_row));
  EXPECT_EQ(LoadError(dir), dir + "/trajectory.csv:5:" + std::to_string(c1 + 2) +
                                ": base_x_m: expected a number, got '1e'");

  WriteFile(dir + "/trajectory.csv", good.substr(0, good.size() - 1));  // no final newline
  EXPECT_EQ(LoadError(dir).rfind(
                dir + "/trajectory.csv:" + std::to_string(lines.size()) + ": truncated row", 0),
            0u)
      << LoadError(dir);

  WriteFile(dir + "/trajectory.csv", good);
  EXPECT_EQ(LoadError(dir), "");
}

TEST(InspectFiles, SummaryThatIsNotJson) {
  const std::string dir = CopyRun(Base(), "bad_summary");
  WriteFile(dir + "/summary.json", "{\n  \"duration_s\": 20,\n  oops\n}\n");
  EXPECT_EQ(LoadError(dir).rfind(dir + "/summary.json:3: not valid JSON: ", 0), 0u)
      << LoadError(dir);
  WriteFile(dir + "/summary.json", "{\"robot\": \"gecko\"}\n");
  EXPECT_EQ(LoadError(dir), dir + "/summary.json: duration_s: missing or not a number");
}

TEST(InspectFiles, BadWindowAndLegAreInputErrors) {
  const std::string dir = Base();
  auto r = RunClimbsim("inspect " + dir + " --from 30");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err,
            "climbsim inspect: --from: the window 30 .. inf s holds none of the run (0 .. 20 s)\n");
  r = RunClimbsim("inspect " + dir + " --from 5 --to 2");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "climbsim inspect: --from: must be below --to, got 5 and 2\n");
  r = RunClimbsim("inspect " + dir + " --leg XX");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.err, "climbsim inspect: --leg: 'XX' is not a leg of the robot (LF, RF, LH, RH)\n");
}

}  // namespace
