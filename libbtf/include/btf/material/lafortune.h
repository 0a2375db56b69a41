// Multi-lobe Lafortune model (Lafortune et al. 1997) in the normalization of the published one-lobe
// fits of Ngan et al. 2005:
//   f = kd / pi + sum_lobes rho (n + 2) / (2 pi) / max(|cx|,|cy|,|cz|)^n
//                  * max(0, cx wi.x wo.x + cy wi.y wo.y + cz wi.z wo.z)^n.
// Dividing by the largest |c|^n bounds each lobe by a Phong lobe of albedo rho, so kd + sum rho <= 1
// per channel keeps the model energy-conserving. Each lobe is a cos^n lobe around the axis
// normalize(c * wo), which is how it is sampled. The mixture weights depend on wo: a lobe weighs
// mean(rho) (|c * wo| / max|c|)^n, the bound on its albedo at wo, so that fitted lobes which are
// strong only at grazing angles (Ngan's cz < |cxy|) do not waste draws at normal view.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "btf/material/material.h"

namespace btf {

struct LafortuneLobe {
  Rgb rho;         // lobe albedo bound per channel
  glm::vec3 c;     // (cx, cy, cz); cx = cy = -cz gives a Phong lobe, cx != cy an anisotropic one
  float exponent;  // n >= 0
};

// Every evaluation sums all lobes; a model of thousands would make a render or a table crawl.
inline constexpr std::size_t kMaxLafortuneLobes = 64;

class Lafortune final : public Material {
 public:
  // Albedos finite and >= 0, every c finite and not all zero, exponents finite and >= 0
  // (throws btf::Error naming the lobe).
  Lafortune(Rgb diffuse_albedo, std::vector<LafortuneLobe> lobes);

  Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::optional<BsdfSample> sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const override;
  float pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::string name() const override;
  bool isReciprocal() const override { return true; }
  bool isAnisotropic() const override;

  const Rgb& diffuseAlbedo() const { return kd_; }
  const std::vector<LafortuneLobe>& lobes() const { return lobes_; }

 private:
  // Mixture weight of lobe i at wo (see above) and the length of its axis c * wo.
  float lobeWeight(std::size_t i, const glm::vec3& wo, float& axis_length) const;

  Rgb kd_;
  std::vector<LafortuneLobe> lobes_;
  std::vector<float> inv_max_c_;  // 1 / max(|cx|,|cy|,|cz|) per lobe
};

}  // namespace btf
