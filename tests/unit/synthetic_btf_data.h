// Small in-memory BTFs made from analytic materials, for tests and benchmarks of BTF consumers:
// every texel is a flat sample of a GGX-over-Lambert material whose diffuse albedo and roughness
// vary smoothly over the texels, so value(x, y, view, light) = material.eval(light dir, view dir).
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "btf/core/btf_directions.h"
#include "btf/io/btf_data.h"
#include "btf/material/ggx.h"
#include "btf/material/lambert.h"

namespace btf::test {

// Per-texel Ggx(kd(x, y), f0 0.04, alpha(x, y)): albedo in [0.1, 0.8] per channel with different
// patterns per channel, alpha in [0.15, 0.6]. `specular = false` gives a Lambert-only BTF.
inline BtfData makeAnalyticBtf(int width, int height, bool specular = true, std::string name = "analytic") {
  BtfData data(width, height, std::move(name));
  const auto& dirs = btfDirections();
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float u = (float(x) + 0.5f) / float(width), v = (float(y) + 0.5f) / float(height);
      const Rgb albedo(0.45f + 0.35f * std::sin(6.0f * u + 1.0f), 0.45f + 0.35f * std::cos(5.0f * v),
                       0.45f + 0.35f * std::sin(4.0f * (u + v)));
      const float alpha = 0.15f + 0.45f * (0.5f + 0.5f * std::sin(7.0f * u * v + 3.0f * u));
      const Ggx ggx(albedo, Rgb(0.04f), alpha, alpha);
      const Lambert lambert(albedo);
      for (int view = 0; view < kBtfDirectionCount; ++view)
        for (int light = 0; light < kBtfDirectionCount; ++light) {
          const glm::vec3& wi = dirs[std::size_t(light)].w;
          const glm::vec3& wo = dirs[std::size_t(view)].w;
          data.at(x, y, view, light) = specular ? ggx.eval(wi, wo) : lambert.eval(wi, wo);
        }
    }
  return data;
}

// A source whose views are shorter than width x height x 81 (a faulty reader): consumers must
// reject it rather than read past the end of its views.
class ShortViewSource final : public BtfSource {
 public:
  int width() const override { return 2; }
  int height() const override { return 2; }
  std::string name() const override { return "short-views"; }
  void loadView(int, std::vector<Rgb>& out) const override { out.assign(10, Rgb(1.0f)); }
};

}  // namespace btf::test
