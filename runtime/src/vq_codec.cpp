// The VQ codec of a runtime file: the decoded codebooks of a .btfz (compress/vq_btf.h) as flat
// tables, walked as VqBtf walks them (top code -> level 3 -> level 2 -> level-1 value and chroma
// pair), with the same arithmetic (src/compress/vq_impl.h's decodeSample), so that every value is
// the library's bit for bit.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "codec.h"
#include "btf_runtime/file_layout.h"

namespace btfrt {

namespace {

using namespace file;
using detail::operator*;
using detail::operator+=;

class VqCodec final : public Codec {
 public:
  VqCodec(const unsigned char* data, std::size_t size, const std::string& what);

  Rgb value(int x, int y, int view, int light) const override {
    return sample(ringCode(texel(x, y), view, int(lights_[std::size_t(light)].ring)), light);
  }
  Rgb weightedSum(int x, int y, const int* views, const int* lights, const float* weights, int count) const override {
    const std::size_t t = texel(x, y);
    Rgb sum{};
    if (levels_ == 1) {
      for (int k = 0; k < count; ++k)
        sum += sample(ringCode(t, views[k], int(lights_[std::size_t(lights[k])].ring)), lights[k]) * weights[k];
      return sum;
    }
    // As VqBtf::weightedSum: a stencil lists a view's lights together, so its slice code is walked
    // once; the codes first, then the stored values, then the arithmetic, so that the loads of one
    // step do not wait for another's (cache misses overlap). The sum is the same, in the same order.
    constexpr int kBlock = 16;
    std::array<RingCode, kBlock> codes;
    std::array<std::uint16_t, kBlock> value, chroma_r, chroma_b;
    for (int begin = 0; begin < count; begin += kBlock) {
      const int n = std::min(count - begin, kBlock);
      int slice_view = -1;
      SliceCode slice{};
      for (int k = 0; k < n; ++k) {
        const int v = views[begin + k];
        if (v != slice_view) slice = sliceCode(t, slice_view = v);
        codes[std::size_t(k)] = ringCode(slice, int(lights_[std::size_t(lights[begin + k])].ring));
      }
      for (int k = 0; k < n; ++k) {
        const Light& at = lights_[std::size_t(lights[begin + k])];
        const RingCode& c = codes[std::size_t(k)];
        const std::uint16_t* q = &chroma_[at.chroma + 2 * std::size_t(c.chroma) * at.size];
        value[std::size_t(k)] = l1_[at.l1 + std::size_t(c.entry) * at.size];
        chroma_r[std::size_t(k)] = q[0];
        chroma_b[std::size_t(k)] = q[1];
      }
      for (int k = 0; k < n; ++k)
        sum += decode(codes[std::size_t(k)].scale, value[std::size_t(k)], chroma_r[std::size_t(k)], chroma_b[std::size_t(k)]) *
               weights[begin + k];
    }
    return sum;
  }
  void lightRings(int x, int y, int view, Rings& rings, float*) const override {
    const std::size_t t = texel(x, y);
    SliceCode slice{};
    if (levels_ >= 2) slice = sliceCode(t, view);
    for (int r = 0; r < detail::kRingCount; ++r) {
      const RingCode code = levels_ >= 2 ? ringCode(slice, r) : ringCode(t, view, r);
      const Ring& ring = rings_[std::size_t(r)];
      rings.cdf[std::size_t(r)] = &l1_cdf_[ring.cdf_start + std::size_t(code.entry) * (ring.size + 1)];
      // VqBtf::lightRings' scale x sum, as BtfMaterial's ring mass takes it.
      rings.luminance[std::size_t(r)] = std::max(code.scale * l1_sum_[ring.sum_start + code.entry], 0.0f);
    }
  }

 private:
  std::size_t texel(int x, int y) const { return std::size_t(y) * std::size_t(width) + std::size_t(x); }
  std::size_t slot(int view) const { return std::size_t(view_slot_[std::size_t(view)]); }
  SliceCode sliceCode(std::size_t t, int view) const {
    if (levels_ == 2) return top_codes_[t * view_count_ + slot(view)];
    const SliceCode c3 = top_codes_[t];
    const std::size_t k = std::size_t(c3.entry) * view_count_ + slot(view);
    SliceCode c2 = l3_packed_.empty() ? l3_codes_[k] : unpacked(l3_packed_[k]);
    c2.scale *= c3.scale;
    return c2;
  }
  RingCode ringCode(const SliceCode& slice, int r) const {
    RingCode c1 = l2_codes_[std::size_t(slice.entry) * detail::kRingCount + std::size_t(r)];
    c1.scale *= slice.scale;
    return c1;
  }
  RingCode ringCode(std::size_t t, int view, int r) const {
    if (levels_ == 1) return top_ring_codes_[(t * view_count_ + slot(view)) * detail::kRingCount + std::size_t(r)];
    return ringCode(sliceCode(t, view), r);
  }
  SliceCode unpacked(PackedCode p) const {
    const float power = detail::bitsFloat(std::uint32_t((p.scale >> 10) + 127 - 40) << 23);
    return {p.entry, p.scale == 0 ? 0.0f : scale_fractions_[p.scale & 1023u] * power};
  }
  Rgb sample(const RingCode& code, int light) const {
    const Light& at = lights_[std::size_t(light)];
    const std::uint16_t* q = &chroma_[at.chroma + 2 * std::size_t(code.chroma) * at.size];
    return decode(code.scale, l1_[at.l1 + std::size_t(code.entry) * at.size], q[0], q[1]);
  }
  // The stored value and chroma pair to RGB (vq_impl.h's decodeSample).
  Rgb decode(float scale, std::uint16_t value, std::uint16_t r, std::uint16_t b) const {
    const float lum = scale * (float(value) * (1.0f / 65535.0f));
    const float cr = float(r) * chroma_step_, cb = float(b) * chroma_step_;
    const float cg = std::max((1.0f - 0.2126f * cr - 0.0722f * cb) * (1.0f / 0.7152f), 0.0f);
    return {lum * cr, lum * cg, lum * cb};
  }

  int levels_ = 0;
  std::size_t view_count_ = 0;
  float chroma_step_ = 0;
  std::vector<std::int32_t> view_slot_;
  std::vector<Ring> rings_;
  std::vector<Light> lights_;
  std::vector<std::uint16_t> l1_, chroma_;
  std::vector<float> l1_cdf_, l1_sum_;
  std::vector<RingCode> l2_codes_, top_ring_codes_;
  std::vector<SliceCode> l3_codes_, top_codes_;
  std::vector<PackedCode> l3_packed_;
  std::vector<float> scale_fractions_;
};

[[noreturn]] void fail(const std::string& what, const std::string& problem) {
  throw std::runtime_error(what + ": " + problem);
}

template <class T>
std::vector<T> readSection(const unsigned char* data, std::size_t size, const Section& s, const char* name,
                           const std::string& what) {
  if (s.offset > size || s.bytes > size - s.offset)
    fail(what, std::string("section ") + name + " lies beyond the end of the file (truncated?)");
  if (s.bytes % sizeof(T) != 0) fail(what, std::string("section ") + name + " holds a partial record");
  std::vector<T> out(std::size_t(s.bytes / sizeof(T)));
  if (!out.empty()) std::memcpy(out.data(), data + s.offset, std::size_t(s.bytes));
  return out;
}

VqCodec::VqCodec(const unsigned char* data, std::size_t size, const std::string& what) {
  Header h;
  std::memcpy(&h, data, sizeof h);
  levels_ = int(h.levels);
  view_count_ = h.view_count;
  chroma_step_ = h.chroma_step;
  width = int(h.width);
  height = int(h.height);
  view_rings = int(h.view_rings);
  if (h.width < 1 || h.height < 1 || h.width > 65536 || h.height > 65536) fail(what, "invalid texel size");
  if (h.levels < 1 || h.levels > 3) fail(what, "invalid VQ level count " + std::to_string(h.levels));
  if (h.ring_count != std::uint32_t(detail::kRingCount) || h.light_count != std::uint32_t(detail::kDirectionCount))
    fail(what, "not on the 81-direction set (" + std::to_string(h.ring_count) + " rings, " +
                   std::to_string(h.light_count) + " lights)");
  if (h.view_rings < 1 || h.view_rings > 6 ||
      h.view_count != std::uint32_t(detail::kRingStarts[h.view_rings - 1] + detail::kRingSizes[h.view_rings - 1]))
    fail(what, "the views are not whole rings from the pole");
  if (!(std::isfinite(h.chroma_step) && h.chroma_step > 0.0f)) fail(what, "invalid chromaticity step");
  if (h.section_count != kVqSectionCount)
    fail(what, std::to_string(h.section_count) + " sections, the VQ codec has " + std::to_string(kVqSectionCount));
  if (size < kHeaderBytes + sizeof(Section) * kVqSectionCount) fail(what, "truncated section table");
  Section sections[kVqSectionCount];
  std::memcpy(sections, data + kHeaderBytes, sizeof sections);
  auto section = [&](auto type, VqSection s, const char* name) {
    return readSection<decltype(type)>(data, size, sections[s], name, what);
  };
  view_slot_ = section(std::int32_t{}, kViewSlot, "view_slot");
  rings_ = section(Ring{}, kRings, "rings");
  lights_ = section(Light{}, kLights, "lights");
  l1_ = section(std::uint16_t{}, kL1Values, "l1_values");
  chroma_ = section(std::uint16_t{}, kChroma, "chroma");
  l1_cdf_ = section(float{}, kL1Cdf, "l1_cdf");
  l1_sum_ = section(float{}, kL1Sum, "l1_sum");
  l2_codes_ = section(RingCode{}, kL2Codes, "l2_codes");
  l3_codes_ = section(SliceCode{}, kL3Codes, "l3_codes");
  l3_packed_ = section(PackedCode{}, kL3Packed, "l3_packed");
  scale_fractions_ = section(float{}, kScaleFractions, "scale_fractions");
  top_codes_ = section(SliceCode{}, kTopCodes, "top_codes");
  top_ring_codes_ = section(RingCode{}, kTopRingCodes, "top_ring_codes");

  // Every index inside its table, so that no lookup can read outside the file's arrays.
  auto require = [&](bool ok, const std::string& problem) {
    if (!ok) fail(what, problem);
  };
  require(view_slot_.size() == std::size_t(detail::kDirectionCount), "view_slot holds " + std::to_string(view_slot_.size()) + " entries, expected 81");
  for (std::size_t v = 0; v < view_slot_.size(); ++v) {
    const bool held = v < view_count_;  // whole rings from the pole: views 0 .. view_count - 1
    require(held ? view_slot_[v] >= 0 && std::size_t(view_slot_[v]) < view_count_ : view_slot_[v] == -1,
            "view_slot of view " + std::to_string(v) + " is invalid");
  }
  require(rings_.size() == std::size_t(detail::kRingCount), "rings holds " + std::to_string(rings_.size()) + " entries, expected 6");
  require(lights_.size() == std::size_t(detail::kDirectionCount), "lights holds " + std::to_string(lights_.size()) + " entries, expected 81");
  for (int r = 0; r < detail::kRingCount; ++r) {
    const Ring& g = rings_[std::size_t(r)];
    const std::string ring = "ring " + std::to_string(r);
    const std::uint64_t n = g.size;
    require(n == std::uint64_t(detail::kRingSizes[std::size_t(r)]) && g.first_light == std::uint32_t(detail::kRingStarts[std::size_t(r)]),
            ring + " is not the 81-direction set's");
    require(g.l1_entries >= 1 && std::uint64_t(g.l1_start) + n * g.l1_entries <= l1_.size(), ring + ": level-1 entries outside l1_values");
    require(g.chroma_entries >= 1 && std::uint64_t(g.chroma_start) + 2 * n * g.chroma_entries <= chroma_.size(),
            ring + ": chroma entries outside chroma");
    require(std::uint64_t(g.cdf_start) + (n + 1) * g.l1_entries <= l1_cdf_.size(), ring + ": CDFs outside l1_cdf");
    require(std::uint64_t(g.sum_start) + g.l1_entries <= l1_sum_.size(), ring + ": sums outside l1_sum");
    for (std::uint32_t a = 0; a < g.size; ++a) {
      const Light& l = lights_[g.first_light + a];
      require(l.ring == std::uint32_t(r) && l.size == g.size && l.l1 == g.l1_start + a && l.chroma == g.chroma_start + 2 * a,
              "light " + std::to_string(g.first_light + a) + " does not address its ring's entries");
    }
  }
  auto checkRingCodes = [&](const std::vector<RingCode>& codes, const char* name) {
    for (std::size_t i = 0; i < codes.size(); ++i) {
      const Ring& g = rings_[i % std::size_t(detail::kRingCount)];
      require(codes[i].entry < g.l1_entries && codes[i].chroma < g.chroma_entries,
              std::string(name) + " code " + std::to_string(i) + " is outside its codebook");
      require(std::isfinite(codes[i].scale) && codes[i].scale >= 0.0f, std::string(name) + " code " + std::to_string(i) + " has an invalid scale");
    }
  };
  auto checkSliceCodes = [&](const std::vector<SliceCode>& codes, std::size_t bound, const char* name) {
    for (std::size_t i = 0; i < codes.size(); ++i) {
      require(codes[i].entry < bound, std::string(name) + " code " + std::to_string(i) + " is outside its codebook");
      require(std::isfinite(codes[i].scale) && codes[i].scale >= 0.0f, std::string(name) + " code " + std::to_string(i) + " has an invalid scale");
    }
  };
  const std::size_t T = std::size_t(h.width) * std::size_t(h.height);
  auto requireCount = [&](std::size_t n, std::size_t expected, const char* name) {
    require(n == expected, std::string(name) + " holds " + std::to_string(n) + " records, expected " + std::to_string(expected));
  };
  if (levels_ == 1) {
    requireCount(top_ring_codes_.size(), T * view_count_ * std::size_t(detail::kRingCount), "top_ring_codes");
    checkRingCodes(top_ring_codes_, "top_ring_codes");
  } else {
    require(!l2_codes_.empty() && l2_codes_.size() % std::size_t(detail::kRingCount) == 0, "l2_codes is empty or has a partial entry");
    checkRingCodes(l2_codes_, "l2_codes");
    const std::size_t l2 = l2_codes_.size() / std::size_t(detail::kRingCount);
    if (levels_ == 2) {
      requireCount(top_codes_.size(), T * view_count_, "top_codes");
      checkSliceCodes(top_codes_, l2, "top_codes");
    } else {
      const std::size_t l3 = l3_codes_.size() + l3_packed_.size();
      require(l3_codes_.empty() != l3_packed_.empty() && l3 % view_count_ == 0,
              "level 3 is empty, in both forms, or has a partial entry");
      checkSliceCodes(l3_codes_, l2, "l3_codes");
      for (std::size_t i = 0; i < l3_packed_.size(); ++i)
        require(l3_packed_[i].entry < l2, "l3_packed code " + std::to_string(i) + " is outside its codebook");
      require(scale_fractions_.size() == 1024, "scale_fractions holds " + std::to_string(scale_fractions_.size()) + " values, expected 1024");
      for (float f : scale_fractions_) require(std::isfinite(f) && f >= 1.0f && f < 2.0f, "scale_fractions holds a value outside [1, 2)");
      requireCount(top_codes_.size(), T, "top_codes");
      checkSliceCodes(top_codes_, l3 / view_count_, "top_codes");
    }
  }
}

}  // namespace

std::shared_ptr<const Codec> readVqCodec(const unsigned char* data, std::size_t size, const std::string& what) {
  return std::make_shared<const VqCodec>(data, size, what);
}

}  // namespace btfrt
