// Shifted Gamma Distribution microfacet model (Bagher, Soler, Holzschuch, "Accurate fitting of
// measured reflectances using a Shifted Gamma micro-facet distribution", EGSR 2012), evaluated
// exactly as dj_brdf evaluates the published MERL fits (docs/design-notes.md#measured-data), with
// i = wi, o = wo, h = normalize(i + o), every parameter per RGB channel:
//   f = (rho_d + rho_s F D G / (cos_i cos_o)) / pi
//   D = kap exp(-(alpha + tan^2 theta_h / alpha)) / (pi (alpha + tan^2 theta_h / alpha)^p cos^4 theta_h)
//   G = G1(i) G1(o),  G1(k) = clamp(1 + lambda (1 - exp(c max(0, theta_k - theta0)^k)), 0, 1)
//   F = f0 - cos_d f1 + (1 - cos_d)^5 (1 - f0),  cos_d = i.h   (angles theta_k, theta0 in radians)
// One guard beyond dj_brdf: f is clamped to >= 0 per channel. Some published fits have f1 > f0, so
// F < 0 near cos_d = 1 (blue-fabric, white-fabric2, white-paint); their diffuse term keeps f
// positive (checked in test_fit_models.cpp), but a negative f would be unphysical and a MERL
// table would read it as "unmeasured". Arithmetic is in double (c reaches 1e38, k reaches 900).
//
// Sampling: a mixture of the cosine hemisphere and, per channel, two half-vector proposals:
// GGX with the SGD's slope scale alpha (the (alpha + t^2/alpha)^-p core) and Beckmann with
// alpha_b = sqrt(alpha) (the exp(-t^2/alpha) envelope), wi = reflect(wo, h). The split between
// core and envelope follows the mass of the shifted gamma density y^-p e^-y (y = alpha + t^2/alpha)
// near its start; channel weights follow each channel's specular strength. The density is the
// exact mixture density; the cosine share is at least 10% so that grazing configurations, where
// reflected half vectors fall below the horizon, are still covered.
#pragma once

#include <array>
#include <string>

#include "btf/material/material.h"

namespace btf {

// The published parameters of one colour channel (columns of sgd_bagher2012_merl.csv).
struct SgdChannel {
  double rho_d = 0, rho_s = 0, alpha = 1, p = 0, f0 = 1, f1 = 0, kap = 1, lambda = 0, c = 0, k = 1, theta0 = 0;
};

struct SgdParameters {
  std::array<SgdChannel, 3> channel;  // R, G, B
};

class Sgd final : public Material {
 public:
  // Every parameter finite; rho_d, rho_s, kap >= 0; alpha > 0 (throws btf::Error naming the
  // channel and parameter). label names the material in name(), e.g. "gold-metallic-paint".
  explicit Sgd(const SgdParameters& parameters, std::string label = {});

  Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::optional<BsdfSample> sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const override;
  float pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::string name() const override;
  bool isReciprocal() const override { return true; }

  const SgdParameters& parameters() const { return parameters_; }

 private:
  static constexpr int kLobes = 6;  // channel c: GGX core 2c, Beckmann envelope 2c + 1

  SgdParameters parameters_;
  std::string label_;
  float diffuse_probability_ = 1.0f;
  std::array<float, kLobes> lobe_probability_{};  // sums to 1 - diffuse_probability_
  std::array<float, kLobes> lobe_alpha_{};
};

}  // namespace btf
