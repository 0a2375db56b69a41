// The virtual gonioreflectometer of `btf-datagen btf` (data-gen/synthetic): a flat sample gives the
// material's f exactly, self-shadowing darkens grazing light on bumpy samples, values are finite
// and >= 0, and the output depends on the seed only (not on the thread count).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <memory>
#include <vector>

#include "btf/core/math.h"
#include "btf/material/ggx.h"
#include "btf/material/lambert.h"
#include "btf_patterns.h"
#include "synthetic_btf.h"

namespace btf::synthetic {
namespace {

constexpr BtfPattern kPatterns[] = {BtfPattern::Fabric, BtfPattern::Stones, BtfPattern::Paint, BtfPattern::Leather};

TEST(SyntheticBtf, FlatLambertGivesAlbedoOverPiAtEveryEntry) {
  const Rgb albedo(0.2f, 0.5f, 0.8f);
  const SyntheticBtf btf(Microgeometry(5, 4, 3, std::make_shared<Lambert>(albedo)), "flat");
  const Rgb expected = albedo * kInvPi;
  std::vector<Rgb> values;
  for (int v = 0; v < kBtfDirectionCount; ++v) {
    btf.loadView(v, values);
    ASSERT_EQ(values.size(), std::size_t(kBtfDirectionCount) * 20);
    // Every light of the set is above the horizon (theta <= 75 degrees).
    for (std::size_t i = 0; i < values.size(); ++i)
      ASSERT_EQ(values[i], expected) << "view " << v << " light " << i / 20 << " texel " << i % 20;
  }
}

TEST(SyntheticBtf, FlatGlossyMaterialGivesItsBrdfExactly) {
  // The tangent frame of a flat hit point is the reference frame, so f is evaluated at the
  // measured directions themselves.
  const auto ggx = std::make_shared<Ggx>(Rgb(0.3f, 0.2f, 0.1f), Rgb(0.04f), 0.2f, 0.5f);
  Microgeometry geometry(3, 3, 2, ggx);
  for (float& h : geometry.heights) h = 1.5f;  // any constant height: no parallax, no shadow
  const SyntheticBtf btf(std::move(geometry), "flat-ggx");
  std::vector<Rgb> values;
  for (int v = 0; v < kBtfDirectionCount; v += 4) {
    btf.loadView(v, values);
    for (int l = 0; l < kBtfDirectionCount; ++l) {
      const Rgb f = ggx->eval(btfDirections()[std::size_t(l)].w, btfDirections()[std::size_t(v)].w);
      for (std::size_t t = 0; t < 9; ++t) ASSERT_EQ(values[std::size_t(l) * 9 + t], f) << "view " << v << " light " << l;
    }
  }
}

// Mean over texels of the red channel at one view and light.
double meanAt(const std::vector<Rgb>& view_values, int light, std::size_t texels) {
  double sum = 0;
  for (std::size_t t = 0; t < texels; ++t) sum += view_values[std::size_t(light) * texels + t].r;
  return sum / double(texels);
}

TEST(SyntheticBtf, SelfShadowingDarkensGrazingLightOnBumpyPatterns) {
  // Each pattern's height field with one Lambertian material: a flat sample gives albedo/pi for
  // every light, so the ratio grazing/overhead is 1 there; on the bumpy one, shadows must pull
  // it below 1 and clearly below the same field rendered without shadow rays (seen in Release:
  // shadowed 0.95..0.98, unshadowed 1.08..1.19 at view 0, seed 3).
  const Rgb albedo(0.5f);
  const int grazing = btfDirectionIndex(5, 0);  // theta 75, phi 0
  for (BtfPattern pattern : kPatterns) {
    Microgeometry geometry = makePatternMicrogeometry(pattern, 24, 24, 3);
    geometry.materials = {std::make_shared<Lambert>(albedo)};
    std::fill(geometry.material_ids.begin(), geometry.material_ids.end(), 0);
    std::fill(geometry.tints.begin(), geometry.tints.end(), Rgb(1.0f));
    const SyntheticBtf shadowed(geometry, "shadowed");
    const SyntheticBtf unshadowed(geometry, "unshadowed", SyntheticBtfOptions{false});
    std::vector<Rgb> a, b;
    shadowed.loadView(0, a);
    unshadowed.loadView(0, b);
    const std::size_t texels = shadowed.texelCount();
    const double ratio_shadowed = meanAt(a, grazing, texels) / meanAt(a, 0, texels);
    const double ratio_unshadowed = meanAt(b, grazing, texels) / meanAt(b, 0, texels);
    // Flat: exactly 1. Without shadows the ratio even exceeds 1 (facets turned away from the light
    // count 0, not negative), so the shadow rays must do all of the darkening.
    EXPECT_LT(ratio_shadowed, 0.99) << btfPatternName(pattern);
    EXPECT_LT(ratio_shadowed, ratio_unshadowed - 0.05) << btfPatternName(pattern);
    EXPECT_EQ(meanAt(a, 0, texels), meanAt(b, 0, texels)) << "nothing is shadowed from overhead";
  }
}

TEST(SyntheticBtf, PatternValuesAreFiniteNonNegativeAndNotAllZero) {
  for (BtfPattern pattern : kPatterns) {
    const auto btf = makeSyntheticBtf(pattern, 16, 16, 5);
    std::vector<Rgb> values;
    std::size_t positive = 0, total = 0;
    for (int v = 0; v < kBtfDirectionCount; ++v) {
      btf->loadView(v, values);
      for (const Rgb& c : values) {
        ASSERT_TRUE(c.isFinite() && c.minComponent() >= 0.0f) << btf->name() << " view " << v;
        positive += c.maxComponent() > 0.0f;
      }
      total += values.size();
    }
    EXPECT_GT(positive, total / 2) << btf->name();
    EXPECT_LT(positive, total) << btf->name() << ": some entries are in shadow or masked";
  }
}

TEST(SyntheticBtf, SameSeedSameValuesWhateverTheThreadCount) {
  for (BtfPattern pattern : kPatterns) {
    std::vector<Rgb> one, two, other_seed;
    {
      tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 1);
      makeSyntheticBtf(pattern, 16, 16, 9)->loadView(40, one);
    }
    {
      tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
      makeSyntheticBtf(pattern, 16, 16, 9)->loadView(40, two);
    }
    makeSyntheticBtf(pattern, 16, 16, 10)->loadView(40, other_seed);
    EXPECT_EQ(one, two) << btfPatternName(pattern);
    EXPECT_NE(one, other_seed) << btfPatternName(pattern);
  }
}

TEST(SyntheticBtf, PatternsDoNotRepeatWithinThePatch) {
  // A tileable pattern could still be one small tile repeated; compare the texture of the
  // overhead view with every shift of itself: none may match closely.
  constexpr int kSize = 32;
  for (BtfPattern pattern : kPatterns) {
    const auto btf = makeSyntheticBtf(pattern, kSize, kSize, 2);
    std::vector<Rgb> values;
    btf->loadView(0, values);
    const int light = btfDirectionIndex(2, 3);  // theta 30
    auto at = [&](int x, int y) { return values[std::size_t(light) * kSize * kSize + std::size_t(y) * kSize + std::size_t(x)].luminance(); };
    double energy = 0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) energy += double(at(x, y)) * at(x, y);
    double closest = 1e30;
    for (int dy = 0; dy < kSize; ++dy)
      for (int dx = 0; dx < kSize; ++dx) {
        if (dx == 0 && dy == 0) continue;
        double diff = 0;
        for (int y = 0; y < kSize; ++y)
          for (int x = 0; x < kSize; ++x) {
            const double d = at(x, y) - at((x + dx) % kSize, (y + dy) % kSize);
            diff += d * d;
          }
        closest = std::min(closest, diff / energy);
      }
    EXPECT_GT(closest, 0.01) << btfPatternName(pattern) << ": a shifted copy matches within 1% of the energy";
  }
}

TEST(SyntheticBtf, ObliqueViewsShowParallax) {
  // The texel shows what its view ray hits: on a bumpy field at 75 degrees that is not the point
  // under the texel centre, on a flat one it is.
  const auto btf = makeSyntheticBtf(BtfPattern::Stones, 16, 16, 1);
  const glm::vec3 wo = btfDirections()[std::size_t(btfDirectionIndex(5, 0))].w;
  double shift = 0;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      const glm::vec3 hit = btf->viewHit(x, y, wo);
      shift += std::abs(hit.x - (float(x) + 0.5f));
      EXPECT_NEAR(hit.y, float(y) + 0.5f, 1e-4f) << "the view ray runs in the x-z plane";
      // hit.z is the height there and tan(75) * height the horizontal offset.
      EXPECT_NEAR(hit.x - (float(x) + 0.5f), hit.z * wo.x / wo.z, 1e-3f);
    }
  EXPECT_GT(shift / 256.0, 0.2);
}

}  // namespace
}  // namespace btf::synthetic
