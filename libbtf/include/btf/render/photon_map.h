// Photon mapping (Jensen 1996) as a second estimator over the same Scene as the path tracer:
// photons leave the lights in proportion to their power, bounce by the materials' own sample(),
// and are stored at every surface hit; radiance is estimated from the photons near a point.
//
// Estimates: k nearest photons (the radius is the k-th distance, capped at max_radius) or every
// photon within a fixed radius; a surface-normal filter keeps photons of the same surface
// (n_photon . n > normal_filter_cos, arriving on the shaded side); a cone (Jensen's filter, k = 1)
// or Epanechnikov kernel weighs them by distance, normalized over the disk.
//
// Modes: direct visualization (the estimate at the first surface the camera sees), final
// gathering (at the first hit: emission, next-event estimation and one material sample, whose
// second hit reads the photon map), and progressive photon mapping in the probabilistic form of
// Knaus and Zwicker (2011): independent passes, each with fresh photons and a radius shrinking as
// r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1), averaged, so bias and variance both go to zero.
//
// Photon i is traced from its own random stream and photons are collected in fixed chunks, so the
// map (and the image) is the same for any thread count.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "btf/render/integrator.h"
#include "btf/render/photon_kdtree.h"

namespace btf::render {

enum class PhotonKernel { Cone, Epanechnikov };
enum class PhotonMode { DirectVisualization, FinalGathering, Progressive };

struct PhotonSettings {
  std::uint64_t photons = 200'000;  // emitted per map (per pass for the progressive mode)
  int k = 50;                       // neighbours of a k-nearest estimate; 0: fixed radius
  float radius = 0.0f;              // fixed radius, or the first radius of the progressive mode;
                                    // 0: 1% of the scene's bounding radius
  float max_radius = 0.0f;          // cap of the k-nearest radius; 0: 5% of the bounding radius
  PhotonKernel kernel = PhotonKernel::Epanechnikov;
  float normal_filter_cos = 0.9f;
  int passes = 16;                  // progressive mode
  float alpha = 2.0f / 3.0f;        // progressive mode: the share of photons each pass keeps
};

struct StoredPhoton {
  glm::vec3 wi;     // direction the photon came from (unit, world, pointing away from the surface)
  glm::vec3 n;      // geometric normal at the hit, turned towards wi
  Rgb power;        // flux (W)
};

class PhotonMap {
 public:
  // Traces `count` photons through the scene (seed and depth limits from settings).
  PhotonMap(const Scene& scene, std::uint64_t count, const RenderSettings& settings);

  std::size_t size() const { return photons_.size(); }
  std::uint64_t emitted() const { return emitted_; }
  const PhotonKdTree& tree() const { return tree_; }
  std::span<const StoredPhoton> photons() const { return photons_; }  // in tree order
  // Wall-clock seconds of the two phases: tracing the photons (parallel), then collecting them
  // and building the search tree.
  double traceSeconds() const { return trace_seconds_; }
  double buildSeconds() const { return build_seconds_; }

  // Radiance leaving `hit` towards wo (local, shading frame) from the photons around it.
  Rgb estimate(const SurfaceHit& hit, const Material& material, const glm::vec3& wo, const PhotonSettings& settings,
               float radius, std::vector<PhotonKdTree::Neighbor>& scratch) const;

 private:
  PhotonKdTree tree_;
  std::vector<StoredPhoton> photons_;
  std::uint64_t emitted_ = 0;
  double trace_seconds_ = 0, build_seconds_ = 0;
};

std::unique_ptr<Integrator> makePhotonMapper(PhotonMode mode, const PhotonSettings& settings);

}  // namespace btf::render
