// Perceptual and noise-floor measures of BTFs (io/btf_quality.h): mean SSIM against values
// computed here by the direct formula, and the noise floor against noise of known sigma.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <random>
#include <vector>

#include "btf/core/btf_directions.h"
#include "btf/core/error.h"
#include "btf/io/btf_data.h"
#include "btf/io/btf_quality.h"
#include "support/test_support.h"

namespace btf {
namespace {

// Uniform in [0, 1) from 53 bits, and a standard normal by Box-Muller: both written out so that
// the data is the same on every standard library (std::normal_distribution is not portable).
double uniform01(std::mt19937_64& rng) { return double(rng() >> 11) * 0x1p-53; }

double gaussian(std::mt19937_64& rng) {
  const double u1 = 1.0 - uniform01(rng);  // (0, 1]: the log stays finite
  const double u2 = uniform01(rng);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

// The display transform of btf_quality.h, written out in double.
using test::srgbEncode;

double displayLuma(const Rgb& rgb, double white) {
  double encoded[3];
  for (int c = 0; c < 3; ++c) encoded[c] = srgbEncode(std::clamp(double(rgb[c]) / white, 0.0, 1.0));
  return 0.2126 * encoded[0] + 0.7152 * encoded[1] + 0.0722 * encoded[2];
}

// SSIM of one image by the direct formula: every window position, two-pass means and
// (co)variances with equal weights, C1 = 0.01^2, C2 = 0.03^2.
double directImageSsim(const BtfData& a, const BtfData& b, int view, int light, double white, int window) {
  const int w = a.width(), h = a.height(), wx = std::min(window, w), wy = std::min(window, h);
  const double c1 = 1e-4, c2 = 9e-4;
  double total = 0;
  int windows = 0;
  for (int y0 = 0; y0 + wy <= h; ++y0)
    for (int x0 = 0; x0 + wx <= w; ++x0) {
      std::vector<double> xs, ys;
      for (int y = y0; y < y0 + wy; ++y)
        for (int x = x0; x < x0 + wx; ++x) {
          xs.push_back(displayLuma(a.at(x, y, view, light), white));
          ys.push_back(displayLuma(b.at(x, y, view, light), white));
        }
      const double n = double(xs.size());
      double mx = 0, my = 0;
      for (std::size_t i = 0; i < xs.size(); ++i) mx += xs[i] / n, my += ys[i] / n;
      double vx = 0, vy = 0, cxy = 0;
      for (std::size_t i = 0; i < xs.size(); ++i) {
        vx += (xs[i] - mx) * (xs[i] - mx) / n;
        vy += (ys[i] - my) * (ys[i] - my) / n;
        cxy += (xs[i] - mx) * (ys[i] - my) / n;
      }
      total += (2 * mx * my + c1) * (2 * cxy + c2) / ((mx * mx + my * my + c1) * (vx + vy + c2));
      ++windows;
    }
  return total / windows;
}

// Every value of every held view uniform in [lo, hi), channel by channel.
void fillUniform(BtfData& data, std::uint64_t seed, float lo = 0.0f, float hi = 1.0f) {
  std::mt19937_64 rng(seed);
  for (const int v : data.views().views())
    for (int light = 0; light < kBtfDirectionCount; ++light)
      for (int y = 0; y < data.height(); ++y)
        for (int x = 0; x < data.width(); ++x)
          for (int c = 0; c < 3; ++c) data.at(x, y, v, light)[c] = lo + (hi - lo) * float(uniform01(rng));
}

// A copy of data (same views) with Gaussian noise of the given sigma on every value.
BtfData withNoise(const BtfData& data, double sigma, std::uint64_t seed, std::string name = "noisy") {
  BtfData noisy(data.width(), data.height(), std::move(name), data.views());
  std::mt19937_64 rng(seed);
  for (const int v : data.views().views())
    for (int light = 0; light < kBtfDirectionCount; ++light)
      for (int y = 0; y < data.height(); ++y)
        for (int x = 0; x < data.width(); ++x)
          for (int c = 0; c < 3; ++c)
            noisy.at(x, y, v, light)[c] = data.at(x, y, v, light)[c] + float(sigma * gaussian(rng));
  return noisy;
}

// Images with structure: smooth patterns over the texels that change with the light.
BtfData makePatternBtf(int width, int height, BtfViewSet views, std::string name = "pattern") {
  BtfData data(width, height, std::move(name), std::move(views));
  for (const int v : data.views().views())
    for (int light = 0; light < kBtfDirectionCount; ++light)
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
          const float s = 0.5f + 0.4f * std::sin(0.7f * float(x) + 0.3f * float(light)) * std::cos(0.5f * float(y) + 0.1f * float(v));
          data.at(x, y, v, light) = Rgb(s, 0.8f * s + 0.1f, 0.6f * s);
        }
  return data;
}

TEST(BtfQualitySsim, IdenticalBtfsGiveOne) {
  const BtfData a = makePatternBtf(16, 12, BtfViewSet({0, 7}));
  const BtfSsimStats s = compareBtfSsim(a, a);
  EXPECT_GE(s.mean_ssim, 0.999999);
  EXPECT_LE(s.mean_ssim, 1.000001);
  EXPECT_GE(s.min_image_ssim, 0.999999);
  EXPECT_EQ(s.images, 2u * 81u);
}

TEST(BtfQualitySsim, DecreasesAsNoiseGrows) {
  const BtfData a = makePatternBtf(24, 20, BtfViewSet({3}));
  BtfSsimOptions options;
  options.white = 1.0f;
  double previous = 1.0;
  for (const double sigma : {0.002, 0.01, 0.03, 0.1, 0.3}) {
    const BtfSsimStats s = compareBtfSsim(a, withNoise(a, sigma, 7), options);
    EXPECT_LT(s.mean_ssim, previous) << "sigma " << sigma;
    EXPECT_LE(s.min_image_ssim, s.mean_ssim);
    EXPECT_GT(s.mean_ssim, -1.0);
    previous = s.mean_ssim;
  }
  EXPECT_LT(previous, 0.5);  // the strongest noise is plainly visible
}

// rel_rmse_display is the rel_rmse of the encoded colours: 0 for identical BTFs, and for a test that
// is the reference scaled by k (nothing clipped, every value on the power segment of the curve)
// close to |k^(1/2.4) - 1|, the error of a pure 1/2.4 power, where the linear error is |k - 1|.
TEST(BtfQualitySsim, DisplayedRelRmseIsTheErrorOfTheEncodedColours) {
  BtfData a(6, 5, "reference", BtfViewSet({0, 2})), b(6, 5, "scaled", BtfViewSet({0, 2}));
  for (const int v : {0, 2})
    for (int l = 0; l < kBtfDirectionCount; ++l)
      for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 6; ++x) {
          const float value = 0.05f + 0.005f * float(x + 6 * y) + 0.001f * float(l);
          a.at(x, y, v, l) = Rgb(value, 0.9f * value, 0.8f * value);
          b.at(x, y, v, l) = a.at(x, y, v, l) * 0.8f;
        }
  BtfSsimOptions options;
  options.white = 1.0f;
  EXPECT_EQ(compareBtfSsim(a, a, options).rel_rmse_display, 0.0);
  const double expected = 1.0 - std::pow(0.8, 1.0 / 2.4);  // 1.055 c^(1/2.4) - 0.055: not a pure power
  const double got = compareBtfSsim(a, b, options).rel_rmse_display;
  // The curve's offset makes the encoded ratio differ a little from k^(1/2.4): within 20% of it.
  EXPECT_GT(got, 0.8 * expected);
  EXPECT_LT(got, 1.2 * expected);
  EXPECT_GT(got, 0.02);  // and far from the linear error of 0.2 scaled down to nothing
}

// One image differs (the others are black in both, SSIM exactly 1 each): its SSIM is the direct
// formula's, on one window (8 x 8) and on sliding windows (11 x 9: 4 x 2 positions).
TEST(BtfQualitySsim, MatchesTheDirectFormula) {
  for (const auto& [w, h] : {std::pair{8, 8}, std::pair{11, 9}}) {
    BtfData a(w, h, "reference", BtfViewSet({0})), b(w, h, "test", BtfViewSet({0}));
    const int light = 5;
    std::mt19937_64 rng(11);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) {
          const double base = 1.2 * uniform01(rng);  // some values above white
          a.at(x, y, 0, light)[c] = float(base);
          b.at(x, y, 0, light)[c] = float(std::max(0.0, base + 0.15 * gaussian(rng) + 0.05 * x / w));
        }
    BtfSsimOptions options;
    options.white = 1.0f;
    const BtfSsimStats s = compareBtfSsim(a, b, options);
    const double expected = directImageSsim(a, b, 0, light, 1.0, 8);
    ASSERT_LT(expected, 0.95) << "the images should differ visibly";
    EXPECT_NEAR(s.min_image_ssim, expected, 1e-5) << w << " x " << h;
    EXPECT_NEAR(s.mean_ssim, (80.0 + expected) / 81.0, 1e-6);
    EXPECT_FLOAT_EQ(s.white, 1.0f);
    EXPECT_EQ(s.images, 81u);
  }
}

// Flat images have no variance: SSIM is the luminance term alone, (2 l1 l2 + C1) / (l1^2 + l2^2 + C1).
TEST(BtfQualitySsim, ConstantImagesGiveTheLuminanceTerm) {
  BtfData a(10, 10, "grey 0.2", BtfViewSet({0})), b(10, 10, "grey 0.3", BtfViewSet({0}));
  for (int light = 0; light < kBtfDirectionCount; ++light)
    for (int y = 0; y < 10; ++y)
      for (int x = 0; x < 10; ++x) {
        a.at(x, y, 0, light) = Rgb(0.2f);
        b.at(x, y, 0, light) = Rgb(0.3f);
      }
  BtfSsimOptions options;
  options.white = 1.0f;
  const BtfSsimStats s = compareBtfSsim(a, b, options);
  const double l1 = srgbEncode(0.2), l2 = srgbEncode(0.3);
  const double expected = (2 * l1 * l2 + 1e-4) / (l1 * l1 + l2 * l2 + 1e-4);
  EXPECT_NEAR(s.mean_ssim, expected, 1e-6);
  EXPECT_NEAR(s.min_image_ssim, expected, 1e-6);
  EXPECT_LT(expected, 0.99);
}

// A one-texel BTF (from a BRDF) is one 1 x 1 window per image: the luminance term per light.
TEST(BtfQualitySsim, OneTexelBtfUsesOneWindowPerImage) {
  BtfData a(1, 1, "brdf", BtfViewSet({0, 1})), b(1, 1, "fit", BtfViewSet({0, 1}));
  fillUniform(a, 1);
  fillUniform(b, 2);
  BtfSsimOptions options;
  options.white = 1.0f;
  const BtfSsimStats s = compareBtfSsim(a, b, options);
  double sum = 0;
  for (const int v : {0, 1})
    for (int light = 0; light < kBtfDirectionCount; ++light) {
      const double l1 = displayLuma(a.at(0, 0, v, light), 1.0), l2 = displayLuma(b.at(0, 0, v, light), 1.0);
      sum += (2 * l1 * l2 + 1e-4) / (l1 * l1 + l2 * l2 + 1e-4);
    }
  EXPECT_NEAR(s.mean_ssim, sum / 162.0, 1e-6);
  EXPECT_EQ(s.images, 162u);
}

// Above white the camera saturates: values above it in both BTFs compare as white, however
// different they are.
TEST(BtfQualitySsim, ValuesAboveWhiteMakeNoDifference) {
  BtfData a = makePatternBtf(12, 12, BtfViewSet({0}), "reference");
  const BtfData noisy = withNoise(a, 0.05, 3);
  BtfData at_white = noisy, far_above = noisy;
  std::mt19937_64 rng(5);
  for (int light = 0; light < kBtfDirectionCount; ++light)
    for (int y = 0; y < 12; ++y)
      for (int x = 0; x < 12; ++x)
        if (uniform01(rng) < 0.2) {
          a.at(x, y, 0, light) = Rgb(1.5f);
          at_white.at(x, y, 0, light) = Rgb(1.0f);
          far_above.at(x, y, 0, light) = Rgb(40.0f, 3.0f, 1.01f);
        }
  BtfSsimOptions options;
  options.white = 1.0f;
  const BtfSsimStats near = compareBtfSsim(a, at_white, options);
  const BtfSsimStats far = compareBtfSsim(a, far_above, options);
  EXPECT_LT(near.mean_ssim, 0.99);
  EXPECT_DOUBLE_EQ(near.mean_ssim, far.mean_ssim);
  EXPECT_DOUBLE_EQ(near.min_image_ssim, far.min_image_ssim);

  // The reference's own white is the default.
  a.setWhite(1.0f);
  const BtfSsimStats own = compareBtfSsim(a, far_above);
  EXPECT_FLOAT_EQ(own.white, 1.0f);
  EXPECT_DOUBLE_EQ(own.mean_ssim, far.mean_ssim);
}

// Without a white of its own, the reference's 99.9th percentile (nearest rank) is white.
TEST(BtfQualitySsim, DefaultWhiteIsThePercentile) {
  BtfData a(4, 4, "float data", BtfViewSet({2, 9}));
  fillUniform(a, 9, 0.0f, 3.0f);
  std::vector<float> all;
  for (const int v : {2, 9})
    for (int light = 0; light < kBtfDirectionCount; ++light)
      for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
          for (int c = 0; c < 3; ++c) all.push_back(a.at(x, y, v, light)[c]);
  std::sort(all.begin(), all.end());
  const auto rank = std::size_t(std::ceil(0.999 * double(all.size())));
  const BtfSsimStats s = compareBtfSsim(a, a);
  EXPECT_EQ(s.white, all[rank - 1]);
  EXPECT_LT(s.white, all.back());

  // All zero and no white: nothing to scale by.
  const BtfData zero(4, 4, "all-zero", BtfViewSet({0}));
  EXPECT_THAT([&] { compareBtfSsim(zero, zero); },
              testing::ThrowsMessage<Error>(testing::HasSubstr("all-zero")));
}

TEST(BtfQualitySsim, IndependentOfTheThreadCount) {
  const BtfData a = makePatternBtf(20, 16, BtfViewSet({0, 40}));
  const BtfData b = withNoise(a, 0.04, 17);
  BtfSsimStats one, two;
  {
    const tbb::global_control control(tbb::global_control::max_allowed_parallelism, 1);
    one = compareBtfSsim(a, b);
  }
  {
    const tbb::global_control control(tbb::global_control::max_allowed_parallelism, 2);
    two = compareBtfSsim(a, b);
  }
  EXPECT_EQ(one.mean_ssim, two.mean_ssim);
  EXPECT_EQ(one.min_image_ssim, two.min_image_ssim);
}

TEST(BtfQualitySsim, PartialViews) {
  const BtfData a = makePatternBtf(9, 9, BtfViewSet({0, 5}), "two views");
  const BtfData same_views = withNoise(a, 0.02, 1);
  BtfData more_views = makePatternBtf(9, 9, BtfViewSet({0, 5, 7}), "three views");
  const BtfSsimStats s = compareBtfSsim(a, same_views);
  EXPECT_EQ(s.images, 162u);
  EXPECT_LT(s.mean_ssim, 1.0);
  // Views the reference does not hold are not looked at.
  EXPECT_GE(compareBtfSsim(a, more_views).mean_ssim, 0.999999);

  const BtfData fewer = makePatternBtf(9, 9, BtfViewSet({0}), "one view");
  EXPECT_THAT([&] { compareBtfSsim(a, fewer); },
              testing::ThrowsMessage<Error>(testing::AllOf(testing::HasSubstr("one view"), testing::HasSubstr("two views"))));
}

TEST(BtfQualitySsim, SizeMismatchNamesBoth) {
  const BtfData a(8, 8, "eight", BtfViewSet({0})), b(8, 9, "eight by nine", BtfViewSet({0}));
  EXPECT_THAT([&] { compareBtfSsim(a, b); },
              testing::ThrowsMessage<Error>(testing::AllOf(testing::HasSubstr("eight by nine"), testing::HasSubstr("with eight"),
                                                           testing::HasSubstr("8 x 9"), testing::HasSubstr("8 x 8"))));
  BtfSsimOptions bad;
  bad.window = 0;
  EXPECT_THROW(compareBtfSsim(a, a, bad), Error);
  bad.window = 8;
  bad.white = 0.0f;
  EXPECT_THROW(compareBtfSsim(a, a, bad), Error);
}

// Smooth over light azimuth: an albedo per texel and channel times 0.5 + 0.05 cos(phi_light).
BtfData makeSmoothBtf(int width, int height, BtfViewSet views) {
  BtfData data(width, height, "smooth", std::move(views));
  const auto& dirs = btfDirections();
  for (const int v : data.views().views())
    for (int light = 0; light < kBtfDirectionCount; ++light) {
      const double phi = dirs[std::size_t(light)].phi_deg * M_PI / 180.0;
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
          for (int c = 0; c < 3; ++c) {
            const double albedo = 1.0 + 0.2 * std::sin(0.9 * x + 1.3 * y + 2.0 * c);
            data.at(x, y, v, light)[c] = float(albedo * (0.5 + 0.05 * std::cos(phi)));
          }
    }
  return data;
}

double rmsOf(const BtfData& data) {
  double squares = 0;
  for (const int v : data.views().views())
    for (int light = 0; light < kBtfDirectionCount; ++light)
      for (int y = 0; y < data.height(); ++y)
        for (int x = 0; x < data.width(); ++x)
          for (int c = 0; c < 3; ++c) squares += double(data.at(x, y, v, light)[c]) * data.at(x, y, v, light)[c];
  return std::sqrt(squares / (double(data.entryCount()) * 3.0));
}

TEST(BtfQualityNoiseFloor, RecoversTheNoiseSigma) {
  const BtfData smooth = makeSmoothBtf(16, 16, BtfViewSet({0, 10, 30}));
  const BtfNoiseFloor clean = estimateBtfNoiseFloor(smooth);
  EXPECT_EQ(clean.residuals, 16u * 16u * 3u * 80u * 3u);  // no subsampling at this size
  double smallest_noisy = 1e9;
  for (const double sigma : {0.03, 0.06, 0.12}) {
    const BtfData noisy = withNoise(smooth, sigma, 42);
    const BtfNoiseFloor floor = estimateBtfNoiseFloor(noisy);
    EXPECT_NEAR(floor.rms_noise, sigma, 0.1 * sigma) << "sigma " << sigma;
    EXPECT_NEAR(floor.rel_rmse, floor.rms_noise / rmsOf(noisy), 1e-9);
    smallest_noisy = std::min(smallest_noisy, floor.rel_rmse);
  }
  // The smooth signal's own curvature reads as a little noise, far below the smallest real noise.
  EXPECT_LT(clean.rel_rmse, 0.1 * smallest_noisy);
  EXPECT_GT(clean.rel_rmse, 0.0);
}

TEST(BtfQualityNoiseFloor, AllZeroThrows) {
  const BtfData zero(4, 4, "blank btf", BtfViewSet({0}));
  EXPECT_THAT([&] { estimateBtfNoiseFloor(zero); }, testing::ThrowsMessage<Error>(testing::HasSubstr("blank btf")));
}

// ---------------------------------------------------------------------------------------------
// compareBtfQuality: the three measures in one pass.

// A source that counts how often each of its views is loaded.
class CountingSource : public BtfSource {
 public:
  explicit CountingSource(const BtfData& data) : data_(data) {}
  int width() const override { return data_.width(); }
  int height() const override { return data_.height(); }
  const BtfViewSet& views() const override { return data_.views(); }
  void loadView(int view, std::vector<Rgb>& out) const override {
    ++loads_[view];
    data_.loadView(view, out);
  }
  std::string name() const override { return data_.name(); }
  int loads(int view) const { return loads_.count(view) ? loads_.at(view) : 0; }

 private:
  const BtfData& data_;
  mutable std::map<int, int> loads_;
};

TEST(BtfQualityAll, EqualsTheThreeMeasuresBitForBitLoadingEveryViewOnce) {
  // A partial test BTF holding one view more than the reference: only the reference's are read.
  const BtfData reference_data = makePatternBtf(13, 11, BtfViewSet({0, 9, 40}), "reference");
  const BtfData noisy = withNoise(reference_data, 0.03, 7);
  BtfData test_data(13, 11, "test", BtfViewSet({0, 9, 40, 60}));
  for (const int v : noisy.views().views()) std::copy(noisy.view(v), noisy.view(v) + noisy.viewValueCount(v), test_data.view(v));
  for (const std::optional<float> white : {std::optional<float>(), std::optional<float>(0.5f)}) {
    BtfSsimOptions options;
    options.white = white;
    options.window = 5;
    const CountingSource reference(reference_data), test(test_data);
    const BtfQuality q = compareBtfQuality(reference, test, options);
    for (const int v : reference_data.views().views()) {
      // Finding the white when none is given is a pass of its own over the reference.
      EXPECT_EQ(reference.loads(v), white ? 1 : 2) << "view " << v;
      EXPECT_EQ(test.loads(v), 1) << "view " << v;
    }
    EXPECT_EQ(test.loads(60), 0);

    const BtfErrorStats e = compareBtf(reference_data, test_data);
    const BtfSsimStats ssim = compareBtfSsim(reference_data, test_data, options);
    const BtfNoiseFloor noise = estimateBtfNoiseFloor(reference_data);
    EXPECT_EQ(q.error.rel_rmse, e.rel_rmse);
    EXPECT_EQ(q.error.psnr_db, e.psnr_db);
    EXPECT_EQ(q.error.rmse, e.rmse);
    EXPECT_EQ(q.error.reference_max, e.reference_max);
    EXPECT_EQ(q.error.entries, e.entries);
    EXPECT_EQ(q.ssim.mean_ssim, ssim.mean_ssim);
    EXPECT_EQ(q.ssim.min_image_ssim, ssim.min_image_ssim);
    EXPECT_EQ(q.ssim.rel_rmse_display, ssim.rel_rmse_display);
    EXPECT_EQ(q.ssim.white, ssim.white);
    EXPECT_EQ(q.ssim.images, ssim.images);
    EXPECT_EQ(q.noise.rel_rmse, noise.rel_rmse);
    EXPECT_EQ(q.noise.rms_noise, noise.rms_noise);
    EXPECT_EQ(q.noise.residuals, noise.residuals);
    EXPECT_GT(q.error.rel_rmse, 0.0);
    EXPECT_LT(q.ssim.mean_ssim, 1.0);
  }
}

TEST(BtfQualityAll, RefusesWhatTheThreeMeasuresRefuse) {
  const BtfData a = makePatternBtf(8, 8, BtfViewSet({0, 5}), "two views");
  const BtfData narrower = makePatternBtf(7, 8, BtfViewSet({0, 5}), "seven wide");
  const BtfData fewer = makePatternBtf(8, 8, BtfViewSet({0}), "one view");
  const BtfData zero(8, 8, "blank btf", BtfViewSet({0, 5}));
  using testing::AllOf;
  using testing::HasSubstr;
  EXPECT_THAT([&] { compareBtfQuality(a, narrower); },
              testing::ThrowsMessage<Error>(AllOf(HasSubstr("seven wide"), HasSubstr("two views"))));
  EXPECT_THAT([&] { compareBtfQuality(a, fewer); },
              testing::ThrowsMessage<Error>(AllOf(HasSubstr("one view"), HasSubstr("two views"))));
  BtfSsimOptions bad_window;
  bad_window.window = 0;
  EXPECT_THAT([&] { compareBtfQuality(a, a, bad_window); }, testing::ThrowsMessage<Error>(HasSubstr("window")));
  BtfSsimOptions white;
  white.white = 1.0f;
  EXPECT_THAT([&] { compareBtfQuality(zero, a, white); }, testing::ThrowsMessage<Error>(HasSubstr("blank btf")));
}

}  // namespace
}  // namespace btf
