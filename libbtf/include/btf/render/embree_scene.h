// The one place Embree appears: a device, one scene of triangle meshes built at high quality, and
// single-ray closest-hit and occlusion queries. Embree's error callback becomes btf::Error, so a
// failure inside Embree is reported like every other error of the library.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <memory>
#include <vector>

#include "btf/render/camera.h"
#include "btf/render/triangle_mesh.h"

namespace btf::render {

struct RayHit {
  float t;
  std::uint32_t mesh;      // index into the meshes given to the constructor
  std::uint32_t triangle;  // index into that mesh's triangles
  glm::vec2 barycentric;   // (b1, b2): the point is (1 - b1 - b2) p0 + b1 p1 + b2 p2
};

class EmbreeScene {
 public:
  // Builds the BVH over the meshes (their data is copied into Embree's buffers, so they need not
  // outlive the scene). Throws btf::Error with Embree's message if the device or the build fails.
  explicit EmbreeScene(const std::vector<const TriangleMesh*>& meshes);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  // The closest hit with t in [ray.tmin, ray.tmax], or nothing.
  bool intersect(const Ray& ray, RayHit& hit) const;
  // True when anything lies on the ray with t in [ray.tmin, ray.tmax].
  bool occluded(const Ray& ray) const;

  glm::vec3 boundsMin() const { return bounds_min_; }
  glm::vec3 boundsMax() const { return bounds_max_; }

 private:
  struct Handles;
  std::unique_ptr<Handles> handles_;
  glm::vec3 bounds_min_, bounds_max_;
};

}  // namespace btf::render
