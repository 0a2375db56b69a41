// Fits to BTF texels (fit/btf_texel.h, fitAnalytic on scattered data): a texel or the mean over
// texels comes out of the BTF as a one-texel BTF, its entries become measurements at the measured
// direction pairs, and a fit to a texel that holds an analytic model recovers the model.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "support/tier.h"
#include "btf/core/btf_directions.h"
#include "btf/core/error.h"
#include "btf/fit/analytic_fit.h"
#include "btf/fit/btf_texel.h"
#include "btf/material/ggx.h"
#include "fit_expectations.h"

namespace btf {
namespace {

using testing::HasSubstr;

// Value of texel (x, y) at (view, light): distinct for every entry.
Rgb patternValue(int x, int y, int view, int light) {
  return Rgb(float(x + 1), float(y + 1), 0.01f * float(view) + 0.0001f * float(light));
}

TEST(BtfTexel, PicksTheTexelOrTheMeanOverTexels) {
  const BtfViewSet views = BtfViewSet::upToTheta(15.0f);
  BtfData btf(3, 2, "pattern", views);
  for (const int v : views.views())
    for (int light = 0; light < kBtfDirectionCount; ++light)
      for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x) btf.at(x, y, v, light) = patternValue(x, y, v, light);

  const BtfData texel = btfTexel(btf, glm::ivec2(2, 1));
  const BtfData mean = btfTexel(btf, std::nullopt);
  ASSERT_EQ(texel.width(), 1);
  ASSERT_EQ(texel.views().count(), views.count());
  for (const int v : views.views())
    for (int light = 0; light < kBtfDirectionCount; ++light) {
      EXPECT_EQ(texel.at(0, 0, v, light), patternValue(2, 1, v, light));
      const Rgb m = mean.at(0, 0, v, light);
      EXPECT_FLOAT_EQ(m.r, 2.0f);  // mean of x + 1 over x = 0, 1, 2
      EXPECT_FLOAT_EQ(m.g, 1.5f);  // mean of y + 1 over y = 0, 1
      EXPECT_FLOAT_EQ(m.b, patternValue(0, 0, v, light).b);
    }
  try {
    (void)btfTexel(btf, glm::ivec2(3, 0));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("pattern: texel (3, 0) lies outside its 3 x 2 texels"));
  }
  EXPECT_THROW((void)btfTexel(btf, glm::ivec2(0, -1)), Error);

  // Measurements: wi the light, wo the view, one per held view and light.
  const std::vector<MeasuredReflectance> m = texelMeasurements(texel);
  ASSERT_EQ(m.size(), std::size_t(views.count()) * kBtfDirectionCount);
  const int second_view = views.view(1);
  const MeasuredReflectance& e = m[kBtfDirectionCount + 5];
  EXPECT_EQ(e.wi, btfDirections()[5].w);
  EXPECT_EQ(e.wo, btfDirections()[std::size_t(second_view)].w);
  EXPECT_EQ(e.f, patternValue(2, 1, second_view, 5));
  EXPECT_THROW((void)texelMeasurements(btf), Error);  // not a one-texel BTF
}

// A BTF whose texel (1, 0) is a GGX and whose texel (0, 0) is not: the fit to texel (1, 0) at the
// 81 x 81 measured pairs recovers the GGX within 5% (noiseless data, as the table fits).
BTF_SLOW_TEST(AnalyticFit, RecoversGgxFromABtfTexel) {
  const Rgb kd(0.35f, 0.25f, 0.1f), f0(0.04f, 0.05f, 0.07f);
  const Ggx truth(kd, f0, 0.25f, 0.25f);
  BtfData btf(2, 1, "ggx-texel");
  for (int v = 0; v < kBtfDirectionCount; ++v)
    for (int light = 0; light < kBtfDirectionCount; ++light) {
      btf.at(0, 0, v, light) = Rgb(0.5f);
      btf.at(1, 0, v, light) = truth.eval(btfDirections()[std::size_t(light)].w, btfDirections()[std::size_t(v)].w);
    }
  const std::vector<MeasuredReflectance> data = texelMeasurements(btfTexel(btf, glm::ivec2(1, 0)));
  AnalyticFitOptions options;
  options.objective = FitObjective::Log;
  options.family = ModelFamily::Ggx;
  const AnalyticFit fit = fitAnalytic(data, options);
  test::expectGgxRecovered(fit.parameters, kd, f0, 0.25f, 0.05f);
  EXPECT_EQ(fit.report.samples, data.size());
  EXPECT_LT(fit.report.rel_rmse, 0.01);
  EXPECT_NEAR(measuredRelRmse(truth, data), 0.0, 1e-12);
  EXPECT_GT(measuredRelRmse(Ggx(kd, f0, 0.1f, 0.1f), data), 0.1);
}

// Unusable measurements (NaN, negative, below the horizon) are left out and counted; too few usable
// ones are an error that says how many there are.
TEST(AnalyticFit, ScatteredDataLeavesOutUnusableMeasurementsAndNeedsEnough) {
  const Ggx truth(Rgb(0.3f), Rgb(0.04f), 0.3f, 0.3f);
  std::vector<MeasuredReflectance> data;
  for (int v = 0; v < kBtfDirectionCount && data.size() < kMinimumFitSamples; v += 3)
    for (int light = 0; light < kBtfDirectionCount && data.size() < kMinimumFitSamples; light += 7) {
      const glm::vec3 wi = btfDirections()[std::size_t(light)].w, wo = btfDirections()[std::size_t(v)].w;
      data.push_back({wi, wo, truth.eval(wi, wo)});
    }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<MeasuredReflectance> bad = {
      {{0, 0, 1}, {0, 0, 1}, Rgb(nan, 0.1f, 0.1f)},
      {{0, 0, 1}, {0, 0, 1}, Rgb(0.1f, -1.0f, 0.1f)},
      {{0, 0, -1}, {0, 0, 1}, Rgb(0.1f)},
      {{0, 0, 1}, {0, 0, 1}, Rgb(std::numeric_limits<float>::infinity())},
  };
  std::vector<MeasuredReflectance> mixed = data;
  mixed.insert(mixed.end(), bad.begin(), bad.end());
  AnalyticFitOptions options;
  options.family = ModelFamily::Ggx;
  options.objective = FitObjective::Log;
  options.starts = 2;
  const AnalyticFit fit = fitAnalytic(mixed, options);
  EXPECT_EQ(fit.report.samples, kMinimumFitSamples);
  EXPECT_EQ(fit.report.excluded, bad.size());
  EXPECT_TRUE(std::isfinite(fit.report.rel_rmse));

  mixed.erase(mixed.begin());
  try {
    (void)fitAnalytic(mixed, options);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("only " + std::to_string(kMinimumFitSamples - 1) + " of " + std::to_string(mixed.size())));
  }
}

}  // namespace
}  // namespace btf
