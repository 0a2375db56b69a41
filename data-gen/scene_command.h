// `btf-datagen scene KIND -o DIR`: the built-in validation scenes, written as scene files with the
// generated materials they reference:
//   cornell  the Cornell box (the shared OBJ) with a sphere of a generated measured-style BRDF, the
//            tall box covered by a compressed synthetic BTF and the short box in a real RGL material
//   furnace  a sphere of the generated BRDF in a uniform white environment (every pixel shows the
//            directional albedo at its view angle)
//   plane    a Lambertian plane under one rectangular area light, whose radiance has a closed form
//   closeup  a sphere of the generated BRDF filling the frame under a point light (btf fit-scene)
//   distant  the same sphere small and far away under a uniform environment (btf fit-scene)
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

namespace btf::datagen {

struct SceneCommandOptions {
  std::string kind = "cornell";
  std::string output;
  std::string brdf;    // a material file for the sphere; empty: generate one from --preset
  std::string btf;     // a .btfz or BTF image folder for the tall box; empty: generate one
  std::string rgl;     // an RGL .bsdf for the short box; empty: the shared vch_golden_yellow_rgb
  std::string meshes;  // folder of the shared meshes; empty: the build's ../shared/data/real/meshes
  std::string preset = "rough-gold";
  std::string sampler = "material";
  int resolution = 256;
  int spp = 64;
  std::uint64_t seed = 1;
};

CLI::App* addSceneCommand(CLI::App& app, SceneCommandOptions& options);
void runSceneCommand(const SceneCommandOptions& options);

}  // namespace btf::datagen
