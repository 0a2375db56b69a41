// btf.render: a scene file rendered by the path tracer (or a photon mapper) into a numpy image.
#include <optional>
#include <string>

#include "bindings.h"
#include "btf/core/error.h"
#include "btf/render/integrator.h"
#include "btf/render/photon_map.h"
#include "btf/render/scene_loader.h"

namespace btf::python {
namespace {

std::unique_ptr<render::Integrator> renderIntegrator(const std::string& name, std::uint64_t photons, int passes) {
  render::PhotonSettings photon;
  photon.photons = photons;
  photon.passes = passes;
  if (name == "pt") return render::makePathTracer();
  if (name == "photon") return render::makePhotonMapper(render::PhotonMode::DirectVisualization, photon);
  if (name == "photon-gather") return render::makePhotonMapper(render::PhotonMode::FinalGathering, photon);
  if (name == "ppm") return render::makePhotonMapper(render::PhotonMode::Progressive, photon);
  throw py::value_error("integrator: expected 'pt', 'photon', 'photon-gather' or 'ppm', got '" + name + "'");
}

py::array imageArray(Image&& image) {
  const std::vector<py::ssize_t> shape = {image.height, image.width, image.channels};
  return ownedFloatArray(std::move(image.pixels), shape);
}

py::object renderScene(const py::handle& scene_in, std::optional<int> spp, std::uint64_t seed, std::optional<int> max_depth,
                       std::optional<int> width, std::optional<int> height, const std::string& integrator_name,
                       const std::string& sampler, std::uint64_t photons, int passes, bool strict, bool return_stats) {
  const std::string scene_path = toPath(scene_in);
  const auto integrator = renderIntegrator(integrator_name, photons, passes);
  render::RenderResult result;
  render::RenderSettings settings;
  int image_width = 0, image_height = 0;
  {
    py::gil_scoped_release release;
    render::SceneLoadOptions load;
    load.sampler_override = sampler;
    load.strict = strict;
    render::SceneDescription description = render::loadSceneDescription(scene_path, load);
    settings.spp = spp.value_or(description.render.spp);
    settings.max_depth = max_depth.value_or(description.render.max_depth);
    settings.rr_min_depth = description.render.rr_min_depth;
    settings.seed = seed;
    // A smaller image of the same view: the camera's field of view spans the shorter side.
    if (width) description.camera.width = *width;
    if (height) description.camera.height = *height;
    image_width = description.camera.width;
    image_height = description.camera.height;
    const render::Scene scene(std::move(description));
    result = integrator->render(scene, settings);
    if (const std::optional<std::string> bad = nonFinitePixel(result.color))
      throw FileError(scene_path, "the render is not finite, " + *bad + " (a radiance or reflectance of the scene overflows)");
  }
  const render::RenderStats s = result.stats;
  py::array image = imageArray(std::move(result.color));
  if (!return_stats) return image;
  py::dict stats;
  stats["scene"] = scene_path;
  stats["integrator"] = integrator->name();
  stats["width"] = image_width;
  stats["height"] = image_height;
  stats["spp"] = settings.spp;
  stats["seed"] = settings.seed;
  stats["seconds"] = s.seconds;
  stats["rays"] = s.rays();
  stats["rays_per_s"] = s.seconds > 0 ? double(s.rays()) / s.seconds : 0.0;
  stats["camera_rays"] = s.camera_rays;
  stats["extension_rays"] = s.extension_rays;
  stats["shadow_rays"] = s.shadow_rays;
  stats["photons"] = s.photons;
  stats["photons_emitted"] = s.photons_emitted;
  stats["photon_seconds"] = s.photon_seconds;
  return py::make_tuple(image, stats);
}

}  // namespace

void bindRender(py::module_& m) {
  m.def("render", &renderScene, py::arg("scene"), py::arg("spp") = py::none(), py::arg("seed") = 1,
        py::arg("max_depth") = py::none(), py::arg("width") = py::none(), py::arg("height") = py::none(),
        py::arg("integrator") = "pt", py::arg("sampler") = "", py::arg("photons") = 200'000, py::arg("passes") = 16,
        py::arg("strict") = false, py::arg("return_stats") = false,
        R"doc(render(scene, spp=None, seed=1, max_depth=None, width=None, height=None, integrator='pt',
       sampler='', photons=200000, passes=16, strict=False, return_stats=False)
    -> array (height, width, 3) float32, or (array, stats dict) with return_stats

Renders a scene file (JSON) to linear RGB radiance, as `btf render` (which also writes the
EXR). Rows top to bottom.
  spp, max_depth  default: the scene's
  seed            of the pixel streams; the image does not depend on the thread count
  width, height   override the camera's image size (the field of view spans the shorter side)
  integrator      'pt' (path tracing), 'photon', 'photon-gather' or 'ppm'
  sampler         replaces every material's sampler (a name of btf.sampler_names())
  photons, passes photons per map (per pass for ppm) and ppm's passes
  strict          make the scene's warnings errors
  return_stats    also return the render's statistics (seconds, rays, ...) as `btf render --json`)doc");
}

}  // namespace btf::python
