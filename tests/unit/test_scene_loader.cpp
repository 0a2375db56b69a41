// Scene files (scene_loader.h): every material type, samplers, OBJ .mtl materials with per-part
// overrides, transforms, shading, shapes and lights, paths relative to the scene; and for every bad
// input a FileError naming the scene file and the JSON pointer of the offending value. Also the
// checks the Scene constructor makes of a description built in code.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "btf/compress/octree_table.h"
#include "btf/core/error.h"
#include "btf/core/progress.h"
#include "btf/io/merl.h"
#include "btf/material/ggx.h"
#include "btf/material/lafortune.h"
#include "btf/material/lambert.h"
#include "btf/material/octree_brdf.h"
#include "btf/material/phong.h"
#include "btf/material/rgl_brdf.h"
#include "btf/material/tabulated_brdf.h"
#include "btf/material/ward.h"
#include "btf/render/integrator.h"
#include "btf/render/scene.h"
#include "btf/render/scene_loader.h"
#include "btf/sampling/binned_sampler.h"
#include "support/test_support.h"

namespace btf::render {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

void writeText(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// A floor (white Lambert, facing up) under a small quad light facing down, seen from above.
json baseScene() {
  return json::parse(R"({
    "camera": {"position": [0, 1, 3], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov_deg": 40, "resolution": [16, 12]},
    "materials": {"white": {"type": "lambert", "albedo": [0.7, 0.6, 0.5]}},
    "shapes": [
      {"type": "quad", "corner": [-1, 0, -1], "edge_u": [0, 0, 2], "edge_v": [2, 0, 0], "material": "white"},
      {"type": "quad", "corner": [-0.25, 1.5, -0.25], "edge_u": [0.5, 0, 0], "edge_v": [0, 0, 0.5], "emission": [5, 4, 3]}
    ]
  })");
}

fs::path writeScene(const test::TempDir& dir, const json& scene, const std::string& name = "scene.json") {
  const fs::path path = dir / name;
  writeText(path, scene.dump(2));
  return path;
}

SceneDescription loadScene(const test::TempDir& dir, const json& scene, const SceneLoadOptions& options = {}) {
  return loadSceneDescription(writeScene(dir, scene), options);
}

// Expects loading `file` to throw a FileError naming the file and containing every one of `parts`
// (the JSON pointer first).
void expectLoadError(const fs::path& file, const std::vector<std::string>& parts, const SceneLoadOptions& options = {}) {
  try {
    loadSceneDescription(file, options);
    ADD_FAILURE() << "no error for " << file;
  } catch (const FileError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(file.string()), std::string::npos) << "the scene file is not named: " << what;
    for (const std::string& part : parts) EXPECT_NE(what.find(part), std::string::npos) << "'" << part << "' not in: " << what;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not a FileError: " << e.what();
  }
}

void expectSceneError(const json& scene, const std::vector<std::string>& parts) {
  test::TempDir dir;
  expectLoadError(writeScene(dir, scene), parts);
}

// ---------------------------------------------------------------------------------------------
// What loads

TEST(SceneLoader, BaseScene) {
  test::TempDir dir;
  const SceneDescription d = loadScene(dir, baseScene());
  EXPECT_EQ(d.file, dir / "scene.json");
  EXPECT_EQ(d.camera.position, glm::vec3(0, 1, 3));
  EXPECT_EQ(d.camera.look_at, glm::vec3(0));
  EXPECT_FLOAT_EQ(d.camera.fov_deg, 40.0f);
  EXPECT_EQ(d.camera.width, 16);
  EXPECT_EQ(d.camera.height, 12);
  EXPECT_EQ(d.render.spp, RenderDefaults{}.spp);
  ASSERT_EQ(d.materials.size(), 1u);
  EXPECT_EQ(d.materials[0].name, "white");
  ASSERT_EQ(d.shapes.size(), 2u);
  EXPECT_EQ(d.shapes[0].material, 0);
  EXPECT_TRUE(d.shapes[0].emission.isBlack());
  EXPECT_EQ(d.shapes[1].material, -1);  // a pure emitter
  EXPECT_EQ(d.shapes[1].emission, Rgb(5, 4, 3));
  EXPECT_FALSE(d.shapes[1].two_sided_emission);
  // The quad's winding: the floor faces up, the light down.
  const TriangleMesh& floor = d.shapes[0].mesh;
  const glm::uvec3 t = floor.triangles[0];
  EXPECT_GT(glm::cross(floor.positions[t.y] - floor.positions[t.x], floor.positions[t.z] - floor.positions[t.x]).y, 0.0f);
  const Scene scene(d);
  ASSERT_EQ(scene.lights().size(), 1u);
  EXPECT_NEAR(scene.shapeArea(1), 0.25f, 1e-6f);
}

TEST(SceneLoader, RenderSettings) {
  test::TempDir dir;
  json s = baseScene();
  s["render"] = {{"spp", 7}, {"max_depth", 5}, {"rr_min_depth", 2}};
  s["comment"] = "comments are allowed at the top";
  const SceneDescription d = loadScene(dir, s);
  EXPECT_EQ(d.render.spp, 7);
  EXPECT_EQ(d.render.max_depth, 5);
  EXPECT_EQ(d.render.rr_min_depth, 2);
}

TEST(SceneLoader, AnalyticMaterials) {
  test::TempDir dir;
  json s = baseScene();
  s["materials"] = json::parse(R"({
    "white": {"type": "lambert", "albedo": 0.5},
    "shiny": {"type": "phong", "diffuse": [0.2, 0.2, 0.2], "specular": [0.5, 0.5, 0.5], "exponent": 40},
    "plastic": {"type": "ggx", "diffuse": [0.2, 0.02, 0.02], "f0": [0.04, 0.04, 0.04], "alpha": 0.2},
    "brushed": {"type": "ggx", "diffuse": 0, "f0": [0.9, 0.6, 0.3], "alpha": [0.1, 0.4]},
    "wood": {"type": "ward", "diffuse": [0.3, 0.2, 0.1], "specular": 0.1, "alpha": [0.2, 0.3]},
    "paint": {"type": "lafortune", "diffuse": [0.1, 0.1, 0.1],
              "lobes": [{"rho": [0.4, 0.4, 0.4], "c": [-1, -1, 1], "exponent": 20},
                        {"rho": 0.1, "c": [-0.5, -1, 0.8], "exponent": 5}]}
  })");
  const SceneDescription d = loadScene(dir, s);
  ASSERT_EQ(d.materials.size(), 6u);
  auto find = [&](const std::string& name) -> const SceneMaterial& {
    for (const SceneMaterial& m : d.materials)
      if (m.name == name) return m;
    throw std::runtime_error("no material " + name);
  };
  const glm::vec3 wi = glm::normalize(glm::vec3(0.3f, 0.1f, 0.9f)), wo = glm::normalize(glm::vec3(-0.2f, 0.4f, 0.8f));
  const auto* lambert = dynamic_cast<const Lambert*>(find("white").material.get());
  ASSERT_NE(lambert, nullptr);
  EXPECT_EQ(lambert->albedo(), Rgb(0.5f));
  EXPECT_NEAR(lambert->eval(wi, wo).g, 0.5f / std::numbers::pi_v<float>, 1e-6f);
  EXPECT_NE(dynamic_cast<const Phong*>(find("shiny").material.get()), nullptr);
  EXPECT_NE(dynamic_cast<const Ggx*>(find("plastic").material.get()), nullptr);
  EXPECT_FALSE(find("plastic").material->isAnisotropic());
  EXPECT_NE(dynamic_cast<const Ggx*>(find("brushed").material.get()), nullptr);
  EXPECT_TRUE(find("brushed").material->isAnisotropic());
  EXPECT_NE(dynamic_cast<const Ward*>(find("wood").material.get()), nullptr);
  EXPECT_TRUE(find("wood").material->isAnisotropic());
  EXPECT_NE(dynamic_cast<const Lafortune*>(find("paint").material.get()), nullptr);
  for (const SceneMaterial& m : d.materials) {
    EXPECT_EQ(m.sampler, "material") << m.name;
    EXPECT_EQ(m.sampled, m.material) << m.name;  // the material's own sampler
    EXPECT_EQ(m.mapping, UvMapping::Mesh);
    const Rgb f = m.material->eval(wi, wo);
    EXPECT_TRUE(f.isFinite() && f.minComponent() >= 0.0f && f.average() > 0.0f) << m.name;
  }
}

TEST(SceneLoader, MerlMaterialRelativeToTheScene) {
  test::TempDir dir;
  const Rgb albedo(0.5f, 0.4f, 0.3f);
  fs::create_directories(dir / "tables");
  writeMerl(dir / "tables/diffuse.binary", tabulate(Lambert(albedo)));
  json s = baseScene();
  s["materials"]["table"] = {{"type", "merl"}, {"file", "tables/diffuse.binary"}};
  s["materials"]["nearest"] = {{"type", "merl"}, {"file", (dir / "tables/diffuse.binary").string()}, {"lookup", "nearest"}};
  s["shapes"][0]["material"] = "table";
  const SceneDescription d = loadScene(dir, s);
  ASSERT_EQ(d.materials.size(), 3u);
  int found = 0;
  const glm::vec3 wi = glm::normalize(glm::vec3(0.3f, 0.1f, 0.9f)), wo = glm::normalize(glm::vec3(-0.2f, 0.4f, 0.8f));
  for (const SceneMaterial& m : d.materials) {
    const auto* table = dynamic_cast<const TabulatedBrdf*>(m.material.get());
    if (!table) continue;
    ++found;
    EXPECT_EQ(table->lookup(), m.name == "nearest" ? TableLookup::Nearest : TableLookup::Interpolated);
    const Rgb f = table->eval(wi, wo);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(f[c], albedo[c] / std::numbers::pi_v<float>, 0.01f * albedo[c]) << m.name;
  }
  EXPECT_EQ(found, 2);

  json bad = s;
  bad["materials"]["table"]["lookup"] = "cubic";
  expectLoadError(writeScene(dir, bad, "bad-lookup.json"), {"/materials/table/lookup", "interpolated"});
  bad = s;
  bad["materials"]["table"]["file"] = "tables/missing.binary";
  expectLoadError(writeScene(dir, bad, "missing.json"), {"/materials/table/file", "missing.binary"});
}

TEST(SceneLoader, RglMaterial) {
  const fs::path bsdf = test::sharedDataDir() / "rgl_bsdf/paper_white_rgb.bsdf";
  ASSERT_TRUE(fs::exists(bsdf)) << "no " << bsdf;
  test::TempDir dir;
  json s = baseScene();
  s["materials"]["paper"] = {{"type", "rgl"}, {"file", bsdf.string()}};
  s["shapes"][0]["material"] = "paper";
  const SceneDescription d = loadScene(dir, s);
  ASSERT_EQ(d.materials.size(), 2u);
  const SceneMaterial& paper = d.materials[0].name == "paper" ? d.materials[0] : d.materials[1];
  ASSERT_EQ(paper.name, "paper");
  EXPECT_NE(dynamic_cast<const RglBrdf*>(paper.material.get()), nullptr);
  EXPECT_GT(paper.material->eval(glm::vec3(0, 0, 1), glm::normalize(glm::vec3(0.1f, 0, 1))).average(), 0.0f);
}

// A model written by `btf fit`, as a material: the file's parameters, and its errors named.
TEST(SceneLoader, FittedMaterial) {
  test::TempDir dir;
  writeText(dir / "fits/ggx.json", R"({"format": "libbtf-fit", "version": 1, "model": "ggx",
    "parameters": {"diffuse": [0.2, 0.3, 0.4], "f0": [0.04, 0.04, 0.04], "alpha": 0.2}})");
  json s = baseScene();
  s["materials"]["fit"] = {{"type", "fitted"}, {"file", "fits/ggx.json"}};
  s["shapes"][0]["material"] = "fit";
  const SceneDescription d = loadScene(dir, s);
  const SceneMaterial& fit = d.materials[0].name == "fit" ? d.materials[0] : d.materials[1];
  ASSERT_NE(dynamic_cast<const Ggx*>(fit.material.get()), nullptr);
  const glm::vec3 wi(0, 0, 1), wo = glm::normalize(glm::vec3(0.3f, 0, 1));
  EXPECT_EQ(fit.material->eval(wi, wo).g, Ggx(Rgb(0.2f, 0.3f, 0.4f), Rgb(0.04f), 0.2f, 0.2f).eval(wi, wo).g);
  writeText(dir / "fits/bad.json", R"({"format": "libbtf-fit", "version": 1, "model": "ggx",
    "parameters": {"diffuse": [0.2, 0.3, 0.4], "f0": [0.04, 0.04, 2], "alpha": 0.2}})");
  s["materials"]["fit"]["file"] = "fits/bad.json";
  try {
    (void)loadScene(dir, s);
    ADD_FAILURE() << "no error";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("/parameters/f0/2"), std::string::npos) << e.what();
  }
}

// An octree table written by `btf convert`, as a material with its lookup.
TEST(SceneLoader, OctreeMaterial) {
  test::TempDir dir;
  const Lambert lambert(Rgb(0.2f, 0.4f, 0.6f));
  writeOctreeFile(dir / "white.octree", OctreeTable::build(tabulate(lambert), 0.0));
  json s = baseScene();
  s["materials"]["oct"] = {{"type", "octree"}, {"file", "white.octree"}, {"lookup", "nearest"}};
  s["shapes"][0]["material"] = "oct";
  const SceneDescription d = loadScene(dir, s);
  const SceneMaterial& oct = d.materials[0].name == "oct" ? d.materials[0] : d.materials[1];
  ASSERT_NE(dynamic_cast<const OctreeBrdf*>(oct.material.get()), nullptr);
  EXPECT_NE(oct.material->name().find("lookup=nearest"), std::string::npos);
  const glm::vec3 wi(0, 0, 1), wo = glm::normalize(glm::vec3(0.3f, 0, 1));
  EXPECT_NEAR(oct.material->eval(wi, wo).b, lambert.eval(wi, wo).b, 1e-6f);
  s["materials"]["oct"]["lookup"] = "cubic";
  EXPECT_THAT(test::errorOf([&] { (void)loadScene(dir, s); }), ::testing::HasSubstr("expected interpolated, nearest or truncated"));
}

TEST(SceneLoader, SamplerChoices) {
  test::TempDir dir;
  json s = baseScene();
  const std::vector<std::string> samplers = {"material", "cosine", "uniform", "tabulated", "dp-cdf", "quadtree"};
  s["materials"] = json::object();
  for (const std::string& name : samplers) s["materials"]["m-" + name] = {{"type", "lambert"}, {"albedo", 0.5}, {"sampler", name}};
  s["shapes"][0]["material"] = "m-cosine";
  const SceneDescription d = loadScene(dir, s);
  ASSERT_EQ(d.materials.size(), samplers.size());
  const glm::vec3 wi = glm::normalize(glm::vec3(0.6f, 0.0f, 0.8f)), wo(0, 0, 1);
  for (const SceneMaterial& m : d.materials) {
    ASSERT_EQ(m.name, "m-" + m.sampler);
    ASSERT_NE(m.sampled, nullptr);
    // Whatever the sampler, eval is the material's.
    EXPECT_FLOAT_EQ(m.sampled->eval(wi, wo).r, m.material->eval(wi, wo).r) << m.name;
    const bool binned = dynamic_cast<const BinnedSampler*>(m.sampled.get()) != nullptr;
    EXPECT_EQ(binned, m.sampler == "tabulated" || m.sampler == "dp-cdf" || m.sampler == "quadtree") << m.name;
    if (m.sampler == "material") {
      EXPECT_EQ(m.sampled, m.material);
    } else if (m.sampler == "cosine") {
      EXPECT_NEAR(m.sampled->pdf(wi, wo), 0.8f / std::numbers::pi_v<float>, 1e-6f);
    } else if (m.sampler == "uniform") {
      EXPECT_NEAR(m.sampled->pdf(wi, wo), 0.5f / std::numbers::pi_v<float>, 1e-6f);
    }
  }

  // The command line's --sampler replaces every material's.
  SceneLoadOptions options;
  options.sampler_override = "uniform";
  const SceneDescription u = loadScene(dir, s, options);
  for (const SceneMaterial& m : u.materials) {
    EXPECT_EQ(m.sampler, "uniform") << m.name;
    EXPECT_NEAR(m.sampled->pdf(wi, wo), 0.5f / std::numbers::pi_v<float>, 1e-6f);
  }

  json bad = baseScene();
  bad["materials"]["white"]["sampler"] = "importance";
  expectSceneError(bad, {"/materials/white/sampler", "unknown sampler 'importance'", "dp-cdf"});
  bad["materials"]["white"]["sampler"] = 3;
  expectSceneError(bad, {"/materials/white/sampler", "expected a string"});
  options.sampler_override = "importance";
  expectLoadError(writeScene(dir, baseScene()), {"/materials/white", "unknown sampler 'importance'"}, options);
}

// A unit cube as an OBJ without normals, in two groups with materials from its .mtl.
void writeCubeObj(const fs::path& obj) {
  writeText(obj.parent_path() / "cube.mtl",
            "newmtl sides\nKd 0.2 0.4 0.6\nKe 0 0 0\n\n"
            "newmtl top\nKd 0.9 0.9 0.9\nKe 2 3 4\n");
  writeText(obj,
            "mtllib cube.mtl\n"
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
            "g sides\nusemtl sides\n"
            "f 1 3 4 2\nf 1 2 6 5\nf 1 5 7 3\nf 2 4 8 6\nf 3 7 8 4\n"
            "g lid\nusemtl top\n"
            "f 5 6 8 7\n");
}

TEST(SceneLoader, MeshShadingAndRelativePaths) {
  test::TempDir dir;
  // The scene in one folder, the mesh in a sibling: "../meshes/cube.obj" resolves against the
  // scene's folder, not the working directory.
  writeCubeObj(dir / "meshes/cube.obj");
  json s = baseScene();
  s["shapes"].push_back({{"file", "../meshes/cube.obj"}, {"material", "white"}});
  s["shapes"].push_back({{"file", "../meshes/cube.obj"}, {"material", "white"}, {"crease_deg", 180}});
  s["shapes"].push_back({{"file", "../meshes/cube.obj"}, {"material", "white"}, {"shading", "flat"}});
  s["shapes"].push_back({{"type", "mesh"}, {"file", "../meshes/cube.obj"}, {"material", "white"}, {"shading", "smooth"}});
  ASSERT_FALSE(fs::exists("../meshes/cube.obj"));
  fs::create_directories(dir / "scenes");
  const SceneDescription d = loadSceneDescription(writeScene(dir, s, "scenes/scene.json"));
  // Each file gives two parts (sides, lid).
  ASSERT_EQ(d.shapes.size(), 2u + 4u * 2u);
  std::size_t sides_vertices[4] = {}, lid_vertices[4] = {};
  for (int k = 0; k < 4; ++k)
    for (int p = 0; p < 2; ++p) {
      const TriangleMesh& mesh = d.shapes[2 + 2 * k + p].mesh;
      EXPECT_NE(mesh.name.find("cube.obj"), std::string::npos) << mesh.name;
      (mesh.file_material == "top" ? lid_vertices : sides_vertices)[k] = mesh.positions.size();
      if (k == 2) {
        EXPECT_TRUE(mesh.normals.empty()) << "flat shading keeps no vertex normals";
      } else {
        EXPECT_EQ(mesh.normals.size(), mesh.positions.size());
      }
      EXPECT_EQ(mesh.triangles.size(), mesh.file_material == "top" ? 2u : 10u);
    }
  // Smooth with the default 60-degree crease: the five sides keep their edges (each corner one
  // vertex per face: 4 x 5); with 180 degrees the 8 corners are shared (the lid's 4 included).
  EXPECT_EQ(sides_vertices[0], 20u);
  EXPECT_EQ(sides_vertices[1], 8u);
  EXPECT_EQ(sides_vertices[3], sides_vertices[0]);
  EXPECT_EQ(lid_vertices[0], 4u);

  json bad = s;
  bad["shapes"][2]["shading"] = "phong";
  expectLoadError(writeScene(dir, bad, "scenes/bad-shading.json"), {"/shapes/2/shading", "smooth or flat"});
  bad = s;
  bad["shapes"][3]["crease_deg"] = 270;
  expectLoadError(writeScene(dir, bad, "scenes/bad-crease.json"), {"/shapes/3/crease_deg", "[0, 180]"});
}

struct CapturedLog {
  std::vector<std::string> warnings;
  CapturedLog() {
    setLogHook([this](LogLevel level, std::string_view message) {
      if (level == LogLevel::Warning) warnings.emplace_back(message);
    });
  }
  ~CapturedLog() { setLogHook(nullptr); }
};

// Smooth normals need the degenerate faces gone first; what goes is still reported.
TEST(SceneLoader, SmoothMeshReportsDroppedTriangles) {
  test::TempDir dir;
  writeText(dir / "dirty.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\n"
            "f 1 2 3\nf 1 2 4\n");  // the second face is collinear
  json s = baseScene();
  s["shapes"].push_back({{"file", "dirty.obj"}, {"material", "white"}});
  CapturedLog log;
  const SceneDescription d = loadScene(dir, s);
  ASSERT_EQ(d.shapes.size(), 3u);
  EXPECT_EQ(d.shapes[2].mesh.triangles.size(), 1u);
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_NE(log.warnings[0].find("dirty.obj"), std::string::npos) << log.warnings[0];
  EXPECT_NE(log.warnings[0].find("1 of zero area"), std::string::npos) << log.warnings[0];
}

TEST(SceneLoader, ObjMtlMaterialsAndPartOverrides) {
  test::TempDir dir;
  writeCubeObj(dir / "cube.obj");
  json s = baseScene();
  s["materials"]["gold"] = {{"type", "ggx"}, {"diffuse", 0}, {"f0", {1.0, 0.8, 0.3}}, {"alpha", 0.3}};
  s["shapes"].push_back({{"file", "cube.obj"}, {"material", "mtl"}});
  s["shapes"].push_back({{"file", "cube.obj"}, {"material", "mtl"}, {"part_materials", {{"sides", "gold"}}}});
  // Group names work too; the emission of the file is not used for an overridden part.
  s["shapes"].push_back({{"file", "cube.obj"}, {"material", "mtl"}, {"part_materials", {{"lid", "white"}}}});
  const SceneDescription d = loadScene(dir, s);
  ASSERT_EQ(d.shapes.size(), 8u);
  auto materialName = [&](const SceneShape& shape) { return d.materials[std::size_t(shape.material)].name; };
  for (int k = 0; k < 3; ++k)
    for (int p = 0; p < 2; ++p) {
      const SceneShape& shape = d.shapes[std::size_t(2 + 2 * k + p)];
      const bool lid = shape.mesh.file_material == "top";
      ASSERT_GE(shape.material, 0);
      if ((k == 1 && !lid)) {
        EXPECT_EQ(materialName(shape), "gold");
      } else if (k == 2 && lid) {
        EXPECT_EQ(materialName(shape), "white");
        EXPECT_TRUE(shape.emission.isBlack());
      } else {
        const auto* lambert = dynamic_cast<const Lambert*>(d.materials[std::size_t(shape.material)].material.get());
        ASSERT_NE(lambert, nullptr) << materialName(shape);
        EXPECT_EQ(lambert->albedo(), lid ? Rgb(0.9f) : Rgb(0.2f, 0.4f, 0.6f));
        EXPECT_EQ(shape.emission, lid ? Rgb(2, 3, 4) : Rgb(0.0f));
      }
    }

  json bad = s;
  bad["shapes"][3]["part_materials"] = {{"side", "gold"}};
  expectLoadError(writeScene(dir, bad, "no-part.json"), {"/shapes/3/part_materials/side", "no part named 'side'"});
  bad["shapes"][3]["part_materials"] = {{"sides", "silver"}};
  expectLoadError(writeScene(dir, bad, "no-material.json"), {"/shapes/3/part_materials/sides", "unknown material 'silver'"});
  bad["shapes"][3]["part_materials"] = {{"sides", 1}};
  expectLoadError(writeScene(dir, bad, "not-a-string.json"), {"/shapes/3/part_materials/sides", "expected a string"});
}

TEST(SceneLoader, CornellBoxMtl) {
  const fs::path obj = test::sharedDataDir() / "meshes/cornell_box/CornellBox-Original.obj";
  ASSERT_TRUE(fs::exists(obj)) << "no " << obj;
  test::TempDir dir;
  json s = baseScene();
  s["materials"]["gold"] = {{"type", "ggx"}, {"diffuse", 0}, {"f0", {1.0, 0.8, 0.3}}, {"alpha", 0.3}};
  s["shapes"] = json::array({{{"file", obj.string()}, {"material", "mtl"}, {"part_materials", {{"tallBox", "gold"}}}}});
  const SceneDescription d = loadScene(dir, s);
  std::map<std::string, const SceneShape*> by_part;
  std::size_t triangles = 0;
  for (const SceneShape& shape : d.shapes) {
    by_part[shape.mesh.file_material] = &shape;
    triangles += shape.mesh.triangles.size();
  }
  EXPECT_EQ(triangles, 36u);
  for (const char* part : {"floor", "ceiling", "backWall", "rightWall", "leftWall", "shortBox", "tallBox", "light"})
    ASSERT_TRUE(by_part.count(part)) << part;
  EXPECT_EQ(by_part["light"]->emission, Rgb(17, 12, 4));
  const auto* left = dynamic_cast<const Lambert*>(d.materials[std::size_t(by_part["leftWall"]->material)].material.get());
  ASSERT_NE(left, nullptr);
  EXPECT_EQ(left->albedo(), Rgb(0.63f, 0.065f, 0.05f));
  EXPECT_EQ(d.materials[std::size_t(by_part["tallBox"]->material)].name, "gold");
  EXPECT_NE(dynamic_cast<const Lambert*>(d.materials[std::size_t(by_part["shortBox"]->material)].material.get()), nullptr);
  // The box is lit by its own light.
  const Scene scene(d);
  ASSERT_EQ(scene.lights().size(), 1u);
  EXPECT_EQ(scene.lights()[0].kind, Scene::LightPower::Kind::Area);

  // The file keeps the tall box in group "shortBox": an override of the .mtl name "shortBox"
  // must still paint the short box alone.
  s["shapes"][0]["part_materials"] = {{"shortBox", "gold"}};
  const SceneDescription short_gold = loadScene(dir, s);
  std::size_t gold_triangles = 0;
  for (const SceneShape& shape : short_gold.shapes) {
    const bool gold = short_gold.materials[std::size_t(shape.material)].name == "gold";
    EXPECT_EQ(gold, shape.mesh.file_material == "shortBox") << shape.mesh.name << " [" << shape.mesh.file_material << "]";
    if (gold) gold_triangles += shape.mesh.triangles.size();
  }
  EXPECT_EQ(gold_triangles, 12u);

  // Skipping the short box leaves the tall one.
  s["shapes"][0].erase("part_materials");
  s["shapes"][0]["skip_parts"] = {"shortBox", "light"};
  s["shapes"].push_back(baseScene()["shapes"][1]);  // a light instead of the box's own
  const SceneDescription skipped = loadScene(dir, s);
  std::size_t kept_triangles = 0;
  for (const SceneShape& shape : skipped.shapes) {
    EXPECT_NE(shape.mesh.file_material, "shortBox");
    EXPECT_NE(shape.mesh.file_material, "light");
    if (shape.mesh.file_material == "tallBox") kept_triangles += shape.mesh.triangles.size();
  }
  EXPECT_EQ(kept_triangles, 12u);
  s["shapes"][0]["skip_parts"] = {"shortbox"};
  expectLoadError(writeScene(dir, s, "skip-typo.json"), {"/shapes/0/skip_parts", "no part named 'shortbox'"});
  s["shapes"][0].erase("skip_parts");

  s["shapes"][0]["part_materials"] = {{"tallbox", "gold"}};  // names are case-sensitive
  expectLoadError(writeScene(dir, s, "typo.json"), {"/shapes/0/part_materials/tallbox", "no part named"});
}

TEST(SceneLoader, Transforms) {
  test::TempDir dir;
  json s = baseScene();
  // Scale, then rotate, then translate: (1, 0, 0) -> (2, 0, 0) -> (0, 0, -2) -> (0, 0, 3).
  s["shapes"].push_back({{"type", "quad"}, {"corner", {1, 0, 0}}, {"edge_u", {0, 1, 0}}, {"edge_v", {0, 0, 1}},
                         {"material", "white"},
                         {"transform", {{"scale", 2}, {"rotate", {{"axis", {0, 1, 0}}, {"deg", 90}}}, {"translate", {0, 0, 5}}}}});
  // A mirroring scale keeps the vertex normals and the winding in agreement.
  s["shapes"].push_back({{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1}, {"rings", 8}, {"material", "white"},
                         {"transform", {{"scale", {-1, 2, 1}}, {"translate", {0, 3, 0}}}}});
  const SceneDescription d = loadScene(dir, s);
  ASSERT_EQ(d.shapes.size(), 4u);
  const TriangleMesh& quad = d.shapes[2].mesh;
  EXPECT_NEAR(quad.positions[0].x, 0.0f, 1e-5f);
  EXPECT_NEAR(quad.positions[0].y, 0.0f, 1e-5f);
  EXPECT_NEAR(quad.positions[0].z, 3.0f, 1e-5f);
  // edge_u (0, 1, 0) -> (0, 2, 0); edge_v (0, 0, 1) -> (0, 0, 2) -> (2, 0, 0).
  EXPECT_NEAR(quad.positions[2].x, 2.0f, 1e-5f);
  EXPECT_NEAR(quad.positions[2].y, 2.0f, 1e-5f);
  EXPECT_NEAR(quad.positions[2].z, 3.0f, 1e-5f);
  const TriangleMesh& sphere = d.shapes[3].mesh;
  for (std::size_t v = 0; v < sphere.positions.size(); ++v) {
    const glm::vec3 p = sphere.positions[v] - glm::vec3(0, 3, 0);
    EXPECT_NEAR(p.x * p.x + p.y * p.y / 4 + p.z * p.z, 1.0f, 1e-4f);
  }
  for (const glm::uvec3& t : sphere.triangles) {
    const glm::vec3 w = glm::cross(sphere.positions[t.y] - sphere.positions[t.x], sphere.positions[t.z] - sphere.positions[t.x]);
    for (int k = 0; k < 3; ++k) EXPECT_GT(glm::dot(w, sphere.normals[t[k]]), 0.0f);
  }

  json bad = baseScene();
  bad["shapes"][0]["transform"] = {{"scale", 0}};
  expectSceneError(bad, {"/shapes/0/transform/scale", "zero"});
  bad["shapes"][0]["transform"] = {{"rotate", {{"axis", {0, 0, 0}}, {"deg", 10}}}};
  expectSceneError(bad, {"/shapes/0/transform/rotate/axis"});
  bad["shapes"][0]["transform"] = {{"translate", {0, 1}}};
  expectSceneError(bad, {"/shapes/0/transform/translate", "3 numbers"});
  bad["shapes"][0]["transform"] = {{"rotation", {{"axis", {0, 1, 0}}, {"deg", 10}}}};
  expectSceneError(bad, {"/shapes/0/transform/rotation", "unknown key"});
}

TEST(SceneLoader, SpheresQuadsAndLights) {
  test::TempDir dir;
  json s = baseScene();
  s["shapes"].push_back({{"type", "sphere"}, {"center", {0, 0.5, 0}}, {"radius", 0.25}, {"material", "white"}});
  s["shapes"].push_back({{"type", "quad"}, {"corner", {-1, 0, -1}}, {"edge_u", {2, 0, 0}}, {"edge_v", {0, 2, 0}},
                         {"emission", 0.5}, {"two_sided", true}});
  s["lights"] = json::parse(R"([
    {"type": "point", "position": [0, 2, 0], "intensity": [2, 3, 4]},
    {"type": "point", "position": [1, 2, 0], "intensity": 1},
    {"type": "environment", "radiance": [0.1, 0.2, 0.3]}
  ])");
  const SceneDescription d = loadScene(dir, s);
  ASSERT_EQ(d.shapes.size(), 4u);
  const TriangleMesh& sphere = d.shapes[2].mesh;
  ASSERT_EQ(sphere.normals.size(), sphere.positions.size());
  for (const glm::vec3& p : sphere.positions) EXPECT_NEAR(glm::length(p - glm::vec3(0, 0.5f, 0)), 0.25f, 1e-5f);
  EXPECT_TRUE(d.shapes[3].two_sided_emission);
  EXPECT_EQ(d.shapes[3].emission, Rgb(0.5f));
  ASSERT_EQ(d.point_lights.size(), 2u);
  EXPECT_EQ(d.point_lights[0].position, glm::vec3(0, 2, 0));
  EXPECT_EQ(d.point_lights[0].intensity, Rgb(2, 3, 4));
  EXPECT_EQ(d.point_lights[1].intensity, Rgb(1));
  EXPECT_EQ(d.environment_radiance, Rgb(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(d.environment_map, nullptr);
  const Scene scene(d);
  EXPECT_TRUE(scene.hasEnvironment());
  EXPECT_EQ(scene.environment(glm::vec3(0, 1, 0)), Rgb(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(scene.lights().size(), 2u + 2u + 1u);
}

// A material whose name is not a plain word is still pointed at correctly (RFC 6901 escapes).
TEST(SceneLoader, PointersEscapeSlashAndTilde) {
  json s = baseScene();
  s["materials"]["metal/gold~2"] = {{"type", "lambert"}, {"albedo", -1}};
  expectSceneError(s, {"/materials/metal~1gold~02/albedo", "negative"});
}

// ---------------------------------------------------------------------------------------------
// Bad input: a FileError naming the scene file and the JSON pointer

TEST(SceneLoaderErrors, MissingOrMalformedFile) {
  test::TempDir dir;
  expectLoadError(dir / "nothing.json", {"no such scene file"});
  expectLoadError(dir.path(), {"no such scene file"});
  writeText(dir / "broken.json", "{\n  \"camera\": {\"position\": [0, 1, 3],,\n}");
  expectLoadError(dir / "broken.json", {"malformed JSON", "line 2"});
  writeText(dir / "empty.json", "");
  expectLoadError(dir / "empty.json", {"malformed JSON"});
  writeText(dir / "array.json", "[1, 2]");
  expectLoadError(dir / "array.json", {"expected an object"});
}

TEST(SceneLoaderErrors, WrongTypesAndRanges) {
  json s = baseScene();
  s["camera"]["fov_deg"] = "wide";
  expectSceneError(s, {"/camera/fov_deg", "expected a number, got string"});
  s = baseScene();
  s["camera"]["fov_deg"] = 200;
  expectSceneError(s, {"/camera/fov_deg", "(0, 180)"});
  s["camera"]["fov_deg"] = 0;
  expectSceneError(s, {"/camera/fov_deg"});
  s = baseScene();
  s["camera"]["resolution"] = {0, 5};
  expectSceneError(s, {"/camera/resolution/0", "[1, 16384]"});
  s["camera"]["resolution"] = {16, 2.5};
  expectSceneError(s, {"/camera/resolution/1", "integer"});
  s["camera"]["resolution"] = {16};
  expectSceneError(s, {"/camera/resolution", "[width, height]"});
  s = baseScene();
  s["camera"]["position"] = {0, "1", 3};
  expectSceneError(s, {"/camera/position/1", "expected a number"});
  s = baseScene();
  s["camera"]["look_at"] = s["camera"]["position"];
  expectSceneError(s, {"/camera", "look_at"});
  s = baseScene();
  s["camera"]["up"] = {0, -1, -3};  // parallel to the view direction
  expectSceneError(s, {"/camera", "parallel"});
  s = baseScene();
  s["render"] = {{"spp", 0}};
  expectSceneError(s, {"/render/spp"});
  s = baseScene();
  s["materials"]["white"]["albedo"] = "red";
  expectSceneError(s, {"/materials/white/albedo", "expected an array of 3 numbers"});
  s["materials"]["white"]["albedo"] = {0.5, -0.1, 0.5};
  expectSceneError(s, {"/materials/white/albedo", "negative"});
  s = baseScene();
  s["materials"]["white"] = {{"type", "ggx"}, {"diffuse", 0}, {"f0", 0.04}, {"alpha", 0}};
  expectSceneError(s, {"/materials/white/alpha", "positive"});
  s["materials"]["white"]["alpha"] = {0.1, 0.2, 0.3};
  expectSceneError(s, {"/materials/white/alpha"});
  s = baseScene();
  s["materials"] = json::array();
  expectSceneError(s, {"/materials", "expected an object"});
  s = baseScene();
  s["shapes"] = json::object();
  expectSceneError(s, {"/shapes", "expected an array"});
  s = baseScene();
  s["shapes"][1]["two_sided"] = "yes";
  expectSceneError(s, {"/shapes/1/two_sided", "true or false"});
}

TEST(SceneLoaderErrors, UnknownKeys) {
  json s = baseScene();
  s["camera"]["positon"] = s["camera"]["position"];
  s["camera"].erase("position");
  expectSceneError(s, {"/camera/positon", "unknown key", "position"});
  s = baseScene();
  s["shape"] = json::array();
  expectSceneError(s, {"/shape", "unknown key"});
  s = baseScene();
  s["materials"]["white"]["albdo"] = 0.5;
  expectSceneError(s, {"/materials/white/albdo", "unknown key"});
  s = baseScene();
  s["shapes"][0]["colour"] = 0.5;
  expectSceneError(s, {"/shapes/0/colour", "unknown key"});
  s = baseScene();
  s["shapes"][0]["crease_deg"] = 30;  // only meshes have creases
  expectSceneError(s, {"/shapes/0/crease_deg", "unknown key"});
  s = baseScene();
  s["render"] = {{"samples", 4}};
  expectSceneError(s, {"/render/samples", "unknown key"});
  s = baseScene();
  s["lights"] = json::parse(R"([{"type": "point", "position": [0, 1, 0], "intensity": 1, "radius": 2}])");
  expectSceneError(s, {"/lights/0/radius", "unknown key"});
}

TEST(SceneLoaderErrors, MaterialsAndShapes) {
  json s = baseScene();
  s["materials"]["gold"] = {{"type", "gold-ish"}};
  expectSceneError(s, {"/materials/gold/type", "unknown material type 'gold-ish'"});
  s = baseScene();
  s["materials"]["gold"] = {{"albedo", 1}};
  expectSceneError(s, {"/materials/gold", "missing \"type\""});
  s = baseScene();
  s["materials"]["mtl"] = {{"type", "lambert"}, {"albedo", 1}};
  expectSceneError(s, {"/materials/mtl", "reserved"});
  s = baseScene();
  s["shapes"][0]["material"] = "whtie";
  expectSceneError(s, {"/shapes/0/material", "unknown material 'whtie'", "white"});
  s = baseScene();
  s["shapes"][0].erase("material");
  expectSceneError(s, {"/shapes/0", "needs a \"material\""});
  s = baseScene();
  s["shapes"][0] = {{"file", "meshes/none.ply"}, {"material", "white"}};
  expectSceneError(s, {"/shapes/0/file", "no such file", "none.ply"});
  s = baseScene();
  s["shapes"][0] = {{"material", "white"}};
  expectSceneError(s, {"/shapes/0", "missing \"file\""});
  s = baseScene();
  s["shapes"][0]["type"] = "cylinder";
  expectSceneError(s, {"/shapes/0/type", "unknown shape type 'cylinder'"});
  s = baseScene();
  s["shapes"][1]["edge_v"] = {1, 0, 0};  // parallel to edge_u: a zero-area light
  expectSceneError(s, {"/shapes/1", "no area"});
  s = baseScene();
  s["shapes"][1]["emission"] = {1, -1, 1};
  expectSceneError(s, {"/shapes/1/emission", "negative"});
  s = baseScene();
  s["shapes"][0] = {{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", -1}, {"material", "white"}};
  expectSceneError(s, {"/shapes/0/radius", "positive"});
  s["shapes"][0]["radius"] = 1;
  s["shapes"][0]["rings"] = 2;
  expectSceneError(s, {"/shapes/0/rings"});
}

TEST(SceneLoaderErrors, NoShapes) {
  json s = baseScene();
  s.erase("shapes");
  expectSceneError(s, {"missing \"shapes\""});
  s["shapes"] = json::array();
  expectSceneError(s, {"/shapes", "no shape"});
}

TEST(SceneLoaderErrors, Lights) {
  json s = baseScene();
  s["lights"] = json::parse(R"([{"type": "point", "position": [0, 1, 0], "intensity": [0, 0, 0]}])");
  expectSceneError(s, {"/lights/0/intensity", "zero intensity"});
  s["lights"] = json::parse(R"([{"type": "point", "position": [0, 1, 0], "intensity": -1}])");
  expectSceneError(s, {"/lights/0/intensity", "negative"});
  s["lights"] = json::parse(R"([{"type": "environment", "radiance": 1}, {"type": "environment", "radiance": 2}])");
  expectSceneError(s, {"/lights/1", "at most one environment"});
  s["lights"] = json::parse(R"([{"type": "environment", "radiance": 0}])");
  expectSceneError(s, {"/lights/0/radiance", "zero radiance"});
  s["lights"] = json::parse(R"([{"type": "environment", "file": "sky.exr"}])");
  expectSceneError(s, {"/lights/0/file", "no such file"});
  s["lights"] = json::parse(R"([{"type": "environment", "file": "sky.exr", "radiance": 1}])");
  expectSceneError(s, {"/lights/0", "either a \"radiance\" or a \"file\""});
  s["lights"] = json::parse(R"([{"type": "environment", "radiance": 1, "scale": 2}])");
  expectSceneError(s, {"/lights/0/scale", "applies to an environment map"});
  s["lights"] = json::parse(R"([{"type": "area", "position": [0, 1, 0]}])");
  expectSceneError(s, {"/lights/0/type", "unknown light type 'area'"});
  s["lights"] = json::parse(R"({"type": "point"})");
  expectSceneError(s, {"/lights", "expected an array"});
}

// The loader accepts a scene without light; the Scene refuses it, naming the file.
TEST(SceneLoaderErrors, NoLightIsRefusedByTheScene) {
  test::TempDir dir;
  json s = baseScene();
  s["shapes"].erase(1);
  const fs::path file = writeScene(dir, s);
  SceneDescription d = loadSceneDescription(file);
  try {
    const Scene scene(std::move(d));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(file.string()), std::string::npos) << what;
    EXPECT_NE(what.find("no light"), std::string::npos) << what;
  }
}

// ---------------------------------------------------------------------------------------------
// Scenes built in code: the Scene's own cleaning and checks

SceneDescription codeScene(TriangleMesh mesh) {
  SceneDescription d;
  d.camera.position = {0.5f, 0.5f, 3.0f};
  d.camera.look_at = {0.5f, 0.5f, 0.0f};
  d.camera.width = 8;
  d.camera.height = 8;
  d.camera.fov_deg = 30;
  SceneMaterial m;
  m.name = "grey";
  m.material = std::make_shared<Lambert>(Rgb(0.5f));
  m.sampled = m.material;
  d.materials.push_back(m);
  SceneShape shape;
  shape.mesh = std::move(mesh);
  shape.material = 0;
  d.shapes.push_back(std::move(shape));
  d.point_lights.push_back({glm::vec3(0.5f, 0.5f, 2.0f), Rgb(1.0f)});
  return d;
}

// The unit square in z = 0 as a 2 x 2 grid of quads (8 triangles), facing +z.
TriangleMesh grid() {
  TriangleMesh mesh;
  mesh.name = "grid";
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) mesh.positions.push_back({0.5f * float(i), 0.5f * float(j), 0.0f});
  for (std::uint32_t j = 0; j < 2; ++j)
    for (std::uint32_t i = 0; i < 2; ++i) {
      const std::uint32_t a = 3 * j + i;
      mesh.triangles.push_back({a, a + 1, a + 4});
      mesh.triangles.push_back({a, a + 4, a + 3});
    }
  return mesh;
}

TEST(SceneLoaderScene, DropsNanAndDegenerateTrianglesAndRendersTheRest) {
  TriangleMesh mesh = grid();
  mesh.name = "dirty-grid";
  const auto nan_vertex = std::uint32_t(mesh.positions.size());
  mesh.positions.push_back({std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f});
  mesh.triangles.push_back({0, 1, nan_vertex});  // NaN
  mesh.triangles.push_back({0, 1, 2});           // collinear
  mesh.triangles.push_back({4, 4, 5});           // repeated corner
  mesh.triangles.push_back({0, 1, 99});          // out of range
  CapturedLog log;
  const Scene scene(codeScene(mesh));
  EXPECT_EQ(scene.description().shapes[0].mesh.triangles.size(), 8u);
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_NE(log.warnings[0].find("dirty-grid"), std::string::npos) << log.warnings[0];
  EXPECT_NE(log.warnings[0].find("dropped 4 triangles"), std::string::npos) << log.warnings[0];
  EXPECT_NE(log.warnings[0].find("2 of zero area"), std::string::npos) << log.warnings[0];
  EXPECT_NEAR(scene.shapeArea(0), 1.0f, 1e-6f);

  // Every part of the square is still hit.
  for (const glm::vec2 xy : {glm::vec2(0.1f, 0.1f), glm::vec2(0.9f, 0.2f), glm::vec2(0.4f, 0.8f)}) {
    SurfaceHit hit;
    ASSERT_TRUE(scene.intersect(Ray{glm::vec3(xy, 1.0f), glm::vec3(0, 0, -1)}, hit));
    EXPECT_NEAR(hit.t, 1.0f, 1e-5f);
    EXPECT_NEAR(hit.ng.z, 1.0f, 1e-6f);
  }
  RenderSettings settings;
  settings.spp = 2;
  const RenderResult result = makePathTracer()->render(scene, settings);
  ASSERT_EQ(result.color.width, 8);
  ASSERT_EQ(result.color.height, 8);
  for (float v : result.color.pixels) ASSERT_TRUE(std::isfinite(v));
  EXPECT_GT(result.color.at(4, 4, 0), 0.0f);  // the middle of the image sees the lit square
}

// Vertices that no (kept) triangle uses are not part of the scene: an infinite one of a dropped
// triangle, or a stray point far away, must not blow up the scene's bounds.
TEST(SceneLoaderScene, BoundsIgnoreVerticesNoTriangleUses) {
  TriangleMesh mesh = grid();
  const auto far_vertex = std::uint32_t(mesh.positions.size());
  mesh.positions.push_back({0.0f, std::numeric_limits<float>::infinity(), 0.0f});
  mesh.positions.push_back({1e6f, 0.0f, 0.0f});  // used by nothing
  mesh.triangles.push_back({0, 1, far_vertex});
  CapturedLog log;
  const Scene scene(codeScene(mesh));
  EXPECT_NEAR(scene.boundsRadius(), 0.5f * std::sqrt(2.0f), 1e-5f);
  EXPECT_NEAR(scene.boundsCenter().x, 0.5f, 1e-6f);
  EXPECT_NEAR(scene.boundsCenter().y, 0.5f, 1e-6f);
  RenderSettings settings;
  settings.spp = 2;
  const RenderResult result = makePathTracer()->render(scene, settings);
  for (float v : result.color.pixels) ASSERT_TRUE(std::isfinite(v));
  EXPECT_GT(result.color.at(4, 4, 0), 0.0f);
}

TEST(SceneLoaderScene, MeshWithOnlyDegenerateTrianglesIsAnError) {
  TriangleMesh mesh;
  mesh.name = "collapsed-mesh";
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {std::numeric_limits<float>::infinity(), 0, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 0, 1}, {0, 1, 3}};
  SceneDescription d = codeScene(mesh);
  d.file = "/somewhere/scene.json";
  CapturedLog log;
  try {
    const Scene scene(std::move(d));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("collapsed-mesh"), std::string::npos) << what;
    EXPECT_NE(what.find("/somewhere/scene.json"), std::string::npos) << what;
    EXPECT_NE(what.find("no valid triangle"), std::string::npos) << what;
  }
}

TEST(SceneLoaderScene, CodeSceneChecks) {
  SceneDescription d = codeScene(grid());
  d.shapes[0].material = 1;
  EXPECT_THROW(Scene{d}, Error);
  d = codeScene(grid());
  d.shapes.clear();
  EXPECT_THROW(Scene{d}, Error);
  d = codeScene(grid());
  d.point_lights[0].intensity = Rgb(1.0f, -1.0f, 1.0f);
  EXPECT_THROW(Scene{d}, Error);
  d = codeScene(grid());
  d.shapes[0].emission = Rgb(-1.0f, 0.0f, 0.0f);
  EXPECT_THROW(Scene{d}, Error);
  d = codeScene(grid());
  d.point_lights.clear();
  EXPECT_THROW(Scene{d}, Error);
  d.environment_radiance = Rgb(0.2f);
  EXPECT_NO_THROW(Scene{d});
}

}  // namespace
}  // namespace btf::render
