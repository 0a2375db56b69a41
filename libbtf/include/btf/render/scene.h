// A scene ready to render: what a scene file describes (SceneDescription, filled by scene_loader.h
// or by code), and the Scene built from it: the Embree BVH over every mesh, surface points with
// their shading frames, and the lights with the distribution that chooses among them.
//
// Lights: emitting meshes (area lights: one-sided along the winding's normal unless two-sided),
// point lights, and one environment (a constant radiance or a lat-long map). Next-event
// estimation picks a light with probability proportional to its power, then a point on it
// (area lights: a triangle by area, then a uniform point; the environment map: by luminance).
//
// Shading: a hit's geometric normal is the triangle's; its shading normal interpolates the vertex
// normals barycentrically. Surfaces are two-sided: both normals are turned towards the side the
// ray came from. Shading-normal light leaks are handled as Veach proposed (1997, §5.3): a direction
// counts as reflected only if it lies on the same side of the geometric and the shading normal as
// the view does; a direction that the two normals disagree about carries nothing.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "btf/core/frame.h"
#include "btf/core/rgb.h"
#include "btf/material/material.h"
#include "btf/render/camera.h"
#include "btf/render/environment_map.h"
#include "btf/render/triangle_mesh.h"

namespace btf::render {

class EmbreeScene;

// How a material's texture coordinates are found at a surface point: the mesh's own UVs, or a
// projection of the world position (planar: onto the plane normal to `axis`; box: onto the plane
// of the dominant axis of the geometric normal), times `uv_scale` in both cases.
enum class UvMapping { Mesh, Planar, Box };

struct SceneMaterial {
  std::string name;
  std::shared_ptr<const Material> material;  // eval() of the data
  std::shared_ptr<const Material> sampled;   // the same eval() with the chosen sampler's sample()/pdf()
  std::string sampler = "material";
  UvMapping mapping = UvMapping::Mesh;
  int planar_axis = 1;  // 0 = x, 1 = y, 2 = z
  float uv_scale = 1.0f;
};

struct SceneShape {
  TriangleMesh mesh;
  int material = -1;  // index into SceneDescription::materials; -1: black (a pure emitter)
  Rgb emission{0.0f};  // radiance leaving the surface; non-zero makes the shape an area light
  bool two_sided_emission = false;
};

struct PointLight {
  glm::vec3 position{0.0f};
  Rgb intensity{0.0f};  // W/sr per channel
};

struct RenderDefaults {
  int spp = 16;
  int max_depth = 16;     // path segments at most
  int rr_min_depth = 3;   // Russian roulette starts after this many segments
};

struct SceneDescription {
  std::filesystem::path file;  // the scene file (for messages), empty for scenes built in code
  CameraSettings camera;
  std::vector<SceneMaterial> materials;
  std::vector<SceneShape> shapes;
  std::vector<PointLight> point_lights;
  Rgb environment_radiance{0.0f};                        // a constant environment
  std::shared_ptr<const EnvironmentMap> environment_map;  // or a map (then the constant is unused)
  RenderDefaults render;
};

struct SurfaceHit {
  float t = 0;
  glm::vec3 p{0.0f};
  glm::vec3 ng{0.0f, 0.0f, 1.0f};  // geometric normal, turned towards the incoming ray
  Frame shading;                    // shading frame, its normal turned like ng
  glm::vec2 uv{0.0f};               // after the material's mapping
  std::uint32_t shape = 0;
  std::uint32_t triangle = 0;
  bool front = true;  // the ray hit the side the winding's normal points to
};

struct LightSample {
  glm::vec3 wi;     // from the shading point towards the light (unit, world)
  float distance;   // to the light point; infinity for the environment
  Rgb radiance;     // arriving radiance (point lights: intensity / distance^2)
  float pdf;        // solid-angle density including the choice of light; a probability for delta lights
  bool delta;       // a point light: no other technique can find it
};

class Scene {
 public:
  // Cleans every mesh (dropped triangles are counted in one warning per mesh through btf::log),
  // builds the BVH and the light distributions. Throws btf::Error naming the scene file for a
  // scene with no light, a light of zero area or with negative or non-finite power, a shape
  // without triangles, or a material index out of range.
  explicit Scene(SceneDescription description);
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  const SceneDescription& description() const { return description_; }
  const PinholeCamera& camera() const { return camera_; }
  const EmbreeScene& embree() const { return *embree_; }

  // The closest surface on the ray, with shading data.
  bool intersect(const Ray& ray, SurfaceHit& hit) const;
  bool occluded(const Ray& ray) const;
  // A ray leaving a surface point towards `direction`, offset along the geometric normal so that it
  // does not find the surface it starts on.
  Ray spawnRay(const SurfaceHit& from, const glm::vec3& direction) const;
  // A shadow ray from a surface point to `target` (a point on a light), aimed from the offset
  // origin and stopping just short of the target, so that it finds neither end's surface.
  Ray spawnRayTo(const SurfaceHit& from, const glm::vec3& target) const;

  const SceneMaterial* materialOf(const SurfaceHit& hit) const;
  // Radiance the surface emits towards -ray_direction (zero unless its shape is an area light).
  Rgb emitted(const SurfaceHit& hit) const;
  // Density (solid angle, seen from `from`) with which sampleLight() would have chosen the point of
  // an emitting surface `hit` found by a ray from `from`.
  float areaLightPdf(const glm::vec3& from, const SurfaceHit& hit, const glm::vec3& direction) const;

  std::optional<LightSample> sampleLight(const glm::vec3& from, float u_select, glm::vec2 u) const;
  bool hasEnvironment() const { return environment_light_ >= 0; }
  Rgb environment(const glm::vec3& direction) const;
  // Density with which sampleLight() draws this direction of the environment, choice included.
  float environmentPdf(const glm::vec3& direction) const;

  // Bounding sphere of the geometry (for the environment's power and photon emission).
  glm::vec3 boundsCenter() const { return bounds_center_; }
  float boundsRadius() const { return bounds_radius_; }
  // Total emitted power per channel of every light (W), for photon emission in proportion to power.
  struct LightPower {
    enum class Kind { Area, Point, Environment } kind;
    int index;  // shape or point light index; -1 for the environment
    Rgb power;
  };
  const std::vector<LightPower>& lights() const { return lights_; }
  // A point of an area light's shape drawn uniformly by area, with its geometric normal.
  struct SurfacePoint {
    glm::vec3 p;
    glm::vec3 n;
    glm::vec2 uv;
  };
  SurfacePoint sampleShapeArea(int shape, float u_triangle, glm::vec2 u) const;
  float shapeArea(int shape) const;

 private:
  SceneDescription description_;
  PinholeCamera camera_;
  std::unique_ptr<EmbreeScene> embree_;
  std::vector<LightPower> lights_;
  std::vector<float> light_cdf_;  // over lights_, by luminance of power
  std::vector<int> light_of_shape_;  // index into lights_ or -1
  std::vector<std::vector<float>> triangle_cdf_;  // per emitting shape, by area
  std::vector<float> shape_area_;
  int environment_light_ = -1;
  glm::vec3 bounds_center_{0.0f};
  float bounds_radius_ = 1.0f;
  float ray_epsilon_ = 1e-4f;

  float lightProbability(int light) const;
};

}  // namespace btf::render
