#include "bench_materials.h"

#include <algorithm>
#include <filesystem>

#include "btf/core/error.h"
#include "btf/material/registry.h"
#include "btf/material/tabulated_brdf.h"
#include "presets.h"

namespace btf::cli {
namespace {

std::vector<std::string> rglFiles() {
  std::vector<std::string> files;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(BTF_RGL_BUILD_DIR), ec))
    if (entry.path().extension() == ".bsdf") files.push_back(entry.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

const datagen::Preset* presetNamed(const std::string& name) {
  for (const datagen::Preset& p : datagen::presets())
    if (p.name == name) return &p;
  return nullptr;
}

}  // namespace

std::vector<std::string> defaultBenchMaterialNames(bool quick) {
  if (quick) return {"plastic-red"};
  // Every generator preset (diffuse to near-mirror, anisotropic brushed metal: the quadtree's
  // acceptance is reported for each); fits of a glossy plastic and a metallic paint; the real
  // measurements.
  std::vector<std::string> names;
  for (const datagen::Preset& p : datagen::presets()) names.push_back(p.name);
  names.push_back("merl-fit:sgd:blue-acrylic");
  names.push_back("merl-fit:abc:gold-metallic-paint");
  for (const std::string& file : rglFiles()) names.push_back(file);
  return names;
}

BenchMaterial loadBenchMaterial(const std::string& name) {
  if (const datagen::Preset* preset = presetNamed(name)) {
    // Through the table, as btf-datagen writes it: the sampler sees measured-style data.
    auto table = std::make_shared<const MerlTable>(tabulate(*preset->make()));
    return {name, std::make_shared<TabulatedBrdf>(std::move(table), TableLookup::Interpolated)};
  }
  IdentifiedMaterial material = [&] {
    try {
      return identifyMaterial(name);
    } catch (const Error& e) {
      std::string presets;
      for (const datagen::Preset& p : datagen::presets()) presets += (presets.empty() ? "" : ", ") + p.name;
      throw Error("'" + name + "' is not a preset (" + presets + ") nor a material file or spec: " + e.what());
    }
  }();
  return {materialLabel(material), createMaterial(material.params)};
}

BenchMaterial asTable(const BenchMaterial& m) {
  if (dynamic_cast<const TabulatedBrdf*>(m.material.get())) return m;
  auto table = std::make_shared<const MerlTable>(tabulate(*m.material));
  return {m.name + " (MERL table)", std::make_shared<TabulatedBrdf>(std::move(table), TableLookup::Interpolated)};
}

}  // namespace btf::cli
