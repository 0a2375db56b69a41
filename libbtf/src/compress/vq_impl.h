// The stored form of a VqBtf (private to src/compress/): codebooks and index streams as written to
// .btfz, plus decoded float tables for fast lookups (built by prepare()).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "btf/compress/vq_btf.h"
#include "btf/core/btf_directions.h"

namespace btf {

// 16-bit log2 scales: code 0 is zero; code q > 0 is 2^(q / 1024 - 40), i.e. 2^-40 .. 2^24 with a
// relative step of 0.068 % (rounding error <= 0.034 %).
inline std::uint16_t encodeVqScale(float s) {
  if (!(s > 0.0f)) return 0;
  const double q = std::round((std::log2(double(s)) + 40.0) * 1024.0);
  return std::uint16_t(std::clamp(q, 1.0, 65535.0));
}
inline float decodeVqScale(std::uint16_t q) { return q == 0 ? 0.0f : float(std::exp2(double(q) / 1024.0 - 40.0)); }

// Level-1 entries are stored as 16-bit fixed point in [0, 1] (unit vectors of non-negative data).
inline std::uint16_t encodeVqEntryValue(float v) { return std::uint16_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 65535.0f)); }
inline float decodeVqEntryValue(std::uint16_t q) { return float(q) / 65535.0f; }

// Chromaticity grid step: a quarter of the tolerance, so that quantizing a new entry costs at most
// chroma_epsilon / 8 per component (always within its own tolerance).
inline float vqChromaStep(float chroma_epsilon) { return 0.25f * chroma_epsilon; }

struct VqBtf::Impl {
  int width = 0, height = 0;
  std::string name;
  VqOptions options;
  VqStats stats;

  // Level 1: per ring, entries of btfRingSize(ring) values (ring 0: the single entry {1}).
  std::array<std::vector<std::uint16_t>, kBtfRingCount> l1;
  // Chromaticity codebooks, per ring: entries of btfRingSize(ring) pairs (i, j), the grid
  // coordinates of (R/Y, B/Y) = (i, j) * vqChromaStep(chroma_epsilon) at each light azimuth.
  std::array<std::vector<std::int32_t>, kBtfRingCount> chroma;
  // Level 2 entries (levels >= 2): kBtfRingCount codes per entry.
  std::vector<std::uint32_t> l2_index, l2_chroma;
  std::vector<std::uint16_t> l2_scale;
  // Level 3 entries (levels == 3): kBtfDirectionCount (view) codes per entry.
  std::vector<std::uint32_t> l3_index;
  std::vector<std::uint16_t> l3_scale;
  // Top stream, texel t = y * width + x: levels 1: per (t, view, ring) index, scale and chroma;
  // levels 2: per (t, view) level-2 index and scale; levels 3: per t level-3 index and scale.
  std::vector<std::uint32_t> top_index, top_chroma;
  std::vector<std::uint16_t> top_scale;

  // Decoded tables (prepare()).
  std::array<std::vector<float>, kBtfRingCount> l1_values, l1_cdf, l1_sum;
  // Per ring and chroma entry, btfRingSize(ring) triples (r, g, b): RGB = luminance * (r, g, b).
  std::array<std::vector<float>, kBtfRingCount> chroma_rgb;
  std::vector<float> l2_scale_f, l3_scale_f, top_scale_f;
  // The same l1_values and chroma_rgb, all rings in one array each, for gathers by ring
  // (vq_stream.cpp): ring r starts at l1_offset[r], chroma_offset[r] (in floats).
  std::vector<float> l1_flat, chroma_flat;
  std::array<std::int32_t, 8> l1_offset{}, chroma_offset{};

  std::size_t l1Count(int ring) const { return l1[std::size_t(ring)].size() / std::size_t(btfRingSize(ring)); }
  std::size_t l2Count() const { return l2_index.size() / kBtfRingCount; }
  std::size_t l3Count() const { return l3_index.size() / kBtfDirectionCount; }
  std::size_t chromaCount(int ring) const { return chroma[std::size_t(ring)].size() / (2 * std::size_t(btfRingSize(ring))); }

  // Checks that every index is inside its codebook and the streams have their sizes (throws
  // btf::Error with `what` prefixed), then builds the decoded tables.
  void prepare(const std::string& what);

  // Level-1 code (entry, scale, chroma entry of ring r) of texel t, view v, ring r.
  struct RingCode {
    std::uint32_t entry;
    float scale;
    std::uint32_t chroma;
  };
  RingCode ringCode(std::size_t t, int v, int r) const {
    if (options.levels == 1) {
      const std::size_t k = (t * kBtfDirectionCount + std::size_t(v)) * kBtfRingCount + std::size_t(r);
      return {top_index[k], top_scale_f[k], top_chroma[k]};
    }
    std::uint32_t e2;
    float s;
    if (options.levels == 2) {
      const std::size_t k = t * kBtfDirectionCount + std::size_t(v);
      e2 = top_index[k];
      s = top_scale_f[k];
    } else {
      const std::size_t k = std::size_t(top_index[t]) * kBtfDirectionCount + std::size_t(v);
      e2 = l3_index[k];
      s = top_scale_f[t] * l3_scale_f[k];
    }
    const std::size_t k = std::size_t(e2) * kBtfRingCount + std::size_t(r);
    return {l2_index[k], s * l2_scale_f[k], l2_chroma[k]};
  }
};

}  // namespace btf
