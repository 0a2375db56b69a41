// VqBtf::values: a stream of measured samples decoded in groups, each step of the chain of lookups
// (top -> level 3 -> level 2 -> level-1 value and chroma, vq_impl.h) done for the whole group
// before the next, with a prefetch of the step after. One sample's lookups depend on each other;
// a group's do not, so its cache misses overlap instead of following one another ("group
// prefetching"). The arithmetic is value()'s (ringCode, sample), so the results are its
// own bit for bit. An earlier version ran the chain in AVX2 gathers over parallel arrays; these
// records (one cache line per step) with plain loads decode faster (BM_BtfDecodeVqStream/16:
// 68.8 -> 94.8 M samples/s, README) and need no CPU dispatch.
#include <algorithm>
#include <cstdint>

#include "btf/core/error.h"
#include "vq_impl.h"

namespace btf {
namespace {

// Samples per group: enough misses in flight to fill the core's line-fill buffers, few enough that
// the group's state stays in registers and L1.
constexpr std::size_t kGroup = 16;

template <class T>
void prefetch(const T* p) {
  __builtin_prefetch(p, 0, 3);
}

// A group of samples of a three-level VqBtf (indices checked by the caller).
void decodeGroup(const VqBtf::Impl& m, const BtfSampleIndex* s, std::size_t n, Rgb* out) {
  std::size_t k3[kGroup], k2[kGroup];
  float scale[kGroup];
  for (std::size_t i = 0; i < n; ++i) {
    k3[i] = std::size_t(s[i].y) * std::size_t(m.width) + std::size_t(s[i].x);
    prefetch(&m.top_codes[k3[i]]);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const VqBtf::Impl::ScaledIndex c3 = m.top_codes[k3[i]];
    scale[i] = c3.scale;
    k3[i] = std::size_t(c3.entry) * kBtfDirectionCount + std::size_t(s[i].view);
    prefetch(&m.l3_codes[k3[i]]);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const VqBtf::Impl::ScaledIndex c2 = m.l3_codes[k3[i]];
    scale[i] = c2.scale * scale[i];
    k2[i] = std::size_t(c2.entry) * kBtfRingCount + m.lights[std::size_t(s[i].light)].ring;
    prefetch(&m.l2_codes[k2[i]]);
  }
  VqBtf::Impl::RingCode c1[kGroup];
  for (std::size_t i = 0; i < n; ++i) {
    c1[i] = m.l2_codes[k2[i]];
    c1[i].scale *= scale[i];
    const VqBtf::Impl::LightAddress& at = m.lights[std::size_t(s[i].light)];
    prefetch(&m.l1_flat[at.l1 + std::size_t(c1[i].entry) * at.size]);
    prefetch(&m.chroma_flat[at.chroma + 2 * std::size_t(c1[i].chroma) * at.size]);
  }
  for (std::size_t i = 0; i < n; ++i) out[i] = m.sample(c1[i], s[i].light);
}

}  // namespace

void VqBtf::values(std::span<const BtfSampleIndex> samples, std::span<Rgb> out) const {
  checkSampleIndices(samples, out.size());
  const Impl& m = *impl_;
  if (m.options.levels != 3) {
    for (std::size_t i = 0; i < samples.size(); ++i) out[i] = value(samples[i].x, samples[i].y, samples[i].view, samples[i].light);
    return;
  }
  for (std::size_t i = 0; i < samples.size(); i += kGroup)
    decodeGroup(m, &samples[i], std::min(kGroup, samples.size() - i), &out[i]);
}

}  // namespace btf
