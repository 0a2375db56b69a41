// The .btfz container: round trips, and a clear FileError for every kind of damaged input.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "btf/core/error.h"
#include "btf/io/container.h"
#include "support/test_support.h"

namespace btf {
namespace {
namespace fs = std::filesystem;

using Bytes = std::vector<std::byte>;

Bytes fileBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<char> chars{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  Bytes bytes(chars.size());
  if (!chars.empty()) std::memcpy(bytes.data(), chars.data(), chars.size());
  return bytes;
}

void writeBytes(const fs::path& path, const Bytes& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// The standard CRC-32 (reflected polynomial 0xEDB88320), written out independently of zlib so
// the tests can forge files whose checksums are right but whose contents are wrong.
std::uint32_t referenceCrc32(const std::byte* data, std::size_t size) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < size; ++i) {
    crc ^= std::uint32_t(data[i]);
    for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

template <class T> T readAt(const Bytes& b, std::size_t offset) {
  T v;
  std::memcpy(&v, b.data() + offset, sizeof(T));
  return v;
}
template <class T> void writeAt(Bytes& b, std::size_t offset, T v) { std::memcpy(b.data() + offset, &v, sizeof(T)); }

// Byte offsets of the table entries of a valid file (format in container.h).
struct Layout {
  std::vector<std::size_t> entries;  // start of each table entry
  std::size_t table_end = 0;         // where the table CRC is
};
Layout layoutOf(const Bytes& b) {
  Layout layout;
  const auto count = readAt<std::uint32_t>(b, 12);
  std::size_t at = 16;
  for (std::uint32_t i = 0; i < count; ++i) {
    layout.entries.push_back(at);
    at += 38 + readAt<std::uint16_t>(b, at + 36);
  }
  layout.table_end = at;
  return layout;
}
void fixTableCrc(Bytes& b) {
  const Layout layout = layoutOf(b);
  writeAt<std::uint32_t>(b, layout.table_end, referenceCrc32(b.data(), layout.table_end));
}

Bytes bytesOf(const std::string& text) {
  Bytes b(text.size());
  std::memcpy(b.data(), text.data(), text.size());
  return b;
}

// Three sections: JSON header, a compressible zstd section and a small raw one.
std::vector<ContainerSection> sampleSections() {
  std::vector<ContainerSection> s(3);
  s[0].type = SectionType::Header;
  s[0].name = "header";
  s[0].data = bytesOf(R"({"kind":"test","levels":2})");
  s[1].type = SectionType::IndexStream;
  s[1].name = "level1/indices";
  s[1].compress = true;
  ByteWriter w;
  for (std::uint32_t i = 0; i < 2000; ++i) w.put<std::uint32_t>(i % 37);
  s[1].data = w.bytes();
  s[2].type = SectionType::Scales;
  s[2].name = "scales";
  s[2].data = bytesOf("0123456789abcdef");
  return s;
}

// Expects readContainer(path) to throw FileError naming the file; returns the message.
std::string readError(const fs::path& path) {
  try {
    readContainer(path);
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not a FileError: " << e.what();
    return "";
  }
  ADD_FAILURE() << "no error for " << path;
  return "";
}

void expectContains(const std::string& message, const std::string& part) {
  EXPECT_NE(message.find(part), std::string::npos) << "'" << message << "' does not contain '" << part << "'";
}

void expectSameSections(const std::vector<ContainerSection>& a, const std::vector<ContainerSection>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].type, b[i].type);
    EXPECT_EQ(a[i].name, b[i].name);
    EXPECT_EQ(a[i].compress, b[i].compress);
    EXPECT_EQ(a[i].data, b[i].data) << a[i].name;
    EXPECT_EQ(a[i].stored_bytes, b[i].stored_bytes) << a[i].name;
  }
}

TEST(Container, RoundTripWithAndWithoutZstd) {
  test::TempDir dir;
  auto sections = sampleSections();
  const std::uint64_t size = writeContainer(dir / "a.btfz", sections);
  EXPECT_EQ(size, fs::file_size(dir / "a.btfz"));
  // The writer reports what it stored: zstd shrinks the repetitive section, the others are raw.
  EXPECT_LT(sections[1].stored_bytes, sections[1].data.size() / 4);
  EXPECT_EQ(sections[0].stored_bytes, sections[0].data.size());
  EXPECT_EQ(sections[2].stored_bytes, sections[2].data.size());
  const auto back = readContainer(dir / "a.btfz");
  expectSameSections(sections, back);
  std::uint64_t stored = 0;
  for (const auto& s : sections) stored += s.stored_bytes;
  EXPECT_EQ(size, containerTableBytes(sections) + stored);

  // The same content without compression reads back identically, only larger on disk.
  for (auto& s : sections) s.compress = false;
  const std::uint64_t raw_size = writeContainer(dir / "b.btfz", sections);
  EXPECT_GT(raw_size, size);
  expectSameSections(sections, readContainer(dir / "b.btfz"));
}

TEST(Container, EmptySectionsAndNoSections) {
  test::TempDir dir;
  std::vector<ContainerSection> sections(2);
  sections[0].name = "empty-raw";
  sections[1].name = "empty-asked-zstd";  // stored raw: a zstd frame would be larger
  sections[1].compress = true;
  writeContainer(dir / "e.btfz", sections);
  const auto back = readContainer(dir / "e.btfz");
  expectSameSections(sections, back);
  EXPECT_TRUE(back[0].data.empty());
  EXPECT_TRUE(back[1].data.empty());

  std::vector<ContainerSection> none;
  writeContainer(dir / "none.btfz", none);
  EXPECT_TRUE(readContainer(dir / "none.btfz").empty());
}

TEST(Container, IncompressibleSectionsAreStoredRaw) {
  test::TempDir dir;
  std::vector<ContainerSection> sections(1);
  sections[0].name = "noise";
  sections[0].compress = true;
  std::uint64_t state = 1;
  for (int i = 0; i < 256; ++i) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;  // LCG: incompressible bytes
    sections[0].data.push_back(std::byte(state >> 56));
  }
  writeContainer(dir / "n.btfz", sections);
  EXPECT_FALSE(sections[0].compress);
  EXPECT_EQ(sections[0].stored_bytes, 256u);
  expectSameSections(sections, readContainer(dir / "n.btfz"));
}

TEST(Container, OutputIsDeterministic) {
  test::TempDir dir;
  auto a = sampleSections(), b = sampleSections();
  writeContainer(dir / "a.btfz", a);
  writeContainer(dir / "b.btfz", b);
  EXPECT_EQ(fileBytes(dir / "a.btfz"), fileBytes(dir / "b.btfz"));
}

TEST(Container, RejectsEmptyFile) {
  test::TempDir dir;
  writeBytes(dir / "empty.btfz", {});
  expectContains(readError(dir / "empty.btfz"), "empty");
}

TEST(Container, RejectsMissingFile) {
  test::TempDir dir;
  readError(dir / "missing.btfz");
}

TEST(Container, RejectsWrongMagic) {
  test::TempDir dir;
  auto sections = sampleSections();
  writeContainer(dir / "a.btfz", sections);
  Bytes b = fileBytes(dir / "a.btfz");
  b[0] = std::byte{'P'};
  writeBytes(dir / "bad.btfz", b);
  expectContains(readError(dir / "bad.btfz"), "magic");
  // A text-mode transfer turning \r\n into \n damages the magic too.
  Bytes text = fileBytes(dir / "a.btfz");
  text.erase(text.begin() + 4);
  writeBytes(dir / "text.btfz", text);
  expectContains(readError(dir / "text.btfz"), "magic");
  writeBytes(dir / "json.btfz", bytesOf("{\"not\": \"a container\"}"));
  expectContains(readError(dir / "json.btfz"), "magic");
}

TEST(Container, RejectsFutureAndZeroVersion) {
  test::TempDir dir;
  auto sections = sampleSections();
  writeContainer(dir / "a.btfz", sections);
  Bytes b = fileBytes(dir / "a.btfz");
  ASSERT_EQ(readAt<std::uint32_t>(b, 8), kContainerVersion);
  writeAt<std::uint32_t>(b, 8, kContainerVersion + 1);
  fixTableCrc(b);  // a real future file has a valid checksum: the version alone must be the reason
  writeBytes(dir / "future.btfz", b);
  const std::string message = readError(dir / "future.btfz");
  expectContains(message, "version " + std::to_string(kContainerVersion + 1));
  expectContains(message, "newer");
  writeAt<std::uint32_t>(b, 8, 0);
  fixTableCrc(b);
  writeBytes(dir / "zero.btfz", b);
  expectContains(readError(dir / "zero.btfz"), "version 0");
}

TEST(Container, RejectsTruncationAtEveryLength) {
  test::TempDir dir;
  auto sections = sampleSections();
  writeContainer(dir / "a.btfz", sections);
  const Bytes b = fileBytes(dir / "a.btfz");
  ASSERT_GT(b.size(), 100u);
  const Layout layout = layoutOf(b);
  for (std::size_t length = 1; length < b.size(); ++length) {
    SCOPED_TRACE("truncated to " + std::to_string(length) + " of " + std::to_string(b.size()) + " bytes");
    writeBytes(dir / "cut.btfz", Bytes(b.begin(), b.begin() + std::ptrdiff_t(length)));
    const std::string message = readError(dir / "cut.btfz");
    // Once the table is complete the payload sizes no longer fit; before it, the table ends early.
    if (length < layout.table_end + 4)
      expectContains(message, "truncated");
    else
      expectContains(message, "beyond the end of the file");
  }
}

TEST(Container, RejectsAFlippedByteAnywhere) {
  test::TempDir dir;
  auto sections = sampleSections();
  writeContainer(dir / "a.btfz", sections);
  const Bytes b = fileBytes(dir / "a.btfz");
  const Layout layout = layoutOf(b);
  for (std::size_t at = 0; at < b.size(); ++at) {
    // The lowest bit on even offsets, the highest on odd ones: both ends of every field get hit.
    const std::byte mask = at % 2 == 0 ? std::byte{0x01} : std::byte{0x80};
    {
      SCOPED_TRACE("byte " + std::to_string(at) + " of " + std::to_string(b.size()) + " xor " +
                   std::to_string(int(mask)));
      Bytes damaged = b;
      damaged[at] ^= mask;
      writeBytes(dir / "flip.btfz", damaged);
      const std::string message = readError(dir / "flip.btfz");
      if (at < 8)
        expectContains(message, "magic");
      else if (at < 12)
        expectContains(message, "version");
      else if (at >= layout.table_end)
        expectContains(message, "checksum");  // table CRC or a payload
    }
  }
}

TEST(Container, RejectsSizesBeyondTheFileEvenWithAValidTableChecksum) {
  test::TempDir dir;
  auto sections = sampleSections();
  writeContainer(dir / "a.btfz", sections);
  Bytes b = fileBytes(dir / "a.btfz");
  const Layout layout = layoutOf(b);
  // The last section claims far more bytes than the file holds (a huge size must not overflow).
  for (const std::uint64_t stored : {std::uint64_t(1000), ~std::uint64_t(0) - 8}) {
    Bytes forged = b;
    writeAt<std::uint64_t>(forged, layout.entries.back() + 16, stored);
    writeAt<std::uint64_t>(forged, layout.entries.back() + 24, stored);
    fixTableCrc(forged);
    writeBytes(dir / "big.btfz", forged);
    expectContains(readError(dir / "big.btfz"), "beyond the end of the file");
  }
  // An offset that points past the file.
  Bytes forged = b;
  writeAt<std::uint64_t>(forged, layout.entries.back() + 8, std::uint64_t(b.size()) + 100);
  fixTableCrc(forged);
  writeBytes(dir / "offset.btfz", forged);
  readError(dir / "offset.btfz");
  // A section count far beyond what the file can hold.
  forged = b;
  writeAt<std::uint32_t>(forged, 12, 0xFFFFFFF0u);
  writeBytes(dir / "count.btfz", forged);
  expectContains(readError(dir / "count.btfz"), "cannot fit");
}

TEST(Container, RejectsTrailingBytes) {
  test::TempDir dir;
  auto sections = sampleSections();
  writeContainer(dir / "a.btfz", sections);
  Bytes b = fileBytes(dir / "a.btfz");
  b.push_back(std::byte{0});
  writeBytes(dir / "long.btfz", b);
  expectContains(readError(dir / "long.btfz"), "unexpected bytes");
}

TEST(Container, RejectsZstdDataOfTheWrongRawSize) {
  test::TempDir dir;
  auto sections = sampleSections();
  writeContainer(dir / "a.btfz", sections);
  Bytes b = fileBytes(dir / "a.btfz");
  const Layout layout = layoutOf(b);
  const std::size_t entry = layout.entries[1];  // the zstd section
  ASSERT_EQ(readAt<std::uint32_t>(b, entry + 4), 1u);
  for (const std::int64_t delta : {-1, 1, 1000}) {
    Bytes forged = b;
    writeAt<std::uint64_t>(forged, entry + 24, readAt<std::uint64_t>(b, entry + 24) + std::uint64_t(delta));
    fixTableCrc(forged);
    writeBytes(dir / "raw.btfz", forged);
    const std::string message = readError(dir / "raw.btfz");
    expectContains(message, "level1/indices");
    expectContains(message, "decompress");
  }
  // Payload bytes that are not zstd at all, with both checksums made right.
  Bytes forged = b;
  const auto offset = readAt<std::uint64_t>(b, entry + 8);
  const auto stored = readAt<std::uint64_t>(b, entry + 16);
  for (std::uint64_t i = 0; i < stored; ++i) forged[offset + i] = std::byte(i * 7 + 3);
  writeAt<std::uint32_t>(forged, entry + 32, referenceCrc32(forged.data() + offset, stored));
  fixTableCrc(forged);
  writeBytes(dir / "garbage.btfz", forged);
  expectContains(readError(dir / "garbage.btfz"), "zstd");
}

TEST(Container, SectionChecksumIsStandardCrc32OfTheStoredBytes) {
  test::TempDir dir;
  auto sections = sampleSections();
  writeContainer(dir / "a.btfz", sections);
  const Bytes b = fileBytes(dir / "a.btfz");
  const Layout layout = layoutOf(b);
  for (const std::size_t entry : layout.entries) {
    const auto offset = readAt<std::uint64_t>(b, entry + 8);
    const auto stored = readAt<std::uint64_t>(b, entry + 16);
    EXPECT_EQ(readAt<std::uint32_t>(b, entry + 32), referenceCrc32(b.data() + offset, stored));
  }
  EXPECT_EQ(readAt<std::uint32_t>(b, layout.table_end), referenceCrc32(b.data(), layout.table_end));
}

TEST(Container, DuplicateNamesAreRejectedByWriterAndReader) {
  test::TempDir dir;
  std::vector<ContainerSection> sections(2);
  sections[0].name = "same";
  sections[1].name = "same";
  EXPECT_THROW(writeContainer(dir / "dup.btfz", sections), FileError);
  EXPECT_FALSE(fs::exists(dir / "dup.btfz"));  // nothing half-written
  // A forged file with two equal names (same length, so only the table CRC needs fixing).
  sections[1].name = "sane";
  writeContainer(dir / "a.btfz", sections);
  Bytes b = fileBytes(dir / "a.btfz");
  const Layout layout = layoutOf(b);
  b[layout.entries[1] + 38 + 2] = std::byte{'m'};
  fixTableCrc(b);
  writeBytes(dir / "dup.btfz", b);
  expectContains(readError(dir / "dup.btfz"), "two sections are named 'same'");
}

TEST(Container, WriterRejectsEmptyNamesAndBadPaths) {
  test::TempDir dir;
  std::vector<ContainerSection> sections(1);
  EXPECT_THROW(writeContainer(dir / "noname.btfz", sections), FileError);
  sections[0].name = "x";
  EXPECT_THROW(writeContainer(dir / "no-such-folder" / "a.btfz", sections), FileError);
  EXPECT_THROW(writeContainer(dir / "level.btfz", sections, 0), FileError);
}

TEST(Container, RequireSectionNamesTheMissingSection) {
  auto sections = sampleSections();
  EXPECT_EQ(&requireSection(sections, "scales", "f.btfz"), &sections[2]);
  try {
    requireSection(sections, "codebook0", "f.btfz");
    FAIL() << "no error";
  } catch (const FileError& e) {
    expectContains(e.what(), "f.btfz");
    expectContains(e.what(), "codebook0");
  }
}

TEST(ByteWriterReader, RoundTripOfValuesRangesAndStrings) {
  ByteWriter w;
  w.put<std::uint8_t>(7);
  w.put<double>(-2.5);
  const std::vector<float> floats{1.0f, 2.5f, -3.0f};
  w.putAll(floats);
  w.putString("level2");
  struct Pair {
    std::int32_t a;
    float b;
  };
  w.put(Pair{-4, 0.25f});
  EXPECT_EQ(w.size(), 1 + 8 + 12 + 8 + 6 + 8u);

  ContainerSection s;
  s.name = "values";
  s.data = w.bytes();
  ByteReader r(s, "f.btfz");
  EXPECT_EQ(r.get<std::uint8_t>(), 7);
  EXPECT_EQ(r.get<double>(), -2.5);
  std::vector<float> back(3);
  r.getAll(back);
  EXPECT_EQ(back, floats);
  EXPECT_EQ(r.getString(), "level2");
  const auto p = r.get<Pair>();
  EXPECT_EQ(p.a, -4);
  EXPECT_EQ(p.b, 0.25f);
  EXPECT_TRUE(r.atEnd());
  EXPECT_NO_THROW(r.requireEnd());
}

TEST(ByteWriterReader, LittleEndianLayout) {
  ByteWriter w;
  w.put<std::uint32_t>(0x04030201u);
  const auto& b = w.bytes();
  ASSERT_EQ(b.size(), 4u);
  EXPECT_EQ(b[0], std::byte{1});
  EXPECT_EQ(b[3], std::byte{4});
}

TEST(ByteWriterReader, OverrunThrowsFileErrorNamingFileAndSection) {
  ContainerSection s;
  s.name = "level1/scales";
  ByteWriter w;
  w.put<std::uint32_t>(5);
  w.put<std::uint16_t>(1);
  s.data = w.bytes();
  auto expectTruncated = [](auto call) {
    try {
      call();
      ADD_FAILURE() << "no error";
    } catch (const FileError& e) {
      expectContains(e.what(), "f.btfz");
      expectContains(e.what(), "level1/scales");
      expectContains(e.what(), "truncated");
    }
  };
  {
    ByteReader r(s, "f.btfz");
    r.get<std::uint32_t>();
    EXPECT_FALSE(r.atEnd());
    EXPECT_THROW(r.requireEnd(), FileError);
    expectTruncated([&] { r.get<std::uint32_t>(); });
  }
  {
    ByteReader r(s, "f.btfz");
    // A corrupt count must fail before allocating (this would be 2^62 floats).
    expectTruncated([&] { r.getVector<float>(std::uint64_t(1) << 62); });
    std::array<double, 2> two{};
    expectTruncated([&] { r.getAll(two); });
  }
  {
    ByteReader r(s, "f.btfz");
    expectTruncated([&] { r.getString(); });  // the u64 length itself does not fit in 6 bytes
  }
}

}  // namespace
}  // namespace btf
