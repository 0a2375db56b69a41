// Scenes built in code for the renderer's validation tests, and the batch statistics they judge by.
#pragma once

#include <cmath>
#include <memory>
#include <vector>

#include "btf/core/math.h"
#include "btf/render/integrator.h"
#include "btf/render/scene.h"

namespace btf::test {

// A camera of one pixel with a tiny field of view looking at `target` from `eye`: the pixel's
// radiance is the radiance leaving that point (the footprint is well below a millimetre).
inline render::CameraSettings onePixelCamera(const glm::vec3& eye, const glm::vec3& target) {
  render::CameraSettings c;
  c.position = eye;
  c.look_at = target;
  c.up = std::abs(glm::normalize(target - eye).y) > 0.9f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
  c.fov_deg = 0.01f;
  c.width = c.height = 1;
  return c;
}

// The floor y = 0, 2 x 2 around the origin, with +y as normal and +z as the UV tangent.
inline render::SceneShape floorQuad(int material, float half_size = 1.0f) {
  render::SceneShape s;
  s.mesh = render::makeQuad({-half_size, 0, -half_size}, {0, 0, 2 * half_size}, {2 * half_size, 0, 0}, "floor");
  s.material = material;
  return s;
}

// Mean and standard error of one pixel over `batches` renders with different seeds.
struct PixelEstimate {
  Rgb mean{0.0f};
  Rgb standard_error{0.0f};
};
inline PixelEstimate estimatePixel(const render::Scene& scene, const render::Integrator& integrator, int spp,
                                   int batches, std::uint64_t first_seed = 1) {
  std::vector<Rgb> values;
  for (int b = 0; b < batches; ++b) {
    render::RenderSettings settings;
    settings.spp = spp;
    settings.seed = first_seed + std::uint64_t(b);
    const render::RenderResult r = integrator.render(scene, settings);
    values.push_back({r.color.at(0, 0, 0), r.color.at(0, 0, 1), r.color.at(0, 0, 2)});
  }
  PixelEstimate e;
  for (const Rgb& v : values) e.mean += v / float(batches);
  for (int c = 0; c < 3; ++c) {
    double s2 = 0;
    for (const Rgb& v : values) s2 += double(v[c] - e.mean[c]) * double(v[c] - e.mean[c]);
    e.standard_error[c] = float(std::sqrt(s2 / double(batches - 1) / double(batches)));
  }
  return e;
}

}  // namespace btf::test
