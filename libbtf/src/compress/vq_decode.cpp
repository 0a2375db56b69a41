// Decoding a VqBtf: single entries (value), whole views (loadView) and the light rings samplers use.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "btf/core/error.h"
#include "btf/core/cdf1d.h"
#include "vq_impl.h"

namespace btf {

namespace {
template <class T>
void checkIndices(const std::vector<T>& indices, std::size_t bound, const std::string& what, const std::string& stream) {
  for (std::size_t i = 0; i < indices.size(); ++i)
    if (std::size_t(indices[i]) >= bound)
      throw Error(what + ": " + stream + " index " + std::to_string(indices[i]) + " at position " + std::to_string(i) +
                  " is outside its codebook of " + std::to_string(bound) + " entries");
}
void checkSize(std::size_t size, std::size_t expected, const std::string& what, const std::string& stream) {
  if (size != expected)
    throw Error(what + ": " + stream + " holds " + std::to_string(size) + " values, expected " + std::to_string(expected));
}
}  // namespace

void VqBtf::Impl::prepare(const std::string& what) {
  if (width < 1 || height < 1) throw Error(what + ": invalid texel size");
  if (options.levels < 1 || options.levels > 3) throw Error(what + ": invalid level count " + std::to_string(options.levels));
  const std::size_t T = std::size_t(width) * std::size_t(height);
  const std::size_t R = ringCount();
  if (l1.size() != R || chroma.size() != R || l1_basis.size() != R || l1_coef.size() != R)
    throw Error(what + ": codebooks for " + std::to_string(l1.size()) + " rings, the layout has " + std::to_string(R));
  if (std::size_t(layout.lightCount()) != std::size_t(views.directions().maxLightCount()))
    throw Error(what + ": " + layout.describe() + " for " + views.directions().describe());
  l1_cdf.resize(R);
  l1_sum.resize(R);
  for (int r = 0; r < int(R); ++r) {
    if (l1[std::size_t(r)].empty()) throw Error(what + ": level-1 codebook of ring " + std::to_string(r) + " is empty");
    if (l1[std::size_t(r)].size() % std::size_t(ringSize(r)) != 0)
      throw Error(what + ": level-1 codebook of ring " + std::to_string(r) + " has a partial entry");
  }
  for (int r = 0; r < int(R); ++r) {
    const auto& c = chroma[std::size_t(r)];
    if (c.empty() || c.size() % (2 * std::size_t(ringSize(r))) != 0)
      throw Error(what + ": the chromaticity codebook of ring " + std::to_string(r) + " is empty or has a partial entry");
    for (std::int32_t g : c)
      if (g < 0) throw Error(what + ": the chromaticity codebook of ring " + std::to_string(r) + " holds a negative value");
  }
  // Level-1 and chroma indices live where the level below the top stream is, one per ring.
  auto checkPerRing = [&](const std::vector<std::uint32_t>& idx, const std::string& stream, auto count) {
    for (std::size_t i = 0; i < idx.size(); ++i) {
      const int r = int(i % R);
      if (idx[i] >= count(r))
        throw Error(what + ": " + stream + " index " + std::to_string(idx[i]) + " of ring " + std::to_string(r) +
                    " is outside its codebook of " + std::to_string(count(r)) + " entries");
    }
  };
  auto checkL1 = [&](const std::vector<std::uint32_t>& idx, const std::string& stream) {
    checkPerRing(idx, stream, [&](int r) { return l1Count(r); });
  };
  auto checkChroma = [&](const std::vector<std::uint32_t>& idx, const std::string& stream) {
    checkPerRing(idx, stream, [&](int r) { return chromaCount(r); });
  };
  if (options.levels == 1) {
    const std::size_t n = T * viewCount() * R;
    checkSize(top_index.size(), n, what, "top/index");
    checkSize(top_scale.size(), n, what, "top/scale");
    checkSize(top_chroma.size(), n, what, "top/chroma");
    checkL1(top_index, "top/index");
    checkChroma(top_chroma, "top/chroma");
  } else {
    if (l2_index.empty()) throw Error(what + ": the level-2 codebook is empty");
    checkSize(l2_scale.size(), l2_index.size(), what, "level2/scale");
    checkSize(l2_chroma.size(), l2_index.size(), what, "level2/chroma");
    if (l2_index.size() % R != 0) throw Error(what + ": the level-2 codebook has a partial entry");
    checkL1(l2_index, "level2/index");
    checkChroma(l2_chroma, "level2/chroma");
    if (options.levels == 2) {
      checkSize(top_index.size(), T * viewCount(), what, "top/index");
      checkSize(top_scale.size(), T * viewCount(), what, "top/scale");
      checkIndices(top_index, l2Count(), what, "top/index");
    } else {
      if (l3_index.empty()) throw Error(what + ": the level-3 codebook is empty");
      if (l3_index.size() % viewCount() != 0) throw Error(what + ": the level-3 codebook has a partial entry");
      checkSize(l3_scale.size(), l3_index.size(), what, "level3/scale");
      checkIndices(l3_index, l2Count(), what, "level3/index");
      if (!l3_parent.empty()) {
        checkSize(l3_parent.size(), l3Count(), what, "level3/parent");
        for (std::size_t e = 0; e < l3_parent.size(); ++e)
          if (l3_parent[e] > e) throw Error(what + ": level-3 entry " + std::to_string(e) + " derives from a later entry");
      }
      checkSize(top_index.size(), T, what, "top/index");
      checkSize(top_scale.size(), T, what, "top/scale");
      checkIndices(top_index, l3Count(), what, "top/index");
    }
  }
  for (int r = 0; r < int(R); ++r)
    for (std::int32_t g : chroma[std::size_t(r)])
      if (g > 65535)
        throw Error(what + ": the chromaticity codebook of ring " + std::to_string(r) + " holds " + std::to_string(g) +
                    ", beyond the 16-bit grid");
  // Decoded tables.
  for (int r = 0; r < int(R); ++r) {
    const std::size_t n = std::size_t(ringSize(r)), count = l1Count(r);
    auto& cdf = l1_cdf[std::size_t(r)];
    auto& sum = l1_sum[std::size_t(r)];
    cdf.resize(count * (n + 1));
    sum.resize(count);
    std::array<float, BtfRingLayout::kBandSize> values;  // one entry, decoded
    for (std::size_t e = 0; e < count; ++e) {
      for (std::size_t a = 0; a < n; ++a) values[a] = decodeVqEntryValue(l1[std::size_t(r)][e * n + a]);
      sum[e] = float(buildCdf1D(std::span<const float>(values.data(), n), std::span<float>(&cdf[e * (n + 1)], n + 1)) * double(n));
    }
  }
  chroma_step = vqChromaStep(options.chroma_epsilon);
  l1_flat.clear();
  chroma_flat.clear();
  lights.assign(std::size_t(layout.lightCount()), {});
  for (int r = 0; r < int(R); ++r) {
    if (l1_flat.size() + l1[std::size_t(r)].size() > std::size_t(INT32_MAX) ||
        chroma_flat.size() + chroma[std::size_t(r)].size() > std::size_t(INT32_MAX))
      throw Error(what + ": codebooks beyond 2^31 values");
    for (int a = 0; a < ringSize(r); ++a)
      lights[std::size_t(layout.light(r, a))] = {std::uint32_t(l1_flat.size()) + std::uint32_t(a),
                                                 std::uint32_t(chroma_flat.size()) + 2 * std::uint32_t(a),
                                                 std::uint32_t(r), std::uint32_t(ringSize(r))};
    l1_flat.insert(l1_flat.end(), l1[std::size_t(r)].begin(), l1[std::size_t(r)].end());
    for (std::int32_t g : chroma[std::size_t(r)]) chroma_flat.push_back(std::uint16_t(g));
  }
  auto scaledIndices = [](const std::vector<std::uint32_t>& index, const std::vector<std::uint16_t>& scale) {
    std::vector<ScaledIndex> codes(index.size());
    for (std::size_t i = 0; i < index.size(); ++i) codes[i] = {index[i], decodeVqScale(scale[i])};
    return codes;
  };
  auto ringCodes = [](const std::vector<std::uint32_t>& index, const std::vector<std::uint16_t>& scale,
                      const std::vector<std::uint32_t>& chroma_index) {
    std::vector<RingCode> codes(index.size());
    for (std::size_t i = 0; i < index.size(); ++i) codes[i] = {index[i], decodeVqScale(scale[i]), chroma_index[i]};
    return codes;
  };
  l2_codes = ringCodes(l2_index, l2_scale, l2_chroma);
  l3_packed.clear();
  l3_codes.clear();
  if (l2Count() <= 65536) {
    l3_packed.resize(l3_index.size());
    for (std::size_t i = 0; i < l3_index.size(); ++i) l3_packed[i] = {std::uint16_t(l3_index[i]), l3_scale[i]};
  } else {
    l3_codes = scaledIndices(l3_index, l3_scale);
  }
  if (options.levels == 1) {
    top_ring_codes = ringCodes(top_index, top_scale, top_chroma);
    top_codes.clear();
  } else {
    top_codes = scaledIndices(top_index, top_scale);
    top_ring_codes.clear();
  }
}

VqBtf::VqBtf(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) {}
int VqBtf::width() const { return impl_->width; }
int VqBtf::height() const { return impl_->height; }
std::string VqBtf::name() const { return impl_->name; }
const VqOptions& VqBtf::options() const { return impl_->options; }
const VqStats& VqBtf::stats() const { return impl_->stats; }

std::size_t VqBtf::lookupTableBytes() const {
  const Impl& m = *impl_;
  auto bytes = [](const auto& v) { return v.size() * sizeof(v[0]); };
  return bytes(m.l1_flat) + bytes(m.chroma_flat) + bytes(m.l2_codes) + bytes(m.l3_packed) + bytes(m.l3_codes) + bytes(m.top_codes) +
         bytes(m.top_ring_codes);
}

Rgb VqBtf::value(int x, int y, int view, int light) const {
  const Impl& m = *impl_;
  const std::size_t t = std::size_t(y) * std::size_t(m.width) + std::size_t(x);
  return m.sample(m.ringCode(t, view, int(m.lights[std::size_t(light)].ring)), light);
}

const BtfViewSet& VqBtf::views() const { return impl_->views; }

void VqBtf::loadView(int view, std::vector<Rgb>& out) const {
  const Impl& m = *impl_;
  m.views.require(view, m.name);
  const std::size_t T = std::size_t(m.width) * std::size_t(m.height);
  out.resize(T * std::size_t(m.layout.lightCount()));
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, T, 1024), [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t t = range.begin(); t != range.end(); ++t)
      for (int r = 0; r < m.layout.ringCount(); ++r) {
        const Impl::RingCode code = m.ringCode(t, view, r);
        for (int a = 0; a < m.layout.size(r); ++a) {
          const int l = m.layout.light(r, a);
          out[std::size_t(l) * T + t] = m.sample(code, l);
        }
      }
  });
}


Rgb VqBtf::weightedSum(int x, int y, const int* views, const int* lights, const float* weights, int count) const {
  const Impl& m = *impl_;
  const std::size_t t = std::size_t(y) * std::size_t(m.width) + std::size_t(x);
  Rgb sum(0.0f);
  if (m.options.levels == 1) {
    for (int k = 0; k < count; ++k)
      sum += m.sample(m.ringCode(t, views[k], int(m.lights[std::size_t(lights[k])].ring)), lights[k]) * weights[k];
    return sum;
  }
  // Interpolation stencils list a view's lights together: its slice code is walked once. The
  // codes first, then the stored values, then the arithmetic: the loads of one step do not wait
  // for another's (on tables past the L2 cache the lookups are misses, which then overlap).
  constexpr int kBlock = 16;
  std::array<Impl::RingCode, kBlock> codes;
  std::array<std::uint16_t, kBlock> value, chroma_r, chroma_b;
  for (int begin = 0; begin < count; begin += kBlock) {
    const int n = std::min(count - begin, kBlock);
    int slice_view = -1;
    Impl::ScaledIndex slice{};
    for (int k = 0; k < n; ++k) {
      const int v = views[begin + k];
      if (v != slice_view) slice = m.sliceCode(t, slice_view = v);
      codes[std::size_t(k)] = m.ringCode(slice, int(m.lights[std::size_t(lights[begin + k])].ring));
    }
    for (int k = 0; k < n; ++k) {
      const Impl::LightAddress& at = m.lights[std::size_t(lights[begin + k])];
      const Impl::RingCode& c = codes[std::size_t(k)];
      const std::uint16_t* q = &m.chroma_flat[at.chroma + 2 * std::size_t(c.chroma) * at.size];
      value[std::size_t(k)] = m.l1_flat[at.l1 + std::size_t(c.entry) * at.size];
      chroma_r[std::size_t(k)] = q[0];
      chroma_b[std::size_t(k)] = q[1];
    }
    for (int k = 0; k < n; ++k)
      sum += Impl::decodeSample(codes[std::size_t(k)].scale, value[std::size_t(k)], chroma_r[std::size_t(k)],
                                chroma_b[std::size_t(k)], m.chroma_step) *
             weights[begin + k];
  }
  return sum;
}

const BtfRingLayout& VqBtf::ringLayout() const { return impl_->layout; }

VqBtf::WeightedRings VqBtf::weightedRings(std::span<const float> light_weight) const {
  const Impl& m = *impl_;
  if (light_weight.size() != std::size_t(m.layout.lightCount()))
    throw Error("VqBtf::weightedRings: " + std::to_string(light_weight.size()) + " weights for " +
                std::to_string(m.layout.lightCount()) + " lights");
  WeightedRings out;
  const std::size_t R = m.ringCount();
  out.cdf.resize(R);
  out.sum.resize(R);
  std::array<float, BtfRingLayout::kBandSize> values;  // one entry, decoded and weighted
  for (int r = 0; r < int(R); ++r) {
    const std::size_t n = std::size_t(m.ringSize(r)), count = m.l1Count(r);
    auto& cdf = out.cdf[std::size_t(r)];
    auto& sum = out.sum[std::size_t(r)];
    cdf.resize(count * (n + 1));
    sum.resize(count);
    for (std::size_t e = 0; e < count; ++e) {
      for (std::size_t a = 0; a < n; ++a)
        values[a] = decodeVqEntryValue(m.l1[std::size_t(r)][e * n + a]) * light_weight[std::size_t(m.layout.light(r, int(a)))];
      sum[e] = float(buildCdf1D(std::span<const float>(values.data(), n), std::span<float>(&cdf[e * (n + 1)], n + 1)) * double(n));
    }
  }
  if (m.options.levels >= 2) {
    const std::size_t entries = m.l2Count();
    out.slice_cdf.resize(entries * (R + 1));
    out.slice_total.resize(entries);
    std::vector<float> mass(R);
    for (std::size_t i = 0; i < entries; ++i) {
      for (std::size_t r = 0; r < R; ++r) {
        const Impl::RingCode& c = m.l2_codes[i * R + r];
        mass[r] = std::max(c.scale * out.sum[r][c.entry], 0.0f);
      }
      out.slice_total[i] = float(buildCdf1D(mass, std::span<float>(&out.slice_cdf[i * (R + 1)], R + 1)) * double(R));
    }
  }
  return out;
}

VqBtf::SliceCode VqBtf::sliceCode(int x, int y, int view) const {
  const Impl& m = *impl_;
  const std::size_t t = std::size_t(y) * std::size_t(m.width) + std::size_t(x);
  if (m.options.levels == 1) return {t, view, 0, 1.0f};
  const Impl::ScaledIndex c = m.sliceCode(t, view);
  return {t, view, c.entry, c.scale};
}

void VqBtf::prefetch(const SliceCode& slice) const {
  const Impl& m = *impl_;
  if (m.options.levels == 1) return;
  const Impl::RingCode* row = &m.l2_codes[std::size_t(slice.entry) * m.ringCount()];
  for (std::size_t r = 0; r < m.ringCount(); r += 64 / sizeof(Impl::RingCode)) __builtin_prefetch(row + r);
  __builtin_prefetch(row + m.ringCount() - 1);
}

static VqBtf::Impl::RingCode sliceRingCode(const VqBtf::Impl& m, const VqBtf::SliceCode& slice, int ring) {
  if (m.options.levels == 1) return m.ringCode(slice.texel, slice.view, ring);
  return m.ringCode(VqBtf::Impl::ScaledIndex{slice.entry, slice.scale}, ring);
}

VqBtf::LightRing VqBtf::lightRing(const SliceCode& slice, int ring, const WeightedRings& weighted) const {
  const Impl& m = *impl_;
  const Impl::RingCode code = sliceRingCode(m, slice, ring);
  const std::size_t n = std::size_t(m.ringSize(ring)), e = code.entry;
  return {&weighted.cdf[std::size_t(ring)][e * (n + 1)], weighted.sum[std::size_t(ring)][e], code.scale,
          &m.l1[std::size_t(ring)][e * n]};
}

VqBtf::RingMarginal VqBtf::ringMarginal(const SliceCode& slice, const WeightedRings& weighted) const {
  const std::size_t R = impl_->ringCount();
  return {&weighted.slice_cdf[std::size_t(slice.entry) * (R + 1)], slice.scale * weighted.slice_total[slice.entry]};
}

float VqBtf::luminance(const SliceCode& slice, int light) const {
  const Impl& m = *impl_;
  const Impl::LightAddress& at = m.lights[std::size_t(light)];
  const Impl::RingCode code = sliceRingCode(m, slice, int(at.ring));
  return code.scale * decodeVqEntryValue(m.l1_flat[at.l1 + std::size_t(code.entry) * at.size]);
}

void VqBtf::lightRings(int x, int y, int view, std::span<LightRing> rings, const WeightedRings* weighted) const {
  const Impl& m = *impl_;
  const std::size_t t = std::size_t(y) * std::size_t(m.width) + std::size_t(x);
  const std::vector<std::vector<float>>& cdfs = weighted ? weighted->cdf : m.l1_cdf;
  const std::vector<std::vector<float>>& sums = weighted ? weighted->sum : m.l1_sum;
  // The slice's code once, then its rings (rather than one walk from the texel per ring).
  Impl::ScaledIndex slice{};
  if (m.options.levels >= 2) slice = m.sliceCode(t, view);
  for (int r = 0; r < m.layout.ringCount(); ++r) {
    const Impl::RingCode code = m.options.levels >= 2 ? m.ringCode(slice, r) : m.ringCode(t, view, r);
    const std::size_t n = std::size_t(m.ringSize(r)), e = code.entry;
    rings[std::size_t(r)] = {&cdfs[std::size_t(r)][e * (n + 1)], sums[std::size_t(r)][e], code.scale,
                             &m.l1[std::size_t(r)][e * n]};
  }
}

}  // namespace btf
