// `btf info` on BTFs: an image folder (size, value scale, image format) or a .btfz file (what the
// compressor kept: options, codebook sizes, sections and their bytes, ratios; for a database, its
// materials).
#include <algorithm>
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "btf/compress/compressed_btf.h"
#include "btf/compress/factor_btf.h"
#include "btf/compress/vq_btf.h"
#include "btf/compress/vq_database.h"
#include "btf/io/bonn_btf.h"
#include "btf/io/btf_images.h"
#include "btf/io/container.h"
#include "material_input.h"

namespace btf::cli {
namespace {

void runFolderInfo(const std::filesystem::path& folder, bool json) {
  const BtfImageFolder btf = BtfImageFolder::open(folder);
  btf.checkImageHeaders();
  const int views = btf.views().count();
  const std::string ext = btf.imagePath(btf.views().view(0), 0).extension().string();
  const std::optional<BtfTransfer> transfer = btf.transfer();
  if (json) {
    std::cout << nlohmann::json{{"file", folder.string()},
                                {"format", "image-folder BTF"},
                                {"layout", btfImageLayoutName(btf.layout())},
                                {"directions", btf.directions().describe()},
                                {"float_color_space", btf.colorSpace() == BtfColorSpace::Xyz ? "CIE XYZ (D65)" : "linear Rec.709"},
                                {"texels", {btf.width(), btf.height()}},
                                {"views", btf.views().views()},
                                {"images", views * kBtfDirectionCount},
                                {"image_type", ext},
                                {"transfer", transfer ? btfTransferName(*transfer) : "linear (float)"},
                                {"value_scale", btf.valueScale()},
                                {"checked", "btf.json, the names and every image's header (size, channels); "
                                            "not the pixels (btf compress and btf decompress read them)"}}
                     .dump(2)
              << '\n';
    return;
  }
  std::printf("%s: image-folder BTF (%s layout), %d x %d texels, %s x 81 lights (%d %s images)\n", folder.c_str(),
              btfImageLayoutName(btf.layout()).c_str(), btf.width(), btf.height(), btf.views().describe().c_str(),
              views * kBtfDirectionCount, ext.c_str());
  if (btf.directionList())
    std::printf("directions  %s: where light and camera coincide, the light moved aside (%s)\n",
                btf.directions().describe().c_str(), btf.directionList()->filename().c_str());
  if (transfer)
    std::printf("integer images: value = %s(code / max code) x %g (apparent BRDF, 1/sr)\n",
                *transfer == BtfTransfer::Srgb ? "srgb_to_linear" : "", btf.valueScale());
  else if (btf.colorSpace() == BtfColorSpace::Xyz)
    std::printf("float images: CIE XYZ (D65 white), converted to linear Rec.709 (sRGB primaries); values are the "
                "apparent BRDF (1/sr)\n");
  else
    std::printf("float images: values are the apparent BRDF (1/sr)\n");
  std::printf("checked: btf.json, the names and every image's header (size, channels); not the pixels\n");
}

nlohmann::json sectionList(const std::vector<ContainerSection>& sections) {
  nlohmann::json list = nlohmann::json::array();
  for (const ContainerSection& s : sections)
    list.push_back({{"name", s.name}, {"type", std::string(sectionTypeName(s.type))}, {"raw_bytes", s.data.size()},
                    {"stored_bytes", s.stored_bytes}, {"zstd", s.compress}});
  return list;
}

void printSections(const std::vector<ContainerSection>& sections) {
  std::printf("%-28s %-13s %12s %12s\n", "section", "type", "raw bytes", "stored");
  for (const ContainerSection& s : sections)
    std::printf("%-28s %-13s %12zu %12llu%s\n", s.name.c_str(), std::string(sectionTypeName(s.type)).c_str(), s.data.size(),
                static_cast<unsigned long long>(s.stored_bytes), s.compress ? " (zstd)" : "");
}

void runSingleBtfzInfo(const std::filesystem::path& file, const std::vector<ContainerSection>& sections, bool json) {
  const VqBtf btf = VqBtf::read(file);
  const std::uint64_t bytes = std::filesystem::file_size(file);
  const double raw_u8 = double(btf.entryCount()) * 3.0;
  const nlohmann::json facts{{"file", file.string()},
                             {"format", "btfz (multi-level VQ)"},
                             {"texels", {btf.width(), btf.height()}},
                             {"views", btf.views().views()},
                             {"directions", btf.directions().describe()},
                             {"light_rings", btf.ringLayout().sizes()},
                             {"epsilon", btf.options().epsilon},
                             {"chroma_epsilon", btf.options().chroma_epsilon},
                             {"levels", btf.options().levels},
                             {"codebook_entries", btf.stats().codebook_entries},
                             {"bytes", bytes},
                             {"ratio_u8", raw_u8 / double(bytes)},
                             {"ratio_f32", 4.0 * raw_u8 / double(bytes)},
                             {"sections", sectionList(sections)}};
  if (json) {
    std::cout << facts.dump(2) << '\n';
    return;
  }
  std::printf("%s: btfz (multi-level VQ), %d x %d texels x %s x %s\n", file.c_str(), btf.width(), btf.height(),
              btf.views().describe().c_str(), btf.directions().describeLights().c_str());
  if (!btf.directions().isUbo2003()) std::printf("light rings of level 1: %s\n", btf.ringLayout().describe().c_str());
  std::printf("epsilon %g, chroma_epsilon %g, %d levels; codebook entries per level:", btf.options().epsilon,
              btf.options().chroma_epsilon, btf.options().levels);
  for (std::size_t n : btf.stats().codebook_entries) std::printf(" %zu", n);
  std::printf("\n%llu bytes: ratio_u8 %.1f, ratio_f32 %.1f\n", static_cast<unsigned long long>(bytes),
              facts["ratio_u8"].get<double>(), facts["ratio_f32"].get<double>());
  printSections(sections);
}

void runFactorInfo(const std::filesystem::path& file, const std::vector<ContainerSection>& sections, bool json) {
  const FactorBtf btf = FactorBtf::read(file);
  const FactorStats& st = btf.stats();
  const std::uint64_t bytes = std::filesystem::file_size(file);
  const double raw_u8 = double(btf.entryCount()) * 3.0;
  nlohmann::json facts{{"file", file.string()},
                       {"format", "btfz (quantized factors)"},
                       {"texels", {btf.width(), btf.height()}},
                       {"views", btf.views().views()},
                       {"directions", btf.directions().describe()},
                       {"color_model", factorColorModelName(btf.options().color_model)},
                       {"epsilon", btf.options().epsilon},
                       {"components", st.components},
                       {"coefficient_step", st.coefficient_step},
                       {"estimated_rel_rmse", st.estimated_rel_rmse},
                       {"bytes", bytes},
                       {"ratio_u8", raw_u8 / double(bytes)},
                       {"ratio_f32", 4.0 * raw_u8 / double(bytes)},
                       {"sections", sectionList(sections)}};
  if (st.measured_rel_rmse >= 0) facts["measured_rel_rmse"] = st.measured_rel_rmse;
  if (json) {
    std::cout << facts.dump(2) << '\n';
    return;
  }
  std::printf("%s: btfz (quantized factors, %s), %d x %d texels x %s x %s\n", file.c_str(),
              factorColorModelName(btf.options().color_model).c_str(), btf.width(), btf.height(),
              btf.views().describe().c_str(), btf.directions().describeLights().c_str());
  std::printf("epsilon %g; components per colour channel %d %d %d; estimated rel_rmse %.5f", btf.options().epsilon,
              st.components[0], st.components[1], st.components[2], st.estimated_rel_rmse);
  if (st.measured_rel_rmse >= 0) std::printf(", measured on every entry %.5f", st.measured_rel_rmse);
  std::printf("\n%llu bytes: ratio_u8 %.1f, ratio_f32 %.1f\n", static_cast<unsigned long long>(bytes),
              facts["ratio_u8"].get<double>(), facts["ratio_f32"].get<double>());
  printSections(sections);
}

// A database: its options and shared codebooks, then one line per material with the bytes of its
// own sections (the shared ones are listed once).
void runDatabaseInfo(const std::filesystem::path& file, const std::vector<ContainerSection>& sections, bool json) {
  const VqDatabase db = VqDatabase::read(file);
  const std::uint64_t bytes = std::filesystem::file_size(file);
  std::vector<ContainerSection> shared;
  nlohmann::json materials = nlohmann::json::array();
  for (std::size_t i = 0; i < db.size(); ++i) {
    const VqBtf& m = db.materials()[i];
    const std::string prefix = "material" + std::to_string(i) + "/";
    std::uint64_t own = 0;
    for (const ContainerSection& s : sections)
      if (s.name.starts_with(prefix)) own += s.stored_bytes;
    materials.push_back({{"name", m.name()},
                         {"texels", {m.width(), m.height()}},
                         {"views", m.views().views()},
                         {"directions", m.directions().describe()},
                         {"codebook_entries", m.stats().codebook_entries},
                         {"own_stored_bytes", own}});
  }
  for (const ContainerSection& s : sections)
    if (!s.name.starts_with("material")) shared.push_back(s);
  const nlohmann::json facts{{"file", file.string()},
                             {"format", "btfz database (multi-level VQ, shared codebooks)"},
                             {"epsilon", db.options().epsilon},
                             {"chroma_epsilon", db.options().chroma_epsilon},
                             {"levels", db.options().levels},
                             {"shared_codebook_entries", db.sharedEntries()},
                             {"bytes", bytes},
                             {"ratio_u8", db.rawBytesU8() / double(bytes)},
                             {"materials", materials},
                             {"sections", sectionList(sections)}};
  if (json) {
    std::cout << facts.dump(2) << '\n';
    return;
  }
  std::printf("%s: btfz database of %zu materials (multi-level VQ, shared codebooks)\n", file.c_str(), db.size());
  std::printf("epsilon %g, chroma_epsilon %g, %d levels; shared codebook entries (level 1, level 2):",
              db.options().epsilon, db.options().chroma_epsilon, db.options().levels);
  for (std::size_t n : db.sharedEntries()) std::printf(" %zu", n);
  std::printf("\n%llu bytes: ratio_u8 %.1f\n", static_cast<unsigned long long>(bytes), facts["ratio_u8"].get<double>());
  std::printf("%-28s %-12s %6s %14s %12s\n", "material", "texels", "views", "level-3 entries", "own bytes");
  for (const auto& m : materials) {
    const std::string texels = std::to_string(m["texels"][0].get<int>()) + " x " + std::to_string(m["texels"][1].get<int>());
    const auto& entries = m["codebook_entries"];
    std::printf("%-28s %-12s %6zu %14s %12llu\n", m["name"].get<std::string>().c_str(), texels.c_str(), m["views"].size(),
                db.options().levels == 3 ? std::to_string(entries.back().get<std::size_t>()).c_str() : "-",
                static_cast<unsigned long long>(m["own_stored_bytes"].get<std::uint64_t>()));
  }
  std::printf("shared sections:\n");
  printSections(shared);
}

std::string colorModelText(const BonnBtfHeader& h) {
  switch (h.layout) {
    case BonnBtfLayout::Dfmf:
      return "colour model " + std::to_string(h.color_model) + " (" + bonnColorModelName(h.color_model) + ")";
    case BonnBtfLayout::Fmf:
      return h.dynamic_range_reduction ? "RGB, stored as log(x + 1e-5)" : "RGB";
    case BonnBtfLayout::Pvf: return "RGB";
  }
  return "?";
}

// A Bonn .btf file from its headers alone: every count and size is read and checked against the
// file's length, no factor is decoded (so it answers at once for a 1 GB file).
void runBonnInfo(const std::filesystem::path& file, bool json) {
  const BonnBtfHeader h = readBonnBtfHeader(file);
  const BtfDirectionSet& set = *h.directions;
  std::uint64_t factor_bytes = 0;
  nlohmann::json factors = nlohmann::json::array();
  for (const BonnBtfFactor& f : h.factors) {
    factor_bytes += f.bytes();
    factors.push_back({{"components", f.components}, {"rows", f.rows}, {"columns", f.columns},
                       {"scalar_bytes", f.scalar_bytes}, {"bytes", f.bytes()}});
  }
  const std::uint64_t texels = std::uint64_t(h.width) * std::uint64_t(h.height);
  const nlohmann::json facts{{"file", file.string()},
                             {"format", "Bonn BTF (" + bonnBtfLayoutName(h.layout) + ")"},
                             {"signature", h.signature},
                             {"meta_version", h.meta_version},
                             {"measurement_setup", h.measurement_setup},
                             {"image_sensor", h.image_sensor},
                             {"light_source", h.light_source},
                             {"pixels_per_mm", h.pixels_per_mm},
                             {"rgb_scale", h.rgb_scale},
                             {"cosine_in_data", h.cosine_flag},
                             {"channels", h.channel_names},
                             {"xml_bytes", h.xml.size()},
                             {"texels", {h.width, h.height}},
                             {"views", set.viewCount()},
                             {"lights_per_view_max", set.maxLightCount()},
                             {"shared_lights", set.sharedLights()},
                             {"directions", set.describe()},
                             {"rotations", h.rotation_count},
                             {"values", colorModelText(h)},
                             {"factors", factors},
                             {"entries", texels * set.pairCount()},
                             {"bytes", h.file_bytes}};
  if (json) {
    std::cout << facts.dump(2) << '\n';
    return;
  }
  std::printf("%s: Bonn BTF file, %s (signature %s, meta data version %u)\n", file.c_str(),
              bonnBtfLayoutName(h.layout).c_str(), h.signature.c_str(), h.meta_version);
  std::printf("texels      %d x %d\n", h.width, h.height);
  std::printf("directions  %s\n", set.describe().c_str());
  std::printf("set-up      %s | sensor %s | light %s\n", h.measurement_setup.empty() ? "-" : h.measurement_setup.c_str(),
              h.image_sensor.empty() ? "-" : h.image_sensor.c_str(), h.light_source.empty() ? "-" : h.light_source.c_str());
  std::printf("scale       %g pixels/mm, RGB scale (%g, %g, %g)%s\n", double(h.pixels_per_mm), double(h.rgb_scale[0]),
              double(h.rgb_scale[1]), double(h.rgb_scale[2]),
              h.cosine_flag ? "; values hold f cos(theta_l), divided out on reading" : "");
  std::printf("values      %s, decoded to linear RGB (apparent BRDF, 1/sr)\n", colorModelText(h).c_str());
  if (h.rotation_count) std::printf("rotations   %u local frames stored\n", h.rotation_count);
  const char* what = h.layout == BonnBtfLayout::Dfmf ? "channel" : h.layout == BonnBtfLayout::Fmf ? "matrix" : "view";
  std::printf("factors     %zu (%s): ", h.factors.size(), h.layout == BonnBtfLayout::Pvf ? "one per view" : what);
  for (std::size_t i = 0; i < std::min<std::size_t>(h.factors.size(), 4); ++i)
    std::printf("%s%u components x (%u + %u) x %d bytes", i ? "; " : "", h.factors[i].components, h.factors[i].rows,
                h.factors[i].columns, h.factors[i].scalar_bytes);
  std::printf("%s\n", h.factors.size() > 4 ? "; ..." : "");
  std::printf("bytes       %llu (%llu of factors); the %.3g G RGB values it encodes would take %.3g GB as float\n",
              static_cast<unsigned long long>(h.file_bytes), static_cast<unsigned long long>(factor_bytes),
              double(texels * set.pairCount()) * 1e-9, double(texels * set.pairCount()) * 12e-9);
  std::printf("checked: the headers, every factor's dimensions and the file's length; no factor decoded\n");
}

void runBtfzInfo(const std::filesystem::path& file, bool json) {
  const std::vector<ContainerSection> sections = readContainer(file);
  const bool database = std::any_of(sections.begin(), sections.end(),
                                    [](const ContainerSection& s) { return s.name.starts_with("material0/"); });
  if (database) runDatabaseInfo(file, sections, json);
  else if (compressedBtfFormat(file) == "libbtf-factor") runFactorInfo(file, sections, json);
  else runSingleBtfzInfo(file, sections, json);
}

}  // namespace

void runBtfInfo(const std::filesystem::path& path, bool json) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) runFolderInfo(path, json);
  else if (isBonnBtfFile(path)) runBonnInfo(path, json);
  else runBtfzInfo(path, json);
}

}  // namespace btf::cli
