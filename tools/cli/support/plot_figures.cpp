#include "plot_figures.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "btf/core/frame.h"
#include "btf/core/half_diff.h"
#include "btf/core/math.h"

namespace btf::cli {
namespace {

constexpr Rgb kBackground(0.12f);

}  // namespace

Rgb colorMap(float t) {
  // Black - purple - red - orange - pale yellow, spaced evenly.
  static constexpr std::array<Rgb, 5> kStops = {Rgb(0.00f, 0.00f, 0.02f), Rgb(0.33f, 0.07f, 0.50f),
                                                Rgb(0.82f, 0.22f, 0.32f), Rgb(0.99f, 0.58f, 0.22f),
                                                Rgb(0.99f, 0.98f, 0.75f)};
  const float x = std::clamp(t, 0.0f, 1.0f) * float(kStops.size() - 1);
  const int i = std::min(int(x), int(kStops.size()) - 2);
  const float w = x - float(i);
  return kStops[i] * (1.0f - w) + kStops[i + 1] * w;
}

int sliceColumnOf(float theta_h_deg, int size) {
  return int(std::lround(std::sqrt(std::clamp(theta_h_deg, 0.0f, 90.0f) / 90.0f) * float(size - 1)));
}

SliceFigure renderHalfDiffSlice(const Material& material, int size, float decades) {
  std::vector<float> values(std::size_t(size) * size, 0.0f);
  float max_value = 0.0f;
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const float u = (float(x) + 0.5f) / float(size);
      HalfDiff hd;
      hd.theta_h = u * u * kHalfPi;
      hd.theta_d = (1.0f - (float(y) + 0.5f) / float(size)) * kHalfPi;
      hd.phi_d = kHalfPi;
      const DirectionPair pair = fromHalfDiff(hd);
      const float v = material.eval(pair.wi, pair.wo).luminance() * std::max(0.0f, cosTheta(pair.wi));
      values[std::size_t(y) * size + x] = v;
      max_value = std::max(max_value, v);
    }
  }
  SliceFigure figure;
  figure.image = Image(size, size, 3);
  figure.log10_max = max_value > 0 ? std::log10(max_value) : 0.0f;
  figure.log10_min = figure.log10_max - decades;
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const float v = values[std::size_t(y) * size + x];
      const float t = v > 0 ? (std::log10(v) - figure.log10_min) / decades : 0.0f;
      const Rgb c = colorMap(t);
      for (int ch = 0; ch < 3; ++ch) figure.image.at(x, y, ch) = c[ch];
    }
  }
  return figure;
}

Image renderSpherePreview(const Material& material, int size, const glm::vec3& to_light, float exposure_stops) {
  constexpr int kSamplesPerAxis = 2;
  const float scale = kPi * std::exp2(exposure_stops);
  const glm::vec3 light = glm::normalize(to_light);
  const glm::vec3 view(0, 0, 1);
  Image image(size, size, 3);
  for (int py = 0; py < size; ++py) {
    for (int px = 0; px < size; ++px) {
      Rgb sum(0.0f);
      for (int sy = 0; sy < kSamplesPerAxis; ++sy) {
        for (int sx = 0; sx < kSamplesPerAxis; ++sx) {
          const float x = 2.0f * (float(px) + (float(sx) + 0.5f) / kSamplesPerAxis) / float(size) - 1.0f;
          const float y = 1.0f - 2.0f * (float(py) + (float(sy) + 0.5f) / kSamplesPerAxis) / float(size);
          const float r2 = x * x + y * y;
          if (r2 >= 1.0f) {
            sum += kBackground;
            continue;
          }
          const Frame frame = Frame::fromNormal(glm::vec3(x, y, std::sqrt(1.0f - r2)));
          const glm::vec3 wi = frame.toLocal(light), wo = frame.toLocal(view);
          const Rgb radiance = material.eval(wi, wo) * (std::max(0.0f, wi.z) * scale);
          sum += Rgb(srgbEncode(radiance.r), srgbEncode(radiance.g), srgbEncode(radiance.b));
        }
      }
      sum /= float(kSamplesPerAxis * kSamplesPerAxis);
      for (int c = 0; c < 3; ++c) image.at(px, py, c) = sum[c];
    }
  }
  return image;
}

}  // namespace btf::cli
