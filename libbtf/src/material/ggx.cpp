#include "btf/material/ggx.h"

#include "analytic_support.h"
#include "btf/material/model_family.h"
#include "btf/material/registry.h"

namespace btf {

Ggx::Ggx(Rgb diffuse_albedo, Rgb f0, float alpha_x, float alpha_y)
    : kd_(diffuse_albedo), f0_(f0), alpha_x_(alpha_x), alpha_y_(alpha_y) {
  detail::requireDiffuseAlbedo("ggx", "diffuse albedo", kd_);
  detail::requireAlbedo("ggx", "f0", f0_);
  if (f0_.maxComponent() > 1.0f) throw Error("ggx: f0 must be <= 1 in every channel, got " + detail::formatRgb(f0_));
  detail::requirePositive("ggx", "alpha_x", alpha_x_);
  detail::requirePositive("ggx", "alpha_y", alpha_y_);
}

float Ggx::distribution(const glm::vec3& h) const {
  const float x = h.x / alpha_x_, y = h.y / alpha_y_;
  const float s = x * x + y * y + h.z * h.z;
  return 1.0f / (kPi * alpha_x_ * alpha_y_ * s * s);
}

float Ggx::lambda(const glm::vec3& w) const {
  const float x = alpha_x_ * w.x, y = alpha_y_ * w.y;
  const float tan2_alpha2 = (x * x + y * y) / (w.z * w.z);
  return 0.5f * (std::sqrt(1.0f + tan2_alpha2) - 1.0f);
}

Rgb Ggx::fresnel(float cos_theta) const {
  const float m = 1.0f - std::clamp(cos_theta, 0.0f, 1.0f);
  const float m2 = m * m;
  return f0_ + (Rgb(1.0f) - f0_) * (m2 * m2 * m);
}

Rgb Ggx::eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  if (wi.z <= 0.0f || wo.z <= 0.0f) return {};
  const glm::vec3 sum = wi + wo;
  const glm::vec3 h = glm::normalize(sum);
  // Every expression below is symmetric in wi and wo as evaluated, so f is reciprocal to the bit:
  // wi.h = wo.h = |wi + wo| / 2, and the two Lambdas are added before the 1.
  const float g2 = 1.0f / (1.0f + (lambda(wi) + lambda(wo)));
  const Rgb specular = fresnel(0.5f * glm::length(sum)) * (distribution(h) * g2 / (4.0f * (wi.z * wo.z)));
  const Rgb diffuse = kd_ * kInvPi * ((Rgb(1.0f) - fresnel(wi.z)) * (Rgb(1.0f) - fresnel(wo.z)));
  return specular + diffuse;
}

float Ggx::specularProbability(const glm::vec3& wo) const {
  const Rgb f = fresnel(wo.z);
  const float specular = f.average();
  const float diffuse = (kd_ * (Rgb(1.0f) - f)).average();
  return diffuse > 0.0f ? specular / (specular + diffuse) : 1.0f;
}

// Heitz 2018, "Sampling the GGX Distribution of Visible Normals": in the stretched configuration
// where the roughness is 1, the visible normals project to a disk split into two half-disks, the
// far one foreshortened by the view's inclination.
glm::vec3 Ggx::sampleVisibleNormal(const glm::vec3& wo, glm::vec2 u) const {
  const glm::vec3 v = glm::normalize(glm::vec3(alpha_x_ * wo.x, alpha_y_ * wo.y, wo.z));
  const float len2 = v.x * v.x + v.y * v.y;
  const glm::vec3 t1 = len2 > 0.0f ? glm::vec3(-v.y, v.x, 0.0f) / std::sqrt(len2) : glm::vec3(1, 0, 0);
  const glm::vec3 t2 = glm::cross(v, t1);
  const float r = std::sqrt(u.x);
  const float phi = kTwoPi * u.y;
  const float p1 = r * std::cos(phi);
  float p2 = r * std::sin(phi);
  const float s = 0.5f * (1.0f + v.z);
  p2 = (1.0f - s) * safeSqrt(1.0f - p1 * p1) + s * p2;
  const glm::vec3 n = p1 * t1 + p2 * t2 + safeSqrt(1.0f - p1 * p1 - p2 * p2) * v;
  return glm::normalize(glm::vec3(alpha_x_ * n.x, alpha_y_ * n.y, std::max(n.z, 0.0f)));
}

float Ggx::pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  if (wi.z <= 0.0f || wo.z <= 0.0f) return 0.0f;
  const glm::vec3 h = glm::normalize(wi + wo);
  // Visible-normal density G1(wo) max(0, wo.h) D(h) / cos_o, times the reflection Jacobian 1 / (4 wo.h).
  const float specular = distribution(h) / ((1.0f + lambda(wo)) * 4.0f * wo.z);
  const float p = specularProbability(wo);
  return p * specular + (1.0f - p) * cosineHemispherePdf(wi);
}

std::optional<BsdfSample> Ggx::sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const {
  if (wo.z <= 0.0f) return std::nullopt;
  glm::vec3 wi;
  if (detail::chooseFirst(specularProbability(wo), u.x))
    wi = reflect(wo, sampleVisibleNormal(wo, u));
  else
    wi = squareToCosineHemisphere(u);
  if (wi.z <= 0.0f) return std::nullopt;  // reflected below the horizon: a lost draw
  const float p = pdf(wi, wo, uv);
  if (!(p > 0.0f)) return std::nullopt;
  return BsdfSample{wi, eval(wi, wo, uv) * (wi.z / p), p};
}

std::string Ggx::name() const {
  return "ggx(kd=" + detail::formatRgb(kd_) + ", f0=" + detail::formatRgb(f0_) +
         ", alpha=(" + detail::formatFloat(alpha_x_) + "," + detail::formatFloat(alpha_y_) + "))";
}

BTF_REGISTER_MATERIAL(ggx, {.name = modelFamilyName(ModelFamily::Ggx),
                            .summary = "Lambert diffuse + GGX microfacet specular (alpha, or [alpha_x, alpha_y])",
                            .keys = {"diffuse", "f0", "alpha"},
                            .create = [](const MaterialParams& p) -> std::shared_ptr<const Material> {
                              const glm::vec2 a = p.positivePair("alpha");
                              return std::make_shared<Ggx>(p.rgb("diffuse"), p.rgb("f0"), a.x, a.y);
                            }});

}  // namespace btf
