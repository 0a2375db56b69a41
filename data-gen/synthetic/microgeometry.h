// The sample a virtual gonioreflectometer observes: a height field over the reference plane with a
// material map. Lengths and heights are in texels. The field is sampled on a grid finer than the
// texels (samples_per_texel per axis), sample (gx, gy) sitting at ((gx + 0.5), (gy + 0.5)) /
// samples_per_texel, and is periodic over the patch: the patch tiles, so rays that leave one side
// come back on the other and edge texels are shadowed and masked like inner ones.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "btf/core/rgb.h"
#include "btf/material/material.h"

namespace btf::synthetic {

struct Microgeometry {
  int width = 0, height = 0;   // texels of the reference plane
  int samples_per_texel = 4;   // height-field samples per texel along each axis
  // Per grid sample, row-major (gridIndex):
  std::vector<float> heights;               // surface height above the reference plane (texels)
  std::vector<std::uint8_t> material_ids;   // index into `materials`
  std::vector<Rgb> tints;                   // multiplies f: spatial albedo variation within a material
  std::vector<float> tangent_angles;        // tangent direction (radians from +x), for anisotropic materials
  std::vector<std::shared_ptr<const Material>> materials;

  // A flat surface at height 0 of one material (tint 1, tangent along +x).
  Microgeometry(int width, int height, int samples_per_texel, std::shared_ptr<const Material> material);

  int gridWidth() const { return width * samples_per_texel; }
  int gridHeight() const { return height * samples_per_texel; }
  std::size_t gridSize() const { return std::size_t(gridWidth()) * std::size_t(gridHeight()); }
  std::size_t gridIndex(int gx, int gy) const { return std::size_t(gy) * std::size_t(gridWidth()) + std::size_t(gx); }
  // Texel-space position of a grid sample.
  float sampleX(int gx) const { return (float(gx) + 0.5f) / float(samples_per_texel); }
  float sampleY(int gy) const { return (float(gy) + 0.5f) / float(samples_per_texel); }

  // Throws btf::Error unless sizes agree, heights are finite, ids name a material and tints are >= 0.
  void validate() const;
};

}  // namespace btf::synthetic
