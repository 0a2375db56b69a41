// The smaller representations `btf fit-scene` tries for one material of a scene, each written as a
// material file: analytic fits (fit/analytic_fit.h), octree tables at several tolerances
// (compress/octree_table.h) and VQ-compressed forms at several tolerances (compress/vq_btf.h),
// beside the material as the scene gives it. A BRDF (merl, rgl or octree in the scene) is fitted
// and stored from its MERL-layout table; a BTF (btf in the scene) is fitted to its mean texel (which
// drops its texture) and re-compressed from its own data.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "btf/fit/analytic_fit.h"
#include "btf/material/material.h"
#include "btf/material/material_params.h"

namespace btf::cli {

struct FitSceneSettings {
  std::vector<std::string> fits = {"lafortune", "ggx", "ggx:linear", "lafortune:2"};  // family[:lobes][:linear]
  std::vector<double> octree_tolerances = {0.1, 0.03, 0.01};
  std::vector<double> vq_epsilons = {0.1, 0.03};
};

struct MaterialCandidate {
  std::string label;     // e.g. "fit ggx (linear)", "octree t=0.03", "vq eps=0.1", "full"
  std::string kind;      // "fit", "octree", "vq" or "full"
  std::uint64_t bytes = 0;  // of the material file(s) as stored
  std::filesystem::path file;  // the file written (empty for "full": the scene's own)
  std::shared_ptr<const Material> material;
  MaterialParams entry;  // the scene entry naming `file` ("full": the scene's own entry)
  std::string note;      // e.g. the fit's table rel_rmse, or why a candidate was left out
};

// A fit of the settings, "family[:lobes][:linear|log]" (e.g. "lafortune:2", "ggx:linear"); throws
// btf::Error naming the spec.
AnalyticFitOptions parseFitSpec(const std::string& spec);

// The material's type in the scene ("merl", "rgl", "octree", "btf"); other types (analytic models,
// published and own fits) are not reduced: reducible() says so.
bool reducible(const std::string& scene_type);

// Bytes of a material file, or of all files in a folder (an image-folder BTF).
std::uint64_t storedBytes(const std::filesystem::path& path);

// The candidates for a scene material: `entry` is its parameter set as the scene holds it, `file`
// the path it names (resolved), `material` the loaded material, `work` a folder for the files. The
// full material comes last; the others in the order of the settings. Candidates that fail to build
// (a fit that throws, say) or are refused (a degenerate fit: isDegenerateFit) are returned with no
// material and the reason in `note`. Progress is
// reported by the fits and the compressions themselves.
std::vector<MaterialCandidate> makeCandidates(const std::string& name, const MaterialParams& entry,
                                              const std::filesystem::path& file,
                                              std::shared_ptr<const Material> material,
                                              const std::filesystem::path& work, const FitSceneSettings& settings);

}  // namespace btf::cli
