// Tiny BTFs built in memory from analytic materials, for the VQ and BtfMaterial tests: value =
// the material's f for wi = light direction, wo = view direction, with per-texel albedo and
// roughness patterns (a checker of two colours times a gradient, roughness varying along y).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "btf/core/btf_direction_set.h"
#include "btf/io/btf_data.h"
#include "btf/material/ggx.h"

namespace btf::test {

// Texel colour and roughness of the patterns.
inline Rgb patternColour(int x, int y, int width, int height) {
  const Rgb a(0.7f, 0.3f, 0.15f), b(0.2f, 0.45f, 0.6f);
  const float gradient = 0.6f + 0.4f * float(x + 1) / float(width) * float(y + 2) / float(height + 1);
  return (((x / 2 + y / 2) % 2) == 0 ? a : b) * gradient;
}
inline float patternAlpha(int y, int height) { return 0.15f + 0.35f * float(y) / float(std::max(height - 1, 1)); }

// colour_per_texel: value = colour(x, y) x the luminance shape of a grey GGX (constant chromaticity
// per texel); otherwise a GGX with the coloured diffuse base and a white specular lobe (the
// chromaticity varies with direction). On the 81-direction set unless `set` says otherwise.
inline BtfData makeGgxBtf(int width, int height, bool colour_per_texel,
                          const BtfDirectionSetPtr& set = BtfDirectionSet::ubo2003()) {
  BtfData data(width, height, "ggx-pattern", BtfViewSet::all(set));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const Rgb colour = patternColour(x, y, width, height);
      const float alpha = patternAlpha(y, height);
      const Ggx grey(Rgb(0.5f), Rgb(0.04f), alpha, alpha * (x % 3 == 0 ? 1.0f : 0.7f));
      const Ggx coloured(colour, Rgb(0.04f), alpha, alpha);
      for (int v = 0; v < set->viewCount(); ++v)
        for (int l = 0; l < set->lightCount(v); ++l) {
          const glm::vec3 wi = set->lightDirections(v)[std::size_t(l)], wo = set->view(v);
          data.at(x, y, v, l) = colour_per_texel ? colour * grey.eval(wi, wo).g : coloured.eval(wi, wo);
        }
    }
  return data;
}

// rel_rmse of the luminance alone (the part the VQ tolerance bounds).
inline double luminanceRelRmse(const BtfSource& reference, const BtfSource& test) {
  std::vector<Rgb> a, b;
  double err = 0, ref = 0;
  for (int slot = 0; slot < reference.views().count(); ++slot) {
    const int v = reference.views().view(slot);
    reference.loadView(v, a);
    test.loadView(v, b);
    for (std::size_t i = 0; i < a.size(); ++i) {
      const double d = double(b[i].luminance()) - a[i].luminance();
      err += d * d;
      ref += double(a[i].luminance()) * a[i].luminance();
    }
  }
  return std::sqrt(err / ref);
}

// The luminance bound of vq_btf.h: (1 + epsilon sqrt(1 + floor^2) + 2 q)^levels - 1, each stored
// rounding within q = max(epsilon / 16, 0.00034); 2 q is taken as epsilon / 8 + 1e-3.
inline double vqLuminanceBound(float epsilon, int levels, float energy_floor = 1.0f) {
  return std::pow(1.0 + double(epsilon) * (std::sqrt(1.0 + double(energy_floor) * energy_floor) + 0.125) + 1e-3, levels) - 1.0;
}

// RGB bound of vq_btf.h: rel_rmse(RGB) <= kmax / sqrt(1.7797) * lum
//   + sqrt(1.0986 / 1.7797) * m * chroma_epsilon * sqrt(1 + energy_floor^2), with lum the measured
// luminance rel_rmse, kmax the largest |RGB| / luminance of the decoded data (largest chroma
// amplitude) and m = 2 for 3 levels (level 3's whole-texel chroma test), else 1;
// 1.7797 = min |RGB|^2 / Y^2, 1.0986 = max |dRGB|^2 / |d(R/Y, B/Y)|^2.
inline double vqRgbBound(const BtfSource& decoded, double lum, float chroma_epsilon, float energy_floor, int levels) {
  std::vector<Rgb> values;
  double kmax = 0;
  for (int slot = 0; slot < decoded.views().count(); ++slot) {
    decoded.loadView(decoded.views().view(slot), values);
    for (const Rgb& c : values)
      if (c.luminance() > 0)
        kmax = std::max(kmax, std::sqrt(double(c.r) * c.r + double(c.g) * c.g + double(c.b) * c.b) / c.luminance());
  }
  const double m = levels == 3 ? 2.0 : 1.0;
  return kmax / std::sqrt(1.7797) * lum +
         std::sqrt(1.0986 / 1.7797) * m * chroma_epsilon * std::sqrt(1.0 + double(energy_floor) * energy_floor) + 1e-4;
}

// Asserts that two BTFs hold the same views and decode to the same values, bit for bit.
inline void expectSameDecode(const BtfSource& a, const BtfSource& b) {
  ASSERT_EQ(a.views().views(), b.views().views());
  std::vector<Rgb> va, vb;
  for (int slot = 0; slot < a.views().count(); ++slot) {
    const int v = a.views().view(slot);
    a.loadView(v, va);
    b.loadView(v, vb);
    ASSERT_EQ(va.size(), vb.size());
    for (std::size_t i = 0; i < va.size(); ++i) ASSERT_EQ(va[i], vb[i]) << "view " << v << ", entry " << i;
  }
}

}  // namespace btf::test
