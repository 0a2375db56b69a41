#include "acquisition_response.h"

#include <cmath>

#include "btf/core/math.h"

namespace btf::datagen {

float grazingResponse(float theta, float falloff) {
  const float t = std::clamp(theta / kHalfPi, 0.0f, 1.0f);
  const float t2 = t * t, t4 = t2 * t2;
  return 1.0f - falloff * t4 * t4;
}

AcquisitionResponse::AcquisitionResponse(std::shared_ptr<const Material> base, Rgb tint, float falloff,
                                         std::string label)
    : base_(std::move(base)), tint_(tint), falloff_(falloff), label_(std::move(label)) {}

Rgb AcquisitionResponse::factor(const glm::vec3& wi, const glm::vec3& wo) const {
  return tint_ * (grazingResponse(sphericalTheta(wi), falloff_) * grazingResponse(sphericalTheta(wo), falloff_));
}

Rgb AcquisitionResponse::eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv) const {
  return base_->eval(wi, wo, uv) * factor(wi, wo);
}

std::optional<BsdfSample> AcquisitionResponse::sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const {
  std::optional<BsdfSample> s = base_->sample(wo, uv, u);
  if (s) s->weight *= factor(s->wi, wo);
  return s;
}

float AcquisitionResponse::pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv) const {
  return base_->pdf(wi, wo, uv);
}

}  // namespace btf::datagen
