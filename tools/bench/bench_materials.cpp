#include "bench_materials.h"

#include <algorithm>
#include <filesystem>

#include "btf/core/error.h"
#include "btf/fit/merl_fits.h"
#include "btf/material/rgl_brdf.h"
#include "btf/material/tabulated_brdf.h"
#include "merl_fit_report.h"
#include "presets.h"

namespace btf::cli {
namespace {

std::filesystem::path rglFolder() { return BTF_RGL_BUILD_DIR; }

std::vector<std::string> rglStems() {
  std::vector<std::string> stems;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(rglFolder(), ec))
    if (entry.path().extension() == ".bsdf") stems.push_back(entry.path().stem().string());
  std::sort(stems.begin(), stems.end());
  return stems;
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
  names.push_back("blue-acrylic:sgd");
  names.push_back("gold-metallic-paint:abc");
  for (const std::string& stem : rglStems()) names.push_back(stem);
  return names;
}

BenchMaterial loadBenchMaterial(const std::string& name) {
  if (const datagen::Preset* preset = presetNamed(name)) {
    // Through the table, as btf-datagen writes it: the sampler sees measured-style data.
    auto table = std::make_shared<const MerlTable>(tabulate(*preset->make()));
    return {name, std::make_shared<TabulatedBrdf>(std::move(table), TableLookup::Interpolated)};
  }
  const std::filesystem::path rgl = rglFolder() / (name + ".bsdf");
  if (std::filesystem::exists(rgl)) return {name, std::make_shared<RglBrdf>(rgl)};

  const std::size_t colon = name.find(':');
  const std::string merl_name = name.substr(0, colon);
  const FitModel model = colon == std::string::npos ? FitModel::Sgd : parseFitModel(name.substr(colon + 1));
  const MerlFits fits = datagen::loadMerlFits("");
  try {
    return {name, std::shared_ptr<const Material>(makeMerlFitMaterial(fits, merl_name, model))};
  } catch (const Error& e) {
    std::string presets;
    for (const datagen::Preset& p : datagen::presets()) presets += (presets.empty() ? "" : ", ") + p.name;
    std::string stems;
    for (const std::string& s : rglStems()) stems += (stems.empty() ? "" : ", ") + s;
    throw Error("unknown material '" + name + "': not a preset (" + presets + "), not an RGL file (" + stems +
                ") in " + rglFolder().string() + ", and not a MERL fit NAME[:sgd|abc|lafortune]: " + e.what());
  }
}

}  // namespace btf::cli
