#include "btf/render/photon_map.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/progress.h"
#include "btf/core/rng.h"
#include "btf/core/cdf1d.h"
#include "btf/core/warp.h"
#include "render_tiles.h"
#include "shading_rules.h"

namespace btf::render {
namespace {

constexpr std::uint64_t kChunk = 1024;  // photons per task: the unit of deterministic collection

struct Emitted {
  Ray ray;
  Rgb power;
};

// A surface point as a SurfaceHit, to offset rays leaving it the way the scene offsets all rays.
SurfaceHit pointOn(const glm::vec3& p, const glm::vec3& n) {
  SurfaceHit h;
  h.p = p;
  h.ng = n;
  h.shading = Frame::fromNormal(n);
  return h;
}

std::optional<Emitted> emitPhoton(const Scene& scene, const std::vector<float>& light_cdf, Rng& rng) {
  const DiscreteSample choice = sampleDiscrete(light_cdf, rng.uniform());
  if (!(choice.probability > 0.0f)) return std::nullopt;
  const Scene::LightPower& light = scene.lights()[choice.index];
  const glm::vec2 u_pos = rng.uniform2D(), u_dir = rng.uniform2D();
  switch (light.kind) {
    case Scene::LightPower::Kind::Area: {
      const SceneShape& shape = scene.description().shapes[std::size_t(light.index)];
      const Scene::SurfacePoint sp = scene.sampleShapeArea(light.index, rng.uniform(), u_pos);
      glm::vec3 n = sp.n;
      float sides = 1.0f;
      if (shape.two_sided_emission) {
        sides = 2.0f;
        if (rng.uniform() < 0.5f) n = -n;
      }
      // Cosine-weighted directions: flux per photon = Le * pi * area * sides / p(light).
      const glm::vec3 d = Frame::fromNormal(n).toWorld(squareToCosineHemisphere(u_dir));
      const SurfaceHit from = pointOn(sp.p, n);
      return Emitted{scene.spawnRay(from, d), shape.emission * (kPi * scene.shapeArea(light.index) * sides / choice.probability)};
    }
    case Scene::LightPower::Kind::Point: {
      const PointLight& p = scene.description().point_lights[std::size_t(light.index)];
      return Emitted{Ray{p.position, squareToUniformSphere(u_dir)}, p.intensity * (4.0f * kPi / choice.probability)};
    }
    case Scene::LightPower::Kind::Environment: {
      // A direction the light arrives from, then a point on the disk of the scene's bounding
      // radius facing it, outside the scene: flux = L(d) * pi R^2 / (pdf(d) p(light)).
      glm::vec3 d;
      float pdf;
      Rgb radiance;
      const auto& map = scene.description().environment_map;
      if (map) {
        const auto s = map->sample(u_dir);
        if (!s || !(s->pdf > 0.0f)) return std::nullopt;
        d = s->direction;
        pdf = s->pdf;
        radiance = s->radiance;
      } else {
        d = squareToUniformSphere(u_dir);
        pdf = uniformSpherePdf();
        radiance = scene.description().environment_radiance;
      }
      const float r = scene.boundsRadius();
      const glm::vec2 disk = squareToConcentricDisk(u_pos) * r;
      const Frame frame = Frame::fromNormal(d);
      const glm::vec3 origin = scene.boundsCenter() + d * r + frame.s * disk.x + frame.t * disk.y;
      return Emitted{Ray{origin, -d}, radiance * (kPi * r * r / (pdf * choice.probability))};
    }
  }
  return std::nullopt;
}

struct ChunkPhotons {
  std::vector<glm::vec3> positions;
  std::vector<StoredPhoton> photons;
};

void tracePhoton(const Scene& scene, Emitted photon, Rng& rng, const RenderSettings& settings, ChunkPhotons& out) {
  Ray ray = photon.ray;
  Rgb power = photon.power;
  for (int depth = 0; depth < settings.max_depth; ++depth) {
    SurfaceHit hit;
    if (!scene.intersect(ray, hit)) return;
    const SceneMaterial* material = scene.materialOf(hit);
    if (!material) return;
    const glm::vec3 wo_world = -ray.direction;  // towards where the photon came from
    const glm::vec3 wo = hit.shading.toLocal(wo_world);
    if (!(wo.z > 0.0f)) return;
    out.positions.push_back(hit.p);
    out.photons.push_back({wo_world, hit.ng, power});
    if (depth + 1 >= settings.max_depth) return;
    // The material's own sampler continues the photon: sample() draws wi for a given wo, which by
    // reciprocity is the photon's next direction for the direction it came from.
    const auto s = material->material->sample(wo, hit.uv, rng.uniform2D());
    if (!s || !(s->pdf > 0.0f) || !s->weight.isFinite()) return;
    const glm::vec3 next = hit.shading.toWorld(s->wi);
    if (!sameSideOfBothNormals(hit, next)) return;
    // Shading normals make scattering non-symmetric; the adjoint carries Veach's correction
    // |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|) (1997, §5.3).
    const float correction = std::abs(wo.z) * std::abs(glm::dot(next, hit.ng)) /
                             std::max(std::abs(glm::dot(wo_world, hit.ng)) * std::abs(s->wi.z), 1e-8f);
    const Rgb scatter = s->weight * correction;
    if (depth + 1 >= settings.rr_min_depth) {
      const float survive = std::clamp(scatter.maxComponent(), 0.05f, 1.0f);
      if (rng.uniform() >= survive) return;
      power *= scatter / survive;
    } else {
      power *= scatter;
    }
    ray = scene.spawnRay(hit, next);
  }
}

}  // namespace

PhotonMap::PhotonMap(const Scene& scene, std::uint64_t count, const RenderSettings& settings) : emitted_(count) {
  if (count == 0) throw Error("a photon map needs at least one photon");
  std::vector<float> weights, light_cdf;
  for (const auto& light : scene.lights()) weights.push_back(light.power.average());
  light_cdf.resize(weights.size() + 1);
  buildCdf1D(weights, light_cdf);

  const auto start = std::chrono::steady_clock::now();
  const std::uint64_t chunks = (count + kChunk - 1) / kChunk;
  std::vector<ChunkPhotons> collected(chunks);
  Progress progress("photon tracing", chunks);
  tbb::parallel_for(std::uint64_t(0), chunks, [&](std::uint64_t c) {
    ChunkPhotons& out = collected[c];
    for (std::uint64_t i = c * kChunk; i < std::min(count, (c + 1) * kChunk); ++i) {
      // Streams above 2^62 keep the photons' streams apart from the camera's pixel streams.
      Rng rng(settings.seed, (std::uint64_t(1) << 62) + i);
      const auto photon = emitPhoton(scene, light_cdf, rng);
      if (photon && !photon->power.isBlack() && photon->power.isFinite()) tracePhoton(scene, *photon, rng, settings, out);
    }
    progress.advance();
  });
  const auto traced = std::chrono::steady_clock::now();
  trace_seconds_ = std::chrono::duration<double>(traced - start).count();
  std::vector<glm::vec3> positions;
  std::vector<StoredPhoton> photons;
  for (ChunkPhotons& c : collected) {
    positions.insert(positions.end(), c.positions.begin(), c.positions.end());
    photons.insert(photons.end(), c.photons.begin(), c.photons.end());
  }
  // Each photon carries the flux of one of `count` emitted photons.
  const float share = 1.0f / float(count);
  for (StoredPhoton& p : photons) p.power *= share;
  tree_ = PhotonKdTree(std::move(positions));
  photons_.resize(photons.size());
  const auto order = tree_.order();
  for (std::size_t i = 0; i < order.size(); ++i) photons_[i] = photons[order[i]];
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - traced).count();
}

Rgb PhotonMap::estimate(const SurfaceHit& hit, const Material& material, const glm::vec3& wo, const PhotonSettings& settings,
                        float radius, std::vector<PhotonKdTree::Neighbor>& found) const {
  float r2 = radius * radius;
  if (settings.k > 0) {
    tree_.knn(hit.p, std::size_t(settings.k), r2, found);
    if (found.size() == std::size_t(settings.k)) r2 = found.back().distance2;
  } else {
    tree_.withinRadius(hit.p, r2, found);
  }
  if (found.empty() || !(r2 > 0.0f)) return Rgb(0.0f);
  Rgb sum(0.0f);
  for (const PhotonKdTree::Neighbor& nb : found) {
    const StoredPhoton& photon = photons_[nb.index];
    // The same surface, lit from the side being shaded.
    if (glm::dot(photon.n, hit.ng) < settings.normal_filter_cos) continue;
    if (!sameSideOfBothNormals(hit, photon.wi)) continue;
    const float t = nb.distance2 / r2;
    const float weight = settings.kernel == PhotonKernel::Epanechnikov ? 1.0f - t : 1.0f - std::sqrt(t);
    sum += material.eval(hit.shading.toLocal(photon.wi), wo, hit.uv) * photon.power * weight;
  }
  // Kernels normalized over the disk of radius r: Epanechnikov 2 / (pi r^2) (1 - d^2/r^2), the cone
  // 3 / (pi r^2) (1 - d/r).
  const float norm = (settings.kernel == PhotonKernel::Epanechnikov ? 2.0f : 3.0f) / (kPi * r2);
  return sum * norm;
}

namespace {

float defaultRadius(const Scene& scene, float setting, float fraction) {
  return setting > 0.0f ? setting : fraction * scene.boundsRadius();
}

class PhotonMapper final : public Integrator {
 public:
  PhotonMapper(PhotonMode mode, const PhotonSettings& settings) : mode_(mode), settings_(settings) {}

  std::string name() const override {
    switch (mode_) {
      case PhotonMode::DirectVisualization: return "photon";
      case PhotonMode::FinalGathering: return "photon-gather";
      case PhotonMode::Progressive: return "ppm";
    }
    return "photon";
  }

  RenderResult render(const Scene& scene, const RenderSettings& settings) const override {
    validateSettings(settings);
    if (settings_.photons == 0) throw Error("photons must be at least 1");
    if (settings_.k < 0) throw Error("k must not be negative");
    if (mode_ == PhotonMode::Progressive && settings_.passes < 1) throw Error("passes must be at least 1");
    if (!(settings_.alpha > 0.0f && settings_.alpha < 1.0f)) throw Error("alpha must lie in (0, 1)");
    const auto start = std::chrono::steady_clock::now();
    const CameraSettings& cam = scene.camera().settings();
    RenderResult result;
    result.color = Image(cam.width, cam.height, 3);
    std::atomic<std::uint64_t> extension{0}, shadow{0};

    const int passes = mode_ == PhotonMode::Progressive ? settings_.passes : 1;
    double radius2 = std::pow(defaultRadius(scene, settings_.radius, 0.01f), 2.0);
    const float max_radius = defaultRadius(scene, settings_.max_radius, 0.05f);
    PhotonSettings lookup = settings_;
    if (mode_ == PhotonMode::Progressive) lookup.k = 0;  // fixed, shrinking radii
    for (int pass = 0; pass < passes; ++pass) {
      RenderSettings pass_settings = settings;
      pass_settings.seed = settings.seed + std::uint64_t(pass) * 0x9E3779B97F4A7C15ULL;
      const auto t0 = std::chrono::steady_clock::now();
      const PhotonMap map(scene, settings_.photons, pass_settings);
      result.stats.photon_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      result.stats.photons += map.size();
      result.stats.photons_emitted += map.emitted();
      const float radius = mode_ == PhotonMode::Progressive ? float(std::sqrt(radius2)) : (lookup.k > 0 ? max_radius : float(std::sqrt(radius2)));
      const float pass_weight = 1.0f / float(passes);
      forEachTile(cam.width, cam.height, settings.tile_size, "render (" + name() + ")", [&](const TileRange& tile) {
        std::vector<PhotonKdTree::Neighbor> scratch;
        std::uint64_t ext = 0, sh = 0;
        for (int y = tile.y0; y < tile.y1; ++y)
          for (int x = tile.x0; x < tile.x1; ++x) {
            const std::uint64_t pixel = std::uint64_t(y) * std::uint64_t(cam.width) + std::uint64_t(x);
            Rgb sum(0.0f);
            for (int s = 0; s < settings.spp; ++s) {
              Rng rng(pass_settings.seed, pixel);
              rng.seek(std::uint64_t(s) << 32);
              const Ray ray = scene.camera().generateRay(glm::vec2(float(x), float(y)) + rng.uniform2D());
              const Rgb l = mode_ == PhotonMode::FinalGathering ? gather(scene, map, ray, rng, lookup, radius, scratch, ext, sh)
                                                                : visualize(scene, map, ray, lookup, radius, scratch);
              if (l.isFinite()) sum += l;
            }
            for (int c = 0; c < 3; ++c) result.color.at(x, y, c) += sum[c] / float(settings.spp) * pass_weight;
          }
        extension += ext;
        shadow += sh;
      });
      // Knaus and Zwicker's schedule: the next pass keeps (i + alpha) / (i + 1) of the disk's area.
      radius2 *= (double(pass + 1) + settings_.alpha) / double(pass + 2);
    }
    result.stats.camera_rays = std::uint64_t(cam.width) * std::uint64_t(cam.height) * std::uint64_t(settings.spp) * std::uint64_t(passes);
    result.stats.extension_rays = extension;
    result.stats.shadow_rays = shadow;
    result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
  }

 private:
  Rgb visualize(const Scene& scene, const PhotonMap& map, const Ray& ray, const PhotonSettings& lookup, float radius,
                std::vector<PhotonKdTree::Neighbor>& scratch) const {
    const CameraHit c = findCameraHit(scene, ray);
    if (!c.material) return c.radiance;
    return c.radiance + map.estimate(c.hit, *c.material->material, c.wo, lookup, radius, scratch);
  }

  // Emission, next-event estimation and one material sample at the first hit, weighted by MIS as
  // in the path tracer; the photon map answers for everything after the second hit.
  Rgb gather(const Scene& scene, const PhotonMap& map, const Ray& ray, Rng& rng, const PhotonSettings& lookup,
             float radius, std::vector<PhotonKdTree::Neighbor>& scratch, std::uint64_t& ext, std::uint64_t& sh) const {
    const CameraHit c = findCameraHit(scene, ray);
    if (!c.material) return c.radiance;
    const SurfaceHit& hit = c.hit;
    const glm::vec3& wo = c.wo;
    Rgb l = c.radiance;
    const Material& brdf = *c.material->sampled;
    const float u_light = rng.uniform();
    const glm::vec2 u_light2 = rng.uniform2D();
    if (const auto light = scene.sampleLight(hit.p, u_light, u_light2); light && light->pdf > 0.0f && sameSideOfBothNormals(hit, light->wi)) {
      const glm::vec3 wi = hit.shading.toLocal(light->wi);
      const Rgb f = brdf.eval(wi, wo, hit.uv);
      if (!f.isBlack()) {
        ++sh;
        const Ray shadow = std::isinf(light->distance) ? scene.spawnRay(hit, light->wi)
                                                       : scene.spawnRayTo(hit, hit.p + light->wi * light->distance);
        if (!scene.occluded(shadow)) {
          const float w = light->delta ? 1.0f : powerHeuristic(light->pdf, brdf.pdf(wi, wo, hit.uv));
          l += f * light->radiance * (wi.z * w / light->pdf);
        }
      }
    }
    const auto s = brdf.sample(wo, hit.uv, rng.uniform2D());
    if (!s || !(s->pdf > 0.0f) || !s->weight.isFinite()) return l;
    const glm::vec3 next = hit.shading.toWorld(s->wi);
    if (!sameSideOfBothNormals(hit, next)) return l;
    ++ext;
    const Ray bounce = scene.spawnRay(hit, next);
    SurfaceHit second;
    if (!scene.intersect(bounce, second)) {
      if (scene.hasEnvironment()) l += s->weight * scene.environment(next) * powerHeuristic(s->pdf, scene.environmentPdf(next));
      return l;
    }
    const Rgb le = scene.emitted(second);
    if (!le.isBlack()) l += s->weight * le * powerHeuristic(s->pdf, scene.areaLightPdf(hit.p, second, next));
    const SceneMaterial* m2 = scene.materialOf(second);
    if (!m2) return l;
    const glm::vec3 wo2 = second.shading.toLocal(-next);
    if (!(wo2.z > 0.0f)) return l;
    return l + s->weight * map.estimate(second, *m2->material, wo2, lookup, radius, scratch);
  }

  PhotonMode mode_;
  PhotonSettings settings_;
};

}  // namespace

std::unique_ptr<Integrator> makePhotonMapper(PhotonMode mode, const PhotonSettings& settings) {
  return std::make_unique<PhotonMapper>(mode, settings);
}

}  // namespace btf::render
