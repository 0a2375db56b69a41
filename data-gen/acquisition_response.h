// The deterministic part of what a gonioreflectometer does to a reflectance: a colour tint
// (camera/filter response) and signal loss at grazing angles (foreshortened illumination spot and
// sensor footprint). It is a Material decorator, so the albedo that `btf info` should find in a
// generated table is simply this material's albedo.
#pragma once

#include <memory>
#include <string>

#include "btf/material/material.h"

namespace btf::datagen {

// Fraction of the signal kept at polar angle theta (radians): 1 - falloff * (theta / 90 deg)^8.
// Close to 1 up to ~60 deg, 1 - falloff at the horizon.
float grazingResponse(float theta, float falloff);

class AcquisitionResponse final : public Material {
 public:
  // label: the short name() reported (progress lines show it), e.g. the preset's name.
  AcquisitionResponse(std::shared_ptr<const Material> base, Rgb tint, float falloff, std::string label);

  Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::optional<BsdfSample> sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const override;
  float pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::string name() const override { return label_; }
  bool isAnisotropic() const override { return base_->isAnisotropic(); }
  // The response multiplies f by one factor per direction, so it keeps reciprocity.
  bool isReciprocal() const override { return base_->isReciprocal(); }

 private:
  // tint * grazing response of both directions; reciprocal because it is symmetric in wi and wo.
  Rgb factor(const glm::vec3& wi, const glm::vec3& wo) const;

  std::shared_ptr<const Material> base_;
  Rgb tint_;
  float falloff_;
  std::string label_;
};

}  // namespace btf::datagen
