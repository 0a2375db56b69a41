// BtfLookup::values, the stream of measured-sample lookups: bit for bit value() on every form
// (the VqBtf's grouped lookups at three levels, its loop at one and two, the in-memory data), and the
// bad-input checks.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <memory>
#include <vector>

#include "btf/compress/vq_btf.h"
#include "btf/core/error.h"
#include "btf/core/rng.h"
#include "btf_test_data.h"
#include "compress/vq_impl.h"

namespace btf {
namespace {

std::vector<BtfSampleIndex> randomSamples(int width, int height, std::size_t n) {
  Rng rng(3);
  std::vector<BtfSampleIndex> s(n);
  for (auto& q : s)
    q = {int(rng.uniform() * float(width)) % width, int(rng.uniform() * float(height)) % height,
         int(rng.uniform() * kBtfDirectionCount) % kBtfDirectionCount,
         int(rng.uniform() * kBtfDirectionCount) % kBtfDirectionCount};
  s.back() = {width - 1, height - 1, kBtfDirectionCount - 1, kBtfDirectionCount - 1};  // the last entries
  s.front() = {0, 0, 0, 0};
  return s;
}

void expectStreamMatchesValue(const BtfLookup& btf, int width, int height) {
  const std::vector<BtfSampleIndex> samples = randomSamples(width, height, 1001);  // a partial last block
  std::vector<Rgb> out(samples.size());
  btf.values(samples, out);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Rgb v = btf.value(samples[i].x, samples[i].y, samples[i].view, samples[i].light);
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(std::bit_cast<std::uint32_t>(v[c]), std::bit_cast<std::uint32_t>(out[i][c])) << "sample " << i;
  }
}

TEST(BtfValues, StreamGivesValueBitForBitOnEveryForm) {
  const BtfData data = test::makeGgxBtf(6, 5, true);
  expectStreamMatchesValue(data, 6, 5);
  for (int levels : {1, 2, 3}) {
    VqOptions o;
    o.levels = levels;
    const VqBtf vq = compressVq(data, o);
    SCOPED_TRACE(levels);
    expectStreamMatchesValue(vq, 6, 5);
  }
}

// values() groups and prefetches differently for tables past the L2 cache (a full-size BTF's) than
// within it; both give value() bit for bit, full groups and a partial last one, here on a small file.
TEST(BtfValues, BothGroupingsOfTheThreeLevelStreamGiveValueBitForBit) {
  const VqBtf vq = compressVq(test::makeGgxBtf(6, 5, true), {});
  ASSERT_EQ(vq.options().levels, 3);
  const std::vector<BtfSampleIndex> samples = randomSamples(6, 5, 1001);
  for (bool past_l2 : {false, true}) {
    std::vector<Rgb> out(samples.size(), Rgb(-1.0f));
    decodeThreeLevelStream(vq.impl(), samples, out, past_l2);
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const Rgb v = vq.value(samples[i].x, samples[i].y, samples[i].view, samples[i].light);
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(std::bit_cast<std::uint32_t>(v[c]), std::bit_cast<std::uint32_t>(out[i][c]))
            << "sample " << i << (past_l2 ? ", tables past L2" : ", tables within L2");
    }
  }
}

// Lookups decode level-3 scale codes through lookupVqScale (vq_impl.h), the reader's tables through
// decodeVqScale: the same float for every code.
TEST(BtfValues, LookupScaleIsTheStoredScaleForEveryCode) {
  for (std::uint32_t q = 0; q <= 0xffff; ++q)
    ASSERT_EQ(std::bit_cast<std::uint32_t>(lookupVqScale(std::uint16_t(q))),
              std::bit_cast<std::uint32_t>(decodeVqScale(std::uint16_t(q))))
        << "code " << q;
}

// Level 3's table in its two forms (4-byte records while level 2 has at most 2^16 entries, else
// entry and float scale): the same values through value(), values() and both groupings.
TEST(BtfValues, BothFormsOfTheLevelThreeTableDecodeAlike) {
  const VqBtf packed = compressVq(test::makeGgxBtf(6, 5, true), {});
  ASSERT_FALSE(packed.impl().l3_packed.empty());
  ASSERT_TRUE(packed.impl().l3_codes.empty());
  auto wide_impl = std::make_shared<VqBtf::Impl>(packed.impl());
  for (const VqBtf::Impl::PackedIndex& p : wide_impl->l3_packed)
    wide_impl->l3_codes.push_back({p.entry, decodeVqScale(p.scale)});
  wide_impl->l3_packed.clear();
  const VqBtf wide(wide_impl);
  EXPECT_GT(wide.lookupTableBytes(), packed.lookupTableBytes());
  const std::vector<BtfSampleIndex> samples = randomSamples(6, 5, 1001);
  std::vector<Rgb> a(samples.size()), b(samples.size());
  for (bool past_l2 : {false, true}) {
    decodeThreeLevelStream(packed.impl(), samples, a, past_l2);
    decodeThreeLevelStream(wide.impl(), samples, b, past_l2);
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const auto [x, y, view, light] = samples[i];
      ASSERT_EQ(a[i], b[i]) << "sample " << i;
      ASSERT_EQ(packed.value(x, y, view, light), wide.value(x, y, view, light)) << "sample " << i;
    }
  }
  expectStreamMatchesValue(wide, 6, 5);
}

TEST(BtfValues, RejectsIndicesOutsideTheBtfAndSpansOfDifferentSizes) {
  const BtfData data = test::makeGgxBtf(4, 4, false);
  const VqBtf vq = compressVq(data, {});
  std::vector<Rgb> out(1);
  for (const BtfLookup* btf : {static_cast<const BtfLookup*>(&data), static_cast<const BtfLookup*>(&vq)}) {
    for (const BtfSampleIndex bad : {BtfSampleIndex{4, 0, 0, 0}, BtfSampleIndex{0, -1, 0, 0},
                                     BtfSampleIndex{0, 0, 81, 0}, BtfSampleIndex{0, 0, 0, -3}}) {
      const std::vector<BtfSampleIndex> samples{bad};
      EXPECT_THROW(btf->values(samples, out), Error);
    }
    const std::vector<BtfSampleIndex> two(2, BtfSampleIndex{0, 0, 0, 0});
    EXPECT_THROW(btf->values(two, out), Error);
  }
}

}  // namespace
}  // namespace btf
