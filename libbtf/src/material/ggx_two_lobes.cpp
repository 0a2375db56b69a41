#include "btf/material/ggx_two_lobes.h"

#include <algorithm>
#include <cstdio>

#include "btf/material/model_family.h"
#include "btf/material/registry.h"

namespace btf {
namespace {

float meanOf(const Rgb& c) { return (c.r + c.g + c.b) / 3.0f; }

// The smallest share of the draws either lobe keeps.
constexpr float kMinLobeProbability = 0.05f;

}  // namespace

GgxTwoLobes::GgxTwoLobes(Rgb diffuse_albedo, Rgb f0, float alpha, Rgb f0_2, float alpha_2)
    : base_(diffuse_albedo, f0, alpha, alpha), coat_(Rgb(0.0f), f0_2, alpha_2, alpha_2) {
  const float base = meanOf(diffuse_albedo) + meanOf(f0), coat = meanOf(f0_2);
  // Each lobe keeps a share of the draws, so that neither density can vanish where its lobe has
  // energy (a coat of f0 0 reflects nothing, and then its draws only cost variance).
  base_probability_ = base + coat > 0 ? std::clamp(base / (base + coat), kMinLobeProbability, 1.0f - kMinLobeProbability)
                                      : 0.5f;
  char text[224];
  std::snprintf(text, sizeof text, "ggx2(kd=(%g,%g,%g), f0=(%g,%g,%g), alpha=%g, f0_2=(%g,%g,%g), alpha_2=%g)",
                double(diffuse_albedo.r), double(diffuse_albedo.g), double(diffuse_albedo.b), double(f0.r), double(f0.g),
                double(f0.b), double(alpha), double(f0_2.r), double(f0_2.g), double(f0_2.b), double(alpha_2));
  name_ = text;
}

Rgb GgxTwoLobes::eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv) const {
  return base_.eval(wi, wo, uv) + coat_.eval(wi, wo, uv);
}

std::optional<BsdfSample> GgxTwoLobes::sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const {
  // u.x chooses the lobe and is stretched back to [0, 1) for it.
  const bool base = u.x < base_probability_;
  const glm::vec2 v(base ? u.x / base_probability_ : (u.x - base_probability_) / (1.0f - base_probability_), u.y);
  const auto s = (base ? base_ : coat_).sample(wo, uv, glm::min(v, glm::vec2(0.99999994f)));
  if (!s) return std::nullopt;
  const float p = pdf(s->wi, wo, uv);
  if (!(p > 0.0f)) return std::nullopt;
  return BsdfSample{s->wi, eval(s->wi, wo, uv) * (s->wi.z / p), p};
}

float GgxTwoLobes::pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv) const {
  return base_probability_ * base_.pdf(wi, wo, uv) + (1.0f - base_probability_) * coat_.pdf(wi, wo, uv);
}

std::string GgxTwoLobes::name() const { return name_; }

BTF_REGISTER_MATERIAL(ggx2, {.name = modelFamilyName(ModelFamily::Ggx2),
                             .summary = "Lambert diffuse + two GGX lobes (ggx's keys, and f0_2, alpha_2 of the second lobe)",
                             .keys = {"diffuse", "f0", "alpha", "f0_2", "alpha_2"},
                             .create = [](const MaterialParams& p) -> std::shared_ptr<const Material> {
                               return std::make_shared<GgxTwoLobes>(p.rgb("diffuse"), p.rgb("f0"), float(p.positive("alpha")),
                                                                    p.rgb("f0_2"), float(p.positive("alpha_2")));
                             }});

}  // namespace btf
