#include "btf/render/render_output.h"

#include "btf/core/error.h"

namespace btf::render {

std::vector<std::filesystem::path> writeRenderOutputs(const RenderResult& result, const std::filesystem::path& exr,
                                                      float exposure_stops) {
  if (exr.extension() != ".exr") throw FileError(exr, "a render is written as linear OpenEXR: the name must end in .exr");
  std::vector<std::filesystem::path> written;
  writeImage(exr, result.color);
  written.push_back(exr);
  std::filesystem::path preview = exr;
  preview.replace_extension(".png");
  writeImage(preview, toneMapToSrgb(result.color, exposure_stops));
  written.push_back(preview);
  const std::pair<const char*, const Image*> aovs[] = {
      {"albedo", &result.albedo}, {"normal", &result.normal}, {"depth", &result.depth}, {"samples", &result.samples}};
  for (const auto& [name, image] : aovs) {
    if (image->pixels.empty()) continue;
    std::filesystem::path path = exr;
    path.replace_extension(std::string(".") + name + ".exr");
    writeImage(path, *image);
    written.push_back(path);
  }
  return written;
}

}  // namespace btf::render
