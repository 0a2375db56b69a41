// Cosine-weighted sampling for the table materials (TabulatedBrdf, OctreeBrdf), which carry no
// sampler of their own: the tabulated samplers of sampling/ are built on top of them, and this
// exact, table-independent density is what they are compared against.
#pragma once

#include <optional>

#include "btf/material/material.h"
#include "btf/core/warp.h"

namespace btf {

// wi from the cosine-weighted hemisphere and weight f cos / pdf; nothing when wo is below the
// horizon or the draw lands on the horizon itself.
inline std::optional<BsdfSample> sampleCosineWeighted(const Material& material, const glm::vec3& wo, glm::vec2 u) {
  if (!(wo.z > 0)) return std::nullopt;
  const glm::vec3 wi = squareToCosineHemisphere(u);
  const float pdf = cosineHemispherePdf(wi);
  if (!(pdf > 0)) return std::nullopt;
  return BsdfSample{wi, material.eval(wi, wo) * (wi.z / pdf), pdf};
}

// The density of sampleCosineWeighted.
inline float cosineWeightedPdf(const glm::vec3& wi, const glm::vec3& wo) {
  return wo.z > 0 ? cosineHemispherePdf(wi) : 0.0f;
}

}  // namespace btf
