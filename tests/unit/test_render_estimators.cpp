// The renderer's estimators against each other on the Cornell box: the path tracer and progressive
// photon mapping agree per region; every sampler converges to the same image at the Monte Carlo
// rate; compressed materials render like their references. Seeds are fixed, so every run is the
// same; tolerances are stated with what they cover.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include <nlohmann/json.hpp>

#include "support/tier.h"
#include "btf/compress/vq_btf.h"
#include "btf/io/merl.h"
#include "btf/material/btf_material.h"
#include "btf/material/ggx.h"
#include "btf/material/lambert.h"
#include "btf/material/rgl_brdf.h"
#include "btf/material/tabulated_brdf.h"
#include "btf/render/image_metrics.h"
#include "btf/render/photon_map.h"
#include "btf/render/scene_loader.h"
#include "btf/sampling/sampler_choice.h"
#include "btf_test_data.h"
#include "render_test_scenes.h"
#include "sampler_test_materials.h"
#include "support/test_support.h"

namespace btf::test {
namespace {

std::filesystem::path cornellObj() { return sharedDataDir() / "meshes" / "cornell_box" / "CornellBox-Original.obj"; }

// The shared Cornell box; the tall box in a measured-style table (a GGX tabulated into the MERL
// layout), the short box in the real RGL material paper_white when `glossy`.
render::SceneDescription cornell(int resolution, bool glossy, const std::string& sampler = "material") {
  render::SceneLoadOptions options;
  options.sampler_override = sampler;
  TempDir dir;
  const auto scene_file = dir / "scene.json";
  nlohmann::json scene = {{"camera", {{"position", {0, 1, 3.9}}, {"look_at", {0, 1, 0}}, {"fov_deg", 39.3}, {"resolution", {resolution, resolution}}}},
                          {"shapes", {{{"file", cornellObj().string()}, {"material", "mtl"}}}}};
  if (glossy) {
    const auto table = dir / "glossy.binary";
    writeMerl(table, tabulate(Ggx(Rgb(0.3f, 0.25f, 0.2f), Rgb(0.5f), 0.15f, 0.15f)));
    scene["materials"] = {{"table", {{"type", "merl", }, {"file", table.string()}}},
                          {"paper", {{"type", "rgl"}, {"file", (sharedDataDir() / "rgl_bsdf" / "paper_white_rgb.bsdf").string()}}}};
    scene["shapes"][0]["part_materials"] = {{"tallBox", "table"}, {"shortBox", "paper"}};
  }
  std::ofstream(scene_file) << scene.dump();
  return render::loadSceneDescription(scene_file, options);
}

// Which shape each pixel centre sees (-1: nothing).
std::vector<int> shapeAtPixels(const render::Scene& scene) {
  const auto& cam = scene.camera().settings();
  std::vector<int> shape(std::size_t(cam.width) * std::size_t(cam.height), -1);
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      render::SurfaceHit hit;
      if (scene.intersect(scene.camera().generateRay({x + 0.5f, y + 0.5f}), hit))
        shape[std::size_t(y) * std::size_t(cam.width) + std::size_t(x)] = int(hit.shape);
    }
  return shape;
}

std::map<int, Rgb> regionMeans(const Image& image, const std::vector<int>& shape) {
  std::map<int, Rgb> sum;
  std::map<int, int> count;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const int s = shape[std::size_t(y) * std::size_t(image.width) + std::size_t(x)];
      sum[s] += Rgb(image.at(x, y, 0), image.at(x, y, 1), image.at(x, y, 2));
      ++count[s];
    }
  for (auto& [s, v] : sum) v /= float(count[s]);
  return sum;
}

// Path tracing (256 spp) and progressive photon mapping (32 passes of 100,000 photons, radius from
// 1% of the scene's size shrinking with alpha 2/3) on the Cornell box with diffuse walls, a
// tabulated glossy box and a real RGL material: the mean radiance of every wall, box and the light
// agree within 5% (photon mapping's remaining bias at corners and edges plus both estimators'
// noise; the regions' relative standard errors are small beside it).
BTF_STATISTICAL_TEST(RenderEstimators, PathTracingAndProgressivePhotonMappingAgreePerRegion) {
  ASSERT_TRUE(std::filesystem::exists(cornellObj())) << "no shared Cornell box at " << cornellObj();
  const render::Scene scene(cornell(48, true));
  render::RenderSettings settings;
  settings.spp = 256;
  const render::RenderResult pt = render::makePathTracer()->render(scene, settings);
  render::PhotonSettings photon;
  photon.photons = 100'000;
  photon.passes = 32;
  settings.spp = 2;
  const render::RenderResult ppm = render::makePhotonMapper(render::PhotonMode::Progressive, photon)->render(scene, settings);
  const auto shape = shapeAtPixels(scene);
  const auto a = regionMeans(pt.color, shape), b = regionMeans(ppm.color, shape);
  for (const auto& [s, mean] : a) {
    if (s < 0) continue;
    const std::string& name = scene.description().shapes[std::size_t(s)].mesh.name;
    const Rgb other = b.at(s);
    std::printf("  %-60s pt %.4f %.4f %.4f  ppm %.4f %.4f %.4f\n", name.c_str(), mean.r, mean.g, mean.b, other.r, other.g, other.b);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(other[c], mean[c], 0.05 * mean[c] + 1e-4) << name << " channel " << c;
  }
}

// Glossy measured materials under a sky: a tabulated GGX sphere and a sphere of the real RGL
// material paper_white on a diffuse floor, lit by a uniform environment (no small light, so the
// variance is finite and moderate, and the Monte Carlo rate shows at low sample counts).
render::SceneDescription spheresUnderSky(int resolution, const std::string& sampler) {
  render::SceneDescription d;
  auto add = [&](std::string name, std::shared_ptr<const Material> m) {
    d.materials.push_back({std::move(name), m, withSampler(*parseSamplerChoice(sampler), m, coarseSamplerOptions()), sampler});
  };
  add("floor", std::make_shared<Lambert>(Rgb(0.6f)));
  static const auto table =
      std::make_shared<TabulatedBrdf>(std::make_shared<const MerlTable>(tabulate(Ggx(Rgb(0.3f, 0.25f, 0.2f), Rgb(0.5f), 0.15f, 0.15f))));
  add("table", table);
  const auto paper = sharedDataDir() / "rgl_bsdf" / "paper_white_rgb.bsdf";
  add("paper", std::make_shared<RglBrdf>(paper));
  d.shapes.push_back(floorQuad(0, 3.0f));
  d.shapes.push_back({render::makeSphere({-0.45f, 0.4f, 0}, 0.4f, 24, "table sphere"), 1, Rgb(0.0f), false});
  d.shapes.push_back({render::makeSphere({0.45f, 0.4f, 0}, 0.4f, 24, "paper sphere"), 2, Rgb(0.0f), false});
  d.environment_radiance = Rgb(1.0f, 0.95f, 0.9f);
  d.camera.position = {0, 1.2f, 2.6f};
  d.camera.look_at = {0, 0.35f, 0};
  d.camera.width = d.camera.height = resolution;
  return d;
}

// relmse against a 4096-spp reference falls as 1/spp for every sampler (the Monte Carlo rate): the
// slope of log relmse from 4 to 64 spp lies in [-1.2, -0.8] (the reference's own variance, 1/64 of
// the 64-spp image's, flattens it by about 0.02; a biased sampler would level off towards 0).
// relmse is averaged over 16 seeds at 4 spp and 4 seeds at 64 spp: a glossy lobe drawn by the
// cosine warp has weights up to ~20, so one 4-spp image's relmse swings with its few largest
// samples, while the mean over images is what falls as 1/spp.
BTF_STATISTICAL_TEST(RenderEstimators, EverySamplerConvergesToTheSameImageAtTheMonteCarloRate) {
  render::RenderSettings settings;
  settings.spp = 4096;
  settings.seed = 1000;
  const Image reference = render::makePathTracer()->render(render::Scene(spheresUnderSky(24, "material")), settings).color;
  for (const char* sampler : {"material", "cosine", "tabulated", "dp-cdf", "quadtree"}) {
    const render::Scene scene(spheresUnderSky(24, sampler));
    std::vector<double> relmse;
    for (const auto& [spp, seeds] : {std::pair{4, 16}, std::pair{64, 4}}) {
      double sum = 0;
      for (int seed = 1; seed <= seeds; ++seed) {
        settings.spp = spp;
        settings.seed = std::uint64_t(seed);
        sum += render::compareImages(render::makePathTracer()->render(scene, settings).color, reference).relmse;
      }
      relmse.push_back(sum / seeds);
    }
    const double slope = std::log(relmse[1] / relmse[0]) / std::log(16.0);
    std::printf("  %-10s relmse 4 spp %.6f, 64 spp %.6f: slope %.3f\n", sampler, relmse[0], relmse[1], slope);
    EXPECT_GE(slope, -1.2) << sampler;
    EXPECT_LE(slope, -0.8) << sampler;
  }
}

// A compressed BTF (VQ at epsilon 0.02, a one-texel BTF of a BRDF and an 8 x 8 textured BTF) on
// the tall box renders like the uncompressed data on the same scene and seeds: relmse below
// 2e-3 at 64 spp. The bound covers the VQ error (luminance rel_rmse <= ~6% per entry at epsilon
// 0.02, three levels) as it reaches the image, and the paths that part where the sampler's tables
// differ; a wrong lookup or a mismatched uv mapping gives relmse far above it.
BTF_STATISTICAL_TEST(RenderEstimators, CompressedBtfRendersLikeItsReference) {
  ASSERT_TRUE(std::filesystem::exists(cornellObj())) << "no shared Cornell box at " << cornellObj();
  for (const auto& [label, data] : {std::make_pair(std::string("brdf"), makeGgxBtf(1, 1, false)),
                                    std::make_pair(std::string("textured"), makeGgxBtf(8, 8, true))}) {
    auto renderWith = [&](std::shared_ptr<const BtfLookup> btf) {
      render::SceneDescription d = cornell(32, false);
      const auto material = std::make_shared<BtfMaterial>(std::move(btf));
      d.materials.push_back({"btf", material, material, "material", render::UvMapping::Box, 1, 2.0f});
      int covered = 0;
      for (auto& shape : d.shapes)
        if (shape.mesh.file_material == "tallBox") {
          shape.material = int(d.materials.size()) - 1;
          ++covered;
        }
      EXPECT_EQ(covered, 1);
      const render::Scene scene(std::move(d));
      render::RenderSettings settings;
      settings.spp = 64;
      return render::makePathTracer()->render(scene, settings).color;
    };
    const auto reference = std::make_shared<BtfData>(data);
    const auto compressed = std::make_shared<VqBtf>(compressVq(data, VqOptions{}));
    const Image a = renderWith(reference), b = renderWith(compressed);
    const render::ImageComparison c = render::compareImages(b, a);
    std::printf("  %-8s compressed vs reference: relmse %.6f, rel_rmse %.5f\n", label.c_str(), c.relmse, c.rel_rmse);
    EXPECT_LT(c.relmse, 2e-3) << label;
  }
}

}  // namespace
}  // namespace btf::test
