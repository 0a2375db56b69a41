// Constants and small helpers on GLM vectors; directions are unit vectors in the local shading
// frame (+z is the normal, theta measured from +z, phi from +x towards +y).
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace btf {

inline constexpr float kPi = std::numbers::pi_v<float>;
inline constexpr float kInvPi = std::numbers::inv_pi_v<float>;
inline constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;
inline constexpr float kHalfPi = 0.5f * std::numbers::pi_v<float>;
inline constexpr float kInv2Pi = 0.5f * std::numbers::inv_pi_v<float>;

inline float cosTheta(const glm::vec3& w) { return w.z; }
inline float absCosTheta(const glm::vec3& w) { return std::abs(w.z); }
inline bool sameHemisphere(const glm::vec3& a, const glm::vec3& b) { return a.z * b.z > 0.0f; }

// sqrt and acos that tolerate rounding just outside their domain.
inline float safeSqrt(float x) { return std::sqrt(std::max(x, 0.0f)); }
inline float safeAcos(float x) { return std::acos(std::clamp(x, -1.0f, 1.0f)); }

// Unit vector for spherical angles (theta from +z, phi from +x).
inline glm::vec3 sphericalDirection(float theta, float phi) {
  const float sin_theta = std::sin(theta);
  return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), std::cos(theta)};
}
// Polar angle in [0, pi] of a vector; atan2 rather than acos, which loses half the digits near
// the pole.
inline float sphericalTheta(const glm::vec3& w) { return std::atan2(std::hypot(w.x, w.y), w.z); }
// Azimuth in [0, 2 pi) of a vector.
inline float sphericalPhi(const glm::vec3& w) {
  const float phi = std::atan2(w.y, w.x);
  return phi < 0.0f ? phi + kTwoPi : phi;
}

// Mirror direction of w about the normal n (both pointing away from the surface).
inline glm::vec3 reflect(const glm::vec3& w, const glm::vec3& n) { return 2.0f * glm::dot(w, n) * n - w; }

}  // namespace btf
