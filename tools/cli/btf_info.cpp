// `btf info` on BTFs: an image folder (size, value scale, image format) or a .btfz file (what the
// compressor kept: options, codebook sizes, sections and their bytes, ratios).
#include <cstdio>
#include <iostream>

#include <nlohmann/json.hpp>

#include "btf/compress/vq_btf.h"
#include "btf/io/btf_images.h"
#include "btf/io/container.h"
#include "btf_input.h"

namespace btf::cli {
namespace {

void runFolderInfo(const std::filesystem::path& folder, bool json) {
  const BtfImageFolder btf = BtfImageFolder::open(folder);
  const int views = btf.views().count();
  const std::string ext = btf.imagePath(btf.views().view(0), 0).extension().string();
  const std::optional<BtfTransfer> transfer = btf.transfer();
  if (json) {
    std::cout << nlohmann::json{{"file", folder.string()},
                                {"format", "image-folder BTF"},
                                {"texels", {btf.width(), btf.height()}},
                                {"views", btf.views().views()},
                                {"images", views * kBtfDirectionCount},
                                {"image_type", ext},
                                {"transfer", transfer ? btfTransferName(*transfer) : "linear (float)"},
                                {"value_scale", btf.valueScale()}}
                     .dump(2)
              << '\n';
    return;
  }
  std::printf("%s: image-folder BTF, %d x %d texels, %s x 81 lights (%d %s images)\n", folder.c_str(), btf.width(),
              btf.height(), btf.views().describe().c_str(), views * kBtfDirectionCount, ext.c_str());
  if (transfer)
    std::printf("integer images: value = %s(code / max code) x %g (apparent BRDF, 1/sr)\n",
                *transfer == BtfTransfer::Srgb ? "srgb_to_linear" : "", btf.valueScale());
  else
    std::printf("float images: values are the apparent BRDF (1/sr)\n");
}

void runBtfzInfo(const std::filesystem::path& file, bool json) {
  const std::vector<ContainerSection> sections = readContainer(file);
  const VqBtf btf = VqBtf::read(file);
  const std::uint64_t bytes = std::filesystem::file_size(file);
  const double raw_u8 = double(btf.entryCount()) * 3.0;
  nlohmann::json list = nlohmann::json::array();
  for (const ContainerSection& s : sections)
    list.push_back({{"name", s.name}, {"type", std::string(sectionTypeName(s.type))}, {"raw_bytes", s.data.size()},
                    {"stored_bytes", s.stored_bytes}, {"zstd", s.compress}});
  const nlohmann::json facts{{"file", file.string()},
                             {"format", "btfz (multi-level VQ)"},
                             {"texels", {btf.width(), btf.height()}},
                             {"views", btf.views().views()},
                             {"epsilon", btf.options().epsilon},
                             {"chroma_epsilon", btf.options().chroma_epsilon},
                             {"levels", btf.options().levels},
                             {"codebook_entries", btf.stats().codebook_entries},
                             {"bytes", bytes},
                             {"ratio_u8", raw_u8 / double(bytes)},
                             {"ratio_f32", 4.0 * raw_u8 / double(bytes)},
                             {"sections", list}};
  if (json) {
    std::cout << facts.dump(2) << '\n';
    return;
  }
  std::printf("%s: btfz (multi-level VQ), %d x %d texels x %s x 81 lights\n", file.c_str(), btf.width(), btf.height(),
              btf.views().describe().c_str());
  std::printf("epsilon %g, chroma_epsilon %g, %d levels; codebook entries per level:", btf.options().epsilon,
              btf.options().chroma_epsilon, btf.options().levels);
  for (std::size_t n : btf.stats().codebook_entries) std::printf(" %zu", n);
  std::printf("\n%llu bytes: ratio_u8 %.1f, ratio_f32 %.1f\n", static_cast<unsigned long long>(bytes),
              facts["ratio_u8"].get<double>(), facts["ratio_f32"].get<double>());
  std::printf("%-28s %-13s %12s %12s\n", "section", "type", "raw bytes", "stored");
  for (const ContainerSection& s : sections)
    std::printf("%-28s %-13s %12zu %12llu%s\n", s.name.c_str(), std::string(sectionTypeName(s.type)).c_str(), s.data.size(),
                static_cast<unsigned long long>(s.stored_bytes), s.compress ? " (zstd)" : "");
}

}  // namespace

bool isBtfPath(const std::filesystem::path& path) {
  // A folder named like a measured BRDF file (a mistake, say folder.binary) is reported as such by
  // the BRDF readers ("is a directory"), not as a BTF folder without images.
  const std::string ext = path.extension().string();
  if (ext == ".binary" || ext == ".exr" || ext == ".bsdf") return false;
  std::error_code ec;
  return std::filesystem::is_directory(path, ec) || ext == ".btfz";
}

void runBtfInfo(const std::filesystem::path& path, bool json) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) runFolderInfo(path, json);
  else runBtfzInfo(path, json);
}

}  // namespace btf::cli
