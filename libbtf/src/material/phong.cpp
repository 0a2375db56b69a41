#include "btf/material/phong.h"

#include "analytic_support.h"
#include "btf/material/model_family.h"
#include "btf/material/registry.h"

namespace btf {

Phong::Phong(Rgb diffuse_albedo, Rgb specular_albedo, float exponent)
    : kd_(diffuse_albedo), ks_(specular_albedo), exponent_(exponent) {
  detail::requireDiffuseAlbedo("phong", "diffuse albedo", kd_);
  detail::requireAlbedo("phong", "specular albedo", ks_);
  detail::requireNonNegative("phong", "exponent", exponent_);
  const float total = kd_.average() + ks_.average();
  specular_probability_ = total > 0.0f ? ks_.average() / total : 0.0f;
}

// The mirror direction about +z.
static glm::vec3 mirror(const glm::vec3& wo) { return {-wo.x, -wo.y, wo.z}; }

Rgb Phong::eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  if (wi.z <= 0.0f || wo.z <= 0.0f) return {};
  Rgb f = kd_ * kInvPi;
  const float c = glm::dot(wi, mirror(wo));
  if (c > 0.0f) f += ks_ * ((exponent_ + 2.0f) * kInv2Pi * std::pow(c, exponent_));
  return f;
}

float Phong::pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  if (wi.z <= 0.0f || wo.z <= 0.0f) return 0.0f;
  return (1.0f - specular_probability_) * cosineHemispherePdf(wi) +
         specular_probability_ * detail::lobePdf(glm::dot(wi, mirror(wo)), exponent_);
}

std::optional<BsdfSample> Phong::sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const {
  if (wo.z <= 0.0f) return std::nullopt;
  const glm::vec3 wi = detail::chooseFirst(specular_probability_, u.x)
                           ? detail::sampleLobeAround(mirror(wo), exponent_, u)
                           : squareToCosineHemisphere(u);
  // Lobe directions past the horizon are lost draws: the pdf integrates to the chance of a sample.
  if (wi.z <= 0.0f) return std::nullopt;
  const float p = pdf(wi, wo, uv);
  if (!(p > 0.0f)) return std::nullopt;
  return BsdfSample{wi, eval(wi, wo, uv) * (wi.z / p), p};
}

std::string Phong::name() const {
  return "phong(kd=" + detail::formatRgb(kd_) + ", ks=" + detail::formatRgb(ks_) +
         ", n=" + detail::formatFloat(exponent_) + ")";
}

BTF_REGISTER_MATERIAL(phong, {.name = modelFamilyName(ModelFamily::Phong),
                              .summary = "energy-normalized modified Phong",
                              .keys = {"diffuse", "specular", "exponent"},
                              .create = [](const MaterialParams& p) -> std::shared_ptr<const Material> {
                                return std::make_shared<Phong>(p.rgb("diffuse"), p.rgb("specular"),
                                                               float(p.number("exponent", 0, 1e6)));
                              }});

}  // namespace btf
