// The path tracer. Per path vertex:
//   1. emission found by the previous material sample, weighted against light sampling by MIS;
//   2. next-event estimation: one light sample, weighted against material sampling by MIS (delta
//      lights get weight 1, no other technique finds them);
//   3. a material sample continues the path; Russian roulette after rr_min_depth segments.
// Both MIS weights use the power heuristic (beta = 2, Veach 1997, §9.2).
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

#include "btf/core/error.h"
#include "btf/core/progress.h"
#include "btf/core/rng.h"
#include "btf/render/integrator.h"
#include "render_tiles.h"
#include "shading_rules.h"

namespace btf::render {
namespace {

struct FirstHit {
  Rgb albedo{0.0f};
  glm::vec3 normal{0.0f};
  float depth = 0;
};

struct RayCounts {
  std::uint64_t extension = 0, shadow = 0;
};

Rgb tracePath(const Scene& scene, Ray ray, Rng& rng, const RenderSettings& settings, FirstHit* first, RayCounts& counts,
              std::vector<TracedRay>* log) {
  Rgb radiance(0.0f), throughput(1.0f);
  float previous_pdf = 0.0f;  // solid-angle pdf of the material sample that made `ray`
  glm::vec3 previous_point = ray.origin;
  for (int depth = 0;; ++depth) {
    SurfaceHit hit;
    if (depth > 0) ++counts.extension;
    if (log) log->push_back({ray, false});
    if (!scene.intersect(ray, hit)) {
      if (scene.hasEnvironment()) {
        const Rgb le = scene.environment(ray.direction);
        const float w = depth == 0 ? 1.0f : powerHeuristic(previous_pdf, scene.environmentPdf(ray.direction));
        radiance += throughput * le * w;
      }
      break;
    }
    if (first && depth == 0) {
      first->normal = hit.shading.n;
      first->depth = hit.t;
    }
    const Rgb le = scene.emitted(hit);
    if (!le.isBlack()) {
      const float w = depth == 0 ? 1.0f : powerHeuristic(previous_pdf, scene.areaLightPdf(previous_point, hit, ray.direction));
      radiance += throughput * le * w;
    }
    if (depth + 1 >= settings.max_depth) break;
    const SceneMaterial* material = scene.materialOf(hit);
    if (!material) break;
    const glm::vec3 wo_world = -ray.direction;
    const glm::vec3 wo = hit.shading.toLocal(wo_world);
    if (!(wo.z > 0.0f)) break;  // the shading normal turns away from the view: nothing reflects
    const Material& brdf = *material->sampled;

    // Next-event estimation.
    const float u_light = rng.uniform();
    const glm::vec2 u_light2 = rng.uniform2D();
    if (const auto light = scene.sampleLight(hit.p, u_light, u_light2); light && light->pdf > 0.0f) {
      if (sameSideOfBothNormals(hit, light->wi)) {
        const glm::vec3 wi = hit.shading.toLocal(light->wi);
        const Rgb f = brdf.eval(wi, wo, hit.uv);
        if (!f.isBlack()) {
          ++counts.shadow;
          const Ray shadow = std::isinf(light->distance) ? scene.spawnRay(hit, light->wi)
                                                         : scene.spawnRayTo(hit, hit.p + light->wi * light->distance);
          if (log) log->push_back({shadow, true});
          if (!scene.occluded(shadow)) {
            const float w = light->delta ? 1.0f : powerHeuristic(light->pdf, brdf.pdf(wi, wo, hit.uv));
            radiance += throughput * f * light->radiance * (wi.z * w / light->pdf);
          }
        }
      }
    }

    // Continue by material sampling.
    const auto sample = brdf.sample(wo, hit.uv, rng.uniform2D());
    if (first && depth == 0 && sample) first->albedo = sample->weight;
    if (!sample || !(sample->pdf > 0.0f) || sample->weight.isBlack() || !sample->weight.isFinite()) break;
    const glm::vec3 wi_world = hit.shading.toWorld(sample->wi);
    if (!sameSideOfBothNormals(hit, wi_world)) break;
    throughput *= sample->weight;
    previous_pdf = sample->pdf;
    previous_point = hit.p;
    ray = scene.spawnRay(hit, wi_world);

    if (depth + 1 >= settings.rr_min_depth) {
      // Survive with the throughput's largest channel (at most 1, at least 5%), so that paths of
      // little weight end early and the estimate stays unbiased.
      const float survive = std::clamp(throughput.maxComponent(), 0.05f, 1.0f);
      if (rng.uniform() >= survive) break;
      throughput /= survive;
    }
  }
  return radiance;
}

// One image; with a ray log the tiles run in order on this thread, so the log is the render's rays.
RenderResult renderImage(const Scene& scene, const RenderSettings& settings, std::vector<TracedRay>* log) {
  validateSettings(settings);
  const auto start = std::chrono::steady_clock::now();
  const CameraSettings& cam = scene.camera().settings();
  RenderResult result;
  result.color = Image(cam.width, cam.height, 3);
  if (settings.aovs) {
    result.albedo = Image(cam.width, cam.height, 3);
    result.normal = Image(cam.width, cam.height, 3);
    result.depth = Image(cam.width, cam.height, 1);
    result.samples = Image(cam.width, cam.height, 1);
  }
  std::atomic<std::uint64_t> extension{0}, shadow{0};
  auto renderTile = [&](const TileRange& tile) {
    RayCounts counts;
    for (int y = tile.y0; y < tile.y1; ++y)
      for (int x = tile.x0; x < tile.x1; ++x) {
        const std::uint64_t pixel = std::uint64_t(y) * std::uint64_t(cam.width) + std::uint64_t(x);
        Rgb sum(0.0f), albedo(0.0f);
        glm::vec3 normal(0.0f);
        float depth = 0;
        for (int s = 0; s < settings.spp; ++s) {
          Rng rng(settings.seed, pixel);
          rng.seek(std::uint64_t(s) << 32);  // disjoint counter ranges per sample
          const glm::vec2 jitter = rng.uniform2D();
          const Ray ray = scene.camera().generateRay(glm::vec2(float(x), float(y)) + jitter);
          FirstHit first;
          const Rgb l = tracePath(scene, ray, rng, settings, settings.aovs ? &first : nullptr, counts, log);
          // A non-finite sample (a material returning NaN) would poison the pixel; drop it.
          if (l.isFinite()) sum += l;
          albedo += first.albedo;
          normal += first.normal;
          depth += first.depth;
        }
        const float inv = 1.0f / float(settings.spp);
        for (int c = 0; c < 3; ++c) result.color.at(x, y, c) = sum[c] * inv;
        if (settings.aovs) {
          for (int c = 0; c < 3; ++c) {
            result.albedo.at(x, y, c) = albedo[c] * inv;
            result.normal.at(x, y, c) = normal[c] * inv;
          }
          result.depth.at(x, y, 0) = depth * inv;
          result.samples.at(x, y, 0) = float(settings.spp);
        }
      }
    extension += counts.extension;
    shadow += counts.shadow;
  };
  if (log) {
    for (int y0 = 0; y0 < cam.height; y0 += settings.tile_size)
      for (int x0 = 0; x0 < cam.width; x0 += settings.tile_size)
        renderTile(TileRange{x0, y0, std::min(cam.width, x0 + settings.tile_size), std::min(cam.height, y0 + settings.tile_size)});
  } else {
    forEachTile(cam.width, cam.height, settings.tile_size, "render (path tracing)", renderTile);
  }
  result.stats.camera_rays = std::uint64_t(cam.width) * std::uint64_t(cam.height) * std::uint64_t(settings.spp);
  result.stats.extension_rays = extension;
  result.stats.shadow_rays = shadow;
  result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

class PathTracer final : public Integrator {
 public:
  std::string name() const override { return "pt"; }
  RenderResult render(const Scene& scene, const RenderSettings& settings) const override {
    return renderImage(scene, settings, nullptr);
  }
};

}  // namespace

RenderResult renderPathTracedRecording(const Scene& scene, const RenderSettings& settings, std::vector<TracedRay>& rays) {
  return renderImage(scene, settings, &rays);
}

void validateSettings(const RenderSettings& s) {
  if (s.spp < 1) throw Error("spp must be at least 1, got " + std::to_string(s.spp));
  if (s.max_depth < 1) throw Error("max_depth must be at least 1, got " + std::to_string(s.max_depth));
  if (s.rr_min_depth < 1) throw Error("rr_min_depth must be at least 1, got " + std::to_string(s.rr_min_depth));
  if (s.tile_size < 1) throw Error("tile_size must be at least 1, got " + std::to_string(s.tile_size));
}

std::unique_ptr<Integrator> makePathTracer() { return std::make_unique<PathTracer>(); }

}  // namespace btf::render
