#include "btf/compress/compressed_btf.h"

#include <fstream>
#include <vector>

#include "btf/compress/factor_btf.h"
#include "btf/compress/vq_btf.h"
#include "btf/core/error.h"
#include "btf/io/container.h"

namespace btf {

bool isCompressedBtfFormat(std::string_view format) {
  return format == "libbtf-vq" || format == "libbtf-vq-database" || format == "libbtf-factor";
}

std::string compressedBtfFormat(const std::filesystem::path& path) {
  // The header is the first section and stored raw: the first bytes name the format.
  std::vector<unsigned char> head(65536);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path, "cannot be opened");
  in.read(reinterpret_cast<char*>(head.data()), std::streamsize(head.size()));
  head.resize(std::size_t(in.gcount()));
  return std::string(containerFormatOf(head));
}

std::shared_ptr<const BtfSource> readCompressedBtf(const std::filesystem::path& path, std::string_view material) {
  if (compressedBtfFormat(path) == "libbtf-factor") {
    if (!material.empty())
      throw FileError(path, "is a single factor-compressed material, not a database: it has no material '" +
                                std::string(material) + "'");
    return std::make_shared<FactorBtf>(FactorBtf::read(path));
  }
  return std::make_shared<VqBtf>(VqBtf::read(path, material));
}

}  // namespace btf
