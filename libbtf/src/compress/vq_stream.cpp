// VqBtf::values: a stream of measured samples decoded in groups, each step of the chain of lookups
// (top -> level 3 -> level 2 -> level-1 value and chroma, vq_impl.h) done for the whole group
// before the next (with a prefetch of the step after when the tables exceed the L2 cache). One
// sample's lookups depend on each other; a group's do not, so their loads overlap instead of
// following one another, and the last step's arithmetic runs on arrays in vector lanes. The
// arithmetic is value()'s (Impl::sample), in its order, so the results are its own bit for bit.
// An earlier version ran the chain in AVX2 gathers over parallel arrays; these records (one cache
// line per step) with plain loads decode faster (BM_BtfDecodeVqStream measures it;
// docs/design-notes.md#vq-decoding-at-random) and need no CPU dispatch.
#include <algorithm>
#include <cstdint>
#include <type_traits>

#include <unistd.h>

#include "btf/core/error.h"
#include "vq_impl.h"

namespace btf {
namespace {

// Samples per group. Each step of a group waits about once for its slowest load, so a group pays
// one latency per step, shared by its samples. Tables within the L2 cache: 16, few enough that
// the group's state stays in registers and L1. Tables past it (prefetching): a latency is then an
// L3 or DRAM one, and only many more loads in flight amortize it: 128 decoded a full-size
// calibrated BTF faster than 16 or 64 did, and no slower on tables just past the L2 cache (`btf
// bench decode` and BM_BtfDecodeVqStream measure both; docs/design-notes.md#vq-decoding-at-random).
constexpr std::size_t kCachedGroup = 16;
constexpr std::size_t kPrefetchedGroup = 128;

// The L2 cache of this machine (1 MB when the system does not say).
double l2CacheBytes() {
  static const double bytes = [] {
    const long l2 = sysconf(_SC_LEVEL2_CACHE_SIZE);
    return l2 > 0 ? double(l2) : 1e6;
  }();
  return bytes;
}

// A group of n <= kGroup samples of a three-level VqBtf (indices checked by the caller). Count is
// kGroup as a compile-time constant for full groups, so that their loops unroll and vectorize, or a
// size_t.
template <std::size_t kGroup, bool kPacked, class Count>
void decodeGroup(const VqBtf::Impl& m, const BtfSampleIndex* s, Count n, bool prefetching, Rgb* out) {
  auto prefetch = [prefetching](const auto* p) {
    if (prefetching) __builtin_prefetch(p, 0, 3);
  };
  std::size_t k3[kGroup], k2[kGroup];
  float scale[kGroup];
  for (std::size_t i = 0; i < n; ++i) {
    k3[i] = std::size_t(s[i].y) * std::size_t(m.width) + std::size_t(s[i].x);
    prefetch(&m.top_codes[k3[i]]);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const VqBtf::Impl::ScaledIndex c3 = m.top_codes[k3[i]];
    scale[i] = c3.scale;
    k3[i] = std::size_t(c3.entry) * m.viewCount() + m.slotOf(s[i].view);
    if constexpr (kPacked)
      prefetch(&m.l3_packed[k3[i]]);
    else
      prefetch(&m.l3_codes[k3[i]]);
  }
  for (std::size_t i = 0; i < n; ++i) {
    VqBtf::Impl::ScaledIndex c2;
    if constexpr (kPacked)
      c2 = VqBtf::Impl::unpacked(m.l3_packed[k3[i]]);
    else
      c2 = m.l3_codes[k3[i]];
    scale[i] = c2.scale * scale[i];
    k2[i] = std::size_t(c2.entry) * m.ringCount() + m.lights[std::size_t(s[i].light)].ring;
    prefetch(&m.l2_codes[k2[i]]);
  }
  // The last step as Impl::sample, on arrays (the compiler runs its arithmetic in vector lanes).
  std::uint16_t value[kGroup], cr[kGroup], cb[kGroup];
  std::size_t l1_at[kGroup], chroma_at[kGroup];
  for (std::size_t i = 0; i < n; ++i) {
    const VqBtf::Impl::RingCode c1 = m.l2_codes[k2[i]];
    scale[i] = c1.scale * scale[i];
    const VqBtf::Impl::LightAddress& at = m.lights[std::size_t(s[i].light)];
    l1_at[i] = at.l1 + std::size_t(c1.entry) * at.size;
    chroma_at[i] = at.chroma + 2 * std::size_t(c1.chroma) * at.size;
    prefetch(&m.l1_flat[l1_at[i]]);
    prefetch(&m.chroma_flat[chroma_at[i]]);
  }
  for (std::size_t i = 0; i < n; ++i) {
    value[i] = m.l1_flat[l1_at[i]];
    cr[i] = m.chroma_flat[chroma_at[i]];
    cb[i] = m.chroma_flat[chroma_at[i] + 1];
  }
  // Into arrays first: stored straight into the Rgb output the loop would not vectorize, which
  // slows the stream on tables within the cache (BM_BtfDecodeVqStream).
  float r[kGroup], g[kGroup], b[kGroup];
  for (std::size_t i = 0; i < n; ++i) {
    const Rgb c = VqBtf::Impl::decodeSample(scale[i], value[i], cr[i], cb[i], m.chroma_step);
    r[i] = c.r;
    g[i] = c.g;
    b[i] = c.b;
  }
  for (std::size_t i = 0; i < n; ++i) out[i] = Rgb(r[i], g[i], b[i]);
}

template <std::size_t kGroup, bool kPacked>
void decodeAll(const VqBtf::Impl& m, std::span<const BtfSampleIndex> samples, bool prefetching, std::span<Rgb> out) {
  const std::integral_constant<std::size_t, kGroup> full;
  std::size_t i = 0;
  for (; i + kGroup <= samples.size(); i += kGroup) decodeGroup<kGroup, kPacked>(m, &samples[i], full, prefetching, &out[i]);
  if (i < samples.size()) decodeGroup<kGroup, kPacked>(m, &samples[i], samples.size() - i, prefetching, &out[i]);
}
template <std::size_t kGroup>
void decodeAll(const VqBtf::Impl& m, std::span<const BtfSampleIndex> samples, bool prefetching, std::span<Rgb> out) {
  if (m.l3_packed.empty())
    decodeAll<kGroup, false>(m, samples, prefetching, out);
  else
    decodeAll<kGroup, true>(m, samples, prefetching, out);
}

}  // namespace

void decodeThreeLevelStream(const VqBtf::Impl& m, std::span<const BtfSampleIndex> samples, std::span<Rgb> out,
                            bool past_l2) {
  // Prefetching the next step pays when the tables exceed the L2 cache; within it the prefetches
  // are only extra instructions (BM_BtfDecodeVqStream at its smallest sizes).
  if (past_l2)
    decodeAll<kPrefetchedGroup>(m, samples, true, out);
  else
    decodeAll<kCachedGroup>(m, samples, false, out);
}

void VqBtf::values(std::span<const BtfSampleIndex> samples, std::span<Rgb> out) const {
  checkSampleIndices(samples, out.size());
  const Impl& m = *impl_;
  if (m.options.levels != 3) {
    for (std::size_t i = 0; i < samples.size(); ++i) out[i] = value(samples[i].x, samples[i].y, samples[i].view, samples[i].light);
    return;
  }
  decodeThreeLevelStream(m, samples, out, double(lookupTableBytes()) > l2CacheBytes());
}

}  // namespace btf
