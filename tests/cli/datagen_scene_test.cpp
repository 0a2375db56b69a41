// btf-datagen scene: every built-in scene, written to a folder named relative to the working
// directory, loads and renders (the scene names its generated files so that they are found from
// its own folder, not from the working directory).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_test_support.h"

namespace btf::test {
namespace {
namespace fs = std::filesystem;

// Changes the working directory for the scope of a test (each test runs in its own process).
struct WorkingDirectory {
  fs::path previous = fs::current_path();
  explicit WorkingDirectory(const fs::path& to) { fs::current_path(to); }
  ~WorkingDirectory() { fs::current_path(previous); }
};

class DatagenScene : public testing::TestWithParam<std::string> {};

TEST_P(DatagenScene, RendersFromARelativeOutputFolder) {
  TempDir dir;
  const WorkingDirectory cwd(dir.path());
  const std::string kind = GetParam();
  CommandResult r = runDatagen({"scene", kind, "-o", "scenes/" + kind, "--resolution", "8", "--spp", "1", "--preset", "plastic-red"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists("scenes/" + kind + "/scene.json"));
  r = runBtf({"render", "scenes/" + kind + "/scene.json", "-o", kind + ".exr"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(kind + ".exr"));
}

INSTANTIATE_TEST_SUITE_P(Kinds, DatagenScene, testing::Values("cornell", "furnace", "plane", "closeup", "distant"));

TEST(DatagenSceneKinds, CloseupAndDistantShowTheSameMaterial) {
  TempDir dir;
  for (const char* kind : {"closeup", "distant"})
    ASSERT_EQ(runDatagen({"scene", kind, "-o", (dir / kind).string(), "--resolution", "8"}).exit_code, 0);
  std::ifstream a(dir / "closeup" / "scene.json"), b(dir / "distant" / "scene.json");
  const auto sa = nlohmann::json::parse(a), sb = nlohmann::json::parse(b);
  EXPECT_EQ(sa["materials"]["sphere"], sb["materials"]["sphere"]);
  EXPECT_EQ(sa["lights"][0]["type"], "point");
  EXPECT_EQ(sb["lights"][0]["type"], "environment");
}

}  // namespace
}  // namespace btf::test
