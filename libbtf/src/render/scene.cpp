#include "btf/render/scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/progress.h"
#include "btf/render/embree_scene.h"
#include "btf/core/cdf1d.h"
#include "btf/core/warp.h"

namespace btf::render {
namespace {

float triangleArea(const TriangleMesh& mesh, const glm::uvec3& t) {
  return 0.5f * glm::length(glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]));
}

bool nonNegativeFinite(const Rgb& c) { return c.isFinite() && c.minComponent() >= 0.0f; }

std::string describe(const Rgb& c) {
  return "(" + std::to_string(c.r) + ", " + std::to_string(c.g) + ", " + std::to_string(c.b) + ")";
}

glm::vec2 mappedUv(const SceneMaterial& material, glm::vec2 mesh_uv, const glm::vec3& p, const glm::vec3& ng) {
  switch (material.mapping) {
    case UvMapping::Mesh: return mesh_uv * material.uv_scale;
    case UvMapping::Planar: {
      const int a = (material.planar_axis + 1) % 3, b = (material.planar_axis + 2) % 3;
      return glm::vec2(p[a], p[b]) * material.uv_scale;
    }
    case UvMapping::Box: {
      const glm::vec3 n = glm::abs(ng);
      const int axis = n.x >= n.y && n.x >= n.z ? 0 : (n.y >= n.z ? 1 : 2);
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;
      return glm::vec2(p[a], p[b]) * material.uv_scale;
    }
  }
  return mesh_uv;
}

}  // namespace

Scene::Scene(SceneDescription description)
    : description_(std::move(description)), camera_(description_.camera) {
  const std::string where = description_.file.empty() ? std::string("scene") : description_.file.string();
  auto fail = [&](const std::string& problem) -> Error { return Error(where + ": " + problem); };

  std::vector<const TriangleMesh*> meshes;
  for (std::size_t s = 0; s < description_.shapes.size(); ++s) {
    SceneShape& shape = description_.shapes[s];
    TriangleMesh& mesh = shape.mesh;
    if (shape.material < -1 || shape.material >= int(description_.materials.size()))
      throw fail(mesh.name + ": material index " + std::to_string(shape.material) + " out of range");
    if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size()) mesh.normals.clear();
    if (!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size()) mesh.uvs.clear();
    removeInvalidTrianglesWithWarning(mesh);
    if (mesh.triangles.empty()) throw fail(mesh.name + ": the mesh has no valid triangle");
    meshes.push_back(&mesh);
  }
  if (meshes.empty()) throw fail("the scene has no shape");
  embree_ = std::make_unique<EmbreeScene>(meshes);
  bounds_center_ = 0.5f * (embree_->boundsMin() + embree_->boundsMax());
  bounds_radius_ = std::max(0.5f * glm::length(embree_->boundsMax() - embree_->boundsMin()), 1e-6f);
  // Offsets of spawned rays: relative to the scene's size, well above float rounding of positions.
  ray_epsilon_ = 1e-5f * std::max(bounds_radius_, glm::length(bounds_center_)) + 1e-7f;

  // Lights, by power (the choice of light for next-event estimation and for photon emission).
  light_of_shape_.assign(description_.shapes.size(), -1);
  triangle_cdf_.resize(description_.shapes.size());
  shape_area_.assign(description_.shapes.size(), 0.0f);
  for (std::size_t s = 0; s < description_.shapes.size(); ++s) {
    const SceneShape& shape = description_.shapes[s];
    std::vector<float> areas(shape.mesh.triangles.size());
    double area = 0;
    for (std::size_t t = 0; t < areas.size(); ++t) area += areas[t] = triangleArea(shape.mesh, shape.mesh.triangles[t]);
    shape_area_[s] = float(area);
    if (shape.emission.isBlack()) continue;
    if (!nonNegativeFinite(shape.emission))
      throw fail(shape.mesh.name + ": emission " + describe(shape.emission) + " must be finite and non-negative");
    if (!(area > 0.0)) throw fail(shape.mesh.name + ": an emitting shape of zero area");
    triangle_cdf_[s].resize(areas.size() + 1);
    buildCdf1D(areas, triangle_cdf_[s]);
    light_of_shape_[s] = int(lights_.size());
    lights_.push_back({LightPower::Kind::Area, int(s),
                       shape.emission * float(kPi * area * (shape.two_sided_emission ? 2.0 : 1.0))});
  }
  for (std::size_t i = 0; i < description_.point_lights.size(); ++i) {
    const PointLight& light = description_.point_lights[i];
    if (!nonNegativeFinite(light.intensity) || light.intensity.isBlack())
      throw fail("point light " + std::to_string(i) + ": intensity " + describe(light.intensity) +
                 " must be finite, non-negative and not zero");
    lights_.push_back({LightPower::Kind::Point, int(i), light.intensity * (4.0f * kPi)});
  }
  const Rgb environment_mean =
      description_.environment_map ? description_.environment_map->meanRadiance() : description_.environment_radiance;
  if (!nonNegativeFinite(environment_mean))
    throw fail("the environment's radiance " + describe(environment_mean) + " must be finite and non-negative");
  if (!environment_mean.isBlack()) {
    environment_light_ = int(lights_.size());
    // What crosses a disk of the scene's radius, facing each direction in turn.
    lights_.push_back({LightPower::Kind::Environment, -1,
                       environment_mean * (4.0f * kPi * kPi * bounds_radius_ * bounds_radius_)});
  }
  if (lights_.empty()) throw fail("the scene has no light (no emitting shape, point light or environment)");
  std::vector<float> weights;
  for (const LightPower& light : lights_) weights.push_back(light.power.average());
  light_cdf_.resize(weights.size() + 1);
  buildCdf1D(weights, light_cdf_);
}

Scene::~Scene() = default;

float Scene::lightProbability(int light) const { return light_cdf_[std::size_t(light) + 1] - light_cdf_[std::size_t(light)]; }

bool Scene::intersect(const Ray& ray, SurfaceHit& hit) const {
  RayHit rh;
  if (!embree_->intersect(ray, rh)) return false;
  const SceneShape& shape = description_.shapes[rh.mesh];
  const TriangleMesh& mesh = shape.mesh;
  const glm::uvec3 tri = mesh.triangles[rh.triangle];
  const float b1 = rh.barycentric.x, b2 = rh.barycentric.y, b0 = 1.0f - b1 - b2;
  const glm::vec3 &p0 = mesh.positions[tri.x], &p1 = mesh.positions[tri.y], &p2 = mesh.positions[tri.z];
  hit.t = rh.t;
  hit.shape = rh.mesh;
  hit.triangle = rh.triangle;
  // The point from the barycentrics: more accurate than origin + t * direction far from the origin.
  hit.p = b0 * p0 + b1 * p1 + b2 * p2;
  const glm::vec3 e1 = p1 - p0, e2 = p2 - p0;
  glm::vec3 ng = glm::normalize(glm::cross(e1, e2));
  glm::vec3 ns = ng;
  if (!mesh.normals.empty()) {
    const glm::vec3 n = b0 * mesh.normals[tri.x] + b1 * mesh.normals[tri.y] + b2 * mesh.normals[tri.z];
    const float len = glm::length(n);
    if (len > 1e-6f && std::isfinite(len)) ns = n / len;
  }
  glm::vec2 uv{b1, b2};
  Frame frame = Frame::fromNormal(ns);
  if (!mesh.uvs.empty()) {
    const glm::vec2 t0 = mesh.uvs[tri.x], t1 = mesh.uvs[tri.y], t2 = mesh.uvs[tri.z];
    uv = b0 * t0 + b1 * t1 + b2 * t2;
    // dp/du from the triangle's UV parameterization: a tangent that follows the texture, so that
    // anisotropic materials and BTFs keep their orientation across the mesh.
    const glm::vec2 d1 = t1 - t0, d2 = t2 - t0;
    const float det = d1.x * d2.y - d1.y * d2.x;
    if (std::abs(det) > 1e-12f) {
      const glm::vec3 dpdu = (d2.y * e1 - d1.y * e2) / det;
      const glm::vec3 tangent = dpdu - ns * glm::dot(ns, dpdu);
      if (glm::length(tangent) > 1e-6f * glm::length(dpdu)) frame = Frame::fromNormalTangent(ns, dpdu);
    }
  }
  hit.front = glm::dot(ray.direction, ng) < 0.0f;
  if (!hit.front) {
    ng = -ng;
    frame = Frame(frame.s, -frame.t, -frame.n);  // still right-handed
  }
  hit.ng = ng;
  hit.shading = frame;
  hit.uv = uv;
  if (shape.material >= 0) hit.uv = mappedUv(description_.materials[std::size_t(shape.material)], uv, hit.p, ng);
  return true;
}

bool Scene::occluded(const Ray& ray) const { return embree_->occluded(ray); }

Ray Scene::spawnRay(const SurfaceHit& from, const glm::vec3& direction) const {
  const float side = glm::dot(direction, from.ng) >= 0.0f ? 1.0f : -1.0f;
  return Ray{from.p + from.ng * (side * ray_epsilon_ * (1.0f + glm::length(from.p))), direction};
}

Ray Scene::spawnRayTo(const SurfaceHit& from, const glm::vec3& target) const {
  const float side = glm::dot(target - from.p, from.ng) >= 0.0f ? 1.0f : -1.0f;
  Ray ray{from.p + from.ng * (side * ray_epsilon_ * (1.0f + glm::length(from.p))), glm::vec3(0.0f)};
  const glm::vec3 d = target - ray.origin;
  const float distance = glm::length(d);
  ray.direction = d / distance;
  // The target lies on its surface; stopping a relative 1e-4 short of it (well above the float
  // error of the hit distance) keeps the light's own surface out of the test.
  ray.tmax = distance * (1.0f - 1e-4f);
  return ray;
}

const SceneMaterial* Scene::materialOf(const SurfaceHit& hit) const {
  const int m = description_.shapes[hit.shape].material;
  return m >= 0 ? &description_.materials[std::size_t(m)] : nullptr;
}

Rgb Scene::emitted(const SurfaceHit& hit) const {
  const SceneShape& shape = description_.shapes[hit.shape];
  if (shape.emission.isBlack() || !(hit.front || shape.two_sided_emission)) return Rgb(0.0f);
  return shape.emission;
}

float Scene::areaLightPdf(const glm::vec3& from, const SurfaceHit& hit, const glm::vec3& direction) const {
  const int light = light_of_shape_[hit.shape];
  if (light < 0) return 0.0f;
  const float cos_light = std::abs(glm::dot(direction, hit.ng));
  if (!(cos_light > 0.0f)) return 0.0f;
  const glm::vec3 d = hit.p - from;
  return lightProbability(light) / shape_area_[hit.shape] * glm::dot(d, d) / cos_light;
}

Scene::SurfacePoint Scene::sampleShapeArea(int shape_index, float u_triangle, glm::vec2 u) const {
  const TriangleMesh& mesh = description_.shapes[std::size_t(shape_index)].mesh;
  const std::size_t t = sampleDiscrete(triangle_cdf_[std::size_t(shape_index)], u_triangle).index;
  const glm::uvec3 tri = mesh.triangles[t];
  // Uniform by area: the square-root warp of the unit square onto the triangle.
  const float su = std::sqrt(u.x);
  const float b0 = 1.0f - su, b1 = u.y * su, b2 = 1.0f - b0 - b1;
  SurfacePoint point;
  point.p = b0 * mesh.positions[tri.x] + b1 * mesh.positions[tri.y] + b2 * mesh.positions[tri.z];
  point.n = glm::normalize(glm::cross(mesh.positions[tri.y] - mesh.positions[tri.x], mesh.positions[tri.z] - mesh.positions[tri.x]));
  point.uv = mesh.uvs.empty() ? glm::vec2(b1, b2) : b0 * mesh.uvs[tri.x] + b1 * mesh.uvs[tri.y] + b2 * mesh.uvs[tri.z];
  return point;
}

float Scene::shapeArea(int shape) const { return shape_area_[std::size_t(shape)]; }

std::optional<LightSample> Scene::sampleLight(const glm::vec3& from, float u_select, glm::vec2 u) const {
  const DiscreteSample choice = sampleDiscrete(light_cdf_, u_select);
  const LightPower& light = lights_[choice.index];
  const float p_choice = choice.probability;
  if (!(p_choice > 0.0f)) return std::nullopt;
  switch (light.kind) {
    case LightPower::Kind::Area: {
      const SceneShape& shape = description_.shapes[std::size_t(light.index)];
      const SurfacePoint point = sampleShapeArea(light.index, choice.remapped, u);
      const glm::vec3 d = point.p - from;
      const float distance2 = glm::dot(d, d);
      if (!(distance2 > 0.0f)) return std::nullopt;
      const float distance = std::sqrt(distance2);
      const glm::vec3 wi = d / distance;
      const float cos_light = -glm::dot(wi, point.n);
      if (!(cos_light > 0.0f) && !shape.two_sided_emission) return std::nullopt;  // its back faces us
      const float cos_abs = std::abs(cos_light);
      if (!(cos_abs > 0.0f)) return std::nullopt;
      return LightSample{wi, distance, shape.emission, p_choice / shape_area_[std::size_t(light.index)] * distance2 / cos_abs,
                         false};
    }
    case LightPower::Kind::Point: {
      const PointLight& point = description_.point_lights[std::size_t(light.index)];
      const glm::vec3 d = point.position - from;
      const float distance2 = glm::dot(d, d);
      if (!(distance2 > 0.0f)) return std::nullopt;
      const float distance = std::sqrt(distance2);
      return LightSample{d / distance, distance, point.intensity / distance2, p_choice, true};
    }
    case LightPower::Kind::Environment: {
      constexpr float kInf = std::numeric_limits<float>::infinity();
      if (description_.environment_map) {
        const auto s = description_.environment_map->sample(u);
        if (!s || !(s->pdf > 0.0f)) return std::nullopt;
        return LightSample{s->direction, kInf, s->radiance, p_choice * s->pdf, false};
      }
      const glm::vec3 wi = squareToUniformSphere(u);
      return LightSample{wi, kInf, description_.environment_radiance, p_choice * uniformSpherePdf(), false};
    }
  }
  return std::nullopt;
}

Rgb Scene::environment(const glm::vec3& direction) const {
  if (environment_light_ < 0) return Rgb(0.0f);
  return description_.environment_map ? description_.environment_map->eval(direction) : description_.environment_radiance;
}

float Scene::environmentPdf(const glm::vec3& direction) const {
  if (environment_light_ < 0) return 0.0f;
  const float p = description_.environment_map ? description_.environment_map->pdf(direction) : uniformSpherePdf();
  return lightProbability(environment_light_) * p;
}

}  // namespace btf::render
