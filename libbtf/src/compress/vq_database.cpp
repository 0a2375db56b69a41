// VqDatabase: materials with shared codebooks (compress/vq_database.h), their .btfz layout and the
// lossless merge. compressVqDatabase is in vq_compress.cpp, beside the compressor it drives.
//
// Layout: the header (format "libbtf-vq-database") lists the materials in order (name, texels,
// direction set and rings, views when some are missing, level-3 entries, codebook group); the
// shared sections are those of a single-material file, once per ring layout (the first layout's
// unprefixed, layout g's with the prefix "group<g>/"); the per-material ones carry the prefix
// "material<i>/" (vq_sections.h).
#include "btf/compress/vq_database.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <map>
#include <set>
#include <unordered_map>

#include "btf/core/error.h"
#include "vq_impl.h"
#include "vq_sections.h"

namespace btf {

namespace {

std::string materialPrefix(std::size_t i) { return "material" + std::to_string(i) + "/"; }

bool sameShared(const VqBtf::Impl& a, const VqBtf::Impl& b) {
  return a.l1 == b.l1 && a.l1_basis == b.l1_basis && a.l1_coef == b.l1_coef && a.chroma == b.chroma &&
         a.l2_index == b.l2_index && a.l2_scale == b.l2_scale && a.l2_chroma == b.l2_chroma;
}
bool sameOptions(const VqOptions& a, const VqOptions& b) {
  return a.levels == b.levels && a.epsilon == b.epsilon && a.chroma_epsilon == b.chroma_epsilon &&
         a.energy_floor == b.energy_floor;
}
std::string describeOptions(const VqOptions& o) {
  char text[160];
  std::snprintf(text, sizeof text, "levels %d, epsilon %g, chroma_epsilon %g, energy_floor %g", o.levels,
                double(o.epsilon), double(o.chroma_epsilon), double(o.energy_floor));
  return text;
}
std::vector<std::size_t> sharedEntriesOf(const VqBtf::Impl& m) {
  std::vector<std::size_t> entries = vqCodebookEntries(m);
  if (m.options.levels == 3) entries.pop_back();
  return entries;
}
void copyShared(const VqBtf::Impl& from, VqBtf::Impl& to) {
  to.l1 = from.l1;
  to.l1_basis = from.l1_basis;
  to.l1_coef = from.l1_coef;
  to.chroma = from.chroma;
  to.l2_index = from.l2_index;
  to.l2_scale = from.l2_scale;
  to.l2_chroma = from.l2_chroma;
}

std::string groupPrefix(std::size_t g) { return g == 0 ? std::string() : "group" + std::to_string(g) + "/"; }

// The ring-layout groups of a database's materials (vq_database.h): per material its group, groups
// numbered in order of first appearance; `first[g]` is group g's first material.
struct LayoutGroups {
  std::vector<std::size_t> of, first;
};
template <class Materials, class LayoutOf>
LayoutGroups layoutGroups(const Materials& materials, LayoutOf layoutOf) {
  LayoutGroups groups;
  for (std::size_t i = 0; i < materials.size(); ++i) {
    std::size_t g = 0;
    while (g < groups.first.size() && layoutOf(materials[groups.first[g]]) != layoutOf(materials[i])) ++g;
    if (g == groups.first.size()) groups.first.push_back(i);
    groups.of.push_back(g);
  }
  return groups;
}
LayoutGroups layoutGroupsOf(const std::vector<VqBtf>& materials) {
  return layoutGroups(materials, [](const VqBtf& m) -> const BtfRingLayout& { return m.impl().layout; });
}

std::vector<ContainerSection> databaseSections(const std::vector<VqBtf>& materials) {
  const VqBtf::Impl& first = materials.front().impl();
  const LayoutGroups groups = layoutGroupsOf(materials);
  nlohmann::json header = vqOptionsHeader(first);
  header["format"] = kVqDatabaseFormat;
  int version = groups.first.size() > 1 ? 5 : 1;
  for (const VqBtf& material : materials) version = std::max(version, vqSectionsVersion(material.impl()));
  header["format_version"] = version;
  header["codebook_entries"] = sharedEntriesOf(first);
  if (groups.first.size() > 1) {
    nlohmann::json more = nlohmann::json::array();
    for (std::size_t g = 1; g < groups.first.size(); ++g) more.push_back(sharedEntriesOf(materials[groups.first[g]].impl()));
    header["group_codebook_entries"] = std::move(more);
  }
  nlohmann::json list = nlohmann::json::array();
  for (std::size_t i = 0; i < materials.size(); ++i) {
    const VqBtf::Impl& m = materials[i].impl();
    nlohmann::json entry{{"name", m.name}, {"width", m.width}, {"height", m.height}};
    addVqDirectionsHeader(m, entry);
    if (groups.of[i] > 0) entry["group"] = groups.of[i];
    if (m.options.levels == 3) entry["level3_entries"] = m.l3Count();
    list.push_back(std::move(entry));
  }
  header["materials"] = std::move(list);
  std::vector<ContainerSection> sections;
  addVqHeaderSection(header, sections);
  for (std::size_t g = 0; g < groups.first.size(); ++g)
    addVqSharedSections(materials[groups.first[g]].impl(), sections, groupPrefix(g));
  for (std::size_t i = 0; i < materials.size(); ++i) addVqMaterialSections(materials[i].impl(), materialPrefix(i), sections);
  return sections;
}

// Stats a material of a database reports: its codebook sizes, and the database's bytes and ratios.
void setDatabaseStats(std::vector<std::shared_ptr<VqBtf::Impl>>& impls, double raw, std::uint64_t bytes) {
  for (auto& m : impls) {
    m->stats.codebook_entries = vqCodebookEntries(*m);
    m->stats.compressed_bytes = bytes;
    m->stats.ratio_u8 = bytes ? raw / double(bytes) : 0.0;
    m->stats.ratio_f32 = 4.0 * m->stats.ratio_u8;
  }
}

// Interns codebook entries (fixed-length runs of values) by their bytes: the index of the first
// equal entry, or a new one appended to `book`.
template <class T>
class EntryInterner {
 public:
  EntryInterner(std::vector<T>& book, std::size_t length) : book_(book), length_(length) {}
  std::uint32_t intern(const T* values) {
    std::string key(reinterpret_cast<const char*>(values), length_ * sizeof(T));
    const auto [it, added] = index_.try_emplace(std::move(key), std::uint32_t(book_.size() / length_));
    if (added) book_.insert(book_.end(), values, values + length_);
    return it->second;
  }

 private:
  std::vector<T>& book_;
  std::size_t length_;
  std::unordered_map<std::string, std::uint32_t> index_;
};

}  // namespace

std::vector<ContainerSection> vqDatabaseSections(const VqDatabase& database) { return databaseSections(database.materials()); }

VqDatabase::VqDatabase(std::vector<VqBtf> materials) : materials_(std::move(materials)) {
  if (materials_.empty()) throw Error("a VQ database needs at least one material");
  std::set<std::string> seen;
  const VqBtf::Impl& first = materials_.front().impl();
  const LayoutGroups groups = layoutGroupsOf(materials_);
  for (std::size_t i = 0; i < materials_.size(); ++i) {
    const VqBtf::Impl& m = materials_[i].impl();
    // The codebooks are shared within a ring layout: with the group's first material.
    const VqBtf::Impl& group_first = materials_[groups.first[groups.of[i]]].impl();
    if (m.name.empty()) throw Error("a VQ database's materials need names");
    if (!seen.insert(m.name).second) throw Error("a VQ database holds two materials named '" + m.name + "'");
    if (!sameOptions(m.options, first.options))
      throw Error("material '" + m.name + "' was compressed with " + describeOptions(m.options) + ", material '" +
                  first.name + "' with " + describeOptions(first.options) + ": a database has one set of options");
    if (&m != &group_first && !sameShared(m, group_first))
      throw Error("material '" + m.name + "' does not share the codebooks of '" + group_first.name +
                  "' (materials compressed apart are joined by mergeVqDatabases)");
  }
}

std::vector<std::string> VqDatabase::names() const {
  std::vector<std::string> out;
  for (const VqBtf& m : materials_) out.push_back(m.impl().name);
  return out;
}

const VqBtf& VqDatabase::material(std::string_view name) const {
  std::string all;
  for (const VqBtf& m : materials_) {
    if (m.impl().name == name) return m;
    all += (all.empty() ? "" : ", ") + m.impl().name;
  }
  throw Error("no material named '" + std::string(name) + "' (the database holds " + all + ")");
}

std::vector<std::size_t> VqDatabase::sharedEntries() const {
  const LayoutGroups groups = layoutGroupsOf(materials_);
  std::vector<std::size_t> sum = sharedEntriesOf(materials_.front().impl());
  for (std::size_t g = 1; g < groups.first.size(); ++g) {
    const std::vector<std::size_t> more = sharedEntriesOf(materials_[groups.first[g]].impl());
    for (std::size_t l = 0; l < sum.size(); ++l) sum[l] += more[l];
  }
  return sum;
}

double VqDatabase::rawBytesU8() const {
  double raw = 0;
  for (const VqBtf& m : materials_) raw += double(m.entryCount()) * 3.0;
  return raw;
}

std::uint64_t VqDatabase::compressedBytes() const {
  if (bytes_ == 0) bytes_ = vqSectionsBytes(databaseSections(materials_));
  return bytes_;
}

void VqDatabase::write(const std::filesystem::path& path) {
  auto sections = databaseSections(materials_);
  bytes_ = writeContainer(path, sections, vqZstdLevelFor(sections));
}

VqDatabase VqDatabase::read(const std::filesystem::path& path) {
  const auto impls = readVqFile(path);
  std::vector<VqBtf> materials;
  for (const auto& impl : impls) {
    if (impls.size() == 1) impl->name = bareVqName(impl->name);  // a database's names are bare
    materials.emplace_back(impl);
  }
  VqDatabase database(std::move(materials));
  database.bytes_ = std::filesystem::file_size(path);
  return database;
}

std::vector<std::shared_ptr<VqBtf::Impl>> readVqDatabaseSections(const std::vector<ContainerSection>& sections,
                                                                 const nlohmann::json& header,
                                                                 const std::filesystem::path& path,
                                                                 std::string_view only) {
  nlohmann::json list;
  try {
    const int version = header.at("format_version").get<int>();
    if (version < 1 || version > kVqNewestSectionsVersion)
      throw FileError(path, "VQ database format version " + std::to_string(version) +
                                " is not supported (this build reads 1.." + std::to_string(kVqNewestSectionsVersion) + ")");
    list = header.at("materials");
  } catch (const nlohmann::json::exception& e) {
    throw FileError(path, std::string("VQ database header is invalid: ") + e.what());
  }
  // Each material has at least two sections of its own: a longer list is a damaged header, which
  // must not make the reader allocate for it.
  if (!list.is_array() || list.empty() || list.size() > sections.size())
    throw FileError(path, "VQ database header lists no materials, or more than its sections can hold");
  // One group of shared codebooks per ring layout (vq_database.h): group 0's entry counts in
  // "codebook_entries", the others' in "group_codebook_entries".
  std::vector<std::vector<std::size_t>> group_entries{vqHeaderCounts(header, "codebook_entries", path)};
  if (const auto more = header.find("group_codebook_entries"); more != header.end()) {
    if (!more->is_array() || more->size() + 1 > list.size())
      throw FileError(path, "VQ database header's group_codebook_entries is not a list of count lists, one per group");
    for (const auto& counts : *more) {
      const nlohmann::json holder{{"entries", counts}};
      group_entries.push_back(vqHeaderCounts(holder, "entries", path));
    }
  }
  std::vector<std::size_t> group_of(list.size(), 0);
  for (std::size_t i = 0; i < list.size(); ++i) {
    const nlohmann::json& entry = list.at(i);
    if (!entry.is_object() || !entry.contains("group")) continue;
    const nlohmann::json& g = entry.at("group");
    if (!g.is_number_unsigned() || g.get<std::size_t>() >= group_entries.size())
      throw FileError(path, "VQ database header's material " + std::to_string(i) + " has group " + g.dump() + ", not one of its " +
                                std::to_string(group_entries.size()) + " groups");
    group_of[i] = g.get<std::size_t>();
  }
  // Each group's codebooks, with the ring layout of its first material (every member's, checked below).
  std::vector<VqBtf::Impl> shared(group_entries.size());
  for (std::size_t g = 0; g < shared.size(); ++g) {
    const std::size_t first = std::size_t(std::find(group_of.begin(), group_of.end(), g) - group_of.begin());
    if (first == list.size()) throw FileError(path, "VQ database header's codebook group " + std::to_string(g) + " has no material");
    readVqOptions(header, path, shared[g].options);
    try {
      readVqDirectionsHeader(list.at(first), path, shared[g]);
    } catch (const nlohmann::json::exception& e) {
      throw FileError(path, "VQ database header's material " + std::to_string(first) + " is invalid: " + std::string(e.what()));
    } catch (const FileError&) {
      throw;
    } catch (const Error& e) {
      throw FileError(path, "VQ database header's material " + std::to_string(first) +
                                " has invalid directions or views: " + std::string(e.what()));
    }
    readVqSharedSections(sections, path, shared[g], groupPrefix(g));
  }
  bool chroma_checked = false;
  std::vector<std::shared_ptr<VqBtf::Impl>> impls, skipped;
  std::set<std::string> names;
  for (std::size_t i = 0; i < list.size(); ++i) {
    auto m = std::make_shared<VqBtf::Impl>();
    const VqBtf::Impl& books = shared[group_of[i]];
    m->options = books.options;
    std::size_t l3_entries = 0;
    try {
      const nlohmann::json& entry = list.at(i);
      if (!entry.is_object()) throw FileError(path, "VQ database header's material " + std::to_string(i) + " is not an object");
      m->name = entry.at("name").get<std::string>();
      m->width = vqHeaderInt(entry, "width", path);
      m->height = vqHeaderInt(entry, "height", path);
      readVqDirectionsHeader(entry, path, *m);
      if (m->layout != books.layout)
        throw FileError(path, "VQ database material " + std::to_string(i) + " has other light rings (" + m->layout.describe() +
                                  ") than its codebook group " + std::to_string(group_of[i]) + " (" + books.layout.describe() + ")");
      copyShared(books, *m);
      if (m->options.levels == 3) {
        const nlohmann::json& n = entry.at("level3_entries");
        if (!n.is_number_unsigned())
          throw FileError(path, "VQ database header's material " + std::to_string(i) + " has level3_entries " + n.dump() +
                                    ", not a count");
        l3_entries = n.get<std::size_t>();
      }
    } catch (const nlohmann::json::exception& e) {
      throw FileError(path, "VQ database header's material " + std::to_string(i) + " is invalid: " + e.what());
    } catch (const FileError&) {
      throw;
    } catch (const Error& e) {
      throw FileError(path, "VQ database header's material " + std::to_string(i) + " has invalid directions or views: " + e.what());
    }
    if (m->name.empty() || !names.insert(m->name).second)
      throw FileError(path, "VQ database material " + std::to_string(i) + " has an empty or repeated name '" + m->name + "'");
    if (m->width < 1 || m->height < 1 || m->width > 65536 || m->height > 65536)
      throw FileError(path, "VQ database material '" + m->name + "' has an invalid texel size");
    if (!only.empty() && m->name != only) {
      skipped.push_back(std::move(m));  // listed by name in the caller's message, never decoded
      continue;
    }
    readVqMaterialSections(sections, materialPrefix(i), path, *m);
    prepareReadVq(*m, path);
    std::vector<std::size_t> expected = group_entries[group_of[i]];
    if (m->options.levels == 3) expected.push_back(l3_entries);
    if (vqCodebookEntries(*m) != expected)
      throw FileError(path, "VQ database header's codebook entry counts disagree with the sections of material '" +
                                m->name + "' (an edited header?)");
    if (group_of[i] == 0 && !chroma_checked) {  // the header's chroma counts are group 0's
      checkVqChromaEntries(header, *m, path);
      chroma_checked = true;
    }
    impls.push_back(std::move(m));
  }
  double raw = 0;
  for (const auto* list_of : {&impls, &skipped})
    for (const auto& m : *list_of) raw += vqRawValues(*m);
  setDatabaseStats(impls, raw, std::filesystem::file_size(path));
  // Asked for one material that is not there: the names, for the caller to list.
  if (!only.empty() && impls.empty()) return skipped;
  return impls;
}

namespace {

// Merges materials of one ring layout: `subparts` are groups of materials that share codebooks (a
// part's materials of this layout), in order. Each merged material, by its source, in `merged`.
void mergeLayoutGroup(const std::vector<std::vector<const VqBtf*>>& subparts, const VqOptions& options,
                      std::map<const VqBtf*, std::shared_ptr<VqBtf::Impl>>& merged) {
  const BtfRingLayout& layout = subparts.front().front()->impl().layout;
  // The merged shared codebooks: every part's entries, each distinct entry once, in part order (so
  // the first part's entries keep their indices unless it repeats one).
  VqBtf::Impl books;
  books.setLayout(layout);
  const std::size_t R = books.ringCount();
  std::vector<EntryInterner<std::uint16_t>> l1;
  std::vector<EntryInterner<std::int32_t>> chroma;
  l1.reserve(R);
  chroma.reserve(R);
  for (int r = 0; r < int(R); ++r) {
    l1.emplace_back(books.l1[std::size_t(r)], std::size_t(books.ringSize(r)));
    chroma.emplace_back(books.chroma[std::size_t(r)], 2 * std::size_t(books.ringSize(r)));
  }
  // A ring stays basis-coded only where every part has the same basis (parts compressed alone learn
  // their own): then each merged entry keeps the coefficients it came with. Elsewhere the merged
  // ring stores its values one by one, which decodes to the same codes.
  for (int r = 0; r < int(R); ++r) {
    const VqRingBasis& basis = subparts.front().front()->impl().l1_basis[std::size_t(r)];
    bool common = !basis.empty();
    for (const auto& subpart : subparts) common = common && subpart.front()->impl().l1_basis[std::size_t(r)] == basis;
    if (common) books.l1_basis[std::size_t(r)] = basis;
  }
  std::vector<std::uint32_t> l2_key_book;  // (index, scale, chroma) per ring, as one entry
  EntryInterner<std::uint32_t> l2(l2_key_book, 3 * R);
  for (const auto& subpart : subparts) {
    const VqBtf::Impl& src = subpart.front()->impl();
    std::vector<std::vector<std::uint32_t>> l1_map(R), chroma_map(R);
    for (int r = 0; r < int(R); ++r) {
      const std::size_t n = std::size_t(books.ringSize(r));
      for (std::size_t e = 0; e < src.l1Count(r); ++e) {
        const std::size_t before = books.l1[std::size_t(r)].size();
        l1_map[std::size_t(r)].push_back(l1[std::size_t(r)].intern(&src.l1[std::size_t(r)][e * n]));
        if (!books.l1_basis[std::size_t(r)].empty() && books.l1[std::size_t(r)].size() > before) {
          const auto from = src.l1_coef[std::size_t(r)].begin() + std::ptrdiff_t(e * n);
          books.l1_coef[std::size_t(r)].insert(books.l1_coef[std::size_t(r)].end(), from, from + std::ptrdiff_t(n));
        }
      }
      for (std::size_t c = 0; c < src.chromaCount(r); ++c)
        chroma_map[std::size_t(r)].push_back(chroma[std::size_t(r)].intern(&src.chroma[std::size_t(r)][c * 2 * n]));
    }
    std::vector<std::uint32_t> l2_map;
    for (std::size_t e = 0; e < src.l2Count(); ++e) {
      std::vector<std::uint32_t> key(3 * R);
      for (std::size_t r = 0; r < R; ++r) {
        const std::size_t k = e * R + r;
        key[r] = l1_map[r][src.l2_index[k]];
        key[R + r] = src.l2_scale[k];
        key[2 * R + r] = chroma_map[r][src.l2_chroma[k]];
      }
      l2_map.push_back(l2.intern(key.data()));
    }
    for (const VqBtf* material : subpart) {
      auto m = std::make_shared<VqBtf::Impl>(material->impl());
      for (auto& e : m->l3_index) e = l2_map[e];
      if (options.levels == 1) {
        for (std::size_t i = 0; i < m->top_index.size(); ++i) {
          const std::size_t r = i % R;
          m->top_index[i] = l1_map[r][m->top_index[i]];
          m->top_chroma[i] = chroma_map[r][m->top_chroma[i]];
        }
      } else if (options.levels == 2) {
        for (auto& e : m->top_index) e = l2_map[e];
      }
      merged.emplace(material, std::move(m));
    }
  }
  for (std::size_t e = 0; e < l2_key_book.size() / (3 * R); ++e) {
    const std::uint32_t* key = &l2_key_book[e * 3 * R];
    for (std::size_t r = 0; r < R; ++r) {
      books.l2_index.push_back(key[r]);
      books.l2_scale.push_back(std::uint16_t(key[R + r]));
      books.l2_chroma.push_back(key[2 * R + r]);
    }
  }
  for (auto& [source, m] : merged)
    if (m->layout == layout) copyShared(books, *m);
}

}  // namespace

VqDatabase mergeVqDatabases(std::span<const VqDatabase> parts, std::span<const std::string> labels) {
  if (parts.empty()) throw Error("merging VQ databases needs at least one");
  auto label = [&](std::size_t p) { return p < labels.size() ? labels[p] : "database " + std::to_string(p + 1); };
  const VqOptions& options = parts.front().options();
  std::set<std::string> names;
  for (std::size_t p = 0; p < parts.size(); ++p) {
    if (!sameOptions(parts[p].options(), options))
      throw Error("cannot merge: " + label(p) + " was compressed with " + describeOptions(parts[p].options()) + "; " +
                  label(0) + " with " + describeOptions(options) + " (recompress with the same options)");
    for (const std::string& name : parts[p].names())
      if (!names.insert(name).second) throw Error("cannot merge: two materials are named '" + name + "'");
  }
  // The codebooks are per ring layout: each layout's materials are merged on their own, the parts'
  // materials of it in part order (vq_database.h).
  std::vector<const VqBtf*> all;
  for (const VqDatabase& part : parts)
    for (const VqBtf& material : part.materials()) all.push_back(&material);
  const LayoutGroups groups = layoutGroups(all, [](const VqBtf* m) -> const BtfRingLayout& { return m->impl().layout; });
  std::map<const VqBtf*, std::shared_ptr<VqBtf::Impl>> merged_of;
  for (std::size_t g = 0; g < groups.first.size(); ++g) {
    std::vector<std::vector<const VqBtf*>> subparts;
    std::size_t k = 0;
    for (const VqDatabase& part : parts) {
      std::vector<const VqBtf*> subpart;
      for (std::size_t j = 0; j < part.size(); ++j, ++k)
        if (groups.of[k] == g) subpart.push_back(all[k]);
      if (!subpart.empty()) subparts.push_back(std::move(subpart));
    }
    mergeLayoutGroup(subparts, options, merged_of);
  }
  std::vector<VqBtf> materials;
  for (const VqBtf* source : all) {
    const std::shared_ptr<VqBtf::Impl>& m = merged_of.at(source);
    m->prepare("mergeVqDatabases");
    m->stats.codebook_entries = vqCodebookEntries(*m);
    materials.emplace_back(m);
  }
  VqDatabase merged(std::move(materials));
  double seconds = 0;
  for (const VqDatabase& part : parts) seconds += part.seconds();
  merged.setSeconds(seconds);
  return merged;
}

}  // namespace btf
