// The runtime file's header and section table (docs/formats.md#runtime-file-btfrt-from-btf-export---runtime): the one place that
// knows the byte layout, for the runtime's reader (runtime/src/vq_codec.cpp) and the library's writer
// (libbtf/src/compress/vq_runtime_export.cpp). Little-endian throughout; C++17, standard library only.
#pragma once

#include <cstdint>

namespace btfrt::file {

inline constexpr char kMagic[8] = {'B', 'T', 'F', 'R', 'T', '\0', '\r', '\n'};
inline constexpr std::uint32_t kVersion = 1;
inline constexpr std::uint32_t kCodecVq = 1;
inline constexpr std::uint32_t kHeaderBytes = 64;
inline constexpr std::uint32_t kSectionAlignment = 16;

// Bytes 0..63. Sections follow at the offsets of the section table (right after the header).
struct Header {
  char magic[8];
  std::uint32_t version;         // kVersion
  std::uint32_t codec;           // kCodecVq
  std::uint32_t width, height;   // texels
  std::uint32_t levels;          // VQ levels: 1, 2 or 3
  std::uint32_t view_count;      // views held (slots)
  std::uint32_t view_rings;      // rings of views held, from the pole
  std::uint32_t ring_count;      // 6
  std::uint32_t light_count;     // 81
  float chroma_step;             // chromaticity grid step
  std::uint32_t section_count;   // kVqSectionCount
  std::uint32_t reserved;        // 0
  std::uint64_t file_bytes;      // the whole file
};
static_assert(sizeof(Header) == kHeaderBytes, "the header is 64 bytes");

// One entry of the section table: where a section's bytes are, from the file's start.
struct Section {
  std::uint64_t offset, bytes;
};

// The VQ codec's sections, in this order.
enum VqSection : std::uint32_t {
  kViewSlot = 0,   // int32[81]: slot of each 81-set view, -1 if not held
  kRings,          // Ring[ring_count]
  kLights,         // Light[light_count]
  kL1Values,       // uint16[]: level-1 entry values, ring after ring (value / 65535)
  kChroma,         // uint16[]: chromaticity grid pairs (R/Y, B/Y) / chroma_step, ring after ring
  kL1Cdf,          // float[]: per ring and level-1 entry, the CDF of its values (size + 1)
  kL1Sum,          // float[]: per ring and level-1 entry, the sum of its values
  kL2Codes,        // RingCode[l2 entries x ring_count] (levels >= 2)
  kL3Codes,        // SliceCode[l3 entries x view_count] (levels 3 with more than 2^16 level-2 entries)
  kL3Packed,       // PackedCode[l3 entries x view_count] (levels 3 with at most 2^16 level-2 entries)
  kScaleFractions, // float[1024]: 2^(f / 1024), the fractions of PackedCode's scale codes
  kTopCodes,       // SliceCode[texels] (levels 3) or [texels x view_count] (levels 2)
  kTopRingCodes,   // RingCode[texels x view_count x ring_count] (levels 1)
  kVqSectionCount
};

struct Ring {
  std::uint32_t size;            // lights in the ring
  std::uint32_t first_light;     // light index of place 0 (places are consecutive lights)
  std::uint32_t l1_start;        // first value of its entries in kL1Values
  std::uint32_t l1_entries;      // entries (size values each)
  std::uint32_t chroma_start;    // first value of its entries in kChroma
  std::uint32_t chroma_entries;  // entries (2 x size values each)
  std::uint32_t cdf_start;       // first float of its entries' CDFs in kL1Cdf
  std::uint32_t sum_start;       // first float of its entries' sums in kL1Sum
};
struct Light {
  std::uint32_t l1;      // its value of level-1 entry e: kL1Values[l1 + e * size]
  std::uint32_t chroma;  // its pair of chroma entry c: kChroma[chroma + 2 * c * size], [.. + 1]
  std::uint32_t ring, size;
};
struct RingCode {  // a level-1 code: entry, scale (luminance factor), chroma entry
  std::uint32_t entry;
  float scale;
  std::uint32_t chroma;
};
struct SliceCode {  // a level-2 or level-3 code: entry and scale
  std::uint32_t entry;
  float scale;
};
// A level-3 code in 4 bytes (level 3 is the largest table; half the bytes keep more of it in
// cache): the level-2 entry and the 16-bit log2 scale code q, whose scale is 0 for q = 0, else
// fractions[q & 1023] * 2^((q >> 10) - 40) (the power of two built as float bits).
struct PackedCode {
  std::uint16_t entry;
  std::uint16_t scale;
};
static_assert(sizeof(Ring) == 32 && sizeof(Light) == 16 && sizeof(RingCode) == 12 && sizeof(SliceCode) == 8 &&
                  sizeof(PackedCode) == 4,
              "packed records");

}  // namespace btfrt::file
