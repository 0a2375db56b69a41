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
#include "btf_input.h"
#include "measured_file.h"

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
void runRglInfo(const std::string& file, bool json) {
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
                                {"format", describe(MeasuredFormat::RglTensor)},
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
  std::printf("  format      %s, version %d.%d\n", describe(MeasuredFormat::RglTensor).c_str(), tensor.version_major,
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
  TableLookup lookup = TableLookup::Interpolated;
  bool lookup_given = false;
};

void runInfo(const InfoOptions& o) {
  const std::string& file = o.file;
  const bool json = o.json;
  if (o.lookup_given && (isBtfPath(file) || measuredFormatOf(file) == MeasuredFormat::RglTensor))
    throw Error("--lookup does not apply to " + file + ": it chooses how a MERL-layout table is read between its " +
                "cells, and this file is " + (isBtfPath(file) ? "a BTF" : "an RGL .bsdf with its own parameterization"));
  if (isBtfPath(file)) {
    runBtfInfo(file, json);
    return;
  }
  const MeasuredFormat format = measuredFormatOf(file);
  if (format == MeasuredFormat::RglTensor) return runRglInfo(file, json);
  auto table = std::make_shared<const MerlTable>(loadMeasuredTable(file));
  const ChannelStats stats = measuredStats(*table);
  const std::size_t total = MerlTable::kEntriesPerChannel;
  const std::size_t unmeasured = total - stats.measured;
  const double percent = 100.0 * double(unmeasured) / double(total);

  // The lookups answer different questions on near-mirror tables: interpolation follows a peak
  // between samples, truncation (MERL's own reader) gives each sample's value to the whole cell
  // above it; docs/results.md gives the size of the difference on real measured data.
  const TabulatedBrdf brdf(table, o.lookup);
  const char* lookup_name = tableLookupName(o.lookup);
  const nlohmann::json albedo = albedoJson(brdf);
  const std::optional<MerlFitComparison> fits = datagen::compareFitsOfFile(file, o.fits_of);
  const std::optional<OctreeTable> octree =
      format == MeasuredFormat::Octree ? std::optional<OctreeTable>(readOctreeFile(file)) : std::nullopt;

  if (json) {
    std::cout << nlohmann::json{
                     {"file", file},
                     {"format", describe(format)},
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
  std::printf("  format      %s\n", describe(format).c_str());
  if (format == MeasuredFormat::FittedModel)  // shown tabulated below, like any table
    std::printf("  model       %s\n", loadMeasuredMaterial(file, o.lookup)->name().c_str());
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
  cmd->add_option("FILE", o->file, "Measured material (.binary MERL, .exr from btf convert, .bsdf RGL, .json fit, .octree), BTF image folder or .btfz")->required();
  cmd->add_flag("--json", o->json, "Machine-readable output");
  cmd->add_option_function<std::string>(
         "--lookup",
         [o](const std::string& name) {
           o->lookup = parseLookup(name);
           o->lookup_given = true;
         },
         "How the albedo reads a MERL table: interpolated (default), nearest, or truncated (MERL's own reader, "
         "which reads near-mirror tables higher)")
      ->check(CLI::IsMember({"interpolated", "nearest", "truncated"}));
  cmd->add_option("--fits-of", o->fits_of,
                  "Compare with the published fits (SGD, ABC, Lafortune) of this MERL material; by default a file "
                  "named after a MERL material (gold-metallic-paint.binary) is compared with its fits");
  cmd->callback([o] { runInfo(*o); });
}

}  // namespace btf::cli
