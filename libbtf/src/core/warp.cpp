#include "btf/core/warp.h"

#include "btf/core/math.h"

namespace btf {

glm::vec2 squareToConcentricDisk(glm::vec2 u) {
  const glm::vec2 p = 2.0f * u - glm::vec2(1.0f);
  if (p.x == 0 && p.y == 0) return {0, 0};
  float r, theta;
  if (std::abs(p.x) > std::abs(p.y)) {
    r = p.x;
    theta = 0.25f * kPi * (p.y / p.x);
  } else {
    r = p.y;
    theta = kHalfPi - 0.25f * kPi * (p.x / p.y);
  }
  return r * glm::vec2(std::cos(theta), std::sin(theta));
}

glm::vec3 squareToCosineHemisphere(glm::vec2 u) {
  const glm::vec2 d = squareToConcentricDisk(u);
  return {d.x, d.y, safeSqrt(1.0f - d.x * d.x - d.y * d.y)};
}
float cosineHemispherePdf(const glm::vec3& w) { return w.z > 0 ? w.z * kInvPi : 0.0f; }

glm::vec3 squareToUniformHemisphere(glm::vec2 u) {
  const float z = u.x;
  const float r = safeSqrt(1.0f - z * z);
  const float phi = kTwoPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}
float uniformHemispherePdf(const glm::vec3& w) { return w.z > 0 ? kInv2Pi : 0.0f; }

glm::vec3 squareToUniformSphere(glm::vec2 u) {
  const float z = 1.0f - 2.0f * u.x;
  const float r = safeSqrt(1.0f - z * z);
  const float phi = kTwoPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi), z};
}
float uniformSpherePdf() { return 0.25f * kInvPi; }

glm::vec3 squareToCosinePowerHemisphere(glm::vec2 u, float exponent) {
  const float cos_theta = std::pow(1.0f - u.x, 1.0f / (exponent + 1.0f));
  const float sin_theta = safeSqrt(1.0f - cos_theta * cos_theta);
  const float phi = kTwoPi * u.y;
  return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}
float cosinePowerHemispherePdf(const glm::vec3& w, float exponent) {
  return w.z > 0 ? (exponent + 1.0f) * kInv2Pi * std::pow(w.z, exponent) : 0.0f;
}

}  // namespace btf
