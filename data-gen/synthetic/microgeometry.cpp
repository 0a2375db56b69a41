#include "microgeometry.h"

#include <cmath>

#include "btf/core/error.h"

namespace btf::synthetic {

Microgeometry::Microgeometry(int width_, int height_, int samples_per_texel_, std::shared_ptr<const Material> material)
    : width(width_), height(height_), samples_per_texel(samples_per_texel_) {
  if (width < 1 || height < 1 || samples_per_texel < 1)
    throw Error("microgeometry of " + std::to_string(width) + " x " + std::to_string(height) + " texels with " +
                std::to_string(samples_per_texel) + " samples per texel is invalid: all must be >= 1");
  if (!material) throw Error("microgeometry needs a material");
  heights.assign(gridSize(), 0.0f);
  material_ids.assign(gridSize(), 0);
  tints.assign(gridSize(), Rgb(1.0f));
  tangent_angles.assign(gridSize(), 0.0f);
  materials.push_back(std::move(material));
}

void Microgeometry::validate() const {
  const std::size_t n = gridSize();
  if (heights.size() != n || material_ids.size() != n || tints.size() != n || tangent_angles.size() != n)
    throw Error("microgeometry: per-sample arrays must have " + std::to_string(n) + " entries");
  if (materials.empty() || materials.size() > 256) throw Error("microgeometry: needs 1 to 256 materials");
  for (const auto& m : materials)
    if (!m) throw Error("microgeometry: a material is missing");
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(heights[i]) || !std::isfinite(tangent_angles[i]))
      throw Error("microgeometry: sample " + std::to_string(i) + " has a non-finite height or tangent");
    if (material_ids[i] >= materials.size())
      throw Error("microgeometry: sample " + std::to_string(i) + " names material " + std::to_string(material_ids[i]) +
                  " of " + std::to_string(materials.size()));
    if (!tints[i].isFinite() || tints[i].minComponent() < 0.0f)
      throw Error("microgeometry: sample " + std::to_string(i) + " has a negative or non-finite tint");
  }
}

}  // namespace btf::synthetic
