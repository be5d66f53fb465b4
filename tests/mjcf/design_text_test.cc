// The six files mjcf/<preset>.xml are the presets' generated text (GenerateRobotMjcf of
// PresetDesign), character for character: a change to the generator or to a preset fails here
// until the files are written again, with
//   CLIMBSIM_REWRITE_MJCF=1 ctest --test-dir build -R mjcf_presets_current
// (CTest mjcf_presets_current runs this test). Rewriting leaves the test passing and the files
// changed for review in git.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "mjcf_test_util.h"
#include "robot/design.h"

namespace climbsim::sim {
namespace {

std::string ReadFile(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The first line (1-based) where two texts differ.
int FirstDifferingLine(const std::string& a, const std::string& b) {
  int line = 1;
  for (size_t i = 0; i < a.size() && i < b.size() && a[i] == b[i]; ++i) line += a[i] == '\n';
  return line;
}

TEST(MjcfPresetsCurrent, FilesAreTheGeneratedText) {
  const char* rewrite = std::getenv("CLIMBSIM_REWRITE_MJCF");
  for (const std::string& name : PresetNames()) {
    const std::filesystem::path file = mjcf_test::RobotFile(name);
    const std::string text = GenerateRobotMjcf(PresetDesign(name));
    if (rewrite && std::string(rewrite) == "1") {
      std::ofstream(file, std::ios::binary | std::ios::trunc) << text;
    }
    const std::string on_disk = ReadFile(file);
    EXPECT_EQ(on_disk, text) << file.string() << " is not the generated text of preset " << name
                             << " (first at line " << FirstDifferingLine(on_disk, text)
                             << "); write it again with CLIMBSIM_REWRITE_MJCF=1 ctest "
                                "--test-dir build -R mjcf_presets_current";
  }
}

}  // namespace
}  // namespace climbsim::sim
