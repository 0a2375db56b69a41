#include "btf/material/lafortune.h"

#include "analytic_support.h"
#include "btf/material/model_family.h"
#include "btf/material/registry.h"

namespace btf {

Lafortune::Lafortune(Rgb diffuse_albedo, std::vector<LafortuneLobe> lobes)
    : kd_(diffuse_albedo), lobes_(std::move(lobes)) {
  detail::requireDiffuseAlbedo("lafortune", "diffuse albedo", kd_);
  if (lobes_.size() > kMaxLafortuneLobes)
    throw Error("lafortune: " + std::to_string(lobes_.size()) + " lobes; at most " + std::to_string(kMaxLafortuneLobes));
  for (std::size_t i = 0; i < lobes_.size(); ++i) {
    const LafortuneLobe& lobe = lobes_[i];
    const std::string which = "lobe " + std::to_string(i);
    detail::requireAlbedo("lafortune", (which + " rho").c_str(), lobe.rho);
    detail::requireNonNegative("lafortune", (which + " exponent").c_str(), lobe.exponent);
    const float max_c = std::max({std::abs(lobe.c.x), std::abs(lobe.c.y), std::abs(lobe.c.z)});
    if (!std::isfinite(lobe.c.x + lobe.c.y + lobe.c.z) || !(max_c > 0.0f))
      throw Error("lafortune: " + which + " coefficients c must be finite and not all zero, got (" +
                  detail::formatFloat(lobe.c.x) + "," + detail::formatFloat(lobe.c.y) + "," +
                  detail::formatFloat(lobe.c.z) + ")");
    inv_max_c_.push_back(1.0f / max_c);
  }
}

Rgb Lafortune::eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  if (wi.z <= 0.0f || wo.z <= 0.0f) return {};
  Rgb f = kd_ * kInvPi;
  // wi * wo first: the products commute exactly, so f is reciprocal to the bit.
  const glm::vec3 product = wi * wo;
  for (std::size_t i = 0; i < lobes_.size(); ++i) {
    const LafortuneLobe& lobe = lobes_[i];
    // Scaling by 1/max|c| before the power keeps huge or tiny c from overflowing.
    const float d = glm::dot(lobe.c, product) * inv_max_c_[i];
    if (d > 0.0f) f += lobe.rho * ((lobe.exponent + 2.0f) * kInv2Pi * std::pow(d, lobe.exponent));
  }
  return f;
}

float Lafortune::lobeWeight(std::size_t i, const glm::vec3& wo, float& axis_length) const {
  axis_length = glm::length(lobes_[i].c * wo);
  // A lobe whose axis vanishes (e.g. cz = 0 at normal view) reflects nothing and draws nothing.
  if (!(axis_length > 0.0f)) return 0.0f;
  return lobes_[i].rho.average() * std::pow(axis_length * inv_max_c_[i], lobes_[i].exponent);
}

float Lafortune::pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  if (wi.z <= 0.0f || wo.z <= 0.0f) return 0.0f;
  const float diffuse = kd_.average();
  float total = diffuse, lobes = 0.0f;
  for (std::size_t i = 0; i < lobes_.size(); ++i) {
    float length;
    const float weight = lobeWeight(i, wo, length);
    if (weight <= 0.0f) continue;
    total += weight;
    lobes += weight * detail::lobePdf(glm::dot(wi, lobes_[i].c * wo) / length, lobes_[i].exponent);
  }
  // A black material still draws (cosine) directions, with zero weight.
  if (!(total > 0.0f)) return cosineHemispherePdf(wi);
  return (diffuse * cosineHemispherePdf(wi) + lobes) / total;
}

std::optional<BsdfSample> Lafortune::sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const {
  if (wo.z <= 0.0f) return std::nullopt;
  const float diffuse = kd_.average();
  float total = diffuse;
  for (std::size_t i = 0; i < lobes_.size(); ++i) {
    float length;
    total += lobeWeight(i, wo, length);
  }
  // Choose a component with u.x scaled to [0, total), then rescale u.x within the chosen one.
  float x = u.x * total;
  glm::vec3 wi;
  if (!(total > 0.0f) || x < diffuse) {
    if (total > 0.0f) u.x = std::min(x / diffuse, 0x1.fffffep-1f);
    wi = squareToCosineHemisphere(u);
  } else {
    x -= diffuse;
    std::size_t chosen = lobes_.size();
    float chosen_weight = 0.0f, chosen_length = 0.0f;
    for (std::size_t i = 0; i < lobes_.size(); ++i) {
      float length;
      const float weight = lobeWeight(i, wo, length);
      if (weight <= 0.0f) continue;
      chosen = i;  // the last lobe with weight also absorbs rounding at the top of the range
      chosen_weight = weight;
      chosen_length = length;
      if (x < weight) break;
      x -= weight;
    }
    if (chosen == lobes_.size()) return std::nullopt;
    u.x = std::clamp(x / chosen_weight, 0.0f, 0x1.fffffep-1f);
    wi = detail::sampleLobeAround(lobes_[chosen].c * wo / chosen_length, lobes_[chosen].exponent, u);
  }
  if (wi.z <= 0.0f) return std::nullopt;  // lobe draws past the horizon are lost draws
  const float p = pdf(wi, wo, uv);
  if (!(p > 0.0f)) return std::nullopt;
  return BsdfSample{wi, eval(wi, wo, uv) * (wi.z / p), p};
}

bool Lafortune::isAnisotropic() const {
  for (const LafortuneLobe& lobe : lobes_)
    if (lobe.c.x != lobe.c.y) return true;
  return false;
}

std::string Lafortune::name() const {
  std::string s = "lafortune(kd=" + detail::formatRgb(kd_);
  for (const LafortuneLobe& lobe : lobes_)
    s += ", lobe(rho=" + detail::formatRgb(lobe.rho) + ", c=(" + detail::formatFloat(lobe.c.x) + "," +
         detail::formatFloat(lobe.c.y) + "," + detail::formatFloat(lobe.c.z) + "), n=" +
         detail::formatFloat(lobe.exponent) + ")";
  return s + ")";
}

BTF_REGISTER_MATERIAL(lafortune, {.name = modelFamilyName(ModelFamily::Lafortune),
                                  .summary = "Lambert diffuse + generalized cosine lobes",
                                  .keys = {"diffuse", "lobes"},
                                  .create = [](const MaterialParams& p) -> std::shared_ptr<const Material> {
                                    std::vector<LafortuneLobe> lobes;
                                    for (const MaterialParams& lobe : p.list("lobes")) {
                                      lobe.allowOnly({"rho", "c", "exponent"});
                                      lobes.push_back({lobe.rgb("rho"), lobe.vec3("c"),
                                                       float(lobe.number("exponent", 0, 1e6))});
                                    }
                                    return std::make_shared<Lafortune>(p.rgb("diffuse"), std::move(lobes));
                                  }});

}  // namespace btf
