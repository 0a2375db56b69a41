// What every estimator of the rendering equation shares: its settings, its result, and the
// interface the path tracer and the photon mappers implement over the same Scene, so that "two
// estimators agree" compares like with like.
//
// Determinism: every pixel sample draws from its own counter-based stream (seed, pixel, sample),
// and every pixel is computed by one thread from start to end, so the image is the same for any
// thread count and any tile order.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "btf/io/image.h"
#include "btf/render/scene.h"

namespace btf::render {

struct RenderSettings {
  int spp = 16;
  std::uint64_t seed = 1;
  int max_depth = 16;    // path segments at most (1: direct view of emitters only)
  int rr_min_depth = 3;  // Russian roulette by throughput after this many segments
  bool aovs = false;     // albedo, shading normal, depth and sample count of the first hit
  int tile_size = 16;
};

struct RenderStats {
  double seconds = 0;
  std::uint64_t camera_rays = 0;
  std::uint64_t extension_rays = 0;  // closest-hit rays after the camera's
  std::uint64_t shadow_rays = 0;
  std::uint64_t photons = 0;          // photon mappers: photons stored
  std::uint64_t photons_emitted = 0;  // photon mappers: photons traced from the lights
  double photon_seconds = 0;          // photon mappers: time spent tracing and building the maps
  std::uint64_t rays() const { return camera_rays + extension_rays + shadow_rays; }
};

struct RenderResult {
  Image color;  // linear RGB radiance
  // AOVs (empty unless requested): albedo = mean f cos / pdf of the first hit's material sample
  // (an estimate of its directional albedo), normal = world-space shading normal (RGB = xyz),
  // depth = distance to the first hit (0 where nothing is hit), samples = samples per pixel.
  Image albedo, normal, depth, samples;
  RenderStats stats;
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  // Throws btf::Error for settings out of range (spp < 1, max_depth < 1, ...).
  virtual RenderResult render(const Scene& scene, const RenderSettings& settings) const = 0;
  virtual std::string name() const = 0;
};

// Unidirectional path tracing: next-event estimation and material sampling combined by multiple
// importance sampling (power heuristic), Russian roulette by throughput after rr_min_depth.
std::unique_ptr<Integrator> makePathTracer();

// For benchmarks: renders like makePathTracer() on one thread and appends every ray it traces
// (camera, extension and shadow rays, in order) to `rays`, so that a bare loop of BVH queries can
// be timed on exactly the rays of a render.
struct TracedRay {
  Ray ray;
  bool shadow;  // an occlusion query; otherwise a closest-hit query
};
RenderResult renderPathTracedRecording(const Scene& scene, const RenderSettings& settings, std::vector<TracedRay>& rays);

// Checks what every integrator requires of the settings; throws btf::Error naming the setting.
void validateSettings(const RenderSettings& settings);

}  // namespace btf::render
