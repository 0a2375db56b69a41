// The .btfz sections of VQ-compressed BTFs (private to src/compress/), shared by the single-material
// files (vq_io.cpp) and the databases of materials with shared codebooks (vq_database.cpp):
//   shared:       "level1/ring<r>" (and "level1/basis<r>" for a basis-coded ring), "chroma/ring<r>",
//                 "level2/{index,scale,chroma}"
//                 (in a database, once per ring layout: layout g >= 1 with the prefix "group<g>/")
//   per material: PREFIX "level3/{index,scale}", PREFIX "top/{index,scale,chroma}" (those the level
//                 count uses; PREFIX is "" in a single-material file, "material<i>/" in a database)
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "btf/compress/vq_database.h"
#include "btf/io/container.h"
#include "vq_impl.h"

namespace btf {

inline constexpr const char* kVqDatabaseFormat = "libbtf-vq-database";

// A single-material file's name carries the compressor's " (vq)" (compressVq); as a material
// (in a database, or selected by name) it goes by the name without it.
inline std::string bareVqName(const std::string& name) {
  return name.ends_with(" (vq)") ? name.substr(0, name.size() - 5) : name;
}

void addVqSection(std::vector<ContainerSection>& sections, SectionType type, std::string name, std::vector<std::byte> data);
void addVqHeaderSection(const nlohmann::json& header, std::vector<ContainerSection>& sections);
// The direction set, ring layout and views held (vq_directions.cpp): header keys "directions" and
// "rings" when the set is not UBO2003, "views" when some are missing. The reader sets m.views and
// m.layout (throws FileError, or btf::Error for a set the direction-set checks refuse).
bool vqHasOwnDirections(const VqBtf::Impl& m);
void addVqDirectionsHeader(const VqBtf::Impl& m, nlohmann::json& header);
void readVqDirectionsHeader(const nlohmann::json& header, const std::filesystem::path& path, VqBtf::Impl& m);
// Values of the BTF as stored before compression: texels x (view, light) pairs held x 3.
double vqRawValues(const VqBtf::Impl& m);
// Header keys of the options and the chroma grid (both formats).
nlohmann::json vqOptionsHeader(const VqBtf::Impl& m);
// Format version of the sections (both formats): 5 for a database of several ring layouts (one group
// of shared codebooks each, vq_database.cpp), 4 when the BTF is on its own direction set
// (vq_directions.cpp; a reader of 3 would take it for UBO2003), 3 when level 3 has derived entries (vq_impl.h:
// "level3/parent" and exceptions alone in "level3/index"), 2 when a level-1 ring is basis-coded
// (vq_basis.h: "level1/basis<r>" and coefficients in "level1/ring<r>"), else 1, as files were
// before; an older reader would misread either. Readers take 1..kVqNewestSectionsVersion.
inline constexpr int kVqNewestSectionsVersion = 5;
bool hasDerivedLevel3(const VqBtf::Impl& m);
int vqSectionsVersion(const VqBtf::Impl& m);
// The shared codebooks' sections, names prefixed by `prefix` ("" in a single-material file and for
// a database's first ring layout, "group<g>/" for its layout g >= 1).
void addVqSharedSections(const VqBtf::Impl& m, std::vector<ContainerSection>& sections, const std::string& prefix);
void addVqMaterialSections(const VqBtf::Impl& m, const std::string& prefix, std::vector<ContainerSection>& sections);
// A database's sections, as VqDatabase::write stores them (vq_database.cpp).
std::vector<ContainerSection> vqDatabaseSections(const VqDatabase& database);
// The zstd level the writer uses for these sections, and the file size they will make.
int vqZstdLevelFor(const std::vector<ContainerSection>& sections);
std::uint64_t vqSectionsBytes(const std::vector<ContainerSection>& sections);

// Readers: each throws FileError naming `path` and what is wrong.
const ContainerSection& vqSection(const std::vector<ContainerSection>& sections, const std::string& name,
                                  const std::filesystem::path& path);
nlohmann::json parseVqHeader(const std::vector<ContainerSection>& sections, const std::filesystem::path& path);
// Header fields read strictly (type and range), each a FileError naming the key and the value.
int vqHeaderInt(const nlohmann::json& object, const char* key, const std::filesystem::path& path);
float vqHeaderFloat(const nlohmann::json& object, const char* key, const std::filesystem::path& path);
std::vector<std::size_t> vqHeaderCounts(const nlohmann::json& object, const char* key, const std::filesystem::path& path);
// The header's per-ring "chroma_entries" must be the sections' counts.
void checkVqChromaEntries(const nlohmann::json& header, const VqBtf::Impl& m, const std::filesystem::path& path);
void readVqOptions(const nlohmann::json& header, const std::filesystem::path& path, VqOptions& options);
void readVqSharedSections(const std::vector<ContainerSection>& sections, const std::filesystem::path& path, VqBtf::Impl& m,
                          const std::string& prefix);
void readVqMaterialSections(const std::vector<ContainerSection>& sections, const std::string& prefix,
                            const std::filesystem::path& path, VqBtf::Impl& m);
// Impl::prepare with its errors as FileErrors of `path`.
void prepareReadVq(VqBtf::Impl& m, const std::filesystem::path& path);
// Entries per level as VqStats::codebook_entries counts them (level 1 without ring 0's seed).
std::vector<std::size_t> vqCodebookEntries(const VqBtf::Impl& m);

// The materials of a .btfz file, single or database (in the database's order): all of them, or
// with `only` the one of that name (when there is one; the others are not decoded).
std::vector<std::shared_ptr<VqBtf::Impl>> readVqFile(const std::filesystem::path& path, std::string_view only = {});
std::vector<std::shared_ptr<VqBtf::Impl>> readVqDatabaseSections(const std::vector<ContainerSection>& sections,
                                                                 const nlohmann::json& header,
                                                                 const std::filesystem::path& path,
                                                                 std::string_view only = {});

}  // namespace btf
