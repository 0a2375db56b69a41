#include "btf/material/lambert.h"

#include "analytic_support.h"
#include "btf/core/math.h"
#include "btf/core/warp.h"
#include "btf/material/model_family.h"
#include "btf/material/registry.h"

namespace btf {

Lambert::Lambert(Rgb albedo) : albedo_(albedo) { detail::requireDiffuseAlbedo("lambert", "albedo", albedo); }

Rgb Lambert::eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  if (wi.z <= 0.0f || wo.z <= 0.0f) return {};
  return albedo_ * kInvPi;
}

std::optional<BsdfSample> Lambert::sample(const glm::vec3& wo, glm::vec2, glm::vec2 u) const {
  if (wo.z <= 0.0f) return std::nullopt;
  const glm::vec3 wi = squareToCosineHemisphere(u);
  // The disk's rim maps onto the horizon itself, where the material reflects nothing.
  if (wi.z <= 0.0f) return std::nullopt;
  return BsdfSample{wi, albedo_, cosineHemispherePdf(wi)};
}

float Lambert::pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const {
  if (wi.z <= 0.0f || wo.z <= 0.0f) return 0.0f;
  return cosineHemispherePdf(wi);
}

std::string Lambert::name() const { return "lambert(albedo=" + detail::formatRgb(albedo_) + ")"; }

BTF_REGISTER_MATERIAL(lambert, {.name = modelFamilyName(ModelFamily::Lambert),
                                .summary = "ideal diffuse reflector",
                                .keys = {"albedo"},
                                .create = [](const MaterialParams& p) -> std::shared_ptr<const Material> {
                                  return std::make_shared<Lambert>(p.rgb("albedo"));
                                }});

}  // namespace btf
