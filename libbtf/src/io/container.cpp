#include "btf/io/container.h"

#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>
#include <limits>
#include <set>
#include <system_error>

#include "btf/io/atomic_file.h"

namespace btf {
namespace fs = std::filesystem;
namespace {

constexpr std::array<char, 8> kMagic{'B', 'T', 'F', 'Z', '\r', '\n', '\x1a', '\n'};
constexpr std::uint32_t kFlagZstd = 1u;
// Fixed bytes of a table entry before the name: type, flags, offset, stored, raw, crc, name length.
constexpr std::size_t kEntryFixedBytes = 4 + 4 + 8 + 8 + 8 + 4 + 2;
constexpr std::size_t kPreambleBytes = kMagic.size() + 4 + 4;

std::uint32_t crc32Of(const std::byte* data, std::size_t size) {
  uLong crc = crc32(0L, Z_NULL, 0);
  // zlib takes uInt lengths: feed large buffers in pieces.
  while (size > 0) {
    const auto piece = static_cast<uInt>(std::min<std::size_t>(size, std::numeric_limits<uInt>::max()));
    crc = crc32(crc, reinterpret_cast<const Bytef*>(data), piece);
    data += piece;
    size -= piece;
  }
  return static_cast<std::uint32_t>(crc);
}

bool isKnownType(std::uint32_t type) {
  return type >= std::uint32_t(SectionType::Header) && type <= std::uint32_t(SectionType::Other);
}

std::string quotedName(const std::string& name) { return "'" + name + "'"; }

// Cursor over the file's bytes that turns any overrun into a "truncated" FileError.
class FileCursor {
 public:
  FileCursor(const std::vector<std::byte>& bytes, const fs::path& path) : bytes_(bytes), path_(path) {}
  template <class T> T get(const char* what) {
    need(sizeof(T), what);
    T value;
    std::memcpy(&value, bytes_.data() + offset_, sizeof(T));
    offset_ += sizeof(T);
    return value;
  }
  std::string getString(std::size_t length, const char* what) {
    need(length, what);
    std::string text(reinterpret_cast<const char*>(bytes_.data() + offset_), length);
    offset_ += length;
    return text;
  }
  std::size_t offset() const { return offset_; }

 private:
  void need(std::size_t bytes, const char* what) const {
    if (bytes > bytes_.size() - offset_)
      throw FileError(path_, std::string("is truncated: it ends (at byte ") + std::to_string(bytes_.size()) +
                                 ") inside the " + what);
  }
  const std::vector<std::byte>& bytes_;
  const fs::path& path_;
  std::size_t offset_ = 0;
};

std::vector<std::byte> readWholeFile(const fs::path& path) {
  requireReadableFile(path);
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw FileError(path, "cannot be opened for reading");
  const std::streamoff size = in.tellg();
  if (size < 0) throw FileError(path, "cannot determine its size");
  std::vector<std::byte> bytes(static_cast<std::size_t>(size));
  in.seekg(0);
  if (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), size))
    throw FileError(path, "read failed after " + std::to_string(in.gcount()) + " of " + std::to_string(size) + " bytes");
  return bytes;
}

struct TableEntry {
  std::uint32_t type = 0, flags = 0;
  std::uint64_t offset = 0, stored = 0, raw = 0;
  std::uint32_t crc = 0;
  std::string name;
};

std::vector<std::byte> decompressSection(const TableEntry& e, const std::byte* stored, const fs::path& path) {
  const std::string where = "section " + quotedName(e.name);
  const unsigned long long content = ZSTD_getFrameContentSize(stored, e.stored);
  if (content == ZSTD_CONTENTSIZE_ERROR)
    throw FileError(path, where + " is not valid zstd data");
  // Our writer always records the content size; without it the raw size could not be checked
  // before allocating it.
  if (content == ZSTD_CONTENTSIZE_UNKNOWN)
    throw FileError(path, where + ": zstd frame does not record its size (not written by libbtf)");
  if (content != e.raw)
    throw FileError(path, where + ": zstd data decompresses to " + std::to_string(content) + " bytes, the table says " +
                              std::to_string(e.raw));
  std::vector<std::byte> raw(static_cast<std::size_t>(e.raw));
  const std::size_t got = ZSTD_decompress(raw.data(), raw.size(), stored, e.stored);
  if (ZSTD_isError(got))
    throw FileError(path, where + ": zstd data does not decompress to its raw size of " + std::to_string(e.raw) +
                              " bytes (" + ZSTD_getErrorName(got) + ")");
  if (got != e.raw)
    throw FileError(path, where + ": zstd data decompresses to " + std::to_string(got) + " bytes, the table says " +
                              std::to_string(e.raw));
  return raw;
}

}  // namespace

std::uint64_t containerTableBytes(std::span<const ContainerSection> sections) {
  std::uint64_t bytes = kPreambleBytes + 4;  // + the table CRC
  for (const auto& s : sections) bytes += kEntryFixedBytes + s.name.size();
  return bytes;
}

const char* sectionTypeName(SectionType type) {
  switch (type) {
    case SectionType::Header: return "header";
    case SectionType::Codebook: return "codebook";
    case SectionType::IndexStream: return "index-stream";
    case SectionType::Scales: return "scales";
    case SectionType::Other: return "other";
  }
  return "unknown";
}

std::uint64_t writeContainer(const fs::path& path, std::span<ContainerSection> sections, int zstd_level) {
  if (sections.size() > std::numeric_limits<std::uint32_t>::max())
    throw FileError(path, "too many sections (" + std::to_string(sections.size()) + ")");
  if (zstd_level < 1 || zstd_level > ZSTD_maxCLevel())
    throw FileError(path, "zstd level " + std::to_string(zstd_level) + " is outside 1.." +
                              std::to_string(ZSTD_maxCLevel()));
  std::set<std::string> names;
  for (const auto& s : sections) {
    if (s.name.empty()) throw FileError(path, "a section has an empty name");
    if (s.name.size() > std::numeric_limits<std::uint16_t>::max())
      throw FileError(path, "section name is longer than 65535 bytes: " + s.name.substr(0, 40) + "...");
    if (!isKnownType(std::uint32_t(s.type)))
      throw FileError(path, "section " + quotedName(s.name) + " has an unknown type " + std::to_string(std::uint32_t(s.type)));
    if (!names.insert(s.name).second) throw FileError(path, "two sections are named " + quotedName(s.name));
  }

  // Stored payloads: zstd frames that record their content size (checked against the table on reading).
  std::vector<std::vector<std::byte>> compressed(sections.size());
  for (std::size_t i = 0; i < sections.size(); ++i) {
    if (!sections[i].compress) continue;
    const auto& raw = sections[i].data;
    std::vector<std::byte>& out = compressed[i];
    out.resize(ZSTD_compressBound(raw.size()));
    ZSTD_CCtx* ctx = ZSTD_createCCtx();
    if (ctx == nullptr) throw FileError(path, "cannot create a zstd context (out of memory)");
    ZSTD_CCtx_setParameter(ctx, ZSTD_c_compressionLevel, zstd_level);
    // No zstd content checksum: the section CRC already covers the stored bytes, and 4 bytes per
    // section matter for BRDF-sized files (a few KB).
    ZSTD_CCtx_setParameter(ctx, ZSTD_c_checksumFlag, 0);
    ZSTD_CCtx_setParameter(ctx, ZSTD_c_contentSizeFlag, 1);
    const std::size_t n = ZSTD_compress2(ctx, out.data(), out.size(), raw.data(), raw.size());
    ZSTD_freeCCtx(ctx);
    if (ZSTD_isError(n))
      throw FileError(path, "section " + quotedName(sections[i].name) + ": zstd compression failed: " + ZSTD_getErrorName(n));
    out.resize(n);
    // Incompressible data (already packed or tiny) is stored raw: never larger than its raw size.
    if (n >= raw.size()) {
      sections[i].compress = false;
      out = {};
    }
  }
  auto storedOf = [&](std::size_t i) -> const std::vector<std::byte>& {
    return sections[i].compress ? compressed[i] : sections[i].data;
  };

  const std::size_t payload_start = containerTableBytes(sections);

  ByteWriter head;
  head.putAll(kMagic);
  head.put<std::uint32_t>(kContainerVersion);
  head.put<std::uint32_t>(static_cast<std::uint32_t>(sections.size()));
  std::uint64_t offset = payload_start;
  for (std::size_t i = 0; i < sections.size(); ++i) {
    const auto& s = sections[i];
    const auto& stored = storedOf(i);
    head.put<std::uint32_t>(std::uint32_t(s.type));
    head.put<std::uint32_t>(s.compress ? kFlagZstd : 0u);
    head.put<std::uint64_t>(offset);
    head.put<std::uint64_t>(stored.size());
    head.put<std::uint64_t>(s.data.size());
    head.put<std::uint32_t>(crc32Of(stored.data(), stored.size()));
    head.put<std::uint16_t>(static_cast<std::uint16_t>(s.name.size()));
    head.putAll(std::span<const char>(s.name.data(), s.name.size()));
    offset += stored.size();
  }
  head.put<std::uint32_t>(crc32Of(head.bytes().data(), head.size()));

  writeFileAtomically(path, [&](std::ofstream& out) {
    out.write(reinterpret_cast<const char*>(head.bytes().data()), std::streamsize(head.size()));
    for (std::size_t i = 0; i < sections.size(); ++i) {
      const auto& stored = storedOf(i);
      out.write(reinterpret_cast<const char*>(stored.data()), std::streamsize(stored.size()));
    }
  });
  for (std::size_t i = 0; i < sections.size(); ++i) sections[i].stored_bytes = storedOf(i).size();
  return offset;
}

std::vector<ContainerSection> readContainer(const fs::path& path) {
  const std::vector<std::byte> file = readWholeFile(path);
  if (file.empty()) throw FileError(path, "is empty, expected a libbtf container (.btfz, .octree)");
  const std::uint64_t file_size = file.size();
  FileCursor cursor(file, path);

  // Magic: a shorter file whose bytes match the magic's start is a truncated container.
  const std::size_t magic_bytes = std::min(file.size(), kMagic.size());
  if (std::memcmp(file.data(), kMagic.data(), magic_bytes) != 0)
    throw FileError(path, "is not a libbtf container (.btfz, .octree): wrong magic bytes");
  cursor.getString(kMagic.size(), "magic bytes");
  const auto version = cursor.get<std::uint32_t>("version");
  if (version == 0) throw FileError(path, "has container version 0, which does not exist (corrupt file)");
  if (version > kContainerVersion)
    throw FileError(path, "has container version " + std::to_string(version) + ", newer than this reader (version " +
                              std::to_string(kContainerVersion) + "); update libbtf to read it");
  const auto count = cursor.get<std::uint32_t>("section count");
  if (std::uint64_t(count) * kEntryFixedBytes > file_size - cursor.offset())
    throw FileError(path, "is truncated or corrupt: " + std::to_string(count) + " sections cannot fit in " +
                              std::to_string(file_size) + " bytes");

  std::vector<TableEntry> table(count);
  for (auto& e : table) {
    e.type = cursor.get<std::uint32_t>("section table");
    e.flags = cursor.get<std::uint32_t>("section table");
    e.offset = cursor.get<std::uint64_t>("section table");
    e.stored = cursor.get<std::uint64_t>("section table");
    e.raw = cursor.get<std::uint64_t>("section table");
    e.crc = cursor.get<std::uint32_t>("section table");
    const auto name_length = cursor.get<std::uint16_t>("section table");
    e.name = cursor.getString(name_length, "section table");
  }
  const std::size_t table_end = cursor.offset();
  const auto table_crc = cursor.get<std::uint32_t>("section table checksum");
  if (crc32Of(file.data(), table_end) != table_crc)
    throw FileError(path, "section table checksum mismatch: the file is corrupt");

  // The table is intact: check it describes a consistent file before touching any payload.
  std::set<std::string> names;
  std::uint64_t expected_offset = cursor.offset();
  for (const auto& e : table) {
    const std::string where = "section " + quotedName(e.name);
    if (e.name.empty()) throw FileError(path, "a section has an empty name");
    if (!names.insert(e.name).second) throw FileError(path, "two sections are named " + quotedName(e.name));
    if (!isKnownType(e.type)) throw FileError(path, where + " has an unknown type " + std::to_string(e.type));
    if ((e.flags & ~kFlagZstd) != 0) throw FileError(path, where + " has unknown flags " + std::to_string(e.flags));
    if (e.offset != expected_offset)
      throw FileError(path, where + " starts at byte " + std::to_string(e.offset) + ", expected " +
                                std::to_string(expected_offset));
    if (e.stored > file_size - std::min(file_size, e.offset))
      throw FileError(path, where + " (" + std::to_string(e.stored) + " bytes at " + std::to_string(e.offset) +
                                ") extends beyond the end of the file (" + std::to_string(file_size) +
                                " bytes): truncated");
    if (!(e.flags & kFlagZstd) && e.stored != e.raw)
      throw FileError(path, where + " is stored uncompressed but its sizes differ (" + std::to_string(e.stored) +
                                " vs " + std::to_string(e.raw) + ")");
    expected_offset = e.offset + e.stored;
  }
  if (expected_offset != file_size)
    throw FileError(path, "has " + std::to_string(file_size - expected_offset) + " unexpected bytes after the last section");

  std::vector<ContainerSection> sections(count);
  for (std::size_t i = 0; i < table.size(); ++i) {
    const auto& e = table[i];
    const std::byte* stored = file.data() + e.offset;
    if (crc32Of(stored, e.stored) != e.crc)
      throw FileError(path, "section " + quotedName(e.name) + " checksum mismatch: the file is corrupt");
    auto& s = sections[i];
    s.type = SectionType(e.type);
    s.name = e.name;
    s.compress = (e.flags & kFlagZstd) != 0;
    s.stored_bytes = e.stored;
    if (s.compress)
      s.data = decompressSection(e, stored, path);
    else
      s.data.assign(stored, stored + e.stored);
  }
  return sections;
}

std::string containerFormatOf(std::span<const unsigned char> head) {
  if (head.size() < kMagic.size() || std::memcmp(head.data(), kMagic.data(), kMagic.size()) != 0) return {};
  // The header JSON is written compact by nlohmann::json: "format":"NAME".
  const std::string_view text(reinterpret_cast<const char*>(head.data()), head.size());
  constexpr std::string_view key = "\"format\":\"";
  const std::size_t at = text.find(key);
  if (at == std::string_view::npos) return {};
  const std::size_t end = text.find('"', at + key.size());
  if (end == std::string_view::npos) return {};
  return std::string(text.substr(at + key.size(), end - at - key.size()));
}

const ContainerSection& requireSection(std::span<const ContainerSection> sections, std::string_view name,
                                       const fs::path& path) {
  for (const auto& s : sections)
    if (s.name == name) return s;
  throw FileError(path, "has no section '" + std::string(name) + "'");
}

void ByteWriter::append(const void* data, std::size_t size) {
  if (size == 0) return;
  // resize and copy rather than insert: GCC 12 at -O3 misreads insert's growth of an empty vector
  // as a write past its end (-Wstringop-overflow).
  const std::size_t old = bytes_.size();
  bytes_.resize(old + size);
  std::memcpy(bytes_.data() + old, data, size);
}

void ByteReader::requireEnd() const {
  if (!atEnd())
    throw FileError(path_, "section '" + section_->name + "' has " + std::to_string(remaining()) +
                               " unexpected bytes at its end");
}

void ByteReader::fail(std::uint64_t count, std::size_t size) const {
  throw FileError(path_, "section '" + section_->name + "' is truncated: needs " + std::to_string(count) + " x " +
                             std::to_string(size) + " bytes at offset " + std::to_string(offset_) + ", has " +
                             std::to_string(remaining()));
}

}  // namespace btf
