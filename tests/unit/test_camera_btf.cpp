// CameraBtf: registration jitter, sensor noise and 8-bit sRGB codes on top of any BTF, each doing
// what it says and no more, deterministically.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "btf/core/error.h"
#include "camera_btf.h"
#include "support/test_support.h"

namespace btf {
namespace {
using synthetic::CameraBtf;
using synthetic::CameraOptions;
using testing::HasSubstr;
using test::errorOf;

BtfData rampBtf(int width, int height, BtfViewSet views) {
  BtfData data(width, height, "ramp", views);
  for (const int v : views.views())
    for (int l = 0; l < kBtfDirectionCount; ++l)
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
          data.at(x, y, v, l) = Rgb(0.1f + 0.05f * float(x), 0.2f + 0.03f * float(y), 0.05f + 0.004f * float(l));
  return data;
}

std::vector<Rgb> viewOf(const BtfSource& source, int view) {
  std::vector<Rgb> values;
  source.loadView(view, values);
  return values;
}

TEST(CameraBtf, WithNothingToDoItPassesTheValuesThrough) {
  const BtfData clean = rampBtf(5, 4, BtfViewSet({0, 3}));
  CameraOptions options;
  options.white = 10.0f;
  const CameraBtf camera(clean, options);
  EXPECT_EQ(camera.views(), clean.views());
  EXPECT_EQ(camera.white(), 10.0f);
  EXPECT_EQ(viewOf(camera, 3), viewOf(clean, 3));
}

TEST(CameraBtf, QuantizedValuesAreDecoded8BitSrgbCodesWithinHalfACode) {
  const BtfData clean = rampBtf(6, 5, BtfViewSet({0}));
  CameraOptions options;
  options.white = 0.3f;
  options.quantize = true;
  const std::vector<Rgb> a = viewOf(clean, 0), b = viewOf(CameraBtf(clean, options), 0);
  auto encode = [](double v) { return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055; };
  int clipped = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double code = encode(b[i][c] / 0.3) * 255.0;
      EXPECT_NEAR(code, std::round(code), 1e-3) << "a whole code";
      const double want = encode(std::min(a[i][c], 0.3f) / 0.3) * 255.0;
      EXPECT_LE(std::abs(code - want), 0.5 + 1e-3);
      if (a[i][c] > 0.3f) {
        ++clipped;
        EXPECT_EQ(b[i][c], 0.3f) << "clipped at white";
      }
    }
  EXPECT_GT(clipped, 0) << "the ramp reaches above white, so clipping was tested";
}

TEST(CameraBtf, ReadNoiseHasTheRequestedStdAndIsDeterministic) {
  BtfData flat(32, 32, "flat", BtfViewSet({0, 1}));
  for (const int v : {0, 1})
    for (int l = 0; l < kBtfDirectionCount; ++l)
      for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) flat.at(x, y, v, l) = Rgb(0.5f);
  CameraOptions options;
  options.white = 2.0f;
  options.read_noise = 0.01f;  // std 0.02 in values, far from the clipping at 0 and 2
  const CameraBtf camera(flat, options);
  const std::vector<Rgb> noisy = viewOf(camera, 1);
  double sum = 0, sum2 = 0;
  for (const Rgb& v : noisy)
    for (int c = 0; c < 3; ++c) {
      sum += v[c] - 0.5;
      sum2 += (v[c] - 0.5) * (v[c] - 0.5);
    }
  const double n = double(noisy.size()) * 3, mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  // 248,832 values: the sample std is within 0.5% of the true one with overwhelming probability.
  EXPECT_NEAR(sd, 0.02, 0.02 * 0.02);
  EXPECT_NEAR(mean, 0.0, 5 * 0.02 / std::sqrt(n));
  EXPECT_EQ(viewOf(CameraBtf(flat, options), 1), noisy) << "the same seed, the same noise";
  options.seed = 2;
  EXPECT_NE(viewOf(CameraBtf(flat, options), 1), noisy) << "another seed, other noise";
  EXPECT_NE(viewOf(camera, 0), noisy) << "every view has its own noise";
}

TEST(CameraBtf, JitterShiftsEachImageAndKeepsItsMean) {
  const BtfData clean = rampBtf(8, 6, BtfViewSet({0}));
  CameraOptions options;
  options.white = 100.0f;
  options.jitter = 0.5f;
  const std::vector<Rgb> a = viewOf(clean, 0), b = viewOf(CameraBtf(clean, options), 0);
  const std::size_t texels = 8 * 6;
  int moved = 0;
  for (int l = 0; l < kBtfDirectionCount; ++l) {
    double mean_a = 0, mean_b = 0;
    for (std::size_t t = 0; t < texels; ++t) {
      mean_a += a[std::size_t(l) * texels + t].r;
      mean_b += b[std::size_t(l) * texels + t].r;
      moved += a[std::size_t(l) * texels + t] != b[std::size_t(l) * texels + t];
    }
    // Bilinear resampling of a periodic image preserves its mean.
    EXPECT_NEAR(mean_b, mean_a, 1e-4 * mean_a) << "light " << l;
  }
  EXPECT_GT(moved, int(texels) * 40) << "most images moved";
}

TEST(CameraBtf, RefusesOptionsOutOfRange) {
  const BtfData clean = rampBtf(2, 2, BtfViewSet({0}));
  CameraOptions bad;
  bad.white = 0.0f;
  EXPECT_THAT(errorOf([&] { CameraBtf(clean, bad); }), HasSubstr("white"));
  bad = {};
  bad.jitter = -1.0f;
  EXPECT_THAT(errorOf([&] { CameraBtf(clean, bad); }), HasSubstr("jitter"));
  bad = {};
  bad.read_noise = NAN;
  EXPECT_THAT(errorOf([&] { CameraBtf(clean, bad); }), HasSubstr("read noise"));
}

}  // namespace
}  // namespace btf
