// Continuous MERL table coordinates of a direction pair, shared by the materials that look up a
// MERL-layout table (TabulatedBrdf, OctreeBrdf) so that both read the same cell for a pair.
#pragma once

#include <glm/glm.hpp>

#include <cmath>

#include "btf/core/fast_atan.h"
#include "btf/core/math.h"
#include "btf/io/merl.h"

namespace btf {

// atan2(y, x) for y >= 0, in [0, pi]: std::atan2/std::acos would otherwise dominate a lookup.
inline float atan2UpperHalf(float y, float x) { return kTwoPi * fastAtan2Turns(y, x); }

// Continuous table coordinates (u_h, u_d, u_p) of a direction pair above the horizon: the same
// mapping as MerlTable::*Coordinate, computed from dot and cross products without normalizing.
struct TableCoordinates {
  float u_h, u_d, u_p;
};

inline TableCoordinates tableCoordinates(const glm::vec3& wi, const glm::vec3& wo) {
  const glm::vec3 s = wi + wo;  // along the half vector; s.z > 0 above the horizon
  const float sxy2 = s.x * s.x + s.y * s.y;
  const float theta_h = atan2UpperHalf(std::sqrt(sxy2), s.z);
  // theta_d is half the angle between wi and wo.
  const float theta_d = atan2UpperHalf(glm::length(glm::cross(wi, wo)), 1.0f + glm::dot(wi, wo));
  // phi_d is the azimuth of wi in the frame rotated so that h is the pole (see half_diff.h). With
  // h = s/|s| and sin^2(theta_h) = |h_xy|^2, that frame's x and y components of wi, times
  // sin(theta_h) (which leaves the azimuth unchanged), are:
  const float inv_len2 = 1.0f / (sxy2 + s.z * s.z);
  const float inv_len = std::sqrt(inv_len2);
  const glm::vec3 h = s * inv_len;
  const float hxy2 = sxy2 * inv_len2;
  float dx, dy;
  if (hxy2 > 1e-12f) {
    dx = h.z * (h.x * wi.x + h.y * wi.y) - hxy2 * wi.z;
    dy = h.x * wi.y - h.y * wi.x;
  } else {  // h at the pole: phi_h = 0 by convention, so d = wi.
    dx = wi.x;
    dy = wi.y;
  }
  // Fold onto [0, pi): the line through d, as reciprocity allows.
  if (dy < 0 || (dy == 0 && dx < 0)) {
    dx = -dx;
    dy = -dy;
  }
  const float phi_d = atan2UpperHalf(dy, dx);
  constexpr float kDegPerRad = 180.0f * kInvPi;
  return {std::sqrt(theta_h * (2.0f * kInvPi)) * float(MerlTable::kThetaHalfRes), theta_d * kDegPerRad, phi_d * kDegPerRad};
}

}  // namespace btf
