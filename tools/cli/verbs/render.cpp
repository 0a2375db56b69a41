// `btf render scene.json -o out.exr`: renders a scene file with the path tracer (or a photon
// mapper), writes the linear EXR, a PNG preview and the AOVs, and prints what it cost.
#include <tbb/global_control.h>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>

#include "btf/core/error.h"
#include "btf/render/integrator.h"
#include "btf/render/photon_map.h"
#include "btf/render/render_output.h"
#include "btf/render/scene_loader.h"
#include "btf/sampling/sampler_choice.h"
#include "commands.h"

namespace btf::cli {
namespace {

struct RenderOptions {
  std::string scene;
  std::string output;
  std::optional<int> spp, max_depth;
  std::string integrator = "pt";
  int threads = 0;
  std::uint64_t seed = 1;
  std::string sampler;
  bool aovs = false;
  bool strict = false;
  float exposure = 0;
  bool json = false;
  render::PhotonSettings photon;
  std::string kernel = "epanechnikov";
};

std::unique_ptr<render::Integrator> makeIntegrator(const RenderOptions& o) {
  render::PhotonSettings photon = o.photon;
  photon.kernel = o.kernel == "cone" ? render::PhotonKernel::Cone : render::PhotonKernel::Epanechnikov;
  if (o.integrator == "pt") return render::makePathTracer();
  if (o.integrator == "photon") return render::makePhotonMapper(render::PhotonMode::DirectVisualization, photon);
  if (o.integrator == "photon-gather") return render::makePhotonMapper(render::PhotonMode::FinalGathering, photon);
  if (o.integrator == "ppm") return render::makePhotonMapper(render::PhotonMode::Progressive, photon);
  throw Error("unknown integrator '" + o.integrator + "' (expected pt, photon, photon-gather or ppm)");
}

void runRender(const RenderOptions& o) {
  // Refuse what cannot be written before spending minutes on the render.
  const std::filesystem::path output(o.output);
  if (output.extension() != ".exr") throw FileError(output, "a render is written as linear OpenEXR: the name must end in .exr");
  const std::filesystem::path folder = output.parent_path().empty() ? std::filesystem::path(".") : output.parent_path();
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec)) throw FileError(output, "the output folder does not exist");

  render::SceneLoadOptions load;
  load.sampler_override = o.sampler;
  load.strict = o.strict;
  render::SceneDescription description = render::loadSceneDescription(o.scene, load);
  render::RenderSettings settings;
  settings.spp = o.spp.value_or(description.render.spp);
  settings.max_depth = o.max_depth.value_or(description.render.max_depth);
  settings.rr_min_depth = description.render.rr_min_depth;
  settings.seed = o.seed;
  settings.aovs = o.aovs;
  const auto integrator = makeIntegrator(o);

  std::optional<tbb::global_control> limit;
  if (o.threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(o.threads));
  const render::Scene scene(std::move(description));
  const render::RenderResult result = integrator->render(scene, settings);
  if (const std::optional<std::string> bad = nonFinitePixel(result.color))
    throw FileError(o.scene, "the render is not finite, " + *bad +
                                 " (a radiance or reflectance of the scene overflows); nothing was written");
  const auto written = render::writeRenderOutputs(result, output, o.exposure);

  const render::RenderStats& s = result.stats;
  const double rays_per_s = s.seconds > 0 ? double(s.rays()) / s.seconds : 0.0;
  const auto& cam = scene.camera().settings();
  if (o.json) {
    nlohmann::json files = nlohmann::json::array();
    for (const auto& p : written) files.push_back(p.string());
    std::cout << nlohmann::json{{"scene", o.scene},       {"integrator", integrator->name()},
                                {"width", cam.width},     {"height", cam.height},
                                {"spp", settings.spp},    {"seed", settings.seed},
                                {"seconds", s.seconds},   {"rays", s.rays()},
                                {"rays_per_s", rays_per_s}, {"camera_rays", s.camera_rays},
                                {"extension_rays", s.extension_rays}, {"shadow_rays", s.shadow_rays},
                                {"photons", s.photons},   {"photons_emitted", s.photons_emitted},
                                {"photon_seconds", s.photon_seconds},
                                {"photons_per_s", s.photon_seconds > 0 ? double(s.photons_emitted) / s.photon_seconds : 0.0},
                                {"outputs", files}}
                     .dump(2)
              << "\n";
    return;
  }
  std::printf("%s: %d x %d, %d spp, %s, seed %llu\n", o.scene.c_str(), cam.width, cam.height, settings.spp,
              integrator->name().c_str(), static_cast<unsigned long long>(settings.seed));
  std::printf("  time        %.2f s\n", s.seconds);
  std::printf("  rays        %llu (camera %llu, extension %llu, shadow %llu): %.2f M rays/s\n",
              static_cast<unsigned long long>(s.rays()), static_cast<unsigned long long>(s.camera_rays),
              static_cast<unsigned long long>(s.extension_rays), static_cast<unsigned long long>(s.shadow_rays),
              rays_per_s * 1e-6);
  if (s.photons_emitted > 0)
    std::printf("  photons     %llu emitted, %llu stored in %.2f s: %.2f M photons/s\n",
                static_cast<unsigned long long>(s.photons_emitted), static_cast<unsigned long long>(s.photons),
                s.photon_seconds, s.photon_seconds > 0 ? double(s.photons_emitted) / s.photon_seconds * 1e-6 : 0.0);
  for (const auto& p : written) std::printf("  wrote       %s\n", p.string().c_str());
}

}  // namespace

void registerRenderCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("render", "Render a scene file (JSON) to a linear EXR and a PNG preview");
  auto o = std::make_shared<RenderOptions>();
  cmd->add_option("SCENE", o->scene, "Scene file (.json)")->required();
  cmd->add_option("-o,--output", o->output, "Output image (.exr); the preview goes beside it as .png")->required();
  cmd->add_option("--spp", o->spp, "Samples per pixel (default: the scene's)")->check(CLI::Range(1, 1 << 24));
  cmd->add_option("--max-depth", o->max_depth, "Path segments at most (default: the scene's)")->check(CLI::Range(1, 1024));
  cmd->add_option("--integrator", o->integrator,
                  "pt (path tracing), photon (photon map seen directly), photon-gather (final gathering), "
                  "ppm (progressive photon mapping)")
      ->check(CLI::IsMember({"pt", "photon", "photon-gather", "ppm"}))
      ->capture_default_str();
  cmd->add_option("--photons", o->photon.photons, "Photons per map (per pass for ppm)")
      ->check(CLI::Range(std::uint64_t(1), std::uint64_t(1) << 32))
      ->capture_default_str();
  cmd->add_option("--k", o->photon.k, "Nearest photons per estimate (0: fixed radius)")->check(CLI::Range(0, 10000))->capture_default_str();
  cmd->add_option("--radius", o->photon.radius, "Fixed (or first progressive) radius; 0: 1% of the scene's size")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--passes", o->photon.passes, "Passes of ppm")->check(CLI::Range(1, 100000))->capture_default_str();
  cmd->add_option("--kernel", o->kernel, "Photon kernel: epanechnikov or cone")
      ->check(CLI::IsMember({"epanechnikov", "cone"}))
      ->capture_default_str();
  cmd->add_option("--threads", o->threads, "Worker threads (0: all cores); the image does not depend on it")
      ->check(CLI::Range(0, 1024));
  cmd->add_option("--seed", o->seed, "Seed of the pixel streams")->capture_default_str();
  cmd->add_option("--sampler", o->sampler, "Sampler of every material, replacing the scene's: " + samplerChoiceNames());
  cmd->add_flag("--aovs", o->aovs, "Also write albedo, normal, depth and sample-count images");
  cmd->add_flag("--strict", o->strict,
                "Make the scene's warnings errors (a mesh's missing material library, an unknown usemtl)");
  cmd->add_option("--exposure", o->exposure, "Exposure of the PNG preview in stops")
      ->check(CLI::Range(-64.0f, 64.0f))
      ->capture_default_str();
  cmd->add_flag("--json", o->json, "Machine-readable summary");
  cmd->callback([o] { runRender(*o); });
}

}  // namespace btf::cli
