// analyzeCompressibility on BTFs whose answer is known by construction: scaled copies of a few
// prototypes (distance 0, as many entries and as much rank as prototypes), independent random
// texels (nothing to reuse, full rank), two texels checked against a closed form, and the errors.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <string>
#include <vector>

#include "btf/compress/compressibility.h"
#include "btf/core/error.h"
#include "btf/core/rng.h"
#include "btf_test_data.h"

namespace btf::test {
namespace {

constexpr int kPairs = kBtfDirectionCount * kBtfDirectionCount;

// An exponentially distributed value (mean 1): random ABRDF entries whose vectors are far from
// parallel (cos ~ 0.5 between two of them), so distinct ones are told apart at every epsilon.
float exponential(Rng& rng) { return -std::log(1.0f - rng.uniform()); }

// A grey BTF whose texel t (row-major) is scale[t] * prototype[t % prototypes] over all pairs.
BtfData scaledPrototypes(int width, int height, int prototypes, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<std::vector<float>> proto(static_cast<std::size_t>(prototypes), std::vector<float>(kPairs));
  for (auto& p : proto)
    for (float& v : p) v = exponential(rng);
  BtfData data(width, height, "prototypes");
  for (int t = 0; t < width * height; ++t) {
    const float scale = 0.5f + 1.5f * rng.uniform();
    const auto& p = proto[std::size_t(t % prototypes)];
    for (int v = 0; v < kBtfDirectionCount; ++v)
      for (int l = 0; l < kBtfDirectionCount; ++l)
        data.at(t % width, t / width, v, l) = Rgb(scale * p[std::size_t(v * kBtfDirectionCount + l)]);
  }
  return data;
}

TEST(Compressibility, ScaledCopiesOfFourPrototypesReuseEachOtherAtEveryEpsilon) {
  const BtfData data = scaledPrototypes(4, 4, 4, 11);
  const CompressibilityReport r = analyzeCompressibility(data, {});
  EXPECT_EQ(r.texels, 16);
  EXPECT_EQ(r.directions, 1024);
  for (int t = 0; t < 16; ++t) {
    EXPECT_LT(r.nearest_distance[std::size_t(t)], 1e-5) << t;
    EXPECT_EQ(r.nearest_texel[std::size_t(t)] % 4, t % 4) << "the nearest texel is a copy of the same prototype";
  }
  EXPECT_LT(r.nn_max, 1e-5);
  EXPECT_LT(r.nn_rel_error, 1e-5);
  ASSERT_EQ(r.at_epsilon.size(), 4u);
  for (const CompressibilityAtEpsilon& a : r.at_epsilon) {
    EXPECT_EQ(a.greedy_entries, 4) << a.epsilon;
    EXPECT_LT(a.greedy_rel_error, 1e-5) << a.epsilon;
    EXPECT_EQ(a.rank, 4) << a.epsilon;
    EXPECT_DOUBLE_EQ(a.ratio_u8_bound, 16.0 * 6561 * 3 / (2.0 * 4 * (16 + 6561))) << a.epsilon;
  }
  ASSERT_EQ(r.singular_values.size(), 16u);
  EXPECT_LT(r.singular_values[4], 1e-5 * r.singular_values[0]) << "rank 4 up to float rounding";
  EXPECT_GT(r.singular_values[3], 0.1 * r.singular_values[0]);
}

TEST(Compressibility, IndependentRandomTexelsCannotReuseEachOther) {
  Rng rng(5);
  BtfData data(8, 8, "random");
  for (int v = 0; v < kBtfDirectionCount; ++v)
    for (int l = 0; l < kBtfDirectionCount; ++l)
      for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) data.at(x, y, v, l) = Rgb(exponential(rng));
  const CompressibilityReport r = analyzeCompressibility(data, {});
  // Two independent exponential vectors have cos -> E[a]E[b] / E[a^2] = 1/2, d -> sqrt(3)/2 = 0.87;
  // over 1024 directions cos deviates by ~0.03, so even the best of 63 neighbours stays above 0.7.
  EXPECT_GT(r.nn_p10, 0.7);
  EXPECT_LE(r.nn_max, 1.0);
  EXPECT_GT(r.nn_rel_error, 0.7);
  ASSERT_EQ(r.at_epsilon.size(), 4u);
  for (const CompressibilityAtEpsilon& a : r.at_epsilon) {
    EXPECT_EQ(a.greedy_entries, 64) << a.epsilon;
    EXPECT_EQ(a.greedy_rel_error, 0.0) << "every texel is its own entry";
  }
  // Beyond the mean direction (half the energy) the energy spreads over the other 63 components,
  // each ~0.8 % (> 0.02^2 = 0.04 %): all 64 are needed at epsilon 0.02.
  EXPECT_EQ(r.at_epsilon[0].rank, 64);
  EXPECT_GT(r.at_epsilon[3].rank, 32) << "even at 0.2 most components are needed";
}

TEST(Compressibility, TwoTexelsMatchTheClosedForm) {
  BtfData data(2, 1, "two");
  Rng rng(3);
  for (int v = 0; v < kBtfDirectionCount; ++v)
    for (int l = 0; l < kBtfDirectionCount; ++l) {
      const float a = 1.0f + rng.uniform();
      data.at(0, 0, v, l) = Rgb(a);
      data.at(1, 0, v, l) = Rgb(2.0f * a + 0.1f * (rng.uniform() - 0.5f));
    }
  // Reference in double from the stored luminances over all 6561 pairs.
  double aa = 0, bb = 0, ab = 0;
  for (int v = 0; v < kBtfDirectionCount; ++v)
    for (int l = 0; l < kBtfDirectionCount; ++l) {
      const double a = data.at(0, 0, v, l).luminance(), b = data.at(1, 0, v, l).luminance();
      aa += a * a, bb += b * b, ab += a * b;
    }
  const double d = std::sqrt(1.0 - ab * ab / (aa * bb));
  const double trace = aa + bb, det = aa * bb - ab * ab;
  const double smallest = (trace - std::sqrt(trace * trace - 4 * det)) / 2;  // of the 2 x 2 Gram matrix
  const double rank1_error = std::sqrt(smallest / trace);
  ASSERT_GT(d, 1e-3);
  ASSERT_LT(rank1_error, 0.5 * d) << "two vectors: tail <= d^2/4, so 0.25 d and 0.6 d fall on either side";
  ASSERT_GT(rank1_error, 0.25 * d);

  CompressibilityOptions options;
  options.directions = 0;
  options.epsilons = {0.25 * d, 0.6 * d, 2 * d};
  const CompressibilityReport r = analyzeCompressibility(data, options);
  EXPECT_EQ(r.directions, kPairs);
  EXPECT_NEAR(r.nearest_distance[0], d, 1e-6 * d);
  EXPECT_NEAR(r.nearest_distance[1], d, 1e-6 * d);
  EXPECT_EQ(r.nearest_texel[0], 1);
  EXPECT_EQ(r.nearest_texel[1], 0);
  EXPECT_NEAR(r.nn_p50, d, 1e-6 * d);
  EXPECT_NEAR(r.nn_rel_error, d, 1e-6 * d);
  ASSERT_EQ(r.singular_values.size(), 2u);
  EXPECT_NEAR(r.singular_values[1], std::sqrt(smallest), 1e-6 * std::sqrt(smallest));

  const auto& e = r.at_epsilon;
  EXPECT_EQ(e[0].greedy_entries, 2);
  EXPECT_EQ(e[0].rank, 2);
  EXPECT_EQ(e[0].rank_rel_error, 0.0);
  EXPECT_EQ(e[1].greedy_entries, 2) << "0.6 d < d: no reuse";
  EXPECT_EQ(e[1].rank, 1) << "but one basis vector suffices";
  EXPECT_NEAR(e[1].rank_rel_error, rank1_error, 1e-6 * rank1_error);
  EXPECT_EQ(e[2].greedy_entries, 1);
  EXPECT_NEAR(e[2].greedy_rel_error, std::sqrt(bb / trace) * d, 1e-6 * d) << "texel 1 coded from texel 0";
  EXPECT_EQ(e[2].rank, 1);
}

TEST(Compressibility, ExactCopiesInTheGgxPatternAreFoundAndThreadCountDoesNotMatter) {
  // makeGgxBtf with colour per texel: value = colour(x, y) * grey GGX(alpha(y), x % 3 == 0 ? 1 : 0.7),
  // so every texel has an exact scaled copy in its row (two anisotropy classes per row, 8 rows).
  const BtfData data = makeGgxBtf(8, 8, true);
  CompressibilityOptions options;
  options.epsilons = {1e-4, 0.02};
  CompressibilityReport one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = analyzeCompressibility(data, options);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = analyzeCompressibility(data, options);
  }
  EXPECT_LT(one.nn_max, 1e-4);
  EXPECT_LE(one.at_epsilon[0].greedy_entries, 16);
  EXPECT_LE(one.at_epsilon[1].greedy_entries, one.at_epsilon[0].greedy_entries);
  EXPECT_EQ(one.nearest_distance, two.nearest_distance);
  EXPECT_EQ(one.nearest_texel, two.nearest_texel);
  EXPECT_EQ(one.singular_values, two.singular_values);
  for (std::size_t i = 0; i < one.at_epsilon.size(); ++i) {
    EXPECT_EQ(one.at_epsilon[i].greedy_entries, two.at_epsilon[i].greedy_entries);
    EXPECT_EQ(one.at_epsilon[i].greedy_rel_error, two.at_epsilon[i].greedy_rel_error);
    EXPECT_EQ(one.at_epsilon[i].rank, two.at_epsilon[i].rank);
  }
  options.seed = 2;
  const CompressibilityReport other = analyzeCompressibility(data, options);
  EXPECT_NE(other.singular_values, one.singular_values) << "the seed chooses other directions";
}

TEST(Compressibility, RejectsTooFewTexelsBadOptionsAndBlackData) {
  const BtfData one_texel = scaledPrototypes(1, 1, 1, 1);
  try {
    analyzeCompressibility(one_texel, {});
    ADD_FAILURE() << "no error for one texel";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("at least 2 texels"), std::string::npos) << e.what();
  }
  const BtfData two = scaledPrototypes(2, 1, 2, 1);
  CompressibilityOptions bad;
  bad.directions = -1;
  EXPECT_THROW(analyzeCompressibility(two, bad), Error);
  for (double e : {0.0, 1.0, -0.1, std::nan("")}) {
    CompressibilityOptions o;
    o.epsilons = {0.02, e};
    EXPECT_THROW(analyzeCompressibility(two, o), Error) << e;
  }
  EXPECT_THROW(analyzeCompressibility(BtfData(2, 2), {}), Error) << "all zero";
  // Too large: refused before any view is read (the stub would throw a different message).
  struct Large final : BtfSource {
    int width() const override { return 129; }
    int height() const override { return 128; }
    std::string name() const override { return "large"; }
    void loadView(int, std::vector<Rgb>&) const override { throw Error("large: read"); }
  };
  try {
    analyzeCompressibility(Large(), {});
    ADD_FAILURE() << "no error for 129 x 128 texels";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("use a smaller BTF"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace btf::test
