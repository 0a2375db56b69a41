// The .btfz container: a versioned file of typed, named, checksummed sections (docs/formats.md).
//
// Layout, all integers little-endian:
//   magic "BTFZ\r\n\x1a\n"  (8 bytes: catches text-mode conversion and 7-bit damage, as PNG's does)
//   u32 version (kContainerVersion), u32 section count
//   the table, one entry per section:
//     u32 type (SectionType), u32 flags (bit 0: zstd; other bits must be 0),
//     u64 offset, u64 stored size (bytes on disk), u64 raw size (bytes after decompression),
//     u32 CRC-32 (zlib) of the stored bytes, u16 name length, name (UTF-8, unique, not empty)
//   u32 CRC-32 of everything above (magic, version, count and table)
//   the payloads, back to back in table order, ending exactly at the end of the file.
//
// Why these choices: the version comes right after the magic so that a future layout is reported
// as "newer version" and not as a checksum failure. The section CRC covers the stored bytes so a
// damaged payload is caught before it reaches the zstd decoder; zstd sections must record and
// decompress to exactly their raw size. (No zstd content checksum on top: 4 bytes per section
// matter for BRDF-sized files of a few KB.)
// CRC-32 (not a cryptographic hash) is enough: it detects every burst error up to 32 bits and
// random damage with probability 1 - 2^-32, and zlib, which we link anyway, computes it at GB/s.
//
// Readers reject, each with a FileError naming the file (and the section when there is one): an
// empty file, a wrong magic, a version of 0 or above kContainerVersion, a file truncated anywhere,
// a table or section whose checksum fails, offsets or sizes that do not fit the file, unknown
// flags or types, duplicate or empty names, zstd data that does not decompress to its raw size,
// and trailing bytes after the last section. Writers go through writeFileAtomically (no
// half-written output).
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <ranges>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "btf/core/error.h"

namespace btf {

// The payload helpers copy values with memcpy, which is little-endian only on a little-endian host.
static_assert(std::endian::native == std::endian::little,
              "the .btfz container is little-endian; a big-endian host needs byte swapping in ByteWriter/ByteReader");

inline constexpr std::uint32_t kContainerVersion = 1;

enum class SectionType : std::uint32_t {
  Header = 1,       // UTF-8 JSON: what the file holds and how to read the other sections
  Codebook = 2,     // entries of one codebook
  IndexStream = 3,  // per-texel or per-vector indices
  Scales = 4,       // quantized scales
  Other = 5,
};
// "header", "codebook", ... for messages and `btf info`.
const char* sectionTypeName(SectionType type);

struct ContainerSection {
  SectionType type = SectionType::Other;
  std::string name;               // unique within a file, not empty, at most 65535 bytes, e.g. "level1/ring3"
  std::vector<std::byte> data;    // raw (uncompressed) bytes
  bool compress = false;          // store zstd-compressed (writer); was stored so (reader)
  std::uint64_t stored_bytes = 0; // bytes on disk (filled by the reader and by writeContainer)
};

// Writes the sections (zstd level `zstd_level`, 1..22, for those with compress set) atomically.
// A section whose zstd frame would not be smaller than its raw bytes is stored raw and its
// `compress` is cleared. Fills each section's stored_bytes.
// Returns the file size in bytes: containerTableBytes(sections) + the sum of stored_bytes.
// Throws FileError for duplicate or invalid names and unwritable paths. The output depends only on
// the sections and the level.
std::uint64_t writeContainer(const std::filesystem::path& path, std::span<ContainerSection> sections,
                             int zstd_level = 19);
// Bytes before the first payload: magic, version, count, the table (38 bytes + name per section)
// and its CRC.
std::uint64_t containerTableBytes(std::span<const ContainerSection> sections);
// Reads and verifies every section. Throws FileError as described above.
std::vector<ContainerSection> readContainer(const std::filesystem::path& path);

// The "format" of a container's JSON header ("libbtf-vq", "libbtf-octree", ...) read from the
// first bytes of a file, for recognising a file by its content: empty when the bytes do not start
// with the container's magic or hold no header section's "format" (the header is the first
// section and stored raw, so a few KiB of a file hold it).
std::string containerFormatOf(std::span<const unsigned char> head);

// The section called `name`; throws FileError(path, "has no section '<name>'") if there is none.
const ContainerSection& requireSection(std::span<const ContainerSection> sections, std::string_view name,
                                       const std::filesystem::path& path);

template <class T>
concept ContainerValue = std::is_trivially_copyable_v<T> && !std::is_pointer_v<T>;

// Builds a section payload from plain values (their bytes as in memory, i.e. little-endian).
class ByteWriter {
 public:
  template <ContainerValue T> void put(const T& value) { append(&value, sizeof(T)); }
  // Any contiguous range of values (std::vector, std::array, std::span, ...), without its length.
  template <std::ranges::contiguous_range R>
    requires ContainerValue<std::ranges::range_value_t<R>>
  void putAll(const R& values) {
    append(std::ranges::data(values), std::ranges::size(values) * sizeof(std::ranges::range_value_t<R>));
  }
  // u64 length, then the characters.
  void putString(std::string_view text) {
    put<std::uint64_t>(text.size());
    putAll(std::span<const char>(text.data(), text.size()));
  }
  std::vector<std::byte>& bytes() { return bytes_; }
  std::size_t size() const { return bytes_.size(); }

 private:
  // Out of line: inlined into callers with constant sizes, vector growth draws false
  // -Wstringop-overflow / -Warray-bounds warnings from GCC 12.
  void append(const void* data, std::size_t size);
  std::vector<std::byte> bytes_;
};

// Reads values back from a section; throws FileError(path, "section '<name>' is truncated ...")
// on any overrun, so a reader never reads past the payload.
class ByteReader {
 public:
  ByteReader(const ContainerSection& section, std::filesystem::path path)
      : section_(&section), path_(std::move(path)) {}
  ByteReader(ContainerSection&&, std::filesystem::path) = delete;  // would dangle

  template <ContainerValue T> T get() {
    need(sizeof(T));
    T value;
    std::memcpy(&value, section_->data.data() + offset_, sizeof(T));
    offset_ += sizeof(T);
    return value;
  }
  // Fills a contiguous range (its size says how many values).
  template <std::ranges::contiguous_range R>
    requires ContainerValue<std::ranges::range_value_t<R>>
  void getAll(R&& out) {
    const std::size_t bytes = std::ranges::size(out) * sizeof(std::ranges::range_value_t<R>);
    need(bytes);
    if (bytes > 0) std::memcpy(std::ranges::data(out), section_->data.data() + offset_, bytes);
    offset_ += bytes;
  }
  // `count` values; checks the size before allocating, so a corrupt count cannot exhaust memory.
  template <ContainerValue T> std::vector<T> getVector(std::uint64_t count) {
    if (count > remaining() / sizeof(T)) fail(count, sizeof(T));
    std::vector<T> values(static_cast<std::size_t>(count));
    getAll(values);
    return values;
  }
  std::string getString() {
    const auto length = get<std::uint64_t>();
    const auto chars = getVector<char>(length);
    return std::string(chars.begin(), chars.end());
  }
  std::size_t remaining() const { return section_->data.size() - offset_; }
  bool atEnd() const { return offset_ == section_->data.size(); }
  // Throws FileError unless every byte was read: trailing bytes mean a reader/writer mismatch.
  void requireEnd() const;

 private:
  void need(std::size_t bytes) const {
    if (bytes > remaining()) fail(bytes, 1);
  }
  [[noreturn]] void fail(std::uint64_t count, std::size_t size) const;
  const ContainerSection* section_;
  std::filesystem::path path_;
  std::size_t offset_ = 0;
};

}  // namespace btf
