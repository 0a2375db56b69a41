// VqBtf in .btfz (io/container.h). Sections: "header" (JSON), "level1/ring<r>", "chroma/ring<r>",
// "level2/{index,scale,chroma}", "level3/{index,scale}", "top/{index,scale,chroma}" (those the level
// count uses). Integer streams are stored byte-planar (all lowest bytes, then the next...) in the
// fewest bytes their largest value needs (the first byte of a section says how many): indices into
// small codebooks then leave long runs of zero planes, and zstd (the container's) codes the rest.
#include <tbb/parallel_for.h>
#include <zstd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstring>

#include "btf/core/error.h"
#include "btf/io/container.h"
#include "vq_impl.h"

namespace btf {

namespace {

constexpr int kFormatVersion = 1;

template <class T>
std::vector<std::byte> packPlanar(const std::vector<T>& values) {
  using U = std::make_unsigned_t<T>;
  U largest = 0;
  for (T v : values) largest = std::max(largest, U(v));
  int width = 1;
  while (width < int(sizeof(T)) && (std::uint64_t(largest) >> (8 * width)) != 0) ++width;
  std::vector<std::byte> out(1 + values.size() * std::size_t(width));
  out[0] = std::byte(width);
  for (int b = 0; b < width; ++b)
    for (std::size_t i = 0; i < values.size(); ++i)
      out[1 + std::size_t(b) * values.size() + i] = std::byte((std::uint64_t(U(values[i])) >> (8 * b)) & 0xff);
  return out;
}

template <class T>
std::vector<T> unpackPlanar(const ContainerSection& s, const std::filesystem::path& path) {
  using U = std::make_unsigned_t<T>;
  if (s.data.empty()) throw FileError(path, "section " + s.name + " is empty");
  const int width = int(s.data[0]);
  if (width < 1 || width > int(sizeof(T)) || (s.data.size() - 1) % std::size_t(width) != 0)
    throw FileError(path, "section " + s.name + " has an invalid layout");
  const std::size_t n = (s.data.size() - 1) / std::size_t(width);
  std::vector<T> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t v = 0;
    for (int b = 0; b < width; ++b) v |= std::uint64_t(std::uint8_t(s.data[1 + std::size_t(b) * n + i])) << (8 * b);
    out[i] = T(U(v));
  }
  return out;
}

std::vector<ContainerSection> buildSections(const VqBtf::Impl& m) {
  nlohmann::json header;
  header["format"] = "libbtf-vq";
  header["format_version"] = kFormatVersion;
  header["width"] = m.width;
  header["height"] = m.height;
  header["name"] = m.name;
  // The views held, only when some are missing (absent = all 81: files of complete BTFs are as before).
  if (!m.views.complete()) header["views"] = m.views.views();
  header["levels"] = m.options.levels;
  header["epsilon"] = m.options.epsilon;
  header["chroma_epsilon"] = m.options.chroma_epsilon;
  header["energy_floor"] = m.options.energy_floor;
  header["codebook_entries"] = m.stats.codebook_entries;
  std::vector<std::size_t> chroma_entries;
  for (int r = 0; r < kBtfRingCount; ++r) chroma_entries.push_back(m.chromaCount(r));
  header["chroma_entries"] = chroma_entries;  // per ring, informative (the sections are authoritative)
  header["chroma_step"] = vqChromaStep(m.options.chroma_epsilon);
  std::vector<ContainerSection> sections;
  auto add = [&](SectionType type, std::string name, std::vector<std::byte> data) {
    ContainerSection s;
    s.type = type;
    s.name = std::move(name);
    s.data = std::move(data);
    s.compress = true;
    sections.push_back(std::move(s));
  };
  const std::string text = header.dump();
  std::vector<std::byte> bytes(text.size());
  std::memcpy(bytes.data(), text.data(), text.size());
  add(SectionType::Header, "header", std::move(bytes));
  for (int r = 0; r < kBtfRingCount; ++r)
    add(SectionType::Codebook, "level1/ring" + std::to_string(r), packPlanar(m.l1[std::size_t(r)]));
  for (int r = 0; r < kBtfRingCount; ++r)
    add(SectionType::Codebook, "chroma/ring" + std::to_string(r), packPlanar(m.chroma[std::size_t(r)]));
  if (m.options.levels >= 2) {
    add(SectionType::Codebook, "level2/index", packPlanar(m.l2_index));
    add(SectionType::Codebook, "level2/scale", packPlanar(m.l2_scale));
    add(SectionType::Codebook, "level2/chroma", packPlanar(m.l2_chroma));
  }
  if (m.options.levels == 3) {
    add(SectionType::Codebook, "level3/index", packPlanar(m.l3_index));
    add(SectionType::Codebook, "level3/scale", packPlanar(m.l3_scale));
  }
  add(SectionType::IndexStream, "top/index", packPlanar(m.top_index));
  add(SectionType::Scales, "top/scale", packPlanar(m.top_scale));
  if (m.options.levels == 1) add(SectionType::IndexStream, "top/chroma", packPlanar(m.top_chroma));
  return sections;
}

// zstd's strongest levels cost seconds per MB, paid twice (compressVq's size, then write()): level
// 19 only for small payloads (BRDFs, small or well-compressed BTFs), else level 9, which was ~13x
// faster and 6 % larger on a 32 x 32 synthetic BTF (10 MB stored; level 6: 7 %, level 3: 10 %).
// One level for all larger payloads also keeps ratios comparable across sizes.
int zstdLevelFor(const std::vector<ContainerSection>& sections) {
  std::size_t raw = 0;
  for (const auto& s : sections) raw += s.data.size();
  return raw <= (std::size_t(4) << 20) ? 19 : 9;
}

const ContainerSection& section(const std::vector<ContainerSection>& sections, const std::string& name,
                                const std::filesystem::path& path) {
  for (const auto& s : sections)
    if (s.name == name) return s;
  throw FileError(path, "section " + name + " is missing");
}

}  // namespace

// Bytes the .btfz file will hold: the sections as the container compresses them plus its table.
std::uint64_t vqCompressedBytes(const VqBtf::Impl& impl) {
  const auto sections = buildSections(impl);
  const int level = zstdLevelFor(sections);
  std::vector<std::uint64_t> sizes(sections.size());
  tbb::parallel_for(std::size_t(0), sections.size(), [&](std::size_t i) {
    const auto& data = sections[i].data;
    std::vector<char> buffer(ZSTD_compressBound(data.size()));
    const std::size_t n = ZSTD_compress(buffer.data(), buffer.size(), data.data(), data.size(), level);
    sizes[i] = ZSTD_isError(n) ? data.size() : std::min<std::uint64_t>(n, data.size());
  });
  std::uint64_t total = 8 + 4 + 4 + 8;  // magic, version, count, table checksum
  for (std::size_t i = 0; i < sections.size(); ++i) total += sizes[i] + 38 + sections[i].name.size();
  return total;
}

void VqBtf::write(const std::filesystem::path& path) const {
  auto sections = buildSections(*impl_);
  const std::uint64_t bytes = writeContainer(path, sections, zstdLevelFor(sections));
  impl_->stats.compressed_bytes = bytes;
  const double raw = double(entryCount()) * 3.0;
  impl_->stats.ratio_u8 = raw / double(bytes);
  impl_->stats.ratio_f32 = 4.0 * impl_->stats.ratio_u8;
}

VqBtf VqBtf::read(const std::filesystem::path& path) {
  const auto sections = readContainer(path);
  auto m = std::make_shared<Impl>();
  const auto& h = section(sections, "header", path);
  nlohmann::json header;
  try {
    header = nlohmann::json::parse(std::string(reinterpret_cast<const char*>(h.data.data()), h.data.size()));
    if (header.at("format").get<std::string>() != "libbtf-vq") throw FileError(path, "holds no VQ-compressed BTF");
    const int version = header.at("format_version").get<int>();
    if (version != kFormatVersion)
      throw FileError(path, "VQ format version " + std::to_string(version) + " is not supported (this build reads " +
                                std::to_string(kFormatVersion) + ")");
    m->width = header.at("width").get<int>();
    m->height = header.at("height").get<int>();
    m->name = header.at("name").get<std::string>();
    m->options.levels = header.at("levels").get<int>();
    m->options.epsilon = header.at("epsilon").get<float>();
    m->options.chroma_epsilon = header.at("chroma_epsilon").get<float>();
    m->options.energy_floor = header.at("energy_floor").get<float>();
    m->stats.codebook_entries = header.at("codebook_entries").get<std::vector<std::size_t>>();
    if (header.contains("views")) m->views = BtfViewSet(header.at("views").get<std::vector<int>>());
  } catch (const nlohmann::json::exception& e) {
    throw FileError(path, std::string("VQ header is invalid: ") + e.what());
  } catch (const FileError&) {
    throw;
  } catch (const Error& e) {
    throw FileError(path, std::string("VQ header's views are invalid: ") + e.what());
  }
  if (m->width < 1 || m->height < 1 || m->width > 65536 || m->height > 65536)
    throw FileError(path, "VQ header has an invalid texel size");
  if (m->options.levels < 1 || m->options.levels > 3) throw FileError(path, "VQ header has an invalid level count");
  if (!(m->options.chroma_epsilon >= kVqMinChromaEpsilon) || !(m->options.chroma_epsilon <= 1.0f))
    throw FileError(path, "VQ header has an invalid chroma_epsilon");
  for (int r = 0; r < kBtfRingCount; ++r)
    m->l1[std::size_t(r)] = unpackPlanar<std::uint16_t>(section(sections, "level1/ring" + std::to_string(r), path), path);
  for (int r = 0; r < kBtfRingCount; ++r)
    m->chroma[std::size_t(r)] = unpackPlanar<std::int32_t>(section(sections, "chroma/ring" + std::to_string(r), path), path);
  if (m->options.levels >= 2) {
    m->l2_index = unpackPlanar<std::uint32_t>(section(sections, "level2/index", path), path);
    m->l2_scale = unpackPlanar<std::uint16_t>(section(sections, "level2/scale", path), path);
    m->l2_chroma = unpackPlanar<std::uint32_t>(section(sections, "level2/chroma", path), path);
  }
  if (m->options.levels == 3) {
    m->l3_index = unpackPlanar<std::uint32_t>(section(sections, "level3/index", path), path);
    m->l3_scale = unpackPlanar<std::uint16_t>(section(sections, "level3/scale", path), path);
  }
  m->top_index = unpackPlanar<std::uint32_t>(section(sections, "top/index", path), path);
  m->top_scale = unpackPlanar<std::uint16_t>(section(sections, "top/scale", path), path);
  if (m->options.levels == 1) m->top_chroma = unpackPlanar<std::uint32_t>(section(sections, "top/chroma", path), path);
  try {
    m->prepare("VQ data");
  } catch (const FileError&) {
    throw;
  } catch (const Error& e) {
    throw FileError(path, e.what());
  }
  // The header's codebook sizes must be those of the sections: a header whose view list was edited
  // (checksums recomputed) would otherwise split the level-3 entries at the wrong length and decode
  // wrong values without an error.
  std::vector<std::size_t> entries;
  std::size_t l1 = 0;
  for (int r = 1; r < kBtfRingCount; ++r) l1 += m->l1Count(r);
  entries.push_back(l1);
  if (m->options.levels >= 2) entries.push_back(m->l2Count());
  if (m->options.levels >= 3) entries.push_back(m->l3Count());
  if (entries != m->stats.codebook_entries)
    throw FileError(path, "VQ header's codebook entry counts disagree with its codebook sections (an edited header?)");
  m->stats.compressed_bytes = std::filesystem::file_size(path);
  const double raw = double(m->width) * m->height * double(m->viewCount()) * kBtfDirectionCount * 3.0;
  m->stats.ratio_u8 = raw / double(m->stats.compressed_bytes);
  m->stats.ratio_f32 = 4.0 * m->stats.ratio_u8;
  return VqBtf(m);
}

}  // namespace btf
