// The six presets, generated (robot/presets.cc, GenerateRobotMjcf) and compiled by MuJoCo alone,
// give models byte-identical to the hand-written files in mjcf/: both compiled with mj_loadXML,
// saved with mj_saveModel, the bytes compared (names included).
#include <gtest/gtest.h>
#include <mujoco/mjxmacro.h>
#include <mujoco/mujoco.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "robot/design.h"

namespace climbsim::sim {
namespace {

const std::filesystem::path kSource(CLIMBSIM_SOURCE_DIR);
const std::filesystem::path kBinary(CLIMBSIM_BINARY_DIR);

using ModelPtr = std::unique_ptr<mjModel, decltype(&mj_deleteModel)>;

ModelPtr Load(const std::filesystem::path& file) {
  char error[1000] = "";
  mjModel* m = mj_loadXML(file.c_str(), nullptr, error, sizeof error);
  EXPECT_NE(m, nullptr) << file << ": " << error;
  return ModelPtr(m, mj_deleteModel);
}

std::vector<char> Saved(const mjModel* m) {
  std::vector<char> bytes(mj_sizeModel(m));
  mj_saveModel(m, nullptr, bytes.data(), static_cast<int>(bytes.size()));
  return bytes;
}

// What differs between two models of the same sizes: the first mjModel array that differs
// ("body_pos"), for the failure message.
std::string FirstDifference(const mjModel* a, const mjModel* b) {
  MJMODEL_POINTERS_PREAMBLE(a)
#define X(type, name, nr, nc)             \
  if (a->nr != b->nr) return "size " #nr; \
  if (std::memcmp(a->name, b->name, sizeof(type) * a->nr * (nc)) != 0) return #name;
  MJMODEL_POINTERS
#undef X
  return "options or sizes";
}

class DesignPresets : public testing::TestWithParam<std::string> {};

TEST_P(DesignPresets, GeneratedModelIsTheFileInMjcf) {
  const std::string name = GetParam();
  const std::filesystem::path generated = kBinary / ("design_" + name + ".xml");
  std::ofstream(generated) << GenerateRobotMjcf(PresetDesign(name));
  ModelPtr from_design = Load(generated);
  ModelPtr from_file = Load(kSource / "mjcf" / (name + ".xml"));
  ASSERT_TRUE(from_design && from_file);
  EXPECT_TRUE(Saved(from_design.get()) == Saved(from_file.get()))
      << name << ": " << generated.string() << " differs from mjcf/" << name << ".xml, first in "
      << FirstDifference(from_design.get(), from_file.get());
}

INSTANTIATE_TEST_SUITE_P(Presets, DesignPresets, testing::ValuesIn(PresetNames()),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace climbsim::sim
