// Ideal diffuse reflection, f = albedo / pi, sampled with the cosine-weighted hemisphere (exact:
// the weight f cos / pdf is the albedo itself).
#pragma once

#include "btf/material/material.h"

namespace btf {

class Lambert final : public Material {
 public:
  // albedo: directional-hemispherical reflectance per channel, finite and >= 0 (throws btf::Error).
  explicit Lambert(Rgb albedo);

  Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::optional<BsdfSample> sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const override;
  float pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::string name() const override;
  bool isReciprocal() const override { return true; }

  const Rgb& albedo() const { return albedo_; }

 private:
  Rgb albedo_;
};

}  // namespace btf
