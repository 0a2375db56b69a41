// The .btfz container: a versioned file of typed, named, checksummed sections (ARCHITECTURE.md).
//
//   magic "BTFZ\r\n\x1a\n" (8 bytes: catches text-mode and truncation damage, as PNG's does)
//   u32 version (kContainerVersion), u32 section count
//   per section, a table entry: u32 type, u32 flags (bit 0: zstd), u64 offset, u64 stored size,
//     u64 raw size, u64 checksum of the raw bytes (XXH64 via zstd's public ZSTD_getFrameContentSize
//     is not a checksum, so the checksum is CRC-32 from zlib widened to 64 bits), u16 name length + name
//   u64 checksum of everything above (the table), then the section payloads.
// All integers little-endian. Readers reject: a wrong magic, a version above kContainerVersion,
// a truncated file, a table or section whose checksum fails, sizes that do not fit the file,
// zstd data that does not decompress to its raw size; each with a FileError naming the file and
// the section. Writers go through writeFileAtomically (no half-written output).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace btf {

inline constexpr std::uint32_t kContainerVersion = 1;

enum class SectionType : std::uint32_t {
  Header = 1,       // UTF-8 JSON: what the file holds and how to read the other sections
  Codebook = 2,     // entries of one codebook
  IndexStream = 3,  // per-texel or per-vector indices
  Scales = 4,       // quantized scales
  Other = 5,
};

struct ContainerSection {
  SectionType type = SectionType::Other;
  std::string name;               // unique within a file, e.g. "level1/ring3"
  std::vector<std::byte> data;    // raw (uncompressed) bytes
  bool compress = false;          // store zstd-compressed (writer); was stored so (reader)
  std::uint64_t stored_bytes = 0; // bytes on disk (filled by the reader and by writeContainer)
};

// Writes the sections (zstd level `zstd_level` for those with compress set). Throws FileError.
// Fills each section's stored_bytes. Returns the file size in bytes.
std::uint64_t writeContainer(const std::filesystem::path& path, std::span<ContainerSection> sections,
                             int zstd_level = 19);
// Reads and verifies every section. Throws FileError as described above.
std::vector<ContainerSection> readContainer(const std::filesystem::path& path);

// Little helpers for section payloads: append / read plain little-endian values.
class ByteWriter {
 public:
  template <class T> void put(const T& value);
  template <class T> void putAll(std::span<const T> values);
  std::vector<std::byte>& bytes() { return bytes_; }
 private:
  std::vector<std::byte> bytes_;
};
// Reads values from a section; throws FileError(path, "section <name> is truncated") on overrun.
class ByteReader {
 public:
  ByteReader(const ContainerSection& section, std::filesystem::path path);
  template <class T> T get();
  template <class T> void getAll(std::span<T> out);
  bool atEnd() const { return offset_ == section_->data.size(); }
 private:
  void need(std::size_t bytes) const;
  const ContainerSection* section_;
  std::filesystem::path path_;
  std::size_t offset_ = 0;
};

}  // namespace btf
