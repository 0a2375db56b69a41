// BilinearWarp2D on small grids with parameters: the queries at fixed parameters (Fixed, what an
// RGL file's stream eval holds per wo) give the parameter calls' floats bit for bit, and sample()
// and invert() are inverse maps with the density eval() returns.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "btf/core/error.h"
#include "btf/core/rng.h"
#include "btf/core/bilinear_warp2d.h"

namespace {

// A 5 x 4 grid over two parameters (3 values of a, 2 of b): smooth positive values that differ
// per slice, so that every blend weight matters.
btf::BilinearWarp2D makeWarp(btf::BilinearWarp2D::Mode mode) {
  const int w = 5, h = 4;
  std::vector<float> data;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 2; ++b)
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) data.push_back(0.2f + float((x + 1) * (a + 1)) * 0.3f + float(y * (b + 2)) * 0.17f);
  return btf::BilinearWarp2D(w, h, data, {{0.0f, 0.5f, 1.5f}, {0.0f, 1.0f}}, mode);
}

TEST(BilinearWarp2D, FixedQueriesAreTheParameterQueriesBitForBit) {
  const btf::BilinearWarp2D warp = makeWarp(btf::BilinearWarp2D::Mode::Distribution);
  btf::Rng rng(3, 0);
  // Parameters at nodes, between them and beyond both ends (clamped).
  for (const float a : {0.0f, 0.3f, 0.5f, 1.2f, 1.5f, 2.0f, -1.0f})
    for (const float b : {0.0f, 0.25f, 1.0f}) {
      const float params[2] = {a, b};
      const btf::BilinearWarp2D::Fixed fixed = warp.fixed(params);
      for (int i = 0; i < 200; ++i) {
        const glm::vec2 u = rng.uniform2D();
        const auto s1 = warp.sample(u, params), s2 = fixed.sample(u);
        ASSERT_EQ(s1.p, s2.p);
        ASSERT_EQ(s1.pdf, s2.pdf);
        const auto i1 = warp.invert(u, params), i2 = fixed.invert(u);
        ASSERT_EQ(i1.p, i2.p);
        ASSERT_EQ(i1.pdf, i2.pdf);
        ASSERT_EQ(warp.eval(u, params), fixed.eval(u));
      }
    }
}

TEST(BilinearWarp2D, EveryLastValueAtFixedLeadingParametersIsEvalPerValue) {
  const btf::BilinearWarp2D warp = makeWarp(btf::BilinearWarp2D::Mode::Interpolant);
  btf::Rng rng(4, 0);
  for (const float a : {0.0f, 0.7f, 1.5f}) {
    const float leading[1] = {a};
    const btf::BilinearWarp2D::Fixed fixed = warp.fixedLeading(leading);
    for (int i = 0; i < 200; ++i) {
      const glm::vec2 p = rng.uniform2D();
      float both[2], direct[2];
      fixed.evalAtEveryLastValue(p, both);
      warp.evalAtEveryLastValue(p, leading, direct);
      for (int k = 0; k < 2; ++k) {
        const float params[2] = {a, float(k)};
        ASSERT_EQ(both[k], warp.eval(p, params)) << "value " << k;
        ASSERT_EQ(both[k], direct[k]);
      }
    }
  }
  float one[1];
  EXPECT_THROW(warp.fixedLeading(std::vector<float>{0.0f, 1.0f}), btf::Error);
  EXPECT_THROW(warp.fixedLeading(std::vector<float>{0.0f}).evalAtEveryLastValue({0.5f, 0.5f}, one), btf::Error);
}

TEST(BilinearWarp2D, SampleAndInvertAreInverseWithTheDensityOfEval) {
  const btf::BilinearWarp2D warp = makeWarp(btf::BilinearWarp2D::Mode::Distribution);
  btf::Rng rng(5, 0);
  const float params[2] = {0.9f, 0.4f};
  const btf::BilinearWarp2D::Fixed fixed = warp.fixed(params);
  for (int i = 0; i < 500; ++i) {
    const glm::vec2 u = rng.uniform2D();
    const auto s = fixed.sample(u);
    const auto back = fixed.invert(s.p);
    EXPECT_NEAR(back.p.x, u.x, 2e-5f);
    EXPECT_NEAR(back.p.y, u.y, 2e-5f);
    EXPECT_NEAR(s.pdf, fixed.eval(s.p), 1e-5f * s.pdf);
  }
  // An interpolant has no distribution to sample.
  const btf::BilinearWarp2D interpolant = makeWarp(btf::BilinearWarp2D::Mode::Interpolant);
  EXPECT_THROW(interpolant.fixed(params).sample({0.5f, 0.5f}), btf::Error);
  EXPECT_THROW(interpolant.fixed(params).invert({0.5f, 0.5f}), btf::Error);
}

}  // namespace
