#include "btf/fit/btf_texel.h"

#include <string>

#include "btf/core/error.h"
#include "btf/core/progress.h"

namespace btf {

std::optional<std::string> texelOutside(const BtfSource& btf, glm::ivec2 texel) {
  if (texel.x >= 0 && texel.y >= 0 && texel.x < btf.width() && texel.y < btf.height()) return std::nullopt;
  return "texel (" + std::to_string(texel.x) + ", " + std::to_string(texel.y) + ") lies outside its " +
         std::to_string(btf.width()) + " x " + std::to_string(btf.height()) + " texels";
}

BtfData btfTexel(const BtfSource& btf, std::optional<glm::ivec2> texel) {
  if (texel)
    if (const auto problem = texelOutside(btf, *texel)) throw Error(btf.name() + ": " + *problem);
  const std::string name = btf.name() + (texel ? " texel (" + std::to_string(texel->x) + ", " + std::to_string(texel->y) + ")"
                                               : " mean over texels");
  BtfData out(1, 1, name, btf.views());
  const std::size_t texels = btf.texelCount();
  std::vector<Rgb> view;
  Progress progress("reading " + btf.name(), std::uint64_t(btf.views().count()));
  for (const int v : btf.views().views()) {
    btf.loadView(v, view);
    const int lights = btf.directions().lightCount(v);
    if (view.size() != std::size_t(lights) * texels)
      throw Error(btf.name() + ": view " + std::to_string(v) + " has " + std::to_string(view.size()) + " values, expected " +
                  std::to_string(std::size_t(lights) * texels));
    for (int light = 0; light < lights; ++light) {
      const Rgb* values = view.data() + std::size_t(light) * texels;
      if (texel) {
        out.at(0, 0, v, light) = values[std::size_t(texel->y) * std::size_t(btf.width()) + std::size_t(texel->x)];
        continue;
      }
      // Summed in double, in texel order: the same mean on any machine.
      double sum[3] = {};
      for (std::size_t t = 0; t < texels; ++t)
        for (int c = 0; c < 3; ++c) sum[c] += double(values[t][c]);
      for (int c = 0; c < 3; ++c) out.at(0, 0, v, light)[c] = float(sum[c] / double(texels));
    }
    progress.advance();
  }
  return out;
}

std::vector<MeasuredReflectance> texelMeasurements(const BtfData& texel) {
  if (texel.width() != 1 || texel.height() != 1)
    throw Error(texel.name() + ": expected a one-texel BTF, got " + std::to_string(texel.width()) + " x " +
                std::to_string(texel.height()) + " texels");
  std::vector<MeasuredReflectance> out;
  const BtfDirectionSet& set = texel.directions();
  for (const int v : texel.views().views()) {
    const std::span<const glm::vec3> lights = set.lightDirections(v);
    for (std::size_t light = 0; light < lights.size(); ++light)
      out.push_back({lights[light], set.view(v), texel.at(0, 0, v, int(light))});
  }
  return out;
}

}  // namespace btf
