#include "btf/material/azimuthal_average.h"

#include "btf/core/half_diff.h"
#include "btf/core/math.h"
#include "btf/core/warp.h"
#include "btf/material/registry.h"

namespace btf {

Rgb AzimuthalAverage::eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv) const {
  if (wi.z <= 0 || wo.z <= 0) return Rgb(0.0f);
  // Rotating the pair about the normal keeps (theta_h, theta_d, phi_d) and changes only phi_h.
  HalfDiff hd = toHalfDiff(wi, wo);
  Rgb sum(0.0f);
  for (int k = 0; k < phi_steps_; ++k) {
    hd.phi_h = kTwoPi * (float(k) + 0.5f) / float(phi_steps_);
    const DirectionPair rotated = fromHalfDiff(hd);
    sum += base_->eval(rotated.wi, rotated.wo, uv);
  }
  return sum / float(phi_steps_);
}

std::optional<BsdfSample> AzimuthalAverage::sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const {
  if (wo.z <= 0) return std::nullopt;
  const glm::vec3 wi = squareToCosineHemisphere(u);
  const float density = cosineHemispherePdf(wi);
  if (density <= 0) return std::nullopt;
  return BsdfSample{wi, eval(wi, wo, uv) * (cosTheta(wi) / density), density};
}

float AzimuthalAverage::pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  return wo.z > 0 ? cosineHemispherePdf(wi) : 0.0f;
}

BTF_REGISTER_MATERIAL(azimuthal_average,
                      {.name = "azimuthal-average",
                       .summary = "an anisotropic material averaged over the half vector's azimuth (isotropic)",
                       .keys = {"material"},
                       .create = [](const MaterialParams& p) -> std::shared_ptr<const Material> {
                         return std::make_shared<AzimuthalAverage>(createMaterial(p.child("material")));
                       }});

}  // namespace btf
