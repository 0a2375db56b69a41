// The CIE tables (core/cie.h) against figures published with them, the spectrum -> sRGB
// projection, and the sigmoid-polynomial upsampling (core/rgb_to_spectrum.h) over the sRGB cube.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "btf/core/cie.h"
#include "btf/core/error.h"
#include "btf/core/rgb_to_spectrum.h"

namespace {

using namespace btf;

TEST(Cie, TablesMatchTheirPublishedSums) {
  // The integral of y_bar over 360-830 nm at 5 nm is 106.857 (CIE 015:2018); x_bar and z_bar
  // integrate to the same within 0.05% (an equal-energy spectrum is white, x = y = 1/3).
  double x = 0, y = 0, z = 0, d65 = 0, xd = 0, yd = 0, zd = 0;
  for (int k = 0; k < kCieCount; ++k) {
    x += kCie1931[k].x, y += kCie1931[k].y, z += kCie1931[k].z, d65 += kCieD65[k];
    xd += kCie1931[k].x * kCieD65[k], yd += kCie1931[k].y * kCieD65[k], zd += kCie1931[k].z * kCieD65[k];
  }
  EXPECT_NEAR(5 * y, 106.857, 1e-3);
  EXPECT_NEAR(x / y, 1.0, 5e-4);
  EXPECT_NEAR(z / y, 1.0, 5e-4);
  EXPECT_FLOAT_EQ(kCieD65[40], 100.0f);  // 560 nm
  EXPECT_NEAR(d65, 7880.3178, 1e-2);
  // D65's chromaticity (CIE 015:2018 Table T.3, 2-degree observer): x 0.31272, y 0.32903.
  EXPECT_NEAR(xd / (xd + yd + zd), 0.31272, 5e-5);
  EXPECT_NEAR(yd / (xd + yd + zd), 0.32903, 5e-5);
}

TEST(Cie, ProjectionMapsConstantSpectraToGreyAndIsLinear) {
  const std::vector<float> wl = bsdfWavelengths();
  const SpectrumToRgb project(wl);
  const Rgb white = project(std::vector<float>(wl.size(), 1.0f));
  EXPECT_NEAR(white.r, 1.0f, 1e-6f);
  EXPECT_NEAR(white.g, 1.0f, 1e-6f);
  EXPECT_NEAR(white.b, 1.0f, 1e-6f);
  const Rgb grey = project(std::vector<float>(wl.size(), 3.5f));  // reflectance above 1 is allowed
  EXPECT_NEAR(grey.g, 3.5f, 1e-5f);
  // A coarser grid covering the range sees the same constant.
  const std::vector<float> coarse = {350.0f, 600.0f, 900.0f};
  EXPECT_NEAR(SpectrumToRgb(coarse)(std::vector<float>{0.5f, 0.5f, 0.5f}).b, 0.5f, 1e-6f);
  // A spectrum that only reflects long wavelengths is red.
  std::vector<float> red(wl.size(), 0.0f);
  for (std::size_t k = 0; k < wl.size(); ++k) red[k] = wl[k] >= 600 ? 1.0f : 0.0f;
  const Rgb r = project(red);
  EXPECT_GT(r.r, 0.5f);
  EXPECT_LT(r.g, 0.1f);
}

TEST(Cie, ProjectionRejectsBadGrids) {
  EXPECT_THROW(SpectrumToRgb(std::vector<float>{500.0f}), Error);
  EXPECT_THROW(SpectrumToRgb(std::vector<float>{360.0f, 360.0f, 830.0f}), Error);
  EXPECT_THROW(SpectrumToRgb(std::vector<float>{400.0f, 830.0f}), Error);  // misses 360-400 nm
  EXPECT_THROW(SpectrumToRgb(std::vector<float>{360.0f, NAN, 830.0f}), Error);
}

TEST(SigmoidSpectrum, RoundTripsTheSrgbCubeAndValuesAboveOne) {
  const std::vector<float> wl = bsdfWavelengths();
  const SpectrumToRgb project(wl);
  // An 11^3 grid of the cube times scales 0.01 to 40 (BRDF table values are unbounded): every
  // colour must come back within 1e-5 of its largest component, and every spectrum must be
  // non-negative and at most its scale 2 max(r, g, b).
  int checked = 0;
  double worst_inside = 0, worst_primary = 0;
  for (const float scale : {0.01f, 1.0f, 40.0f})
    for (int i = 0; i <= 10; ++i)
      for (int j = 0; j <= 10; ++j)
        for (int k = 0; k <= 10; ++k) {
          const Rgb rgb = Rgb(i / 10.0f, j / 10.0f, k / 10.0f) * scale;
          const SigmoidSpectrum s = fitSigmoidSpectrum(rgb, project, wl);
          std::vector<float> values(wl.size());
          for (std::size_t n = 0; n < wl.size(); ++n) {
            values[n] = float(s(wl[n]));
            ASSERT_GE(values[n], 0.0f);
            ASSERT_LE(values[n], 2.0f * rgb.maxComponent() * 1.000001f + 1e-30f);
          }
          const Rgb back = project(values);
          const double peak = std::max(1e-30f, rgb.maxComponent());
          const double error = std::max({std::abs(back.r - rgb.r), std::abs(back.g - rgb.g), std::abs(back.b - rgb.b)}) / peak;
          if (rgb.maxComponent() == 0) EXPECT_EQ(back.maxComponent(), 0.0f);
          else if (rgb.minComponent() >= 0.1f * rgb.maxComponent()) worst_inside = std::max(worst_inside, error);
          else worst_primary = std::max(worst_primary, error);
          ++checked;
        }
  EXPECT_EQ(checked, 3 * 11 * 11 * 11);
  EXPECT_LT(worst_inside, 1e-5) << "colours with every component >= 10% of the largest";
  EXPECT_LT(worst_primary, 1e-5) << "purer colours, primaries included";
  std::printf("largest relative residual: %.3g (components >= 10%% of the largest), %.3g (purer colours)\n",
              worst_inside, worst_primary);
}

TEST(SigmoidSpectrum, NegativeComponentsAreTakenAsZero) {
  const std::vector<float> wl = bsdfWavelengths();
  const SpectrumToRgb project(wl);
  const SigmoidSpectrum a = fitSigmoidSpectrum(Rgb(0.4f, -0.1f, 0.2f), project, wl);
  const SigmoidSpectrum b = fitSigmoidSpectrum(Rgb(0.4f, 0.0f, 0.2f), project, wl);
  EXPECT_EQ(a(500.0), b(500.0));
  EXPECT_EQ(fitSigmoidSpectrum(Rgb(-1.0f), project, wl)(550.0), 0.0);
}

}  // namespace
