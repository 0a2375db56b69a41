// Piecewise-constant 1D distributions built into caller storage (cdf1d.h). Fixed seeds; the
// frequency check allows 5 standard deviations per cell (200,000 draws).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "btf/core/error.h"
#include "btf/core/rng.h"
#include "btf/core/cdf1d.h"

TEST(Cdf1D, SamplesCellsInProportionToTheirValuesWithMatchingPdf) {
  const std::array<float, 5> f{1.0f, 0.0f, 3.0f, 0.5f, 2.0f};
  std::array<float, 6> cdf{};  // on the stack: nothing allocated
  EXPECT_NEAR(btf::buildCdf1D(f, cdf), 6.5 / 5.0, 1e-6);
  std::array<int, 5> counts{};
  btf::Rng rng(3);
  constexpr int kDraws = 200'000;
  for (int k = 0; k < kDraws; ++k) {
    const btf::Cdf1DSample s = btf::sampleCdf1D(cdf, rng.uniform());
    ASSERT_EQ(s.cell, std::size_t(s.x * 5.0f));
    ASSERT_EQ(s.pdf, btf::pdfCdf1D(cdf, s.x));
    ++counts[s.cell];
  }
  for (int i = 0; i < 5; ++i) {
    const double p = f[i] / 6.5, sigma = std::sqrt(kDraws * p * (1 - p));
    EXPECT_NEAR(counts[i], kDraws * p, 5 * sigma + 1e-9) << "cell " << i;
    EXPECT_NEAR(btf::pdfCdf1D(cdf, (i + 0.5f) / 5.0f), 5.0 * p, 1e-5);
  }
  EXPECT_EQ(counts[1], 0);  // zero cells are never drawn
}

TEST(Cdf1D, AllZeroOrInvalidFunctionGetsTheUniformCdfAndZeroIntegral) {
  const std::array<float, 4> f{0.0f, -1.0f, std::nanf(""), 0.0f};
  std::array<float, 5> cdf{};
  EXPECT_EQ(btf::buildCdf1D(f, cdf), 0.0);
  EXPECT_FLOAT_EQ(btf::pdfCdf1D(cdf, 0.3f), 1.0f);
  EXPECT_EQ(btf::pdfCdf1D(cdf, 1.5f), 0.0f);
}

TEST(Cdf1D, DiscreteSampleReturnsIndexProbabilityAndReusableRemainder) {
  const std::array<float, 3> f{1.0f, 1.0f, 2.0f};
  std::array<float, 4> cdf{};
  btf::buildCdf1D(f, cdf);
  const btf::DiscreteSample d = btf::sampleDiscrete(cdf, 0.75f);
  EXPECT_EQ(d.index, 2u);
  EXPECT_FLOAT_EQ(d.probability, 0.5f);
  EXPECT_NEAR(d.remapped, 0.5f, 1e-6f);
  EXPECT_EQ(btf::sampleDiscrete(cdf, 0.0f).index, 0u);
  EXPECT_EQ(btf::sampleDiscrete(cdf, 0x1.fffffep-1f).index, 2u);
}

// The search picks its cell by counting (small CDFs) or by bisection (large ones): both must be
// std::upper_bound's cell for every u, on CDFs with empty cells (ties), at the edges and for NaN.
TEST(Cdf1D, CellSearchIsUpperBoundsForSmallAndLargeCdfs) {
  btf::Rng rng(11);
  for (int n : {1, 2, 5, 24, 32, 33, 200}) {
    std::vector<float> f(static_cast<std::size_t>(n)), cdf(static_cast<std::size_t>(n) + 1);
    for (float& v : f) v = rng.uniform() < 0.3f ? 0.0f : rng.uniform();  // some empty cells
    btf::buildCdf1D(f, cdf);
    std::vector<float> us{0.0f, 0x1.fffffep-1f, 1.0f, -0.5f, std::nanf("")};
    for (int k = 0; k < 2000; ++k) us.push_back(rng.uniform());
    for (std::size_t i = 1; i < cdf.size(); ++i) us.push_back(cdf[i]);  // exactly on the edges
    for (float u : us) {
      const auto it = std::upper_bound(cdf.begin() + 1, cdf.end() - 1, u);
      const std::size_t expected = std::size_t(it - cdf.begin()) - 1;
      ASSERT_EQ(btf::sampleDiscrete(cdf, u).index, std::min(expected, std::size_t(n) - 1)) << "n " << n << ", u " << u;
      ASSERT_EQ(btf::sampleCdf1D(cdf, u).cell, btf::sampleCdf1DInCell(cdf, expected, u).cell) << "n " << n << ", u " << u;
    }
  }
}

TEST(Cdf1D, RejectsMismatchedSizes) {
  const std::array<float, 3> f{1.0f, 1.0f, 2.0f};
  std::array<float, 3> cdf{};
  EXPECT_THROW(btf::buildCdf1D(f, cdf), btf::Error);
}
