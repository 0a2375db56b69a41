#include "scene_command.h"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "btf/compress/vq_btf.h"
#include "btf/core/error.h"
#include "btf/io/atomic_file.h"
#include "btf/io/merl.h"
#include "btf/material/tabulated_brdf.h"
#include "btf_patterns.h"
#include "presets.h"

namespace btf::datagen {
namespace fs = std::filesystem;
using nlohmann::json;
namespace {

fs::path defaultMeshes() { return fs::path(BTF_SHARED_DATA_DIR) / "meshes"; }

// The generated BRDF: the preset's exact table (no measurement effects), so that renders of it
// differ from renders of the analytic model by the table lookup only.
fs::path generateBrdf(const SceneCommandOptions& o, const fs::path& dir) {
  if (!o.brdf.empty()) return fs::absolute(o.brdf);
  const fs::path file = dir / (o.preset + ".binary");
  writeMerl(file, tabulate(*findPreset(o.preset).make()));
  std::printf("  wrote %s (preset %s, exact MERL-layout table)\n", file.string().c_str(), o.preset.c_str());
  return fs::absolute(file);  // the scene names it from its own folder, not from the working one
}

fs::path generateBtf(const SceneCommandOptions& o, const fs::path& dir) {
  if (!o.btf.empty()) return fs::absolute(o.btf);
  const fs::path file = dir / "fabric.btfz";
  const auto source = synthetic::makeSyntheticBtf(synthetic::BtfPattern::Fabric, 16, 16, o.seed);
  compressVq(*source, VqOptions{}).write(file);
  std::printf("  wrote %s (synthetic fabric, 16 x 16 texels, VQ at epsilon 0.02)\n", file.string().c_str());
  return fs::absolute(file);
}

// The scene material of a file, by its kind: a MERL table, an RGL file, or a BTF (.btfz or an
// image folder; a compressed BRDF is a one-texel BTF).
json materialOf(const fs::path& file, const std::string& sampler) {
  std::error_code ec;
  if (fs::is_directory(file, ec) || file.extension() == ".btfz") return {{"type", "btf"}, {"file", file.string()}};
  if (file.extension() == ".bsdf") return {{"type", "rgl"}, {"file", file.string()}, {"sampler", sampler}};
  if (file.extension() == ".binary") return {{"type", "merl"}, {"file", file.string()}, {"sampler", sampler}};
  throw FileError(file, "is not a material file (expected .binary, .bsdf, .btfz or a BTF image folder)");
}

json camera(const json& position, const json& look_at, float fov, int resolution) {
  return {{"position", position}, {"look_at", look_at}, {"up", {0, 1, 0}}, {"fov_deg", fov}, {"resolution", {resolution, resolution}}};
}

json cornell(const SceneCommandOptions& o, const fs::path& dir) {
  const fs::path meshes = o.meshes.empty() ? defaultMeshes() : fs::absolute(o.meshes);
  const fs::path obj = meshes / "cornell_box" / "CornellBox-Original.obj";
  if (!fs::exists(obj)) throw FileError(obj, "the Cornell box mesh is missing (give the shared meshes folder with --meshes)");
  const fs::path rgl = o.rgl.empty() ? meshes.parent_path() / "rgl_bsdf" / "vch_golden_yellow_rgb.bsdf" : fs::absolute(o.rgl);
  json block = materialOf(generateBtf(o, dir), o.sampler);
  block["mapping"] = "box";
  block["uv_scale"] = 2.0;
  json materials = {{"sphere", materialOf(generateBrdf(o, dir), o.sampler)}, {"block", block}};
  json part_materials = {{"tallBox", "block"}};
  if (fs::exists(rgl)) {
    materials["film"] = {{"type", "rgl"}, {"file", rgl.string()}, {"sampler", o.sampler}};
    part_materials["shortBox"] = "film";
  } else {
    std::printf("  (no %s: the short box keeps its .mtl colour)\n", rgl.string().c_str());
  }
  return {{"comment", "btf-datagen scene cornell: the Cornell box with a generated measured BRDF (sphere), a compressed synthetic BTF (tall box) and a real RGL material (short box)"},
          {"camera", camera({0, 1, 3.9}, {0, 1, 0}, 39.3f, o.resolution)},
          {"render", {{"spp", o.spp}, {"max_depth", 16}}},
          {"materials", materials},
          {"shapes", {{{"file", obj.string()}, {"material", "mtl"}, {"part_materials", part_materials}},
                      {{"type", "sphere"}, {"center", {-0.42, 0.28, 0.45}}, {"radius", 0.28}, {"material", "sphere"}}}}};
}

json furnace(const SceneCommandOptions& o, const fs::path& dir) {
  return {{"comment", "btf-datagen scene furnace: a sphere of the generated BRDF in a uniform environment of radiance 1; each pixel is the directional albedo at its view angle"},
          {"camera", camera({0, 0, 4}, {0, 0, 0}, 30.0f, o.resolution)},
          {"render", {{"spp", o.spp}, {"max_depth", 32}}},
          {"materials", {{"sphere", materialOf(generateBrdf(o, dir), o.sampler)}}},
          {"shapes", {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1.0}, {"rings", 128}, {"material", "sphere"}}}},
          {"lights", {{{"type", "environment"}, {"radiance", {1, 1, 1}}}}}};
}

// The sphere's material of the fit-scene pair: --brdf, else the RGL file (--rgl, by default the
// shared vch_golden_yellow_rgb: real measured data, which no analytic model fits exactly), else
// the generated preset when the shared data is missing.
json fitSceneMaterial(const SceneCommandOptions& o, const fs::path& dir) {
  if (!o.brdf.empty()) return materialOf(generateBrdf(o, dir), o.sampler);
  const fs::path meshes = o.meshes.empty() ? defaultMeshes() : fs::absolute(o.meshes);
  const fs::path rgl = o.rgl.empty() ? meshes.parent_path() / "rgl_bsdf" / "vch_golden_yellow_rgb.bsdf" : fs::absolute(o.rgl);
  if (fs::exists(rgl)) return materialOf(rgl, o.sampler);
  std::printf("  (no %s: the sphere gets the generated preset)\n", rgl.string().c_str());
  return materialOf(generateBrdf(o, dir), o.sampler);
}

// The same material in two settings, for `btf fit-scene`: a sphere filling the frame under a
// point light (its highlight large and sharp), and the sphere seen small and far away under a
// uniform environment (each pixel shows about its directional albedo).
json closeup(const SceneCommandOptions& o, const fs::path& dir) {
  return {{"comment", "btf-datagen scene closeup: a sphere of the generated BRDF filling the frame under a point light and a dim uniform environment"},
          {"camera", camera({0, 0, 2.8}, {0, 0, 0}, 50.0f, o.resolution)},
          {"render", {{"spp", o.spp}, {"max_depth", 8}}},
          {"materials", {{"sphere", fitSceneMaterial(o, dir)}}},
          {"shapes", {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1.0}, {"rings", 128}, {"material", "sphere"}}}},
          {"lights", {{{"type", "point"}, {"position", {2, 2, 3}}, {"intensity", {12, 12, 12}}},
                      {{"type", "environment"}, {"radiance", {0.05, 0.05, 0.05}}}}}};
}

json distant(const SceneCommandOptions& o, const fs::path& dir) {
  return {{"comment", "btf-datagen scene distant: a sphere of the generated BRDF seen small and far away, lit by a uniform environment only"},
          {"camera", camera({0, 0, 30}, {0, 0, 0}, 25.0f, o.resolution)},
          {"render", {{"spp", o.spp}, {"max_depth", 8}}},
          {"materials", {{"sphere", fitSceneMaterial(o, dir)}}},
          {"shapes", {{{"type", "sphere"}, {"center", {0, 0, 0}}, {"radius", 1.0}, {"rings", 64}, {"material", "sphere"}}}},
          {"lights", {{{"type", "environment"}, {"radiance", {1, 1, 1}}}}}};
}

json plane(const SceneCommandOptions& o) {
  return {{"comment", "btf-datagen scene plane: a Lambertian plane (albedo 0.5) under a 0.5 x 0.5 area light of radiance 10 at height 1; at a point x the radiance is 0.5 / pi times the polygon's irradiance (Lambert's formula)"},
          {"camera", camera({3, 2.5, 2}, {0, 0, 0}, 40.0f, o.resolution)},
          {"render", {{"spp", o.spp}, {"max_depth", 4}}},
          {"materials", {{"white", {{"type", "lambert"}, {"albedo", 0.5}}}}},
          {"shapes", {{{"type", "quad"}, {"corner", {-5, 0, -5}}, {"edge_u", {0, 0, 10}}, {"edge_v", {10, 0, 0}}, {"material", "white"}},
                      {{"type", "quad"}, {"corner", {-0.25, 1, -0.25}}, {"edge_u", {0.5, 0, 0}}, {"edge_v", {0, 0, 0.5}}, {"emission", 10}}}}};
}

}  // namespace

CLI::App* addSceneCommand(CLI::App& app, SceneCommandOptions& o) {
  CLI::App* cmd = app.add_subcommand("scene", "Built-in validation scenes (scene.json and the generated materials it uses): "
                                              "cornell, furnace, plane, closeup or distant");
  cmd->add_option("KIND", o.kind, "cornell, furnace, plane, closeup (a sphere filling the frame under a point light) or distant "
                                  "(the sphere small and far away under a uniform environment)")
      ->check(CLI::IsMember({"cornell", "furnace", "plane", "closeup", "distant"}))
      ->required();
  cmd->add_option("-o,--output", o.output, "Output folder (created)")->required();
  cmd->add_option("--brdf", o.brdf, "Material file of the sphere (default: a table generated from --preset)");
  cmd->add_option("--btf", o.btf, "BTF of the Cornell box's tall box: .btfz or image folder (default: generated, compressed)");
  cmd->add_option("--rgl", o.rgl, "RGL .bsdf of the short box, and of the sphere of closeup and distant unless --brdf is given "
                                  "(default: the shared vch_golden_yellow_rgb)");
  cmd->add_option("--meshes", o.meshes, "Folder of the shared meshes (default: the build's ../shared/data/real/meshes)");
  cmd->add_option("--preset", o.preset, "Preset of the generated BRDF")->capture_default_str();
  cmd->add_option("--sampler", o.sampler, "Sampler of the measured materials")
      ->check(CLI::IsMember({"material", "cosine", "uniform", "tabulated", "dp-cdf", "quadtree"}))
      ->capture_default_str();
  cmd->add_option("--resolution", o.resolution, "Image width and height")->check(CLI::Range(1, 16384))->capture_default_str();
  cmd->add_option("--spp", o.spp, "Samples per pixel the scene asks for")->check(CLI::Range(1, 1 << 20))->capture_default_str();
  cmd->add_option("--seed", o.seed, "Seed of the generated BTF")->capture_default_str();
  return cmd;
}

void runSceneCommand(const SceneCommandOptions& o) {
  const fs::path dir(o.output);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir)) throw FileError(dir, "cannot create the output folder");
  findPreset(o.preset);  // an unknown preset fails before anything is written
  const json scene = o.kind == "cornell"   ? cornell(o, dir)
                     : o.kind == "furnace" ? furnace(o, dir)
                     : o.kind == "closeup" ? closeup(o, dir)
                     : o.kind == "distant" ? distant(o, dir)
                                           : plane(o);
  const fs::path file = dir / "scene.json";
  writeFileAtomically(file, [&](std::ofstream& out) { out << scene.dump(2) << "\n"; });
  std::printf("  wrote %s\n", file.string().c_str());
}

}  // namespace btf::datagen
