// Image comparison measures and the error heat map (render/image_metrics.h), on tiny images whose
// values are known in closed form.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "btf/core/error.h"
#include "btf/io/image.h"
#include "btf/render/image_metrics.h"

namespace {

using btf::Image;
using btf::render::compareImages;
using btf::render::errorHeatMap;

// 2 x 1 pixels: reference (2, 2, 2) and (0, 0, 0); test 0.5 above in every channel. Exact in float.
Image referenceImage(int channels = 3) {
  Image image(2, 1, channels, 0.0f);
  for (int c = 0; c < std::min(channels, 3); ++c) image.at(0, 0, c) = 2.0f;
  return image;
}
Image testImage(int channels = 3) {
  Image image = referenceImage(channels);
  for (int x = 0; x < 2; ++x)
    for (int c = 0; c < std::min(channels, 3); ++c) image.at(x, 0, c) += 0.5f;
  return image;
}

// Closed form of the pair above (every compared value differs by d = 0.5):
//   relmse   = (0.25 / (4 + 0.01) + 0.25 / (0 + 0.01)) / 2
//   rel_rmse = sqrt(0.25) / sqrt((4 + 0) / 2)
//   psnr_db  = 10 log10(2^2 / 0.25)
const double kRelMse = (0.25 / 4.01 + 0.25 / 0.01) / 2.0;
const double kRelRmse = 0.5 / std::sqrt(2.0);
const double kPsnr = 10.0 * std::log10(16.0);

void expectMessageContains(const std::function<void()>& f, const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "no error";
  } catch (const btf::Error& e) {
    for (const std::string& part : parts) EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(ImageMetrics, IdenticalImagesHaveZeroErrorAndInfinitePsnr) {
  const Image a = testImage();
  const auto c = compareImages(a, a);
  EXPECT_EQ(c.relmse, 0.0);
  EXPECT_EQ(c.rel_rmse, 0.0);
  EXPECT_EQ(c.max_abs, 0.0);
  EXPECT_TRUE(std::isinf(c.psnr_db) && c.psnr_db > 0);
  EXPECT_EQ(c.width, 2);
  EXPECT_EQ(c.height, 1);
  EXPECT_EQ(c.channels, 3);
}

TEST(ImageMetrics, KnownDifferenceGivesTheClosedFormValues) {
  for (const int channels : {3, 1}) {
    const auto c = compareImages(testImage(channels), referenceImage(channels));
    EXPECT_NEAR(c.relmse, kRelMse, 1e-12) << channels;
    EXPECT_NEAR(c.rel_rmse, kRelRmse, 1e-12) << channels;
    EXPECT_NEAR(c.psnr_db, kPsnr, 1e-12) << channels;
    EXPECT_EQ(c.max_abs, 0.5) << channels;
    EXPECT_EQ(c.channels, channels == 3 ? 3 : 1);
  }
  // Alpha (a 4th channel) is not compared, nor is the second channel of grey + alpha.
  Image test_rgba = testImage(4), reference_rgba = referenceImage(4);
  test_rgba.at(1, 0, 3) = 1.0f;
  EXPECT_NEAR(compareImages(test_rgba, reference_rgba).relmse, kRelMse, 1e-12);
  EXPECT_NEAR(compareImages(testImage(4), referenceImage(3)).psnr_db, kPsnr, 1e-12);
  Image grey_alpha = testImage(2);
  grey_alpha.at(0, 0, 1) = 7.0f;
  EXPECT_NEAR(compareImages(grey_alpha, referenceImage(1)).rel_rmse, kRelRmse, 1e-12);
  // Relative MSE is not symmetric: the reference's values are in the denominator.
  EXPECT_NEAR(compareImages(referenceImage(), testImage()).relmse, (0.25 / 6.26 + 0.25 / 0.26) / 2.0, 1e-9);
}

TEST(ImageMetrics, AllBlackReferenceGivesInfiniteRelativeErrors) {
  const Image black(2, 2, 3, 0.0f), grey(2, 2, 3, 0.1f);
  const auto c = compareImages(grey, black);
  EXPECT_TRUE(std::isinf(c.rel_rmse) && c.rel_rmse > 0);
  EXPECT_TRUE(std::isinf(c.psnr_db) && c.psnr_db < 0);
  EXPECT_NEAR(c.relmse, 0.01 / 0.01, 1e-6);
  EXPECT_NEAR(c.max_abs, 0.1, 1e-7);
  EXPECT_EQ(compareImages(black, black).rel_rmse, 0.0);
}

TEST(ImageMetrics, MismatchedSizesAndChannelsAreErrorsNamingBothSizes) {
  expectMessageContains([] { compareImages(Image(3, 2, 3), Image(2, 2, 3)); }, {"3x2", "2x2", "test image", "reference image"});
  expectMessageContains([] { compareImages(Image(2, 2, 1), Image(2, 2, 3), "a.exr", "b.exr"); },
                        {"a.exr is 2x2 grey", "b.exr is 2x2 RGB"});
  expectMessageContains([] { compareImages(Image(), Image(2, 2, 3)); }, {"test image", "empty"});
  expectMessageContains([] { errorHeatMap(Image(4, 4, 3), Image(4, 5, 3), 0.5); }, {"4x4", "4x5"});
}

TEST(ImageMetrics, NonFiniteValuesAreErrorsNamingTheImageAndThePixel) {
  Image test = testImage(), reference = referenceImage();
  test.at(1, 0, 2) = std::numeric_limits<float>::quiet_NaN();
  expectMessageContains([&] { compareImages(test, reference, "render.exr", "ref.exr"); },
                        {"render.exr", "pixel (1, 0) channel 2 is NaN"});
  test = testImage();
  reference.at(0, 0, 1) = -std::numeric_limits<float>::infinity();
  expectMessageContains([&] { compareImages(test, reference); }, {"reference image", "pixel (0, 0) channel 1 is infinite"});
  expectMessageContains([&] { errorHeatMap(test, reference, 0.5); }, {"reference image", "infinite"});
  // Not compared, not checked: a NaN alpha.
  Image rgba = testImage(4);
  rgba.at(0, 0, 3) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NO_THROW(compareImages(rgba, testImage(3)));
}

TEST(ImageMetrics, ViridisHitsItsControlPointsAndBrightensMonotonically) {
  // Ends and middle of matplotlib's viridis (entries 0, 255 and 128 of its table).
  const btf::Rgb bottom = btf::render::viridis(0.0), top = btf::render::viridis(1.0), mid = btf::render::viridis(0.5);
  EXPECT_NEAR(bottom.r, 0.267004f, 1e-6f);
  EXPECT_NEAR(bottom.g, 0.004874f, 1e-6f);
  EXPECT_NEAR(bottom.b, 0.329415f, 1e-6f);
  EXPECT_NEAR(top.r, 0.993248f, 1e-6f);
  EXPECT_NEAR(top.g, 0.906157f, 1e-6f);
  EXPECT_NEAR(top.b, 0.143936f, 1e-6f);
  EXPECT_NEAR(mid.r, 0.127568f, 5e-3f);
  EXPECT_NEAR(mid.g, 0.566949f, 5e-3f);
  EXPECT_NEAR(mid.b, 0.550556f, 5e-3f);
  // Clamped outside [0, 1]; NaN maps to the bottom.
  EXPECT_EQ(btf::render::viridis(-3.0), bottom);
  EXPECT_EQ(btf::render::viridis(7.0), top);
  EXPECT_EQ(btf::render::viridis(std::nan("")), bottom);
  float previous = -1.0f;
  for (int k = 0; k <= 100; ++k) {
    const float luminance = btf::render::viridis(k / 100.0).luminance();
    EXPECT_GT(luminance, previous) << k;
    previous = luminance;
  }
}

TEST(ImageMetrics, HeatMapColoursTheRelativeErrorPerPixel) {
  // Pixel 0: r = 2, t = 2.5 -> e = 0.5 / 2.01; pixel 1: r = 0, t = 0.5 -> e = 0.5 / 0.01 = 50.
  const double scale = 2.0 * 0.5 / 2.01;  // pixel 0 lands in the middle of the map
  const Image heat = errorHeatMap(testImage(), referenceImage(), scale);
  ASSERT_EQ(heat.width, 2);
  ASSERT_EQ(heat.height, 1);
  ASSERT_EQ(heat.channels, 3);
  const btf::Rgb mid = btf::render::viridis(0.5), top = btf::render::viridis(1.0);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(heat.at(0, 0, c), mid[c], 1e-6f);
    EXPECT_NEAR(heat.at(1, 0, c), top[c], 1e-6f);  // beyond the scale: the top
  }
  const Image none = errorHeatMap(referenceImage(), referenceImage(), 0.5);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(none.at(1, 0, c), btf::render::viridis(0.0)[c]);
  for (float v : heat.pixels) {
    EXPECT_GE(v, 0.0f);
    EXPECT_LE(v, 1.0f);
  }
  // Grey images give a colour heat map too.
  EXPECT_EQ(errorHeatMap(testImage(1), referenceImage(1), scale).channels, 3);
  for (const double bad : {0.0, -1.0, std::numeric_limits<double>::infinity(), std::nan("")})
    EXPECT_THROW(errorHeatMap(testImage(), referenceImage(), bad), btf::Error) << bad;
}
