// VqBtf in .btfz (io/container.h). Sections: "header" (JSON), "level1/ring<r>" (and
// "level1/basis<r>" for a basis-coded ring, vq_basis.h), "chroma/ring<r>",
// "level2/{index,scale,chroma}", "level3/{index,scale}", "top/{index,scale,chroma}" (those the level
// count uses). Integer streams are stored byte-planar (all lowest bytes, then the next...) in the
// fewest bytes their largest value needs (the first byte of a section says how many): indices into
// small codebooks then leave long runs of zero planes, and zstd (the container's) codes the rest.
#include <tbb/parallel_for.h>
#include <zstd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "btf/core/error.h"
#include "btf/core/value_limits.h"
#include "btf/io/container.h"
#include "vq_impl.h"
#include "vq_sections.h"

namespace btf {

namespace {

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
  nlohmann::json header = vqOptionsHeader(m);
  header["format"] = "libbtf-vq";
  header["format_version"] = vqSectionsVersion(m);
  header["width"] = m.width;
  header["height"] = m.height;
  header["name"] = m.name;
  addVqDirectionsHeader(m, header);
  header["codebook_entries"] = m.stats.codebook_entries;
  std::vector<ContainerSection> sections;
  addVqHeaderSection(header, sections);
  addVqSharedSections(m, sections, "");
  addVqMaterialSections(m, "", sections);
  return sections;
}

}  // namespace

void addVqSection(std::vector<ContainerSection>& sections, SectionType type, std::string name, std::vector<std::byte> data) {
  ContainerSection s;
  s.type = type;
  s.name = std::move(name);
  s.data = std::move(data);
  s.compress = true;
  sections.push_back(std::move(s));
}

void addVqHeaderSection(const nlohmann::json& header, std::vector<ContainerSection>& sections) {
  const std::string text = header.dump();
  std::vector<std::byte> bytes(text.size());
  std::memcpy(bytes.data(), text.data(), text.size());
  addVqSection(sections, SectionType::Header, "header", std::move(bytes));
}

nlohmann::json vqOptionsHeader(const VqBtf::Impl& m) {
  nlohmann::json header;
  header["levels"] = m.options.levels;
  header["epsilon"] = m.options.epsilon;
  header["chroma_epsilon"] = m.options.chroma_epsilon;
  header["energy_floor"] = m.options.energy_floor;
  std::vector<std::size_t> chroma_entries;
  for (int r = 0; r < int(m.ringCount()); ++r) chroma_entries.push_back(m.chromaCount(r));
  header["chroma_entries"] = chroma_entries;  // per ring, informative (the sections are authoritative)
  header["chroma_step"] = vqChromaStep(m.options.chroma_epsilon);
  return header;
}

int vqSectionsVersion(const VqBtf::Impl& m) {
  if (vqHasOwnDirections(m)) return 4;
  if (hasDerivedLevel3(m)) return 3;
  for (const VqRingBasis& basis : m.l1_basis)
    if (!basis.empty()) return 2;
  return 1;
}

void addVqSharedSections(const VqBtf::Impl& m, std::vector<ContainerSection>& sections, const std::string& prefix) {
  for (int r = 0; r < int(m.ringCount()); ++r) {
    const std::string ring = prefix + "level1/ring" + std::to_string(r);
    const VqRingBasis& basis = m.l1_basis[std::size_t(r)];
    if (basis.empty()) {
      addVqSection(sections, SectionType::Codebook, ring, packPlanar(m.l1[std::size_t(r)]));
      continue;
    }
    // "level1/basis<r>": the coefficient step, then the n x n basis, float32. The ring's section
    // holds the coefficients, zigzag-coded, coefficient-major (every entry's first coefficient,
    // then every entry's second...): the dropped tails become long runs of zeros for zstd.
    // The file's only floats: what is written is finite (the reader refuses anything else).
    if (!std::isfinite(basis.step) || !std::all_of(basis.v.begin(), basis.v.end(), [](float x) { return std::isfinite(x); }))
      throw Error(m.name + ": the level-1 basis of ring " + std::to_string(r) + " is not finite; nothing written");
    ByteWriter bytes;
    bytes.put(basis.step);
    bytes.putAll(basis.v);
    addVqSection(sections, SectionType::Codebook, prefix + "level1/basis" + std::to_string(r), std::move(bytes.bytes()));
    const std::vector<std::int32_t>& c = m.l1_coef[std::size_t(r)];
    const std::size_t n = std::size_t(basis.n), entries = c.size() / n;
    std::vector<std::uint32_t> zigzag(c.size());
    for (std::size_t e = 0; e < entries; ++e)
      for (std::size_t j = 0; j < n; ++j) {
        const std::int32_t k = c[e * n + j];
        zigzag[j * entries + e] = k >= 0 ? 2u * std::uint32_t(k) : 2u * std::uint32_t(-(k + 1)) + 1u;
      }
    addVqSection(sections, SectionType::Codebook, ring, packPlanar(zigzag));
  }
  for (int r = 0; r < int(m.ringCount()); ++r)
    addVqSection(sections, SectionType::Codebook, prefix + "chroma/ring" + std::to_string(r), packPlanar(m.chroma[std::size_t(r)]));
  if (m.options.levels >= 2) {
    addVqSection(sections, SectionType::Codebook, prefix + "level2/index", packPlanar(m.l2_index));
    addVqSection(sections, SectionType::Codebook, prefix + "level2/scale", packPlanar(m.l2_scale));
    addVqSection(sections, SectionType::Codebook, prefix + "level2/chroma", packPlanar(m.l2_chroma));
  }
}

bool hasDerivedLevel3(const VqBtf::Impl& m) {
  return std::any_of(m.l3_parent.begin(), m.l3_parent.end(), [](std::uint32_t p) { return p != 0; });
}

namespace {

// Level 3 with derived entries (vq_impl.h): "level3/parent" (0, or the parent's index + 1, per
// entry), "level3/exception_count" (per derived entry) and "level3/exception_view" (their view
// slots, ascending within an entry); "level3/index" and "level3/scale" hold, entry after entry, a
// whole entry's row or a derived entry's codes in its exception views. The exceptions are the
// views whose codes differ from the parent's, so the writer needs only the parents.
void addDerivedLevel3Sections(const VqBtf::Impl& m, const std::string& prefix, std::vector<ContainerSection>& sections) {
  const std::size_t V = m.viewCount();
  std::vector<std::uint32_t> index, counts;
  std::vector<std::uint16_t> scale;
  std::vector<std::uint32_t> slots;  // one byte each up to 256 views (packPlanar)
  for (std::size_t e = 0; e < m.l3Count(); ++e) {
    const std::uint32_t* row = &m.l3_index[e * V];
    const std::uint16_t* row_scale = &m.l3_scale[e * V];
    if (m.l3_parent[e] == 0) {
      index.insert(index.end(), row, row + V);
      scale.insert(scale.end(), row_scale, row_scale + V);
      continue;
    }
    const std::size_t p = std::size_t(m.l3_parent[e] - 1);
    std::uint32_t count = 0;
    for (std::size_t v = 0; v < V; ++v)
      if (row[v] != m.l3_index[p * V + v] || row_scale[v] != m.l3_scale[p * V + v]) {
        slots.push_back(std::uint32_t(v));
        index.push_back(row[v]);
        scale.push_back(row_scale[v]);
        ++count;
      }
    counts.push_back(count);
  }
  addVqSection(sections, SectionType::Codebook, prefix + "level3/parent", packPlanar(m.l3_parent));
  addVqSection(sections, SectionType::Codebook, prefix + "level3/exception_count", packPlanar(counts));
  addVqSection(sections, SectionType::Codebook, prefix + "level3/exception_view", packPlanar(slots));
  addVqSection(sections, SectionType::Codebook, prefix + "level3/index", packPlanar(index));
  addVqSection(sections, SectionType::Codebook, prefix + "level3/scale", packPlanar(scale));
}

// The whole rows of addDerivedLevel3Sections' entries, each section checked against the others.
void readDerivedLevel3Sections(const std::vector<ContainerSection>& sections, const std::string& prefix,
                               const std::filesystem::path& path, VqBtf::Impl& m) {
  const std::size_t V = m.viewCount();
  const std::string at = prefix + "level3/";
  m.l3_parent = unpackPlanar<std::uint32_t>(vqSection(sections, at + "parent", path), path);
  const auto counts = unpackPlanar<std::uint32_t>(vqSection(sections, at + "exception_count", path), path);
  const auto slots = unpackPlanar<std::uint32_t>(vqSection(sections, at + "exception_view", path), path);
  const auto index = unpackPlanar<std::uint32_t>(vqSection(sections, at + "index", path), path);
  const auto scale = unpackPlanar<std::uint16_t>(vqSection(sections, at + "scale", path), path);
  // Each texel adds at most one entry to the seed: a bound on the rows before they are allocated
  // (a derived entry costs a few bytes in the file and a whole row in memory).
  const std::size_t entries = m.l3_parent.size();
  if (entries == 0 || entries > m.top_index.size() + 1)
    throw FileError(path, "section " + at + "parent lists " + std::to_string(entries) + " entries for " +
                              std::to_string(m.top_index.size()) + " texels");
  if (index.size() != scale.size())
    throw FileError(path, "sections " + at + "index and " + at + "scale differ in length");
  m.l3_index.assign(entries * V, 0);
  m.l3_scale.assign(entries * V, 0);
  std::size_t value = 0, derived = 0, slot = 0;
  auto take = [&](std::size_t e, std::size_t v) {
    if (value == index.size()) throw FileError(path, "section " + at + "index ends before entry " + std::to_string(e));
    m.l3_index[e * V + v] = index[value];
    m.l3_scale[e * V + v] = scale[value];
    ++value;
  };
  for (std::size_t e = 0; e < entries; ++e) {
    const std::uint32_t parent = m.l3_parent[e];
    if (parent == 0) {
      for (std::size_t v = 0; v < V; ++v) take(e, v);
      continue;
    }
    if (parent > e)
      throw FileError(path, "section " + at + "parent: entry " + std::to_string(e) + " derives from entry " +
                                std::to_string(parent - 1) + ", not an earlier one");
    if (derived == counts.size())
      throw FileError(path, "section " + at + "exception_count ends before entry " + std::to_string(e));
    const std::size_t count = counts[derived++], p = parent - 1;
    if (count > V)
      throw FileError(path, "section " + at + "exception_count: entry " + std::to_string(e) + " has " +
                                std::to_string(count) + " exceptions in " + std::to_string(V) + " views");
    std::copy_n(&m.l3_index[p * V], V, &m.l3_index[e * V]);
    std::copy_n(&m.l3_scale[p * V], V, &m.l3_scale[e * V]);
    for (std::size_t k = 0; k < count; ++k, ++slot) {
      if (slot == slots.size())
        throw FileError(path, "section " + at + "exception_view ends before entry " + std::to_string(e));
      if (slots[slot] >= V || (k > 0 && slots[slot] <= slots[slot - 1]))
        throw FileError(path, "section " + at + "exception_view: entry " + std::to_string(e) +
                                  "'s view slots are not ascending below " + std::to_string(V));
      take(e, slots[slot]);
    }
  }
  if (derived != counts.size() || slot != slots.size() || value != index.size())
    throw FileError(path, "sections " + at + "* hold more exceptions or codes than their entries use");
}

}  // namespace

void addVqMaterialSections(const VqBtf::Impl& m, const std::string& prefix, std::vector<ContainerSection>& sections) {
  if (m.options.levels == 3 && hasDerivedLevel3(m)) {
    addDerivedLevel3Sections(m, prefix, sections);
  } else if (m.options.levels == 3) {
    addVqSection(sections, SectionType::Codebook, prefix + "level3/index", packPlanar(m.l3_index));
    addVqSection(sections, SectionType::Codebook, prefix + "level3/scale", packPlanar(m.l3_scale));
  }
  addVqSection(sections, SectionType::IndexStream, prefix + "top/index", packPlanar(m.top_index));
  addVqSection(sections, SectionType::Scales, prefix + "top/scale", packPlanar(m.top_scale));
  if (m.options.levels == 1) addVqSection(sections, SectionType::IndexStream, prefix + "top/chroma", packPlanar(m.top_chroma));
  // The texel size again, beside the header's: the index streams hold width x height entries in
  // any arrangement, so without it a header edited from 4 x 4 to 8 x 2 would decode a scrambled
  // texture without an error.
  ByteWriter texels;
  texels.put(std::uint32_t(m.width));
  texels.put(std::uint32_t(m.height));
  addVqSection(sections, SectionType::Other, prefix + "texels", std::move(texels.bytes()));
}

// zstd's strongest levels are far slower per byte than its middle ones, paid twice (compressVq's
// size, then write()): level 19 only for small payloads (BRDFs, small or well-compressed BTFs),
// else level 9, much faster for files only slightly larger, where lower levels give up more size.
// One level for all larger payloads also keeps ratios comparable across sizes.
int vqZstdLevelFor(const std::vector<ContainerSection>& sections) {
  std::size_t raw = 0;
  for (const auto& s : sections) raw += s.data.size();
  return raw <= (std::size_t(4) << 20) ? 19 : 9;
}

const ContainerSection& vqSection(const std::vector<ContainerSection>& sections, const std::string& name,
                                  const std::filesystem::path& path) {
  for (const auto& s : sections)
    if (s.name == name) return s;
  throw FileError(path, "section " + name + " is missing");
}

nlohmann::json parseVqHeader(const std::vector<ContainerSection>& sections, const std::filesystem::path& path) {
  const auto& h = vqSection(sections, "header", path);
  try {
    return nlohmann::json::parse(std::string(reinterpret_cast<const char*>(h.data.data()), h.data.size()));
  } catch (const nlohmann::json::exception& e) {
    throw FileError(path, std::string("VQ header is invalid: ") + e.what());
  }
}

int vqHeaderInt(const nlohmann::json& object, const char* key, const std::filesystem::path& path) {
  const auto it = object.find(key);
  if (it == object.end()) throw FileError(path, std::string("VQ header has no \"") + key + "\"");
  if (!it->is_number_integer() || *it < INT32_MIN || *it > INT32_MAX)
    throw FileError(path, std::string("VQ header's \"") + key + "\" is " + it->dump() + ", not an integer");
  return it->get<int>();
}

float vqHeaderFloat(const nlohmann::json& object, const char* key, const std::filesystem::path& path) {
  const auto it = object.find(key);
  if (it == object.end()) throw FileError(path, std::string("VQ header has no \"") + key + "\"");
  // Checked as the float it is stored in: 1e300 is a finite double and an infinite float.
  if (!it->is_number() || !std::isfinite(it->get<double>()) ||
      std::abs(it->get<double>()) > double(std::numeric_limits<float>::max()))
    throw FileError(path, std::string("VQ header's \"") + key + "\" is " + it->dump() + ", not a finite float");
  return it->get<float>();
}

std::vector<std::size_t> vqHeaderCounts(const nlohmann::json& object, const char* key, const std::filesystem::path& path) {
  const auto it = object.find(key);
  if (it == object.end()) throw FileError(path, std::string("VQ header has no \"") + key + "\"");
  if (!it->is_array()) throw FileError(path, std::string("VQ header's \"") + key + "\" is not a list of counts");
  std::vector<std::size_t> counts;
  for (const auto& v : *it) {
    if (!v.is_number_unsigned())
      throw FileError(path, std::string("VQ header's \"") + key + "\" holds " + v.dump() + ", not a count");
    counts.push_back(v.get<std::size_t>());
  }
  return counts;
}

// nlohmann converts booleans, and floats to integers, without a word: each field is checked for
// its type and range here, so that a damaged header is an error, never a silent default.
void readVqOptions(const nlohmann::json& header, const std::filesystem::path& path, VqOptions& options) {
  options.levels = vqHeaderInt(header, "levels", path);
  options.epsilon = vqHeaderFloat(header, "epsilon", path);
  options.chroma_epsilon = vqHeaderFloat(header, "chroma_epsilon", path);
  options.energy_floor = vqHeaderFloat(header, "energy_floor", path);
  if (options.levels < 1 || options.levels > 3) throw FileError(path, "VQ header has an invalid level count");
  if (!(options.epsilon >= 0.0f) || !(options.epsilon < 1.0f)) throw FileError(path, "VQ header has an invalid epsilon");
  if (!(options.chroma_epsilon >= kVqMinChromaEpsilon) || !(options.chroma_epsilon <= 1.0f))
    throw FileError(path, "VQ header has an invalid chroma_epsilon");
  if (!(options.energy_floor >= 0.0f) || !(options.energy_floor <= kMaxReflectance))
    throw FileError(path, "VQ header has an invalid energy_floor");
  // Informative, but a header that holds it holds it right: the step its chroma_epsilon gives.
  if (header.contains("chroma_step") && vqHeaderFloat(header, "chroma_step", path) != vqChromaStep(options.chroma_epsilon))
    throw FileError(path, "VQ header's chroma_step " + header.at("chroma_step").dump() +
                              " is not the step of its chroma_epsilon (an edited header?)");
}

void checkVqChromaEntries(const nlohmann::json& header, const VqBtf::Impl& m, const std::filesystem::path& path) {
  std::vector<std::size_t> expected;
  for (int r = 0; r < int(m.ringCount()); ++r) expected.push_back(m.chromaCount(r));
  if (vqHeaderCounts(header, "chroma_entries", path) != expected)
    throw FileError(path, "VQ header's chroma_entries disagree with its chromaticity codebook sections (an edited header?)");
}

void readVqSharedSections(const std::vector<ContainerSection>& sections, const std::filesystem::path& path, VqBtf::Impl& m,
                          const std::string& prefix) {
  for (int r = 0; r < int(m.ringCount()); ++r) {
    const std::string ring = prefix + "level1/ring" + std::to_string(r), basis_name = prefix + "level1/basis" + std::to_string(r);
    const auto basis_section =
        std::find_if(sections.begin(), sections.end(), [&](const ContainerSection& s) { return s.name == basis_name; });
    if (basis_section == sections.end()) {
      m.l1[std::size_t(r)] = unpackPlanar<std::uint16_t>(vqSection(sections, ring, path), path);
      continue;
    }
    const std::size_t n = std::size_t(m.ringSize(r));
    if (n == 1 || basis_section->data.size() != (1 + n * n) * sizeof(float))
      throw FileError(path, "section " + basis_name + " is not a step and a " + std::to_string(n) + " x " +
                                std::to_string(n) + " basis");
    ByteReader in(*basis_section, path);
    VqRingBasis& basis = m.l1_basis[std::size_t(r)];
    basis.n = int(n);
    basis.step = in.get<float>();
    basis.v = in.getVector<float>(n * n);
    if (!(basis.step > 0.0f) || !std::isfinite(basis.step) ||
        !std::all_of(basis.v.begin(), basis.v.end(), [](float x) { return std::isfinite(x) && std::abs(x) <= 1.0f; }))
      throw FileError(path, "section " + basis_name + " holds a step or basis value out of range");
    const std::vector<std::uint32_t> zigzag = unpackPlanar<std::uint32_t>(vqSection(sections, ring, path), path);
    if (zigzag.size() % n != 0) throw FileError(path, "section " + ring + " does not hold whole entries");
    const std::size_t entries = zigzag.size() / n;
    std::vector<std::int32_t>& c = m.l1_coef[std::size_t(r)];
    c.resize(zigzag.size());
    for (std::size_t e = 0; e < entries; ++e)
      for (std::size_t j = 0; j < n; ++j) {
        const std::uint32_t z = zigzag[j * entries + e];
        c[e * n + j] = (z & 1u) ? -std::int32_t(z >> 1) - 1 : std::int32_t(z >> 1);
      }
    m.l1[std::size_t(r)].resize(zigzag.size());
    for (std::size_t e = 0; e < entries; ++e) vqBasisCodes(basis, &c[e * n], &m.l1[std::size_t(r)][e * n]);
  }
  for (int r = 0; r < int(m.ringCount()); ++r)
    m.chroma[std::size_t(r)] = unpackPlanar<std::int32_t>(vqSection(sections, prefix + "chroma/ring" + std::to_string(r), path), path);
  if (m.options.levels >= 2) {
    m.l2_index = unpackPlanar<std::uint32_t>(vqSection(sections, prefix + "level2/index", path), path);
    m.l2_scale = unpackPlanar<std::uint16_t>(vqSection(sections, prefix + "level2/scale", path), path);
    m.l2_chroma = unpackPlanar<std::uint32_t>(vqSection(sections, prefix + "level2/chroma", path), path);
  }
}

void readVqMaterialSections(const std::vector<ContainerSection>& sections, const std::string& prefix,
                            const std::filesystem::path& path, VqBtf::Impl& m) {
  // Files written before the section existed have none; their texel size is the header's alone.
  const auto texels =
      std::find_if(sections.begin(), sections.end(), [&](const ContainerSection& s) { return s.name == prefix + "texels"; });
  if (texels != sections.end()) {
    if (texels->data.size() != 2 * sizeof(std::uint32_t))
      throw FileError(path, "section " + prefix + "texels is not a width and a height");
    ByteReader in(*texels, path);
    const auto width = in.get<std::uint32_t>(), height = in.get<std::uint32_t>();
    if (std::int64_t(width) != m.width || std::int64_t(height) != m.height)
      throw FileError(path, "VQ header says " + std::to_string(m.width) + " x " + std::to_string(m.height) +
                                " texels, its sections " + std::to_string(width) + " x " + std::to_string(height) +
                                " (an edited header?)");
  }
  m.top_index = unpackPlanar<std::uint32_t>(vqSection(sections, prefix + "top/index", path), path);
  const bool derived = std::any_of(sections.begin(), sections.end(),
                                   [&](const ContainerSection& s) { return s.name == prefix + "level3/parent"; });
  if (m.options.levels == 3 && derived) {
    readDerivedLevel3Sections(sections, prefix, path, m);
  } else if (m.options.levels == 3) {
    m.l3_index = unpackPlanar<std::uint32_t>(vqSection(sections, prefix + "level3/index", path), path);
    m.l3_scale = unpackPlanar<std::uint16_t>(vqSection(sections, prefix + "level3/scale", path), path);
  }
  m.top_scale = unpackPlanar<std::uint16_t>(vqSection(sections, prefix + "top/scale", path), path);
  if (m.options.levels == 1) m.top_chroma = unpackPlanar<std::uint32_t>(vqSection(sections, prefix + "top/chroma", path), path);
}

void prepareReadVq(VqBtf::Impl& m, const std::filesystem::path& path) {
  try {
    m.prepare("VQ data");
  } catch (const FileError&) {
    throw;
  } catch (const Error& e) {
    throw FileError(path, e.what());
  }
}

std::vector<std::size_t> vqCodebookEntries(const VqBtf::Impl& m) {
  std::vector<std::size_t> entries;
  std::size_t l1 = 0;
  for (int r = 0; r < int(m.ringCount()); ++r)
    if (m.ringSize(r) > 1) l1 += m.l1Count(r);
  entries.push_back(l1);
  if (m.options.levels >= 2) entries.push_back(m.l2Count());
  if (m.options.levels >= 3) entries.push_back(m.l3Count());
  return entries;
}

// Bytes the .btfz file will hold: the sections as the container compresses them plus its table.
std::uint64_t vqSectionsBytes(const std::vector<ContainerSection>& sections) {
  const int level = vqZstdLevelFor(sections);
  std::vector<std::uint64_t> sizes(sections.size());
  tbb::parallel_for(std::size_t(0), sections.size(), [&](std::size_t i) {
    const auto& data = sections[i].data;
    std::vector<char> buffer(ZSTD_compressBound(data.size()));
    const std::size_t n = ZSTD_compress(buffer.data(), buffer.size(), data.data(), data.size(), level);
    sizes[i] = ZSTD_isError(n) ? data.size() : std::min<std::uint64_t>(n, data.size());
  });
  std::uint64_t total = containerTableBytes(sections);
  for (std::uint64_t n : sizes) total += n;
  return total;
}
std::uint64_t vqCompressedBytes(const VqBtf::Impl& impl) { return vqSectionsBytes(buildSections(impl)); }

void VqBtf::write(const std::filesystem::path& path) const {
  auto sections = buildSections(*impl_);
  const std::uint64_t bytes = writeContainer(path, sections, vqZstdLevelFor(sections));
  impl_->stats.compressed_bytes = bytes;
  const double raw = double(entryCount()) * 3.0;
  impl_->stats.ratio_u8 = raw / double(bytes);
  impl_->stats.ratio_f32 = 4.0 * impl_->stats.ratio_u8;
}

std::vector<std::shared_ptr<VqBtf::Impl>> readVqFile(const std::filesystem::path& path, std::string_view only) {
  const auto sections = readContainer(path);
  const nlohmann::json header = parseVqHeader(sections, path);
  std::string format;
  try {
    format = header.at("format").get<std::string>();
  } catch (const nlohmann::json::exception& e) {
    throw FileError(path, std::string("VQ header is invalid: ") + e.what());
  }
  if (format == kVqDatabaseFormat) return readVqDatabaseSections(sections, header, path, only);
  if (format != "libbtf-vq") throw FileError(path, "holds no VQ-compressed BTF");
  auto m = std::make_shared<VqBtf::Impl>();
  try {
    const int version = vqHeaderInt(header, "format_version", path);
    if (version < 1 || version > kVqNewestSectionsVersion)
      throw FileError(path, "VQ format version " + std::to_string(version) + " is not supported (this build reads 1.." +
                                std::to_string(kVqNewestSectionsVersion) + ")");
    m->width = vqHeaderInt(header, "width", path);
    m->height = vqHeaderInt(header, "height", path);
    m->name = header.at("name").get<std::string>();
    m->stats.codebook_entries = vqHeaderCounts(header, "codebook_entries", path);
    readVqDirectionsHeader(header, path, *m);
  } catch (const nlohmann::json::exception& e) {
    throw FileError(path, std::string("VQ header is invalid: ") + e.what());
  } catch (const FileError&) {
    throw;
  } catch (const Error& e) {
    throw FileError(path, std::string("VQ header's directions or views are invalid: ") + e.what());
  }
  readVqOptions(header, path, m->options);
  if (m->width < 1 || m->height < 1 || m->width > 65536 || m->height > 65536)
    throw FileError(path, "VQ header has an invalid texel size");
  readVqSharedSections(sections, path, *m, "");
  readVqMaterialSections(sections, "", path, *m);
  prepareReadVq(*m, path);
  // The header's codebook sizes must be those of the sections: a header whose view list was edited
  // (checksums recomputed) would otherwise split the level-3 entries at the wrong length and decode
  // wrong values without an error.
  if (vqCodebookEntries(*m) != m->stats.codebook_entries)
    throw FileError(path, "VQ header's codebook entry counts disagree with its codebook sections (an edited header?)");
  checkVqChromaEntries(header, *m, path);
  m->stats.compressed_bytes = std::filesystem::file_size(path);
  const double raw = vqRawValues(*m);
  m->stats.ratio_u8 = raw / double(m->stats.compressed_bytes);
  m->stats.ratio_f32 = 4.0 * m->stats.ratio_u8;
  return {m};
}

VqBtf VqBtf::read(const std::filesystem::path& path, std::string_view material) {
  const auto materials = readVqFile(path, material);
  // A single-material file answers to its bare name too.
  auto answersTo = [&](const std::string& name) {
    return name == material || (materials.size() == 1 && bareVqName(name) == material);
  };
  std::string names;
  for (const auto& m : materials) {
    if (material.empty() ? materials.size() == 1 : answersTo(m->name)) return VqBtf(m);
    names += (names.empty() ? "" : ", ") + m->name;
  }
  if (material.empty())
    throw FileError(path, "is a database of " + std::to_string(materials.size()) + " materials (" + names +
                              "): name the one to read");
  throw FileError(path, "holds no material named '" + std::string(material) + "' (it holds " + names + ")");
}

}  // namespace btf
