// Values that are valid numbers and absurd, and debris: every reproduction of issue 39 as a test.
// Nothing non-finite or partial leaves libbtf with exit 0; every error names the input (the file,
// and in a scene the JSON pointer) and the value.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sys/stat.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "btf/io/container.h"
#include "btf/io/image.h"
#include "btf/io/merl.h"
#include "cli_test_support.h"

namespace btf::test {
namespace {
namespace fs = std::filesystem;
using testing::HasSubstr;
using nlohmann::json;

void writeText(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

fs::path fabricExrFolder(const TempDir& dir) {
  const fs::path folder = dir / "f";
  const CommandResult r = runDatagen({"btf", "--pattern", "fabric", "--size", "4", "--format", "exr", "-o", folder.string()});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return folder;
}

// 1. A huge pixel is refused where it is read, naming the image; no output is written.
TEST(BadValues, HugePixelInABtfImageFailsTheCompression) {
  TempDir dir;
  const fs::path folder = fabricExrFolder(dir);
  const fs::path image = folder / "tv030_pv000_tl045_pl000.exr";
  writeImage(image, Image(4, 4, 3, 3e38f));
  const CommandResult r = runBtf({"compress", folder.string(), (dir / "o.btfz").string()});
  expectFailure(r, {image.string(), "3.00000", "e+38"});
  EXPECT_FALSE(fs::exists(dir / "o.btfz"));
}

// 1, 2. value_scale is checked as the float it becomes.
TEST(BadValues, ValueScaleIsCheckedAsAFloat) {
  TempDir dir;
  const fs::path folder = dir / "p";
  ASSERT_EQ(runDatagen({"btf", "--pattern", "fabric", "--size", "4", "--format", "png", "-o", folder.string()}).exit_code, 0);
  // The value as nlohmann::json prints it back.
  for (const auto& [scale, shown] : {std::pair{"3e38", "3e+38"}, {"1e300", "1e+300"}, {"1e-320", "1e-320"}}) {
    writeText(folder / "btf.json", std::string(R"({"value_scale": )") + scale + "}");
    expectFailure(runBtf({"info", folder.string()}), {(folder / "btf.json").string(), "value_scale", shown});
    expectFailure(runBtf({"compress", folder.string(), (dir / "o.btfz").string()}), {"value_scale"});
    EXPECT_FALSE(fs::exists(dir / "o.btfz"));
  }
}

fs::path writeScene(const fs::path& dir, const json& materials, const json& shapes, const json& lights) {
  const json scene = {{"camera", {{"position", {0, 0, 3}}, {"look_at", {0, 0, 0}}, {"resolution", {8, 8}}}},
                      {"materials", materials},
                      {"shapes", shapes},
                      {"lights", lights}};
  const fs::path file = dir / "scene.json";
  writeText(file, scene.dump(2));
  return file;
}

const json kGrey = {{"grey", {{"type", "lambert"}, {"albedo", 0.5}}}};
const json kSphere = json::array({{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"material", "grey"}}});
const json kSky = json::array({{{"type", "environment"}, {"radiance", 1}}});

CommandResult renderScene(const fs::path& scene, const fs::path& out) {
  return runBtf({"render", scene.string(), "-o", out.string(), "--spp", "1"});
}

// 3. Radiances and albedos beyond what a render keeps finite are refused, naming the scene entry.
TEST(BadValues, AbsurdRadianceOrAlbedoFailsTheRender) {
  TempDir dir;
  const fs::path out = dir / "r.exr";
  expectFailure(renderScene(writeScene(dir.path(), kGrey, kSphere, json::array({{{"type", "environment"}, {"radiance", 3e38}}})), out),
                {"scene.json", "/lights/0/radiance"});
  expectFailure(renderScene(writeScene(dir.path(), {{"grey", {{"type", "lambert"}, {"albedo", 3e38}}}}, kSphere, kSky), out),
                {"scene.json", "/materials/grey", "albedo"});
  writeImage(dir / "sky.exr", Image(8, 4, 3, 1e38f));
  expectFailure(renderScene(writeScene(dir.path(), kGrey, kSphere, json::array({{{"type", "environment"}, {"file", "sky.exr"}}})), out),
                {(dir / "sky.exr").string(), "radiance"});
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(dir / "r.png"));
}

// 4. The .btfz header is type-, range- and consistency-checked.
TEST(BadValues, BtfzHeaderNonsenseIsRefused) {
  TempDir dir;
  const fs::path folder = fabricExrFolder(dir);
  const fs::path good = dir / "good.btfz";
  ASSERT_EQ(runBtf({"compress", folder.string(), good.string(), "--no-verify"}).exit_code, 0);
  const std::vector<std::pair<std::string, std::function<void(json&)>>> edits = {
      {"format_version", [](json& h) { h["format_version"] = true; }},
      {"format_version", [](json& h) { h["format_version"] = 1.9; }},
      {"energy_floor", [](json& h) { h["energy_floor"] = 1e300; }},
      {"chroma_step", [](json& h) { h["chroma_step"] = 0.5; }},
      {"8 x 2", [](json& h) { h["width"] = 8, h["height"] = 2; }},
  };
  for (const auto& [what, edit] : edits) {
    const fs::path bad = rewriteContainer(good, dir / "bad.btfz", [&](std::vector<ContainerSection>& sections) {
      for (ContainerSection& s : sections)
        if (s.name == "header") {
          json h = json::parse(std::string(reinterpret_cast<const char*>(s.data.data()), s.data.size()));
          edit(h);
          const std::string text = h.dump();
          s.data.resize(text.size());
          std::memcpy(s.data.data(), text.data(), text.size());
        }
    });
    expectFailure(runBtf({"info", bad.string()}), {bad.string(), what});
  }
}

// 5. What an OBJ leaves to defaults is said, naming the scene entry; --strict makes it an error.
TEST(BadValues, ObjMaterialLibraryProblemsAreWarningsOrStrictErrors) {
  TempDir dir;
  fs::create_directory(dir / "lib.mtl");
  writeText(dir / "quad.obj", "mtllib lib.mtl\nmtllib missing.mtl\nusemtl nowhere\nv 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n");
  const json shapes = json::array({{{"file", "quad.obj"}, {"material", "mtl"}}});
  const fs::path scene = writeScene(dir.path(), json::object(), shapes, kSky);
  const CommandResult warned = renderScene(scene, dir / "w.exr");
  EXPECT_EQ(warned.exit_code, 0) << warned.output;
  EXPECT_THAT(warned.output, HasSubstr("/shapes/0"));
  EXPECT_THAT(warned.output, HasSubstr("lib.mtl' is not a regular file"));
  EXPECT_THAT(warned.output, HasSubstr("missing.mtl' was not found"));
  EXPECT_THAT(warned.output, HasSubstr("nowhere"));
  const CommandResult strict = runBtf({"render", scene.string(), "-o", (dir / "s.exr").string(), "--strict"});
  expectFailure(strict, {scene.string(), "/shapes/0/file", "--strict"});
  EXPECT_FALSE(fs::exists(dir / "s.exr"));
}

// 6. Geometry beyond float range names the scene file and the entry.
TEST(BadValues, SceneGeometryErrorsNameTheSceneFile) {
  TempDir dir;
  writeText(dir / "quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n");
  const std::vector<std::pair<json, std::string>> cases = {
      {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1e300}, {"material", "grey"}}, "/shapes/1/radius"},
      {{{"type", "sphere"}, {"center", {1e300, 0, 0}}, {"radius", 1}, {"material", "grey"}}, "/shapes/1/center/0"},
      {{{"type", "quad"}, {"corner", {0, 0, 0}}, {"edge_u", {1e30, 0, 0}}, {"edge_v", {0, 1e30, 0}}, {"material", "grey"}},
       "/shapes/1"},
      {{{"file", "quad.obj"}, {"material", "grey"}, {"transform", {{"scale", 1e300}}}}, "/shapes/1/transform/scale"},
  };
  for (const auto& [shape, pointer] : cases) {
    json shapes = kSphere;
    shapes.push_back(shape);
    const fs::path scene = writeScene(dir.path(), kGrey, shapes, kSky);
    expectFailure(renderScene(scene, dir / "r.exr"), {scene.string() + ": " + pointer});
  }
}

// 7. A fit file is bounded as the fitter is.
TEST(BadValues, FitFileLobesAreBounded) {
  TempDir dir;
  json lobes = json::array();
  for (int i = 0; i < 1000; ++i) lobes.push_back({{"rho", {0.01, 0.01, 0.01}}, {"c", {-1, -1, 1}}, {"exponent", 10}});
  const json fit = {{"format", "libbtf-fit"}, {"version", 1}, {"model", "lafortune"},
                    {"parameters", {{"diffuse", {0.1, 0.1, 0.1}}, {"lobes", lobes}}}};
  writeText(dir / "many.json", fit.dump());
  expectFailure(runBtf({"plot", (dir / "many.json").string(), "-o", (dir / "p.png").string()}),
                {(dir / "many.json").string(), "1000 lobes", "at most 9"});
  EXPECT_FALSE(fs::exists(dir / "p.png"));
}

// 9. The same render gives the same file, byte for byte: no capture time in the EXR header.
TEST(BadValues, RendersAreByteIdentical) {
  TempDir dir;
  const fs::path scene = writeScene(dir.path(), kGrey, kSphere, kSky);
  ASSERT_EQ(renderScene(scene, dir / "a.exr").exit_code, 0);
  ::sleep(1);  // a capture time has a resolution of one second
  ASSERT_EQ(renderScene(scene, dir / "b.exr").exit_code, 0);
  EXPECT_EQ(readBytes(dir / "a.exr"), readBytes(dir / "b.exr"));
}

// 10. An environment map is opened by content: a PNG named .exr holds display values.
TEST(BadValues, APngNamedExrIsNoEnvironmentMap) {
  TempDir dir;
  writeImage(dir / "sky.png", Image(8, 4, 3, 0.5f));
  fs::rename(dir / "sky.png", dir / "sky.exr");
  const fs::path scene = writeScene(dir.path(), kGrey, kSphere, json::array({{{"type", "environment"}, {"file", "sky.exr"}}}));
  expectFailure(renderScene(scene, dir / "r.exr"), {(dir / "sky.exr").string(), "png", "not OpenEXR"});
}

// 11. A render too large for libbtf to read back is refused before it starts.
TEST(BadValues, RenderSizeAgreesWithTheImageReaders) {
  TempDir dir;
  json scene = json::parse(readBytes(writeScene(dir.path(), kGrey, kSphere, kSky)));
  scene["camera"]["resolution"] = {16384, 16384};
  writeText(dir / "big.json", scene.dump());
  expectFailure(renderScene(dir / "big.json", dir / "r.exr"), {"big.json", "/camera/resolution", "reads back"});
}

// 12. Messages that say what is wrong.
TEST(BadValues, MessagesNameTheRealProblem) {
  TempDir dir;
  std::ofstream(dir / "empty.octree");
  const CommandResult octree = runBtf({"info", (dir / "empty.octree").string()});
  expectFailure(octree, {"empty.octree"});
  EXPECT_THAT(octree.output, testing::Not(HasSubstr("expected a .btfz container")));

  json fit = {{"format", "libbtf-fit"}, {"version", 1}, {"model", "lafortune"},
              {"parameters", {{"diffuse", {0.1, 0.1, 0.1}}, {"lobes", {3}}}}};
  writeText(dir / "lobe.json", fit.dump());
  const CommandResult lobe = runBtf({"info", (dir / "lobe.json").string()});
  expectFailure(lobe, {"/parameters/lobes/0", "expected an object"});
  EXPECT_THAT(lobe.output, testing::Not(HasSubstr("unknown key \"\"")));

  json far = json::parse(readBytes(writeScene(dir.path(), kGrey, kSphere, kSky)));
  far["camera"]["position"] = {0, 0, 3e38};
  writeText(dir / "far.json", far.dump());
  const CommandResult camera = renderScene(dir / "far.json", dir / "r.exr");
  expectFailure(camera, {"far.json", "/camera", "too large"});
  EXPECT_THAT(camera.output, testing::Not(HasSubstr("parallel")));

  ASSERT_EQ(::mkfifo((dir / "pipe.obj").c_str(), 0600), 0);
  const fs::path scene = writeScene(dir.path(), kGrey, json::array({{{"file", "pipe.obj"}, {"material", "grey"}}}), kSky);
  expectFailure(renderScene(scene, dir / "r.exr"), {"pipe.obj", "not a regular file"});
}

}  // namespace
}  // namespace btf::test
