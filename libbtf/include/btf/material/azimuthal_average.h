// An anisotropic material stored in an isotropic table. MERL tables have no phi_h axis, so an
// anisotropic model has to be made isotropic first. Two choices exist: the slice at phi_h = 0 (what
// tabulate() samples) or the average over phi_h. The slice is not a consistent material: the
// anisotropic normalization no longer matches the lobe (a Ward lobe with alpha 0.06 x 0.25 sliced
// along x keeps only ~0.24 of its energy). The average over phi_h is what a measurement of many
// randomly rotated patches of the material would give, and it keeps the azimuth-averaged albedo.
// AzimuthalAverage is that average (midpoint rule over phi_h), an exact isotropic Material; as a
// parameter set, {"type": "azimuthal-average", "material": {the anisotropic material's set}}.
#pragma once

#include <memory>

#include "btf/material/material.h"

namespace btf {

class AzimuthalAverage final : public Material {
 public:
  explicit AzimuthalAverage(std::shared_ptr<const Material> base, int phi_steps = 64)
      : base_(std::move(base)), phi_steps_(phi_steps) {}

  Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  // Cosine-weighted: the base sampler targets one orientation of the lobe, not the average.
  std::optional<BsdfSample> sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const override;
  float pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::string name() const override { return base_->name() + " averaged over phi_h"; }
  // Rotating both directions together keeps reciprocity, and so does averaging over rotations.
  bool isReciprocal() const override { return base_->isReciprocal(); }

 private:
  std::shared_ptr<const Material> base_;
  int phi_steps_;
};

}  // namespace btf
