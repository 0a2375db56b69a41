// BtfMaterial (material/btf_material.h) over in-memory and VQ-compressed tiny BTFs: eval returns
// the data at measured directions and texel centres and interpolates in between; the twofold
// binary-search sampler agrees with its pdf and passes the chi-square test (alpha = 0.01,
// 200,000 draws on 20 x 40 cells, fixed seeds) for a few views, on both paths.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "support/tier.h"
#include "btf/compress/vq_btf.h"
#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/rng.h"
#include "btf/material/btf_material.h"
#include "btf/sampling/chi2.h"
#include "btf_test_data.h"

namespace {

std::shared_ptr<const btf::BtfData> smallBtf() {
  static const auto data = std::make_shared<const btf::BtfData>(btf::test::makeGgxBtf(4, 4, false));
  return data;
}
std::shared_ptr<const btf::VqBtf> smallVq() {
  static const auto vq = std::make_shared<const btf::VqBtf>(btf::compressVq(*smallBtf(), {}));
  return vq;
}

void expectRgbNear(const btf::Rgb& a, const btf::Rgb& b, float rel) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], rel * std::max(1e-3f, std::abs(b[c])));
}

}  // namespace

TEST(BtfMaterial, EvalAtMeasuredDirectionsAndTexelCentresReturnsTheData) {
  const btf::BtfMaterial material(smallBtf());
  const auto& dirs = btf::btfDirections();
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x)
      for (int v : {0, 3, 20, 45, 80})
        for (int l : {0, 1, 6, 13, 40, 70}) {
          const glm::vec2 uv((float(x) + 0.5f) / 4.0f, (float(y) + 0.5f) / 4.0f);
          expectRgbNear(material.eval(dirs[std::size_t(l)].w, dirs[std::size_t(v)].w, uv), smallBtf()->at(x, y, v, l), 1e-4f);
        }
  // Wrapping: uv and uv + 1 are the same point; below the horizon nothing.
  const glm::vec3 wi = dirs[10].w, wo = dirs[30].w;
  expectRgbNear(material.eval(wi, wo, {1.125f, -0.875f}), material.eval(wi, wo, {0.125f, 0.125f}), 1e-5f);
  EXPECT_TRUE(material.eval(-wi, wo, {}).isBlack());
}

TEST(BtfMaterial, InterpolatesBetweenDirectionsAndTexels) {
  const btf::BtfMaterial material(smallBtf());
  const auto& dirs = btf::btfDirections();
  const glm::vec2 centre(0.125f, 0.125f);
  // Halfway in phi between lights 7 and 8 (ring 2, 30 degrees apart).
  const glm::vec3 mid_phi = btf::sphericalDirection(30.0f * btf::kPi / 180.0f, 15.0f * btf::kPi / 180.0f);
  expectRgbNear(material.eval(mid_phi, dirs[1].w, centre), 0.5f * (smallBtf()->at(0, 0, 1, 7) + smallBtf()->at(0, 0, 1, 8)), 1e-3f);
  // A quarter of the way in theta from ring 2 to ring 3 at phi = 0 (lights 7 and 19).
  const glm::vec3 quarter = btf::sphericalDirection(33.75f * btf::kPi / 180.0f, 0.0f);
  expectRgbNear(material.eval(quarter, dirs[1].w, centre), 0.75f * smallBtf()->at(0, 0, 1, 7) + 0.25f * smallBtf()->at(0, 0, 1, 19), 1e-3f);
  // Halfway between texels (0, 0) and (1, 0).
  expectRgbNear(material.eval(dirs[7].w, dirs[1].w, {0.25f, 0.125f}), 0.5f * (smallBtf()->at(0, 0, 1, 7) + smallBtf()->at(1, 0, 1, 7)), 1e-3f);
  // Nearest filtering picks the texel holding uv.
  const btf::BtfMaterial nearest(smallBtf(), btf::BtfTexelFilter::Nearest);
  expectRgbNear(nearest.eval(dirs[7].w, dirs[1].w, {0.26f, 0.01f}), smallBtf()->at(1, 0, 1, 7), 1e-4f);
}

TEST(BtfMaterial, EvaluatesStraightFromTheVqCodebooks) {
  const btf::BtfMaterial material(smallVq());
  const auto& dirs = btf::btfDirections();
  for (int v : {0, 25, 70})
    for (int l : {0, 9, 60}) expectRgbNear(material.eval(dirs[std::size_t(l)].w, dirs[std::size_t(v)].w, {0.375f, 0.625f}), smallVq()->value(1, 2, v, l), 1e-4f);
}

TEST(BtfMaterial, SampleAgreesWithPdfAndWeight) {
  for (const auto& lookup : {std::shared_ptr<const btf::BtfLookup>(smallBtf()), std::shared_ptr<const btf::BtfLookup>(smallVq())}) {
    const btf::BtfMaterial material(lookup);
    btf::Rng rng(5);
    int drawn = 0;
    for (int k = 0; k < 5000; ++k) {
      const glm::vec3 wo = btf::sphericalDirection(rng.uniform() * 1.5f, rng.uniform() * btf::kTwoPi);
      const glm::vec2 uv = rng.uniform2D();
      const auto s = material.sample(wo, uv, rng.uniform2D());
      if (!s) continue;
      ++drawn;
      ASSERT_GT(s->wi.z, 0.0f);
      EXPECT_NEAR(s->pdf, material.pdf(s->wi, wo, uv), 1e-4f * s->pdf);
      const btf::Rgb expected = material.eval(s->wi, wo, uv) * (s->wi.z / s->pdf);
      expectRgbNear(s->weight, expected, 1e-5f);
    }
    EXPECT_EQ(drawn, 5000);
  }
}

TEST(BtfMaterial, SampleDirectionIsSampleWithoutTheWeight) {
  const btf::BtfMaterial material(smallVq());
  btf::Rng rng(6);
  for (int k = 0; k < 2000; ++k) {
    const glm::vec3 wo = k % 100 == 7 ? glm::vec3(0, 0, -1) : btf::sphericalDirection(rng.uniform() * 1.5f, rng.uniform() * btf::kTwoPi);
    const glm::vec2 uv = rng.uniform2D(), u = rng.uniform2D();
    const auto s = material.sample(wo, uv, u);
    const auto d = material.sampleDirection(wo, uv, u);
    ASSERT_EQ(s.has_value(), d.has_value()) << k;
    if (!s) continue;
    EXPECT_EQ(s->wi, d->wi);
    EXPECT_EQ(s->pdf, d->pdf);
  }
}

BTF_STATISTICAL_TEST(BtfMaterial, SamplerPassesChiSquareOnDataAndVq) {
  btf::Chi2Options options;
  options.sample_count = 200'000;
  options.significance = 0.01;
  for (const auto& lookup : {std::shared_ptr<const btf::BtfLookup>(smallBtf()), std::shared_ptr<const btf::BtfLookup>(smallVq())}) {
    const btf::BtfMaterial material(lookup);
    const auto& dirs = btf::btfDirections();
    for (int view : {5, 65}) {
      const btf::Chi2Result r = btf::chi2TestMaterial(material, dirs[std::size_t(view)].w, {0.6f, 0.3f}, options);
      EXPECT_TRUE(r.accepted) << "view " << view << ": " << r.message;
    }
  }
}

TEST(BtfMaterial, OneTexelBtfIsABrdf) {
  const auto brdf = std::make_shared<const btf::BtfData>(btf::test::makeGgxBtf(1, 1, false));
  const btf::BtfMaterial material(brdf);
  const auto& dirs = btf::btfDirections();
  expectRgbNear(material.eval(dirs[12].w, dirs[50].w, {0.7f, 0.2f}), brdf->at(0, 0, 50, 12), 1e-4f);
  EXPECT_THROW(btf::BtfMaterial(nullptr), btf::Error);
}
