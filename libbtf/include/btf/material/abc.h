// ABC microfacet model (Löw, Kronander, Ynnerman, Unger, "BRDF models for accurate and efficient
// rendering of glossy surfaces", ACM TOG 2012), evaluated exactly as dj_brdf evaluates the
// published MERL fits (docs/design-notes.md#measured-data), with h = normalize(wi + wo):
//   f = kd / pi + F(cos_d) D(h) G / (pi cos_i cos_o)
//   D = A / (1 + B (1 - cos theta_h))^C          (A per channel; B, C shared)
//   G = min(1, 2 cos_h cos_i / (h.wi), 2 cos_h cos_o / (h.wo))
//   F = unpolarized dielectric Fresnel reflectance of index `ior` at cos_d = h.wi.
// Note that D carries no 1/4: the fitted A absorbs every constant.
//
// Sampling is exact for the distribution: with u = 1 - cos theta_h (dh = du dphi) the density of
// h proportional to D is proportional to (1 + B u)^-C on [0, 1], whose CDF inverts in closed form.
// wi = reflect(wo, h); mixed with the cosine hemisphere (at least 10%, weighted by kd against the
// specular strength) for the diffuse term and for grazing views where reflections go below the
// horizon.
#pragma once

#include <string>

#include "btf/material/material.h"

namespace btf {

// The published parameters (columns of abc_low2012_merl.csv).
struct AbcParameters {
  Rgb kd;
  Rgb a;
  double b = 1, c = 1, ior = 1.5;
};

class Abc final : public Material {
 public:
  // kd, A finite and >= 0; B > 0, C finite, ior >= 1 (throws btf::Error). label names the material.
  explicit Abc(const AbcParameters& parameters, std::string label = {});

  Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::optional<BsdfSample> sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const override;
  float pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::string name() const override;
  bool isReciprocal() const override { return true; }

  const AbcParameters& parameters() const { return parameters_; }
  // Unpolarized Fresnel reflectance of a dielectric of index ior at cos(angle of incidence).
  static double fresnelDielectric(double cos_theta, double ior);

 private:
  double halfVectorPdf(const glm::vec3& h) const;  // solid-angle density of the h proposal
  glm::vec3 sampleHalfVector(glm::vec2 u) const;

  AbcParameters parameters_;
  std::string label_;
  double log1p_b_ = 0;      // log(1 + B)
  double normalizer_ = 1;   // 2 pi int_0^1 (1 + B u)^-C du
  float diffuse_probability_ = 1.0f;
};

}  // namespace btf
