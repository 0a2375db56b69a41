// The stored form of a VqBtf (private to src/compress/): codebooks and index streams as written to
// .btfz, plus decoded float tables for fast lookups (built by prepare()).
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "btf/compress/vq_btf.h"
#include "btf/core/btf_ring_layout.h"
#include "vq_basis.h"

namespace btf {

// 16-bit log2 scales: code 0 is zero; code q > 0 is 2^(q / 1024 - 40), i.e. 2^-40 .. 2^24 with a
// relative step of 0.068 % (rounding error <= 0.034 %). The compressor rounds codes to a multiple
// of 2^shift (VqPrecision below); decoding does not need to know the shift.
inline std::uint16_t encodeVqScale(float s, int shift = 0) {
  if (!(s > 0.0f)) return 0;
  const double step = double(1 << shift);
  const double q = std::round((std::log2(double(s)) + 40.0) * 1024.0 / step) * step;
  return std::uint16_t(std::clamp(q, step, 65535.0));
}
inline float decodeVqScale(std::uint16_t q) { return q == 0 ? 0.0f : float(std::exp2(double(q) / 1024.0 - 40.0)); }
// decodeVqScale for lookups, without exp2: 2^(f / 1024) for the code's low 10 bits from a table,
// times the power of two of its high 6 bits (built as float bits, exact: every product is a normal
// float). The same floats as decodeVqScale for every code (test_vq_btf.cpp checks all 65,536).
inline const std::array<float, 1024> kVqScaleFractions = [] {
  std::array<float, 1024> t{};
  for (std::size_t f = 0; f < t.size(); ++f) t[f] = float(std::exp2(double(f) / 1024.0));
  return t;
}();
inline float lookupVqScale(std::uint16_t q) {
  const float power = std::bit_cast<float>(std::uint32_t((q >> 10) + 127 - 40) << 23);
  return q == 0 ? 0.0f : kVqScaleFractions[q & 1023u] * power;
}

// Level-1 entries are stored as 16-bit fixed point in [0, 1] (unit vectors of non-negative data),
// rounded to a multiple of 2^shift (1 itself stays 65535).
inline std::uint16_t encodeVqEntryValue(float v, int shift = 0) {
  const float c = std::clamp(v, 0.0f, 1.0f);
  if (shift == 0) return std::uint16_t(std::lround(c * 65535.0f));
  const double step = double(1 << shift);
  return std::uint16_t(std::min(std::round(double(c) * 65535.0 / step) * step, 65535.0));
}
// (A product, not a quotient: lookups decode one per sample.)
inline float decodeVqEntryValue(std::uint16_t q) { return float(q) * (1.0f / 65535.0f); }

// Stored precision matched to the tolerance: codes much finer than the error a level may add
// anyway only cost bytes (the low bits of 16-bit codes are noise to zstd). The compressor rounds
// scale codes and new level-1 values to multiples of 2^shift, the coarsest power of two whose
// rounding stays within kVqQuantizationShare * epsilon relative: a scale's rounding scales its
// whole vector by at most 2^(step / 2) - 1, and a new unit level-1 entry moves by at most
// sqrt(n) step / 2 (n values, at most the largest ring's, `max_ring_size`). The byte-planar sections (vq_io.cpp) then hold zero or
// near-constant low planes, which zstd stores in almost nothing. Decoders read the codes as
// before: the precision is the encoder's choice, not part of the format. A sixteenth of the
// tolerance is the knee of the trade between bytes and error (docs/design-notes.md#vq-stored-precision).
inline constexpr double kVqQuantizationShare = 1.0 / 16.0;
struct VqPrecision {
  int scale_shift = 0;
  int value_shift = 0;
};
inline VqPrecision vqPrecisionFor(float epsilon, int max_ring_size) {
  const double budget = kVqQuantizationShare * double(epsilon);
  VqPrecision p;
  // Scale codes: step 2^shift / 1024 in log2; 2^(step / 2) - 1 <= budget.
  while (p.scale_shift < 10 && std::exp2(std::exp2(p.scale_shift + 1) / 2048.0) - 1.0 <= budget) ++p.scale_shift;
  // Level-1 values: step 2^shift / 65535; sqrt(n) step / 2 <= budget, n the largest ring's size.
  const double n = double(max_ring_size);
  while (p.value_shift < 12 && std::sqrt(n) * std::exp2(p.value_shift + 1) / (2.0 * 65535.0) <= budget) ++p.value_shift;
  return p;
}

// Level 3's derived entries (l3_parent below): the largest share of a texel's views that may be
// exceptions to the entry it nearly matches. Every exception reuses an entry at the tolerance where
// a whole new entry would have been exact, so more of them buy bytes with error: a tenth is the
// share chosen at equal error on the calibrated print (docs/design-notes.md#vq-derived-level-3-entries).
inline constexpr double kVqMaxExceptionShare = 0.1;

// Chromaticity grid step: a quarter of the tolerance, so that quantizing a new entry costs at most
// chroma_epsilon / 8 per component (always within its own tolerance).
inline float vqChromaStep(float chroma_epsilon) { return 0.25f * chroma_epsilon; }

struct VqBtf::Impl {
  int width = 0, height = 0;
  std::string name;
  // The views held; the per-view streams below are indexed by slot (btf_view_set.h). Lookups of a
  // view not held are the caller's error (VqBtf::values checks; value does not, like x and y).
  BtfViewSet views;
  VqOptions options;
  VqStats stats;
  // The lights' rings (core/btf_ring_layout.h): every per-ring codebook and code below is indexed
  // by ring, and a ring's values by place. Set with setLayout, which sizes the per-ring vectors.
  BtfRingLayout layout = BtfRingLayout::ubo2003();
  void setLayout(BtfRingLayout l) {
    layout = std::move(l);
    const std::size_t R = std::size_t(layout.ringCount());
    l1.resize(R), l1_basis.resize(R), l1_coef.resize(R), chroma.resize(R), l1_cdf.resize(R), l1_sum.resize(R);
  }
  std::size_t ringCount() const { return std::size_t(layout.ringCount()); }
  int ringSize(int ring) const { return layout.size(ring); }

  // Level 1: per ring, entries of ringSize(ring) values (a ring of one light: the single entry {1}).
  std::vector<std::vector<std::uint16_t>> l1 = std::vector<std::vector<std::uint16_t>>(6);
  // Rings coded in a learned basis (vq_basis.h): the basis and each entry's coefficients (entry-
  // major, ringSize(ring) per entry), whose reconstruction l1 holds; both empty for rings stored
  // value by value.
  std::vector<VqRingBasis> l1_basis = std::vector<VqRingBasis>(6);
  std::vector<std::vector<std::int32_t>> l1_coef = std::vector<std::vector<std::int32_t>>(6);
  // Chromaticity codebooks, per ring: entries of ringSize(ring) pairs (i, j), the grid
  // coordinates of (R/Y, B/Y) = (i, j) * vqChromaStep(chroma_epsilon) at each light azimuth.
  std::vector<std::vector<std::int32_t>> chroma = std::vector<std::vector<std::int32_t>>(6);
  // Level 2 entries (levels >= 2): ringCount() codes per entry.
  std::vector<std::uint32_t> l2_index, l2_chroma;
  std::vector<std::uint16_t> l2_scale;
  // Level 3 entries (levels == 3): one code per view held (views.count()) per entry.
  std::vector<std::uint32_t> l3_index;
  std::vector<std::uint16_t> l3_scale;
  // Per level-3 entry, 0, or p + 1 when the entry is derived from entry p < e: the same codes but
  // in a few exception views (the compressor's texels that nearly match an entry). Files store a
  // derived entry's exception views alone (vq_io.cpp); in memory every row is whole. Empty: every
  // entry is whole (as levels < 3 and files before format version 3).
  std::vector<std::uint32_t> l3_parent;
  // Top stream, texel t = y * width + x: levels 1: per (t, view slot, ring) index, scale and chroma;
  // levels 2: per (t, view slot) level-2 index and scale; levels 3: per t level-3 index and scale.
  std::vector<std::uint32_t> top_index, top_chroma;
  std::vector<std::uint16_t> top_scale;

  // Decoded tables (prepare()), laid out for random access: a lookup (texel, view, light) walks
  // top -> level 3 -> level 2 -> level-1 value and chroma pair, one cache line per step (codes as
  // {index, float scale} records rather than parallel arrays; level 3's in 4 bytes where they fit,
  // below), and the level-1 values and chroma
  // stay in their stored 16 bits, so that the tables a lookup touches are as small as they can be
  // and random lookups run at the speed of the cache they fit (docs/design-notes.md#vq-decoding-at-random;
  // bench_btf.cpp's BM_BtfDecodeVq* report the tables' size and the lookup rate).
  struct ScaledIndex {
    std::uint32_t entry;
    float scale;
  };
  // Level-1 code of one ring: entry, scale and chroma entry (what ringCode returns).
  struct RingCode {
    std::uint32_t entry;
    float scale;
    std::uint32_t chroma;
  };
  std::vector<RingCode> l2_codes;      // per level-2 entry and ring (levels >= 2)
  // Per level-3 entry and view (levels == 3): as 4-byte records of the level-2 entry and the stored
  // scale code (lookupVqScale) when level 2 has at most 2^16 entries, else as ScaledIndex. Level 3
  // is the largest table of a full-size BTF and its derived entries (l3_parent) add rows; half the
  // bytes per row keep more of it in cache.
  struct PackedIndex {
    std::uint16_t entry;
    std::uint16_t scale;
  };
  std::vector<PackedIndex> l3_packed;
  std::vector<ScaledIndex> l3_codes;
  std::vector<ScaledIndex> top_codes;  // per texel (levels 3) or texel and view (levels 2)
  std::vector<RingCode> top_ring_codes;  // per texel, view and ring (levels 1)
  // All rings' level-1 values (16-bit, as stored) and chroma grid pairs (i, j) in one array each,
  // ring after ring, and where a light's values start in them: light l of ring r (place a) has
  // its value of level-1 entry e at l1_flat[lights[l].l1 + e * ringSize(r)], its chroma pair of
  // chroma entry c at chroma_flat[lights[l].chroma + 2 * c * ringSize(r)].
  std::vector<std::uint16_t> l1_flat, chroma_flat;
  struct LightAddress {
    std::uint32_t l1, chroma;
    std::uint32_t ring, size;
  };
  std::vector<LightAddress> lights;  // per light index
  float chroma_step = 0;
  // Per ring and level-1 entry, the normalized prefix sums of its values and their total, for
  // samplers (VqBtf::lightRings).
  std::vector<std::vector<float>> l1_cdf = std::vector<std::vector<float>>(6), l1_sum = std::vector<std::vector<float>>(6);

  std::size_t l1Count(int ring) const { return l1[std::size_t(ring)].size() / std::size_t(ringSize(ring)); }
  std::size_t l2Count() const { return l2_index.size() / ringCount(); }
  std::size_t viewCount() const { return std::size_t(views.count()); }
  std::size_t slotOf(int v) const { return std::size_t(views.slot(v)); }
  std::size_t l3Count() const { return l3_index.size() / viewCount(); }
  std::size_t chromaCount(int ring) const { return chroma[std::size_t(ring)].size() / (2 * std::size_t(ringSize(ring))); }

  // Checks that every index is inside its codebook and the streams have their sizes (throws
  // btf::Error with `what` prefixed), then builds the decoded tables.
  void prepare(const std::string& what);

  // Level-2 code (entry, scale) of texel t's light slice at view v (levels >= 2).
  ScaledIndex sliceCode(std::size_t t, int v) const {
    if (options.levels == 2) return top_codes[t * viewCount() + slotOf(v)];
    const ScaledIndex c3 = top_codes[t];
    ScaledIndex c2 = l3Code(std::size_t(c3.entry) * viewCount() + slotOf(v));
    c2.scale *= c3.scale;
    return c2;
  }
  // Level-3 code k (entry * viewCount() + slot), from whichever form prepare() built.
  ScaledIndex l3Code(std::size_t k) const { return l3_packed.empty() ? l3_codes[k] : unpacked(l3_packed[k]); }
  static ScaledIndex unpacked(PackedIndex p) { return {p.entry, lookupVqScale(p.scale)}; }
  // Level-1 code of ring r under a slice's level-2 code.
  RingCode ringCode(const ScaledIndex& slice, int r) const {
    RingCode c1 = l2_codes[std::size_t(slice.entry) * ringCount() + std::size_t(r)];
    c1.scale *= slice.scale;
    return c1;
  }
  // Level-1 code (entry, scale, chroma entry) of texel t, view v, ring r.
  RingCode ringCode(std::size_t t, int v, int r) const {
    if (options.levels == 1) return top_ring_codes[(t * viewCount() + slotOf(v)) * ringCount() + std::size_t(r)];
    return ringCode(sliceCode(t, v), r);
  }
  // The measured sample of light `light` under its ring's level-1 code: luminance code.scale times
  // the entry's value, RGB from the chroma pair (R/Y, B/Y) and Y = 0.2126 R + 0.7152 G + 0.0722 B.
  Rgb sample(const RingCode& code, int light) const {
    const LightAddress& at = lights[std::size_t(light)];
    const std::uint16_t* q = &chroma_flat[at.chroma + 2 * std::size_t(code.chroma) * at.size];
    return decodeSample(code.scale, l1_flat[at.l1 + std::size_t(code.entry) * at.size], q[0], q[1], chroma_step);
  }
  // The arithmetic of sample: the stored value and chroma pair to RGB.
  static Rgb decodeSample(float scale, std::uint16_t value, std::uint16_t r, std::uint16_t b, float step) {
    const float lum = scale * decodeVqEntryValue(value);
    const float cr = float(r) * step, cb = float(b) * step;
    const float cg = std::max((1.0f - 0.2126f * cr - 0.0722f * cb) * (1.0f / 0.7152f), 0.0f);
    return {lum * cr, lum * cg, lum * cb};
  }
};

// VqBtf::values for three levels, after its checks (every index within the BTF, out.size() ==
// samples.size()): groups of samples walked one step at a time (vq_stream.cpp), sized and
// prefetched for tables past the L2 cache (past_l2) or within it. values() chooses by
// lookupTableBytes(); the tests run both on small files.
void decodeThreeLevelStream(const VqBtf::Impl& m, std::span<const BtfSampleIndex> samples, std::span<Rgb> out,
                            bool past_l2);

}  // namespace btf
