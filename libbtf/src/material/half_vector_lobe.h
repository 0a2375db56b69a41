// Private helpers of the fitted microfacet models (SGD, ABC): isotropic half-vector distributions
// that are cheap to sample and whose density is known exactly, used as importance-sampling
// proposals. They need not equal the model's own distribution: sample() and pdf() only have to
// agree, so a proposal is chosen for being exact and broad enough, not for matching D perfectly.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

#include "btf/core/math.h"

namespace btf::detail {

// Slope distributions of normals around +z, sampled with density D(h) cos(theta_h) (the
// projected-area normalization, which integrates to 1 over the hemisphere).
enum class SlopeShape { Ggx, Beckmann };

struct HalfVectorLobe {
  SlopeShape shape;
  float alpha;  // slope width: GGX's alpha, or Beckmann's alpha (D ~ exp(-tan^2 / alpha^2))
};

// tan^2 of the polar angle from the components, not from 1 - cos^2, which cancels near the pole.
inline double tan2Theta(const glm::vec3& h) {
  const double xy2 = double(h.x) * h.x + double(h.y) * h.y;
  return xy2 / (double(h.z) * h.z);
}

inline glm::vec3 sampleHalfVector(const HalfVectorLobe& lobe, glm::vec2 u) {
  const double a2 = double(lobe.alpha) * lobe.alpha;
  const double x = std::min(double(u.x), 1.0 - 0x1p-53);
  // Inverse CDFs of tan^2(theta_h): GGX a^2 u / (1 - u), Beckmann -a^2 log(1 - u).
  const double tan2 = lobe.shape == SlopeShape::Ggx ? a2 * x / (1.0 - x) : -a2 * std::log1p(-x);
  const double cos_theta = 1.0 / std::sqrt(1.0 + tan2);
  const double sin_theta = std::sqrt(tan2) * cos_theta;
  const double phi = 2.0 * std::numbers::pi * u.y;
  return {float(sin_theta * std::cos(phi)), float(sin_theta * std::sin(phi)), float(cos_theta)};
}

// Solid-angle density of h from sampleHalfVector: D(h) cos(theta_h).
inline double halfVectorPdf(const HalfVectorLobe& lobe, const glm::vec3& h) {
  if (h.z <= 0.0f) return 0.0;
  const double a2 = double(lobe.alpha) * lobe.alpha;
  const double t = tan2Theta(h) / a2;
  const double cos3 = double(h.z) * h.z * h.z;
  const double shape = lobe.shape == SlopeShape::Ggx ? 1.0 / ((1.0 + t) * (1.0 + t)) : std::exp(-t);
  return shape / (std::numbers::pi * a2 * cos3);
}

}  // namespace btf::detail
