// btf render: the files it writes, its JSON summary, images that do not depend on the thread
// count, and one clear error (non-zero exit, no crash, no file left behind) per kind of bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "btf/io/image.h"
#include "cli_test_support.h"

namespace btf::test {
namespace {
namespace fs = std::filesystem;

// A floor under a quad light, seen at an angle: 16 x 16 pixels, 4 samples per pixel.
nlohmann::json tinyScene() {
  return nlohmann::json::parse(R"({
    "camera": {"position": [0, 1.2, 2.5], "look_at": [0, 0, 0], "fov_deg": 50, "resolution": [16, 16]},
    "render": {"spp": 4, "max_depth": 4},
    "materials": {"white": {"type": "lambert", "albedo": [0.7, 0.6, 0.5]}},
    "shapes": [
      {"type": "quad", "corner": [-1, 0, -1], "edge_u": [0, 0, 2], "edge_v": [2, 0, 0], "material": "white"},
      {"type": "quad", "corner": [-0.3, 1, -0.3], "edge_u": [0.6, 0, 0], "edge_v": [0, 0, 0.6], "emission": [4, 4, 4]}
    ]
  })");
}

fs::path writeScene(const TempDir& dir, const nlohmann::json& scene, const std::string& name = "scene.json") {
  const fs::path path = dir / name;
  std::ofstream(path) << scene.dump(2);
  return path;
}

bool bitwiseEqual(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height && a.channels == b.channels &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
}

TEST(RenderCli, WritesExrPngAndJsonSummary) {
  TempDir dir;
  const fs::path scene = writeScene(dir, tinyScene());
  const CommandResult r = runBtf({"render", scene.string(), "-o", (dir / "out.exr").string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = parseJsonOutput(r);
  EXPECT_EQ(j["width"], 16);
  EXPECT_EQ(j["height"], 16);
  EXPECT_EQ(j["spp"], 4);  // the scene's
  EXPECT_EQ(j["integrator"], "pt");
  EXPECT_EQ(j["camera_rays"].get<std::uint64_t>(), 16u * 16u * 4u);
  EXPECT_GE(j["rays"].get<std::uint64_t>(), j["camera_rays"].get<std::uint64_t>());
  EXPECT_EQ(j["rays"].get<std::uint64_t>(), j["camera_rays"].get<std::uint64_t>() + j["extension_rays"].get<std::uint64_t>() +
                                                  j["shadow_rays"].get<std::uint64_t>());
  EXPECT_GT(j["shadow_rays"].get<std::uint64_t>(), 0u);
  EXPECT_GE(j["seconds"].get<double>(), 0.0);
  EXPECT_LT(j["seconds"].get<double>(), 60.0);
  ASSERT_TRUE(j["outputs"].is_array());
  EXPECT_EQ(j["outputs"].size(), 2u);

  ASSERT_TRUE(fs::exists(dir / "out.exr"));
  ASSERT_TRUE(fs::exists(dir / "out.png"));
  EXPECT_FALSE(fs::exists(dir / "out.albedo.exr"));  // AOVs only when asked for
  const Image color = readImage(dir / "out.exr");
  ASSERT_EQ(color.width, 16);
  ASSERT_EQ(color.height, 16);
  ASSERT_GE(color.channels, 3);
  double sum = 0;
  for (float v : color.pixels) {
    ASSERT_TRUE(std::isfinite(v));
    ASSERT_GE(v, 0.0f);
    sum += v;
  }
  EXPECT_GT(sum, 0.0);  // the lit floor
  const Image preview = readImage(dir / "out.png");
  EXPECT_EQ(preview.width, 16);
  EXPECT_EQ(preview.height, 16);

  // Without --json: a readable summary naming what it wrote.
  const CommandResult text = runBtf({"render", scene.string(), "-o", (dir / "again.exr").string(), "--spp", "1"});
  ASSERT_EQ(text.exit_code, 0) << text.output;
  EXPECT_NE(text.output.find("1 spp"), std::string::npos) << text.output;
  EXPECT_NE(text.output.find((dir / "again.exr").string()), std::string::npos) << text.output;
  EXPECT_NE(text.output.find((dir / "again.png").string()), std::string::npos) << text.output;
}

TEST(RenderCli, AovsAndSppOverride) {
  TempDir dir;
  const fs::path scene = writeScene(dir, tinyScene());
  const CommandResult r = runBtf({"render", scene.string(), "-o", (dir / "out.exr").string(), "--aovs", "--spp", "3", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = parseJsonOutput(r);
  EXPECT_EQ(j["spp"], 3);
  EXPECT_EQ(j["camera_rays"].get<std::uint64_t>(), 16u * 16u * 3u);
  EXPECT_EQ(j["outputs"].size(), 6u);
  for (const char* name : {"out.exr", "out.png", "out.albedo.exr", "out.normal.exr", "out.depth.exr", "out.samples.exr"})
    EXPECT_TRUE(fs::exists(dir / name)) << name;
  const Image samples = readImage(dir / "out.samples.exr");
  ASSERT_EQ(samples.width, 16);
  ASSERT_EQ(samples.height, 16);
  EXPECT_EQ(samples.at(8, 8, 0), 3.0f);
  // The middle of the image sees the floor from about 2.8 units away.
  const Image depth = readImage(dir / "out.depth.exr");
  EXPECT_GT(depth.at(8, 8, 0), 2.0f);
  EXPECT_LT(depth.at(8, 8, 0), 3.5f);
  const Image normal = readImage(dir / "out.normal.exr");
  EXPECT_NEAR(normal.at(8, 8, 1), 1.0f, 1e-4f);  // the floor faces +y
}

TEST(RenderCli, ThreadCountDoesNotChangeTheImage) {
  TempDir dir;
  const fs::path scene = writeScene(dir, tinyScene());
  const CommandResult one = runBtf({"render", scene.string(), "-o", (dir / "one.exr").string(), "--threads", "1", "--seed", "7"});
  ASSERT_EQ(one.exit_code, 0) << one.output;
  const CommandResult two = runBtf({"render", scene.string(), "-o", (dir / "two.exr").string(), "--threads", "2", "--seed", "7"});
  ASSERT_EQ(two.exit_code, 0) << two.output;
  const Image a = readImage(dir / "one.exr"), b = readImage(dir / "two.exr");
  ASSERT_EQ(a.pixels.size(), std::size_t(16 * 16 * a.channels));
  EXPECT_TRUE(bitwiseEqual(a, b));
  // The seed does change it (so the comparison above is not trivially true).
  const CommandResult other = runBtf({"render", scene.string(), "-o", (dir / "other.exr").string(), "--threads", "2", "--seed", "8"});
  ASSERT_EQ(other.exit_code, 0) << other.output;
  EXPECT_FALSE(bitwiseEqual(a, readImage(dir / "other.exr")));
}

TEST(RenderCli, BadOptions) {
  TempDir dir;
  const fs::path scene = writeScene(dir, tinyScene());
  const std::string out = (dir / "out.exr").string();
  expectFailure(runBtf({"render", scene.string(), "-o", out, "--spp", "0"}), {"--spp", "0"});
  expectFailure(runBtf({"render", scene.string(), "-o", out, "--spp", "many"}), {"--spp", "many"});
  expectFailure(runBtf({"render", scene.string(), "-o", out, "--threads", "-1"}), {"--threads"});
  expectFailure(runBtf({"render", scene.string(), "-o", out, "--integrator", "bdpt"}), {"--integrator", "bdpt"});
  expectFailure(runBtf({"render", scene.string(), "-o", out, "--sampler", "importance"}), {scene.string(), "importance"});
  expectFailure(runBtf({"render", scene.string()}), {"--output"});
  EXPECT_EQ(filesIn(dir.path()).size(), 1u);  // the scene alone
}

TEST(RenderCli, BadOutputPaths) {
  TempDir dir;
  const fs::path scene = writeScene(dir, tinyScene());
  const fs::path missing = dir / "no-such-folder" / "out.exr";
  expectFailure(runBtf({"render", scene.string(), "-o", missing.string()}), {missing.string(), "folder does not exist"});
  EXPECT_FALSE(fs::exists(dir / "no-such-folder"));
  for (const char* name : {"out.png", "out.EXR", "out", "out.exr.tmp"}) {
    const fs::path path = dir / name;
    expectFailure(runBtf({"render", scene.string(), "-o", path.string()}), {path.string(), ".exr"});
  }
  // Nothing was written anywhere: not beside the scene, not as a temporary file.
  const std::vector<fs::path> files = filesIn(dir.path());
  ASSERT_EQ(files.size(), 1u);
  EXPECT_EQ(files[0], scene);
}

TEST(RenderCli, BadScenes) {
  TempDir dir;
  const std::string out = (dir / "out.exr").string();
  const fs::path missing = dir / "missing.json";
  expectFailure(runBtf({"render", missing.string(), "-o", out}), {missing.string(), "no such scene file"});

  const fs::path malformed = dir / "malformed.json";
  std::ofstream(malformed) << "{\"camera\": {\"position\": [0, 1, 2]";
  expectFailure(runBtf({"render", malformed.string(), "-o", out}), {malformed.string(), "malformed JSON"});

  nlohmann::json s = tinyScene();
  s["camera"]["fov_deg"] = 200;
  const fs::path fov = writeScene(dir, s, "fov.json");
  expectFailure(runBtf({"render", fov.string(), "-o", out}), {fov.string(), "/camera/fov_deg"});

  s = tinyScene();
  s["shapes"][0]["file"] = "meshes/floor.ply";
  s["shapes"][0].erase("type");
  for (const char* key : {"corner", "edge_u", "edge_v"}) s["shapes"][0].erase(key);
  const fs::path mesh = writeScene(dir, s, "mesh.json");
  expectFailure(runBtf({"render", mesh.string(), "-o", out}), {mesh.string(), "/shapes/0/file", "floor.ply"});

  s = tinyScene();
  s["shapes"].erase(1);
  const fs::path dark = writeScene(dir, s, "dark.json");
  expectFailure(runBtf({"render", dark.string(), "-o", out}), {dark.string(), "no light"});

  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(dir / "out.png"));
}

}  // namespace
}  // namespace btf::test
