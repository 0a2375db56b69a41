// btf fit-scene: with GGX as the only model tried, it picks the fit for a GGX table and keeps a
// table for a retro-reflective Lafortune lobe, which GGX cannot represent; it keeps the full material and
// says so when nothing smaller is within the budget, writes a lean scene that renders, and refuses
// bad options with a clear error and no output.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "btf/io/merl.h"
#include "btf/material/ggx.h"
#include "btf/material/lafortune.h"
#include "btf/material/tabulated_brdf.h"
#include "cli_test_support.h"

namespace btf::test {
namespace {
namespace fs = std::filesystem;

// Two spheres side by side under a point light beside the camera (so that the retro-reflective one
// shows its back-scattering lobe) and a dim environment: 24 x 24 pixels, 4 samples per pixel.
fs::path writeTwoSphereScene(const TempDir& dir) {
  writeMerl(dir / "plastic.binary", tabulate(Ggx(Rgb(0.4f, 0.1f, 0.1f), Rgb(0.04f), 0.15f, 0.15f)));
  writeMerl(dir / "retro.binary", tabulate(Lafortune(Rgb(0.05f), {{Rgb(0.6f), glm::vec3(1.0f, 1.0f, 1.0f), 30.0f}})));
  const nlohmann::json scene = nlohmann::json::parse(R"({
    "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov_deg": 45, "resolution": [24, 24]},
    "render": {"spp": 4, "max_depth": 4},
    "materials": {
      "plastic": {"type": "merl", "file": "plastic.binary"},
      "retro": {"type": "merl", "file": "retro.binary"},
      "wall": {"type": "lambert", "albedo": 0.5}
    },
    "shapes": [
      {"type": "sphere", "center": [-0.8, 0, 0], "radius": 0.7, "material": "plastic"},
      {"type": "sphere", "center": [0.8, 0, 0], "radius": 0.7, "material": "retro"},
      {"type": "quad", "corner": [-3, -3, -1], "edge_u": [6, 0, 0], "edge_v": [0, 6, 0], "material": "wall"}
    ],
    "lights": [
      {"type": "point", "position": [0.3, 0.3, 4], "intensity": [6, 6, 6]},
      {"type": "environment", "radiance": [0.05, 0.05, 0.05]}
    ]
  })");
  const fs::path path = dir / "scene.json";
  std::ofstream(path) << scene.dump(2);
  return path;
}

// Few candidates, so that the test stays short.
std::vector<std::string> fitScene(const fs::path& scene, const fs::path& lean, const std::string& budget) {
  return {"fit-scene", scene.string(), "-o", lean.string(), "--budget", budget, "--fits", "ggx:log", "--tolerances", "0.1",
          "--epsilons", "0.1", "--no-samplers"};
}

nlohmann::json readJson(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

TEST(FitSceneCli, AnalyticForTheAnalyticMaterialATableForTheRetroReflectiveOne) {
  TempDir dir;
  const fs::path scene = writeTwoSphereScene(dir);
  fs::create_directories(dir / "out");
  const fs::path lean = dir / "out" / "lean.json";
  CommandResult r = runBtf(fitScene(scene, lean, "0.01"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = readJson(lean);
  EXPECT_EQ(j["materials"]["plastic"]["type"], "fitted") << r.output;
  EXPECT_NE(j["materials"]["retro"]["type"], "fitted") << r.output;
  EXPECT_EQ(j["materials"]["wall"]["type"], "lambert");
  // Paths are relative to the lean scene's folder; the chosen files were copied there.
  EXPECT_EQ(j["shapes"][0]["type"], "sphere");
  EXPECT_TRUE(fs::exists(lean.parent_path() / j["materials"]["plastic"]["file"].get<std::string>()));
  for (const char* f : {"lean.csv", "lean-samplers.csv", "lean-reference.exr", "lean-lean.exr", "lean-error.png"})
    EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;
  EXPECT_FALSE(fs::exists(dir / "out" / "lean-materials.work"));
  std::ifstream csv(dir / "out" / "lean.csv");
  const std::string table((std::istreambuf_iterator<char>(csv)), std::istreambuf_iterator<char>());
  EXPECT_EQ(table.rfind("material,type,candidate,kind,bytes,eval_per_s,samples_per_s,relmse_image,relmse_seen,chosen,note\n", 0), 0u)
      << table;
  EXPECT_NE(table.find("plastic,merl,fit ggx (log),fit,"), std::string::npos) << table;
  EXPECT_NE(table.find("retro,merl,octree t=0.1,octree,"), std::string::npos) << table;
  // The lean scene renders.
  r = runBtf({"render", lean.string(), "-o", (dir / "out" / "render.exr").string()});
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(FitSceneCli, NothingWithinTheBudgetKeepsTheFullMaterialAndSaysSo) {
  TempDir dir;
  const fs::path scene = writeTwoSphereScene(dir);
  const fs::path lean = dir / "lean.json";
  const CommandResult r = runBtf(fitScene(scene, lean, "1e-12"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("could not be reduced within the budget (kept the full material): plastic retro"), std::string::npos)
      << r.output;
  const nlohmann::json j = readJson(lean);
  EXPECT_EQ(j["materials"]["plastic"]["type"], "merl");
  EXPECT_EQ(j["materials"]["plastic"]["file"], "plastic.binary");
}

TEST(FitSceneCli, BadOptionsFailWithoutOutput) {
  TempDir dir;
  const fs::path scene = writeTwoSphereScene(dir);
  CommandResult r = runBtf(fitScene(scene, dir / "lean.json", "0"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--budget"), std::string::npos) << r.output;
  r = runBtf(fitScene(scene, dir / "lean.txt", "0.01"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("must end in .json"), std::string::npos) << r.output;
  r = runBtf(fitScene(dir / "missing.json", dir / "lean.json", "0.01"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("missing.json"), std::string::npos) << r.output;
  r = runBtf(fitScene(scene, dir / "no-such-folder" / "lean.json", "0.01"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("output folder does not exist"), std::string::npos) << r.output;
  r = runBtf({"fit-scene", scene.string(), "-o", (dir / "lean.json").string(), "--fits", "ggx:7"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("lobes are for lafortune"), std::string::npos) << r.output;
  r = runBtf({"fit-scene", scene.string(), "-o", (dir / "lean.json").string(), "--measure", "pixels"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--measure"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "lean.json"));
  EXPECT_FALSE(fs::exists(dir / "lean-materials.work"));
}

}  // namespace
}  // namespace btf::test
