// Rules every estimator of render/ applies alike, so that the path tracer and the photon mappers
// compute the same thing. Private to render/.
#pragma once

#include <cmath>

#include "btf/render/scene.h"

namespace btf::render {

// The power heuristic (beta = 2, Veach 1997, §9.2): the weight of a technique with density pdf_a
// against one with pdf_b; an infinite pdf_a (a delta) takes all the weight.
inline float powerHeuristic(float pdf_a, float pdf_b) {
  const float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  if (std::isinf(a)) return 1.0f;
  return a + b > 0.0f ? a / (a + b) : 0.0f;
}

// Veach's rule for shading normals: a direction counts only on the side of both the geometric
// and the shading normal where the view is (reflection only; our materials do not transmit).
inline bool sameSideOfBothNormals(const SurfaceHit& hit, const glm::vec3& w) {
  return glm::dot(w, hit.ng) > 0.0f && glm::dot(w, hit.shading.n) > 0.0f;
}

// The first surface a camera ray finds, with what every estimator needs there. `radiance` starts
// as what the ray brings back unconditionally (the environment, or the surface's emission);
// `material` is null when nothing more can be reflected (no surface, no material, or a shading
// normal turned away from the view).
struct CameraHit {
  SurfaceHit hit;
  const SceneMaterial* material = nullptr;
  glm::vec3 wo{0.0f};  // towards the camera, in the shading frame
  Rgb radiance{0.0f};
};

inline CameraHit findCameraHit(const Scene& scene, const Ray& ray) {
  CameraHit c;
  if (!scene.intersect(ray, c.hit)) {
    c.radiance = scene.environment(ray.direction);
    return c;
  }
  c.radiance = scene.emitted(c.hit);
  c.wo = c.hit.shading.toLocal(-ray.direction);
  if (c.wo.z > 0.0f) c.material = scene.materialOf(c.hit);
  return c;
}

}  // namespace btf::render
