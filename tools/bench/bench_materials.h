// The materials of `btf bench sampling`: a btf-datagen preset by name (e.g. "chrome": the preset
// tabulated into a MERL-layout table and read back as a TabulatedBrdf, interpolated, i.e. what the
// generator writes, without the file), or anything the material registry opens (a file of any
// registered format, e.g. an RGL .bsdf with its own warp, or a spec such as
// merl-fit:sgd:blue-acrylic).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "btf/material/material.h"

namespace btf::cli {

struct BenchMaterial {
  std::string name;  // the preset's name, a file's stem, or the spec's label
  std::shared_ptr<const Material> material;
};

// The default list: every generator preset, two MERL fits, and every RGL file of the shared data.
// With `quick`, one preset only.
std::vector<std::string> defaultBenchMaterialNames(bool quick);

// Builds one material; throws btf::Error naming the presets and the registry's formats for a name
// that is neither.
BenchMaterial loadBenchMaterial(const std::string& name);

// The material tabulated into the MERL layout and read back with the interpolated lookup (a table
// stays as it is): every sampler then starts from a measured-style table, none from the material's
// own parameterization. The name gains " (MERL table)".
BenchMaterial asTable(const BenchMaterial& material);

}  // namespace btf::cli
