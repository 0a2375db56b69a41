// Energy-normalized modified Phong (Lafortune & Willems 1994):
//   f = kd / pi + ks (n + 2) / (2 pi) max(0, dot(wi, reflect(wo, normal)))^n.
// Reciprocal, and energy-conserving whenever kd + ks <= 1 per channel (the lobe's cosine-weighted
// integral never exceeds ks). Sampled by a fixed mixture of the cosine hemisphere and a cos^n lobe
// around the mirror direction, chosen in proportion to the mean diffuse and specular albedos.
#pragma once

#include "btf/material/material.h"

namespace btf {

class Phong final : public Material {
 public:
  // Albedos finite and >= 0 per channel, exponent finite and >= 0 (throws btf::Error).
  Phong(Rgb diffuse_albedo, Rgb specular_albedo, float exponent);

  Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::optional<BsdfSample> sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const override;
  float pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::string name() const override;
  bool isReciprocal() const override { return true; }

 private:
  Rgb kd_, ks_;
  float exponent_;
  float specular_probability_;  // chance that sample() draws from the lobe rather than the cosine
};

}  // namespace btf
