#include "btf/render/image_metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>

#include "btf/core/error.h"

namespace btf::render {
namespace {

constexpr double kRelMseEpsilon = 1e-2;   // relmse: (t - r)^2 / (r^2 + kRelMseEpsilon)
constexpr double kHeatMapEpsilon = 0.01;  // heat map: |t - r| / (|r| + kHeatMapEpsilon)

// Entries 0, 17, ..., 255 of matplotlib's 256-entry viridis table (sRGB).
constexpr std::array<std::array<float, 3>, 16> kViridis{{
    {0.267004f, 0.004874f, 0.329415f},
    {0.282656f, 0.100196f, 0.422160f},
    {0.277134f, 0.185228f, 0.489898f},
    {0.253935f, 0.265254f, 0.529983f},
    {0.221989f, 0.339161f, 0.548752f},
    {0.190631f, 0.407061f, 0.556089f},
    {0.163625f, 0.471133f, 0.558148f},
    {0.139147f, 0.533812f, 0.555298f},
    {0.120565f, 0.596422f, 0.543611f},
    {0.134692f, 0.658636f, 0.517649f},
    {0.208030f, 0.718701f, 0.472873f},
    {0.327796f, 0.773980f, 0.406640f},
    {0.477504f, 0.821444f, 0.318195f},
    {0.647257f, 0.858400f, 0.209861f},
    {0.824940f, 0.884720f, 0.106217f},
    {0.993248f, 0.906157f, 0.143936f},
}};

// Colour channels compared per pixel: 3 for an RGB(A) image, 1 for grey (+ alpha).
int comparedChannels(const Image& image) { return image.channels >= 3 ? 3 : 1; }

std::string describeSize(const Image& image) {
  std::string kind = comparedChannels(image) == 3 ? "RGB" : "grey";
  if (image.channels > 3 || image.channels == 2) kind += " (+" + std::to_string(image.channels - comparedChannels(image)) + " ignored)";
  return std::to_string(image.width) + "x" + std::to_string(image.height) + " " + kind;
}

void requireFinite(const Image& image, const std::string& name) {
  const int channels = comparedChannels(image);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < channels; ++c) {
        const float v = image.at(x, y, c);
        if (!std::isfinite(v))
          throw Error(name + ": pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") channel " +
                      std::to_string(c) + " is " + (std::isnan(v) ? "NaN" : "infinite"));
      }
}

void requireComparable(const Image& test, const Image& reference, const std::string& test_name,
                       const std::string& reference_name) {
  const auto require_consistent = [](const Image& image, const std::string& name) {
    if (image.width <= 0 || image.height <= 0 || image.channels <= 0)
      throw Error(name + " is empty (" + std::to_string(image.width) + "x" + std::to_string(image.height) + "x" +
                  std::to_string(image.channels) + ")");
    if (image.pixels.size() != std::size_t(image.width) * std::size_t(image.height) * std::size_t(image.channels))
      throw Error(name + ": pixel data does not match its size");
  };
  require_consistent(test, test_name);
  require_consistent(reference, reference_name);
  if (test.width != reference.width || test.height != reference.height ||
      comparedChannels(test) != comparedChannels(reference))
    throw Error("images differ in size: " + test_name + " is " + describeSize(test) + ", " + reference_name + " is " +
                describeSize(reference));
  requireFinite(test, test_name);
  requireFinite(reference, reference_name);
}

}  // namespace

ImageComparison compareImages(const Image& test, const Image& reference, const std::string& test_name,
                              const std::string& reference_name) {
  requireComparable(test, reference, test_name, reference_name);
  const int channels = comparedChannels(test);
  double sum_rel = 0.0, sum_sq = 0.0, sum_ref_sq = 0.0, max_abs = 0.0, peak = 0.0;
  for (int y = 0; y < test.height; ++y)
    for (int x = 0; x < test.width; ++x)
      for (int c = 0; c < channels; ++c) {
        const double t = test.at(x, y, c), r = reference.at(x, y, c);
        const double d = t - r;
        sum_rel += d * d / (r * r + kRelMseEpsilon);
        sum_sq += d * d;
        sum_ref_sq += r * r;
        max_abs = std::max(max_abs, std::abs(d));
        peak = std::max(peak, std::abs(r));
      }
  const double n = double(test.width) * double(test.height) * double(channels);
  const double mse = sum_sq / n;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  ImageComparison out;
  out.relmse = sum_rel / n;
  out.rel_rmse = mse == 0.0 ? 0.0 : (sum_ref_sq > 0.0 ? std::sqrt(mse) / std::sqrt(sum_ref_sq / n) : kInf);
  out.psnr_db = mse == 0.0 ? kInf : (peak > 0.0 ? 10.0 * std::log10(peak * peak / mse) : -kInf);
  out.max_abs = max_abs;
  out.width = test.width;
  out.height = test.height;
  out.channels = channels;
  return out;
}

Rgb viridis(double x) {
  const double clamped = std::isnan(x) ? 0.0 : std::clamp(x, 0.0, 1.0);
  const double position = clamped * double(kViridis.size() - 1);
  const std::size_t k = std::min(static_cast<std::size_t>(position), kViridis.size() - 2);
  const float f = static_cast<float>(position - double(k));
  const auto& a = kViridis[k];
  const auto& b = kViridis[k + 1];
  return {a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])};
}

Image errorHeatMap(const Image& test, const Image& reference, double scale, const std::string& test_name,
                   const std::string& reference_name) {
  if (!(std::isfinite(scale) && scale > 0.0)) {
    std::ostringstream message;
    message << "error heat map: the scale must be finite and > 0, got " << scale;
    throw Error(message.str());
  }
  requireComparable(test, reference, test_name, reference_name);
  const int channels = comparedChannels(test);
  Image out(test.width, test.height, 3);
  for (int y = 0; y < test.height; ++y)
    for (int x = 0; x < test.width; ++x) {
      double error = 0.0;
      for (int c = 0; c < channels; ++c) {
        const double t = test.at(x, y, c), r = reference.at(x, y, c);
        error += std::abs(t - r) / (std::abs(r) + kHeatMapEpsilon);
      }
      const Rgb colour = viridis(error / double(channels) / scale);
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = colour[c];
    }
  return out;
}

}  // namespace btf::render
