#include "fit_scene_measure.h"

#include <algorithm>
#include <chrono>

#include "btf/core/rng.h"
#include "btf/render/image_metrics.h"
#include "btf/sampling/sampler_choice.h"
#include "btf/core/warp.h"

namespace btf::cli {

FitSpeed measureSpeed(const Material& m) {
  Rng rng(9);
  std::vector<glm::vec3> wi(20000), wo(20000);
  std::vector<glm::vec2> u(20000);
  for (std::size_t k = 0; k < wi.size(); ++k) {
    wi[k] = squareToCosineHemisphere(rng.uniform2D());
    wo[k] = squareToCosineHemisphere(rng.uniform2D());
    u[k] = rng.uniform2D();
  }
  using Clock = std::chrono::steady_clock;
  const glm::vec2 uv(0.5f);
  float sink = 0;
  auto t0 = Clock::now();
  for (std::size_t k = 0; k < wi.size(); ++k) sink += m.eval(wi[k], wo[k], uv).g;
  const double eval_s = std::chrono::duration<double>(Clock::now() - t0).count();
  t0 = Clock::now();
  for (std::size_t k = 0; k < wi.size(); ++k)
    if (const auto s = m.sample(wo[k], uv, u[k])) sink += s->pdf;
  const double sample_s = std::chrono::duration<double>(Clock::now() - t0).count();
  volatile float keep = sink;
  (void)keep;
  return {eval_s > 0 ? double(wi.size()) / eval_s : 0.0, sample_s > 0 ? double(wi.size()) / sample_s : 0.0};
}

render::RenderResult SceneRenderer::result(render::SceneDescription d, int spp, std::uint64_t seed) const {
  render::RenderSettings s = settings;
  s.spp = spp;
  s.seed = seed;
  const render::Scene scene(std::move(d));
  return integrator->render(scene, s);
}

render::SceneDescription withCosineSampling(render::SceneDescription d) {
  for (render::SceneMaterial& m : d.materials) {
    m.sampled = withSampler(SamplerChoice::Cosine, m.material, SamplerOptions{});
    m.sampler = "cosine";
  }
  return d;
}

std::vector<int> firstHitMaterials(const render::SceneDescription& d) {
  const render::Scene scene(d);
  const int w = d.camera.width, h = d.camera.height;
  std::vector<int> out(std::size_t(w) * std::size_t(h), -1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      render::SurfaceHit hit;
      if (scene.intersect(scene.camera().generateRay({float(x) + 0.5f, float(y) + 0.5f}), hit))
        out[std::size_t(y) * std::size_t(w) + std::size_t(x)] = d.shapes[hit.shape].material;
    }
  return out;
}

RenderedError renderedError(const Image& test, const Image& reference, const std::vector<int>& first_hit, int material) {
  RenderedError e;
  e.image = render::compareImages(test, reference).relmse;
  std::size_t n = 0;
  for (const int m : first_hit) n += m == material;
  if (n == 0) {
    e.seen = e.image;
    return e;
  }
  // The material's pixels as two one-row images, measured by the same comparison.
  Image a(int(n), 1, test.channels), b(int(n), 1, reference.channels);
  std::size_t k = 0;
  for (std::size_t p = 0; p < first_hit.size(); ++p) {
    if (first_hit[p] != material) continue;
    for (int c = 0; c < test.channels; ++c) {
      a.pixels[k * std::size_t(test.channels) + std::size_t(c)] = test.pixels[p * std::size_t(test.channels) + std::size_t(c)];
      b.pixels[k * std::size_t(reference.channels) + std::size_t(c)] = reference.pixels[p * std::size_t(reference.channels) + std::size_t(c)];
    }
    ++k;
  }
  e.seen = render::compareImages(a, b).relmse;
  return e;
}

}  // namespace btf::cli
