// VqBtf::values: a stream of measured samples decoded 32 at a time in AVX2 lanes, the chain of
// lookups of ringCode + value (vq_impl.h, vq_decode.cpp) as gathers. Hand-written with intrinsics
// for the same reasons as the DP sampler's lanes (sampling/dp_cdf_batch.cpp): GCC emits no gathers
// for generic tuning, and the products must be value()'s, in its order and without FMA
// contraction (the function is compiled for "avx2" alone), so the lanes give its results bit for bit.
#include <immintrin.h>

#include <algorithm>
#include <cstdint>

#include "btf/core/error.h"
#include "vq_impl.h"
#include "../core/avx2.h"

namespace btf {
namespace {

// Ring, azimuth and ring size of each light, as one lookup: ring | azimuth << 8 | size << 16.
struct LightCodes {
  std::array<std::int32_t, kBtfDirectionCount + 7> code{};  // padded: gathers read 4 bytes, never past
  LightCodes() {
    for (int r = 0; r < kBtfRingCount; ++r)
      for (int a = 0; a < btfRingSize(r); ++a) code[std::size_t(btfRingStart(r) + a)] = r | a << 8 | btfRingSize(r) << 16;
  }
};
const LightCodes& lightCodes() {
  static const LightCodes codes;
  return codes;
}

// Samples per step: four vectors of eight, interleaved step by step so that one vector's gathers
// run while another waits for its own (each sample is a chain of six dependent lookups).
constexpr int kVectors = 4;
constexpr int kLanes = 8 * kVectors;

// kLanes samples of a three-level VqBtf; x, y, view, light in range (checked by the caller).
BTF_AVX2 void decodeLanes(const VqBtf::Impl& m, const BtfSampleIndex* s, Rgb* out) {
  constexpr int V = kVectors;
  static_assert(sizeof(BtfSampleIndex) == 4 * sizeof(int));
  const int* fields = reinterpret_cast<const int*>(s);
  const __m256i stride = _mm256_setr_epi32(0, 4, 8, 12, 16, 20, 24, 28), byte = _mm256_set1_epi32(0xff);
  const __m256i l1_offset = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(m.l1_offset.data()));
  const __m256i chroma_offset = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(m.chroma_offset.data()));
  __m256i view[V], ring[V], azimuth[V], size[V], t[V], k3[V], k2[V];
  __m256 scale[V];
  for (int j = 0; j < V; ++j) {
    const int* f = fields + 32 * j;
    const __m256i x = _mm256_i32gather_epi32(f, stride, 4), y = _mm256_i32gather_epi32(f + 1, stride, 4);
    view[j] = _mm256_i32gather_epi32(f + 2, stride, 4);
    const __m256i code = _mm256_i32gather_epi32(lightCodes().code.data(), _mm256_i32gather_epi32(f + 3, stride, 4), 4);
    ring[j] = _mm256_and_si256(code, byte);
    azimuth[j] = _mm256_and_si256(_mm256_srli_epi32(code, 8), byte);
    size[j] = _mm256_srli_epi32(code, 16);
    t[j] = _mm256_add_epi32(_mm256_mullo_epi32(y, _mm256_set1_epi32(m.width)), x);
  }
  // ringCode, levels == 3.
  for (int j = 0; j < V; ++j) {
    const __m256i e3 = _mm256_i32gather_epi32(reinterpret_cast<const int*>(m.top_index.data()), t[j], 4);
    k3[j] = _mm256_add_epi32(_mm256_mullo_epi32(e3, _mm256_set1_epi32(kBtfDirectionCount)), view[j]);
  }
  for (int j = 0; j < V; ++j) {
    const __m256i e2 = _mm256_i32gather_epi32(reinterpret_cast<const int*>(m.l3_index.data()), k3[j], 4);
    scale[j] = _mm256_mul_ps(_mm256_i32gather_ps(m.top_scale_f.data(), t[j], 4),
                             _mm256_i32gather_ps(m.l3_scale_f.data(), k3[j], 4));
    k2[j] = _mm256_add_epi32(_mm256_mullo_epi32(e2, _mm256_set1_epi32(kBtfRingCount)), ring[j]);
  }
  for (int j = 0; j < V; ++j) {
    const __m256i entry = _mm256_i32gather_epi32(reinterpret_cast<const int*>(m.l2_index.data()), k2[j], 4);
    const __m256i chroma = _mm256_i32gather_epi32(reinterpret_cast<const int*>(m.l2_chroma.data()), k2[j], 4);
    const __m256 code_scale = _mm256_mul_ps(scale[j], _mm256_i32gather_ps(m.l2_scale_f.data(), k2[j], 4));
    // value: luminance from the ring's entry, RGB from its chroma entry.
    const __m256i l1_at = _mm256_add_epi32(_mm256_permutevar8x32_epi32(l1_offset, ring[j]),
                                           _mm256_add_epi32(_mm256_mullo_epi32(entry, size[j]), azimuth[j]));
    const __m256 lum = _mm256_mul_ps(code_scale, _mm256_i32gather_ps(m.l1_flat.data(), l1_at, 4));
    const __m256i c_at = _mm256_add_epi32(
        _mm256_permutevar8x32_epi32(chroma_offset, ring[j]),
        _mm256_mullo_epi32(_mm256_add_epi32(_mm256_mullo_epi32(chroma, size[j]), azimuth[j]), _mm256_set1_epi32(3)));
    alignas(32) float r[8], g[8], b[8];
    _mm256_store_ps(r, _mm256_mul_ps(lum, _mm256_i32gather_ps(m.chroma_flat.data(), c_at, 4)));
    _mm256_store_ps(g, _mm256_mul_ps(lum, _mm256_i32gather_ps(m.chroma_flat.data() + 1, c_at, 4)));
    _mm256_store_ps(b, _mm256_mul_ps(lum, _mm256_i32gather_ps(m.chroma_flat.data() + 2, c_at, 4)));
    for (int k = 0; k < 8; ++k) out[8 * j + k] = Rgb(r[k], g[k], b[k]);
  }
}

}  // namespace

void VqBtf::values(std::span<const BtfSampleIndex> samples, std::span<Rgb> out) const {
  checkSampleIndices(samples, out.size());
  const Impl& m = *impl_;
  // The lanes index with 32-bit integers: larger tables (and other level counts) take the loop.
  const bool lanes = cpuHasAvx2() && m.options.levels == 3 &&
                     std::size_t(m.width) * std::size_t(m.height) < (std::size_t(1) << 31) &&
                     m.l3_index.size() < (std::size_t(1) << 31) && m.l2_index.size() < (std::size_t(1) << 31);
  std::size_t i = 0;
  if (lanes)
    for (; i + kLanes <= samples.size(); i += kLanes) decodeLanes(m, &samples[i], &out[i]);
  for (; i < samples.size(); ++i) out[i] = value(samples[i].x, samples[i].y, samples[i].view, samples[i].light);
}

}  // namespace btf
