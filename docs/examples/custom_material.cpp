// A material type of your own, end to end: one class, one registration, then the type is usable
// everywhere a material is named: in code (createMaterial), and in a scene file rendered by the
// path tracer. The model is Minnaert's darkening-limb BRDF, f = rho / pi * (cos_i cos_o)^(k - 1),
// which libbtf does not ship.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/warp.h"
#include "btf/material/registry.h"
#include "btf/render/integrator.h"
#include "btf/render/scene.h"
#include "btf/render/scene_loader.h"

namespace {

class Minnaert final : public btf::Material {
 public:
  Minnaert(btf::Rgb albedo, float k) : albedo_(albedo), k_(k) {
    if (!(k >= 1.0f && k <= 2.0f)) throw btf::Error("minnaert: k must be in [1, 2]");
  }
  btf::Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 = {}) const override {
    if (wi.z <= 0 || wo.z <= 0) return btf::Rgb(0.0f);
    return albedo_ * (std::pow(wi.z * wo.z, k_ - 1.0f) / btf::kPi);
  }
  // Cosine-weighted sampling: correct for any k, exact for k = 1 (Lambert).
  std::optional<btf::BsdfSample> sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const override {
    if (wo.z <= 0) return std::nullopt;
    const glm::vec3 wi = btf::squareToCosineHemisphere(u);
    const float pdf = btf::cosineHemispherePdf(wi);
    if (pdf <= 0) return std::nullopt;
    return btf::BsdfSample{wi, eval(wi, wo, uv) * (wi.z / pdf), pdf};
  }
  float pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 = {}) const override {
    return wo.z > 0 ? btf::cosineHemispherePdf(wi) : 0.0f;
  }
  std::string name() const override { return "minnaert"; }
  bool isReciprocal() const override { return true; }

 private:
  btf::Rgb albedo_;
  float k_;
};

// The one registration: the type's name, the keys of its parameter set, and how to build it.
// MaterialParams checks each value and names the file and key of any problem.
BTF_REGISTER_MATERIAL(minnaert, {.name = "minnaert",
                                 .summary = "Minnaert's limb-darkening BRDF (an example type)",
                                 .keys = {"albedo", "k"},
                                 .create = [](const btf::MaterialParams& p) -> std::shared_ptr<const btf::Material> {
                                   return std::make_shared<Minnaert>(p.rgb("albedo"), float(p.number("k", 1, 2)));
                                 }});

}  // namespace

int main() {
  namespace fs = std::filesystem;
  // In code: a parameter set, as a scene would hold it.
  btf::MaterialParams params("minnaert");
  params.set("albedo", btf::Rgb(0.7f, 0.5f, 0.3f)).set("k", 1.5);
  const auto material = btf::createMaterial(params);
  const glm::vec3 normal(0, 0, 1);
  std::printf("%s: f(normal, normal) = %.4f\n", material->name().c_str(), material->eval(normal, normal).g);

  // In a scene file: a sphere of it under a uniform sky, rendered by the path tracer.
  const fs::path scene_file = fs::temp_directory_path() / "libbtf-example-minnaert.json";
  std::ofstream(scene_file) << R"({
    "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov_deg": 40, "resolution": [32, 32]},
    "render": {"spp": 16},
    "materials": {"moon": {"type": "minnaert", "albedo": [0.7, 0.5, 0.3], "k": 1.5}},
    "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "moon"}],
    "lights": [{"type": "environment", "radiance": 1}]
  })";
  const btf::render::Scene scene(btf::render::loadSceneDescription(scene_file));
  const btf::render::RenderResult result = btf::render::makePathTracer()->render(scene, btf::render::RenderSettings{});
  // Facing the camera, the sphere reflects the unit sky as integral of f cos_i = 2 rho / (k + 1):
  // 0.4 in green. Each of the 16 paths of the pixel estimates it with a standard deviation of 0.08,
  // so the pixel lies within 0.1 of it (5 standard deviations; the seed is fixed).
  const float centre = result.color.at(16, 16, 1);
  std::printf("rendered %d x %d; radiance at the centre %.3f (green)\n", result.color.width, result.color.height, centre);
  fs::remove(scene_file);
  if (!(std::abs(centre - 0.4f) < 0.1f)) {
    std::fprintf(stderr, "unexpected radiance %g at the sphere's centre\n", centre);
    return 1;
  }

  // A misspelt key is an error naming the key, not a silent default.
  try {
    btf::createMaterial(btf::MaterialParams("minnaert").set("albedo", 0.5).set("kk", 1.2));
    return 1;
  } catch (const btf::Error& e) {
    std::printf("as expected: %s\n", e.what());
  }
  return 0;
}
