// The path tracer against closed forms: a Lambertian plane under a rectangular area light
// (Lambert's polygon formula), and the white furnace (a flat sample of each material under a
// uniform environment returns its directional albedo). Each comparison allows 4 standard errors of
// the batch mean (two-sided, p = 6e-5 of a false failure if the estimator is right) plus the
// stated error of the reference; fixed seeds make every run the same.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "btf/core/error.h"
#include "btf/fit/merl_fits.h"
#include "btf/material/albedo.h"
#include "btf/material/btf_material.h"
#include "btf/material/ggx.h"
#include "btf/material/lafortune.h"
#include "btf/material/lambert.h"
#include "btf/material/phong.h"
#include "btf/material/rgl_brdf.h"
#include "btf/material/tabulated_brdf.h"
#include "btf/material/ward.h"
#include "btf/sampling/sampler_choice.h"
#include "btf_test_data.h"
#include "render_test_scenes.h"
#include "sampler_test_materials.h"
#include "support/test_support.h"

namespace btf::test {
namespace {

using render::SceneDescription;

constexpr double kSigmas = 4.0;

// Irradiance at x (normal n) from a polygon of uniform radiance le: Lambert's formula,
// E = le / 2 * |sum_i theta_i n . normalize(v_i x v_i+1)| with v_i the unit vectors to the corners.
double polygonIrradiance(const std::vector<glm::dvec3>& corners, const glm::dvec3& x, const glm::dvec3& n, double le) {
  double sum = 0;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const glm::dvec3 a = glm::normalize(corners[i] - x), b = glm::normalize(corners[(i + 1) % corners.size()] - x);
    sum += std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) * glm::dot(n, glm::normalize(glm::cross(a, b)));
  }
  return 0.5 * le * std::abs(sum);
}

TEST(RenderValidation, LambertianPlaneUnderAreaLightMatchesLambertsFormula) {
  const float albedo = 0.5f, le = 10.0f;
  const glm::vec3 light_corner(-0.25f, 1.0f, -0.25f), light_u(0.5f, 0, 0), light_v(0, 0, 0.5f);
  const auto pt = render::makePathTracer();
  for (const glm::vec3 x : {glm::vec3(0, 0, 0), glm::vec3(0.5f, 0, 0.2f), glm::vec3(-0.7f, 0, 0.1f), glm::vec3(1.5f, 0, -1.2f)}) {
    SceneDescription d;
    d.materials.push_back({"white", std::make_shared<Lambert>(Rgb(albedo)), std::make_shared<Lambert>(Rgb(albedo))});
    d.shapes.push_back(floorQuad(0, 5.0f));
    render::SceneShape light;
    light.mesh = render::makeQuad(light_corner, light_u, light_v, "light");  // normal -y: faces the floor
    light.emission = Rgb(le);
    d.shapes.push_back(light);
    d.camera = onePixelCamera(x + glm::vec3(3.0f, 2.5f, 0.5f), x);
    const render::Scene scene(std::move(d));
    const PixelEstimate e = estimatePixel(scene, *pt, 2000, 8);
    const std::vector<glm::dvec3> corners = {glm::dvec3(light_corner), glm::dvec3(light_corner + light_u),
                                             glm::dvec3(light_corner + light_u + light_v), glm::dvec3(light_corner + light_v)};
    const double expected = albedo / kPi * polygonIrradiance(corners, glm::dvec3(x), {0, 1, 0}, le);
    std::printf("  x = (%.1f, %.1f): path tracer %.6f +- %.6f, Lambert's formula %.6f\n", x.x, x.z, e.mean.g,
                e.standard_error.g, expected);
    EXPECT_LT(e.standard_error.g, 0.01 * expected);  // the test resolves 4% differences at least
    EXPECT_NEAR(e.mean.g, expected, kSigmas * e.standard_error.g) << x.x << " " << x.z;
  }
}

// The furnace: the floor quad in a uniform environment of radiance 1, seen at theta_o in the plane
// of its tangent (phi_o = 0). Nothing else is in the scene, so the pixel is the directional albedo.
PixelEstimate furnacePixel(std::shared_ptr<const Material> material, std::shared_ptr<const Material> sampled,
                           float theta_o_deg, int spp, int batches) {
  SceneDescription d;
  d.materials.push_back({"m", std::move(material), std::move(sampled)});
  d.shapes.push_back(floorQuad(0));
  d.environment_radiance = Rgb(1.0f);
  const float t = theta_o_deg * kPi / 180.0f;
  // The floor's frame: local x = world +z (the UV tangent), local z = world +y.
  d.camera = onePixelCamera(3.0f * glm::vec3(0, std::cos(t), std::sin(t)), glm::vec3(0));
  const render::Scene scene(std::move(d));
  return estimatePixel(scene, *render::makePathTracer(), spp, batches);
}

struct FurnaceCase {
  std::string label;
  std::shared_ptr<const Material> material;
};

std::vector<FurnaceCase> furnaceMaterials() {
  std::vector<FurnaceCase> cases;
  for (const NamedMaterial& m : samplerTestMaterials()) cases.push_back({m.label, m.material});
  cases.push_back({"lafortune_2_lobes", std::make_shared<Lafortune>(Rgb(0.2f), std::vector<LafortuneLobe>{
                                                                          {Rgb(0.3f), {-1, -1, 1}, 15.0f},
                                                                          {Rgb(0.2f), {-0.9f, -0.9f, 1}, 80.0f}})});
  cases.push_back({"btf_texel", std::make_shared<BtfMaterial>(std::make_shared<BtfData>(makeGgxBtf(1, 1, false)))});
  const auto shared = sharedDataDir();
  for (const char* rgl : {"paper_white_rgb", "vch_golden_yellow_rgb"})
    cases.push_back({rgl, std::make_shared<RglBrdf>(shared / "rgl_bsdf" / (std::string(rgl) + ".bsdf"))});
  cases.push_back({"merl_fit_gold_metallic_paint_sgd",
                   std::shared_ptr<const Material>(makeMerlFitMaterial(MerlFits::load(shared / "fits"), "gold-metallic-paint", ModelFamily::Sgd))});
  return cases;
}

// Every material of the library at three view angles, with its own sampler.
TEST(RenderValidation, WhiteFurnaceReturnsTheDirectionalAlbedoOfEveryMaterial) {
  for (const FurnaceCase& c : furnaceMaterials()) {
    for (const float theta_o : {0.0f, 40.0f, 70.0f}) {
      // The reference: deterministic quadrature for isotropic materials (converged far below the tolerance),
      // Monte Carlo with 2 M samples (its standard error counted) for anisotropic ones.
      const float t = theta_o * kPi / 180.0f;
      Rgb reference, reference_error(0.0f);
      if (c.material->isAnisotropic()) {
        const AlbedoEstimate a = estimateAlbedo(*c.material, {std::sin(t), 0.0f, std::cos(t)}, 2'000'000, 7);
        reference = a.value;
        reference_error = a.standard_error;
      } else {
        reference = integrateAlbedoHalfVector(*c.material, t, 512, 1024);
        reference_error = reference * 1e-3f;
      }
      const PixelEstimate e = furnacePixel(c.material, c.material, theta_o, 1000, 8);
      for (int ch = 0; ch < 3; ++ch) {
        const double sigma = std::hypot(double(e.standard_error[ch]), double(reference_error[ch]));
        EXPECT_NEAR(e.mean[ch], reference[ch], kSigmas * sigma + 1e-5)
            << c.label << " theta_o " << theta_o << " channel " << ch;
        // Energy: nothing reflects more than it receives unless the data does (the reference > 1).
        if (reference[ch] <= 1.0f) {
          EXPECT_LE(e.mean[ch], 1.0f + kSigmas * sigma) << c.label;
        }
      }
      std::printf("  %-34s theta_o %2.0f: furnace %.4f %.4f %.4f (+- %.4f), albedo %.4f %.4f %.4f\n", c.label.c_str(),
                  theta_o, e.mean.r, e.mean.g, e.mean.b, e.standard_error.g, reference.r, reference.g, reference.b);
    }
  }
}

// The same furnace through every sampler of the library: each is an unbiased estimator of the
// same albedo, whatever its variance.
TEST(RenderValidation, WhiteFurnaceAgreesForEverySampler) {
  const auto material = std::make_shared<Ggx>(Rgb(0.2f, 0.3f, 0.1f), Rgb(0.9f), 0.2f, 0.2f);
  const float theta_o = 40.0f;
  const Rgb reference = integrateAlbedoHalfVector(*material, theta_o * kPi / 180.0f, 512, 1024);
  for (const char* name : {"material", "cosine", "uniform", "tabulated", "dp-cdf", "quadtree"}) {
    const auto sampled = withSampler(*parseSamplerChoice(name), material, coarseSamplerOptions());
    const PixelEstimate e = furnacePixel(material, sampled, theta_o, 1000, 8);
    for (int ch = 0; ch < 3; ++ch) {
      const double sigma = std::hypot(double(e.standard_error[ch]), 1e-3 * reference[ch]);
      EXPECT_NEAR(e.mean[ch], reference[ch], kSigmas * sigma) << name << " channel " << ch;
    }
    std::printf("  %-10s furnace %.4f %.4f %.4f (+- %.4f), albedo %.4f %.4f %.4f\n", name, e.mean.r, e.mean.g, e.mean.b,
                e.standard_error.g, reference.r, reference.g, reference.b);
  }
}

// A small closed box with a glossy floor, an area light and a point light: every pixel's value is
// a function of (seed, pixel, sample) only, so the image is the same bit for bit on 1 and 2 threads.
TEST(RenderValidation, ImageDoesNotDependOnTheThreadCount) {
  SceneDescription d;
  const auto white = std::make_shared<Lambert>(Rgb(0.7f));
  const auto glossy = std::make_shared<Ggx>(Rgb(0.1f), Rgb(0.8f), 0.15f, 0.15f);
  d.materials.push_back({"white", white, white});
  d.materials.push_back({"glossy", glossy, glossy});
  d.shapes.push_back(floorQuad(1));
  d.shapes.push_back({render::makeSphere({0, 0.4f, 0}, 0.4f, 16, "ball"), 0, Rgb(0.0f), false});
  render::SceneShape light;
  light.mesh = render::makeQuad({-0.3f, 1.5f, -0.3f}, {0.6f, 0, 0}, {0, 0, 0.6f}, "light");
  light.emission = Rgb(5.0f);
  d.shapes.push_back(light);
  d.point_lights.push_back({{1.0f, 1.0f, 1.0f}, Rgb(0.5f)});
  d.camera.position = {0, 1.2f, 2.5f};
  d.camera.look_at = {0, 0.3f, 0};
  d.camera.width = 40;
  d.camera.height = 30;
  const render::Scene scene(std::move(d));
  render::RenderSettings settings;
  settings.spp = 4;
  settings.tile_size = 8;
  auto renderWith = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    return render::makePathTracer()->render(scene, settings);
  };
  const render::RenderResult one = renderWith(1), two = renderWith(2);
  ASSERT_EQ(one.color.pixels.size(), two.color.pixels.size());
  EXPECT_EQ(one.color.pixels, two.color.pixels);
  double sum = 0;
  for (float v : one.color.pixels) sum += v;
  EXPECT_GT(sum, 0.0);  // the scene is lit: equal images are not two black ones
}

TEST(RenderValidation, SettingsOutOfRangeAreRefused) {
  SceneDescription d;
  d.materials.push_back({"white", std::make_shared<Lambert>(Rgb(0.5f)), std::make_shared<Lambert>(Rgb(0.5f))});
  d.shapes.push_back(floorQuad(0));
  d.environment_radiance = Rgb(1.0f);
  const render::Scene scene(std::move(d));
  render::RenderSettings settings;
  settings.spp = 0;
  EXPECT_THROW(render::makePathTracer()->render(scene, settings), Error);
  settings.spp = 1;
  settings.max_depth = 0;
  EXPECT_THROW(render::makePathTracer()->render(scene, settings), Error);
}

}  // namespace
}  // namespace btf::test
