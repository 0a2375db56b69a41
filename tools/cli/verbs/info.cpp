// `btf info FILE`: compact facts about a measured table, like oiiotool's iinfo.
#include <nlohmann/json.hpp>


#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "btf/compress/octree_table.h"
#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/material/albedo.h"
#include "btf/io/rgl_tensor.h"
#include "btf/material/rgl_brdf.h"
#include "btf/material/tabulated_brdf.h"
#include "commands.h"
#include "merl_fit_report.h"
#include "material_input.h"

namespace btf::cli {
namespace {

// The incidence angles btf-datagen reports its expected albedo at.
constexpr float kAlbedoAnglesDeg[] = {0.0f, 30.0f, 60.0f, 75.0f};

struct ChannelStats {
  Rgb min{std::numeric_limits<float>::infinity()};
  Rgb max{-std::numeric_limits<float>::infinity()};
  Rgb mean{0.0f};
  std::size_t measured = 0;
};

ChannelStats measuredStats(const MerlTable& table) {
  ChannelStats s;
  double sum[3] = {0, 0, 0};  // 1.4M terms: accumulate in double
  for (std::size_t i = 0; i < MerlTable::kEntriesPerChannel; ++i) {
    if (!table.isMeasured(i)) continue;
    const Rgb f = table.reflectance(i);
    for (int c = 0; c < 3; ++c) {
      s.min[c] = std::min(s.min[c], f[c]);
      s.max[c] = std::max(s.max[c], f[c]);
      sum[c] += f[c];
    }
    ++s.measured;
  }
  if (s.measured == 0) return ChannelStats{Rgb(0.0f), Rgb(0.0f), Rgb(0.0f), 0};
  for (int c = 0; c < 3; ++c) s.mean[c] = float(sum[c] / double(s.measured));
  return s;
}

nlohmann::json rgbJson(const Rgb& c) { return {c.r, c.g, c.b}; }

nlohmann::json albedoJson(const Material& material) {
  nlohmann::json albedo = nlohmann::json::array();
  for (float deg : kAlbedoAnglesDeg)
    albedo.push_back({{"theta_o_deg", deg}, {"rgb", rgbJson(integrateAlbedoHalfVector(material, deg * kPi / 180.0f))}});
  return albedo;
}

// An RGL .bsdf: every field of the tensor_file, the material's resolution and description, and
// its albedo evaluated through its own parameterization.
void runRglInfo(const std::string& file, const std::string& format, bool json) {
  const TensorFile tensor = readTensorFile(file);
  const RglBrdf material(tensor);
  const nlohmann::json albedo = albedoJson(material);
  std::vector<float> theta_deg;
  for (float t : material.thetaSamples()) theta_deg.push_back(t * 180.0f / kPi);
  if (json) {
    nlohmann::json fields = nlohmann::json::array();
    for (const TensorField& f : tensor.fields)
      fields.push_back({{"name", f.name}, {"dtype", std::string(dtypeName(f.dtype))}, {"shape", f.shape}});
    std::cout << nlohmann::json{{"file", file},
                                {"format", format},
                                {"version", std::to_string(tensor.version_major) + "." + std::to_string(tensor.version_minor)},
                                {"description", material.description()},
                                {"resolution", material.resolution()},
                                {"vndf_resolution", material.vndfResolution()},
                                {"theta_o_deg", theta_deg},
                                {"fields", fields},
                                {"albedo", albedo}}
                     .dump(2)
              << "\n";
    return;
  }
  std::printf("%s\n", file.c_str());
  std::printf("  format      %s, version %d.%d\n", format.c_str(), tensor.version_major,
              tensor.version_minor);
  std::printf("  description %s\n", material.description().c_str());
  std::printf("  resolution  %d x %d luminance/RGB per incidence, %d x %d VNDF, isotropic, RGB\n", material.resolution(),
              material.resolution(), material.vndfResolution(), material.vndfResolution());
  std::printf("  theta_o     %zu values (deg):", theta_deg.size());
  for (float t : theta_deg) std::printf(" %.1f", t);
  std::printf("\n  fields      name         dtype  shape\n");
  for (const TensorField& f : tensor.fields)
    std::printf("              %-12s %-6s %s\n", f.name.c_str(), std::string(dtypeName(f.dtype)).c_str(),
                f.shapeString().c_str());
  std::printf("  albedo (directional-hemispherical, through the file's parameterization):\n");
  for (const auto& a : albedo)
    std::printf("    theta_o %2.0f deg  %.4f %.4f %.4f\n", a["theta_o_deg"].get<float>(), a["rgb"][0].get<float>(),
                a["rgb"][1].get<float>(), a["rgb"][2].get<float>());
}

struct InfoOptions {
  std::string file;
  bool json = false;
  std::string fits_of;
  std::optional<TableLookup> lookup;
  bool types = false;
};

// --types: what the registry opens, for a user choosing a scene's "type" or a file to give a verb.
void listMaterialTypes(bool json) {
  nlohmann::json out = nlohmann::json::array();
  for (const MaterialType* t : materialTypes()) {
    nlohmann::json formats = nlohmann::json::array();
    for (const MaterialFileFormat& f : t->formats)
      formats.push_back({{"description", f.description}, {"extensions", f.extensions}, {"folder", f.folder}});
    out.push_back({{"type", t->name}, {"summary", t->summary}, {"keys", t->keys}, {"spec_keys", t->spec_keys},
                   {"formats", formats}});
  }
  if (json) {
    std::cout << out.dump(2) << "\n";
    return;
  }
  for (const auto& t : out) {
    std::printf("%-18s %s\n", t["type"].get<std::string>().c_str(), t["summary"].get<std::string>().c_str());
    std::string keys;
    for (const auto& k : t["keys"]) keys += (keys.empty() ? "" : ", ") + k.get<std::string>();
    std::printf("%-18s keys: %s\n", "", keys.empty() ? "(none)" : keys.c_str());
    if (!t["spec_keys"].empty()) {
      std::string spec = t["type"].get<std::string>();
      for (const auto& k : t["spec_keys"]) spec += ":" + k.get<std::string>();
      std::printf("%-18s spec: %s\n", "", spec.c_str());
    }
    for (const auto& f : t["formats"]) {
      std::string where = f["folder"].get<bool>() ? "a folder" : "";
      for (const auto& e : f["extensions"]) where += (where.empty() ? "" : ", ") + e.get<std::string>();
      std::printf("%-18s file: %s (%s)\n", "", f["description"].get<std::string>().c_str(), where.c_str());
    }
  }
}

void runInfo(const InfoOptions& o) {
  if (o.types) return listMaterialTypes(o.json);
  if (o.file.empty()) throw Error("info: give a material (a file, folder or spec), or --types");
  const std::string& file = o.file;
  const bool json = o.json;
  const IdentifiedMaterial material = identifyMaterial(file);
  const bool btf = isBtf(material), rgl = material.type->name == "rgl";
  if (o.lookup && (btf || rgl))
    throw Error("--lookup does not apply to " + file + ": it chooses how a MERL-layout table is read between its " +
                "cells, and this file is " + (btf ? "a BTF" : "an RGL .bsdf with its own parameterization"));
  if (btf) {
    runBtfInfo(material.params.path("file"), json);
    return;
  }
  if (rgl) return runRglInfo(file, material.description, json);
  const std::string& format = material.description;
  auto table = std::make_shared<const MerlTable>(materialTable(material));
  const ChannelStats stats = measuredStats(*table);
  const std::size_t total = MerlTable::kEntriesPerChannel;
  const std::size_t unmeasured = total - stats.measured;
  const double percent = 100.0 * double(unmeasured) / double(total);

  // The lookups answer different questions on near-mirror tables: interpolation follows a peak
  // between samples, truncation (MERL's own reader) gives each sample's value to the whole cell
  // above it; docs/results.md gives the size of the difference on real measured data.
  const TableLookup lookup = o.lookup.value_or(TableLookup::Interpolated);
  const TabulatedBrdf brdf(table, lookup);
  const char* lookup_name = tableLookupName(lookup);
  const nlohmann::json albedo = albedoJson(brdf);
  const std::optional<MerlFitComparison> fits = datagen::compareFitsOfFile(file, o.fits_of);
  const std::optional<OctreeTable> octree =
      material.type->name == "octree" ? std::optional<OctreeTable>(readOctreeFile(file)) : std::nullopt;

  if (json) {
    std::cout << nlohmann::json{
                     {"file", file},
                     {"format", format},
                     {"dims", {MerlTable::kThetaHalfRes, MerlTable::kThetaDiffRes, MerlTable::kPhiDiffRes}},
                     {"samples", total},
                     {"unmeasured", {{"count", unmeasured}, {"percent", percent}}},
                     {"f_measured", {{"min", rgbJson(stats.min)}, {"max", rgbJson(stats.max)}, {"mean", rgbJson(stats.mean)}}},
                     {"lookup", lookup_name},
                     {"albedo", albedo},
                     {"published_fits", fits ? datagen::comparisonJson(*fits) : nlohmann::json()},
                     {"octree", octree ? nlohmann::json{{"nodes", octree->nodes().size()},
                                                        {"leaves", octree->leaves().size()},
                                                        {"tolerance", octree->tolerance()},
                                                        {"file_bytes", std::filesystem::file_size(file)}}
                                       : nlohmann::json()}}
                     .dump(2)
              << "\n";
    return;
  }
  std::printf("%s\n", file.c_str());
  std::printf("  format      %s\n", format.c_str());
  if (!material.type->table)  // a model (a fit, a merl-fit spec): shown tabulated below, like any table
    std::printf("  model       %s\n", createMaterial(material.params)->name().c_str());
  if (octree)
    std::printf("  octree      %zu nodes, %zu leaves, tolerance %g, %ju bytes on disk\n", octree->nodes().size(),
                octree->leaves().size(), octree->tolerance(), std::uintmax_t(std::filesystem::file_size(file)));
  std::printf("  dims        %d x %d x %d (theta_h x theta_d x phi_d), RGB\n", MerlTable::kThetaHalfRes,
              MerlTable::kThetaDiffRes, MerlTable::kPhiDiffRes);
  std::printf("  unmeasured  %zu of %zu samples (%.2f%%)\n", unmeasured, total, percent);
  std::printf("  f (1/sr) of measured samples:   R           G           B\n");
  std::printf("    min       %11.5g %11.5g %11.5g\n", stats.min.r, stats.min.g, stats.min.b);
  std::printf("    max       %11.5g %11.5g %11.5g\n", stats.max.r, stats.max.g, stats.max.b);
  std::printf("    mean      %11.5g %11.5g %11.5g\n", stats.mean.r, stats.mean.g, stats.mean.b);
  std::printf("  albedo (directional-hemispherical, %s lookup):\n", lookup_name);
  for (const auto& a : albedo)
    std::printf("    theta_o %2.0f deg  %.4f %.4f %.4f\n", a["theta_o_deg"].get<float>(), a["rgb"][0].get<float>(),
                a["rgb"][1].get<float>(), a["rgb"][2].get<float>());
  if (fits) datagen::printFitComparison(*fits);
}

}  // namespace

void registerInfoCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("info", "Facts about a measured material: format, dims or fields, value ranges, "
                                         "unmeasured samples, albedo at theta_o = 0, 30, 60, 75 deg");
  auto o = std::make_shared<InfoOptions>();
  cmd->add_option("FILE", o->file,
                  "A material: a file (.binary MERL, .exr from btf convert, .bsdf RGL, .json fit, .octree, .btfz), a "
                  "BTF image folder, or a spec (merl-fit:MODEL:NAME)");
  cmd->add_flag("--types", o->types, "List the material types (a scene's \"type\"), their keys, specs and file formats");
  cmd->add_flag("--json", o->json, "Machine-readable output");
  addLookupOption(*cmd, o->lookup,
                  "How the albedo reads a MERL-layout table (truncation reads near-mirror tables higher)");
  cmd->add_option("--fits-of", o->fits_of,
                  "Compare with the published fits (SGD, ABC, Lafortune) of this MERL material; by default a file "
                  "named after a MERL material (gold-metallic-paint.binary) is compared with its fits");
  cmd->callback([o] { runInfo(*o); });
}

}  // namespace btf::cli
