#include "btf/material/ward.h"

#include "analytic_support.h"
#include "btf/material/model_family.h"
#include "btf/material/registry.h"

namespace btf {

Ward::Ward(Rgb diffuse_albedo, Rgb specular_albedo, float alpha_x, float alpha_y)
    : kd_(diffuse_albedo), ks_(specular_albedo), alpha_x_(alpha_x), alpha_y_(alpha_y) {
  detail::requireDiffuseAlbedo("ward", "diffuse albedo", kd_);
  detail::requireAlbedo("ward", "specular albedo", ks_);
  detail::requirePositive("ward", "alpha_x", alpha_x_);
  detail::requirePositive("ward", "alpha_y", alpha_y_);
  const float total = kd_.average() + ks_.average();
  specular_probability_ = total > 0.0f ? ks_.average() / total : 0.0f;
}

float Ward::distribution(const glm::vec3& m) const {
  const float x = m.x / alpha_x_, y = m.y / alpha_y_;
  const float cos2 = m.z * m.z;
  return std::exp(-(x * x + y * y) / cos2) / (kPi * alpha_x_ * alpha_y_ * cos2 * cos2);
}

Rgb Ward::eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  if (wi.z <= 0.0f || wo.z <= 0.0f) return {};
  const glm::vec3 sum = wi + wo;
  const glm::vec3 m = glm::normalize(sum);
  // 4 (wi.m)^2 = |wi + wo|^2, written symmetrically in wi and wo so reciprocity holds to the bit.
  return kd_ * kInvPi + ks_ * (distribution(m) / glm::dot(sum, sum));
}

float Ward::pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  if (wi.z <= 0.0f || wo.z <= 0.0f) return 0.0f;
  const glm::vec3 m = glm::normalize(wi + wo);
  // Half-vector density D(m) cos_m times the reflection Jacobian 1 / (4 wo.m).
  const float specular = distribution(m) * m.z / (4.0f * glm::dot(wo, m));
  return specular_probability_ * specular + (1.0f - specular_probability_) * cosineHemispherePdf(wi);
}

std::optional<BsdfSample> Ward::sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const {
  if (wo.z <= 0.0f) return std::nullopt;
  glm::vec3 wi;
  if (detail::chooseFirst(specular_probability_, u.x)) {
    // Azimuth: tan(phi) = (ay / ax) tan(2 pi u), in the quadrant of 2 pi u. Then the elevation
    // from tan^2(theta) = -log(u) / (cos^2 phi / ax^2 + sin^2 phi / ay^2); 1 - u avoids log(0).
    const float t = kTwoPi * u.y;
    const float phi = std::atan2(alpha_y_ * std::sin(t), alpha_x_ * std::cos(t));
    const float cos_phi = std::cos(phi), sin_phi = std::sin(phi);
    const float a = cos_phi / alpha_x_, b = sin_phi / alpha_y_;
    const float tan2 = -std::log(1.0f - u.x) / (a * a + b * b);
    const float cos_theta = 1.0f / std::sqrt(1.0f + tan2);
    const float sin_theta = safeSqrt(1.0f - cos_theta * cos_theta);
    const glm::vec3 m{sin_theta * cos_phi, sin_theta * sin_phi, cos_theta};
    wi = reflect(wo, m);  // m facing away from wo sends wi below the horizon, rejected below
  } else {
    wi = squareToCosineHemisphere(u);
  }
  if (wi.z <= 0.0f) return std::nullopt;
  const float p = pdf(wi, wo, uv);
  if (!(p > 0.0f)) return std::nullopt;
  return BsdfSample{wi, eval(wi, wo, uv) * (wi.z / p), p};
}

std::string Ward::name() const {
  return "ward(kd=" + detail::formatRgb(kd_) + ", ks=" + detail::formatRgb(ks_) +
         ", alpha=(" + detail::formatFloat(alpha_x_) + "," + detail::formatFloat(alpha_y_) + "))";
}

BTF_REGISTER_MATERIAL(ward, {.name = modelFamilyName(ModelFamily::Ward),
                             .summary = "Lambert diffuse + Ward specular (alpha, or [alpha_x, alpha_y])",
                             .keys = {"diffuse", "specular", "alpha"},
                             .create = [](const MaterialParams& p) -> std::shared_ptr<const Material> {
                               const glm::vec2 a = p.positivePair("alpha");
                               return std::make_shared<Ward>(p.rgb("diffuse"), p.rgb("specular"), a.x, a.y);
                             }});

}  // namespace btf
