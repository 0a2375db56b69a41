// Microfacet reflection with the GGX / Trowbridge-Reitz distribution (anisotropic alphas along the
// local x and y axes), height-correlated Smith masking-shadowing and Schlick's Fresnel, over a
// Lambertian base:
//   f = F(wi.h) D(h) G2(wi, wo) / (4 cos_i cos_o) + kd / pi (1 - F(cos_i)) (1 - F(cos_o)).
// Coupling: light reaches the diffuse base only through the interface, once on the way in and once
// on the way out, so the base is damped by the Schlick transmittance of both directions (as in
// Ashikhmin & Shirley 2000). That keeps f reciprocal and takes the diffuse share away where
// Fresnel makes the specular lobe strong (grazing angles); a plain (1 - f0) factor would not (at
// 85 degrees a smooth surface reflects ~65% specularly whatever f0, and kd (1 - f0) comes on top).
// With kd <= 1 the directional albedo stays below 1: not proven, but checked where it is tightest
// (kd = 1, f0 in {0, 0.04, 1}, alpha from 0.02 to 1, views up to 89 degrees; the largest value
// seen is about 0.96, test_analytic_materials.cpp).
// Sampling: visible normals (Heitz 2018) for the specular term, the cosine hemisphere for the
// diffuse term, chosen in proportion to their Fresnel-weighted strength at wo.
#pragma once

#include "btf/material/material.h"

namespace btf {

class Ggx final : public Material {
 public:
  // Albedo and f0 finite and >= 0 per channel (f0 <= 1 as well), alphas finite and > 0 (throws).
  Ggx(Rgb diffuse_albedo, Rgb f0, float alpha_x, float alpha_y);

  Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::optional<BsdfSample> sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const override;
  float pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::string name() const override;
  bool isReciprocal() const override { return true; }
  bool isAnisotropic() const override { return alpha_x_ != alpha_y_; }

 private:
  float distribution(const glm::vec3& h) const;  // D(h), normalized so that int D cos_h dh = 1
  float lambda(const glm::vec3& w) const;        // Smith's Lambda; G1 = 1 / (1 + Lambda)
  Rgb fresnel(float cos_theta) const;            // Schlick
  float specularProbability(const glm::vec3& wo) const;
  glm::vec3 sampleVisibleNormal(const glm::vec3& wo, glm::vec2 u) const;

  Rgb kd_, f0_;
  float alpha_x_, alpha_y_;
};

}  // namespace btf
