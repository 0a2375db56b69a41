// Two GGX lobes over a Lambert base: a broad lobe with the diffuse term (the Ggx material) plus a
// second, usually narrower, specular-only lobe. What metallic paints (flakes under a clear coat)
// and clear-coated plastics need, and what Ngan et al. 2005 found fits MERL best among the classic
// models (two Cook-Torrance lobes): f = Ggx(kd, f0, alpha) + Ggx(0, f0_2, alpha_2).
//
// Sampling is the mixture of the two lobes' own samplers, each chosen with a probability
// proportional to its strength (the mean of its f0, plus kd for the first, whose sampler also
// covers the diffuse term), and pdf is the exact mixture density.
#pragma once

#include <string>

#include "btf/material/ggx.h"

namespace btf {

class GgxTwoLobes final : public Material {
 public:
  // Throws btf::Error for parameters Ggx refuses.
  GgxTwoLobes(Rgb diffuse_albedo, Rgb f0, float alpha, Rgb f0_2, float alpha_2);

  Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::optional<BsdfSample> sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const override;
  float pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::string name() const override;
  bool isReciprocal() const override { return true; }

 private:
  Ggx base_, coat_;
  float base_probability_;
  std::string name_;
};

}  // namespace btf
