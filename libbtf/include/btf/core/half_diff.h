// Rusinkiewicz's half/difference parameterization (1998), the coordinate system of MERL tables.
// The half vector h = normalize(wi + wo) has angles (theta_h, phi_h); the difference vector is wi
// expressed in a frame where h is the pole: rotate wi by -phi_h about the normal, then by -theta_h
// about the bitangent. Its angles are (theta_d, phi_d).
#pragma once

#include <glm/glm.hpp>

namespace btf {

struct HalfDiff {
  float theta_h = 0;  // [0, pi/2] for directions in the upper hemisphere
  float phi_h = 0;    // [0, 2 pi)
  float theta_d = 0;  // [0, pi/2]
  float phi_d = 0;    // [0, 2 pi)
};

// wi, wo: unit vectors (not both opposite). Angles follow sphericalTheta/sphericalPhi.
HalfDiff toHalfDiff(const glm::vec3& wi, const glm::vec3& wo);

struct DirectionPair {
  glm::vec3 wi;
  glm::vec3 wo;
};
// Inverse of toHalfDiff.
DirectionPair fromHalfDiff(const HalfDiff& hd);

}  // namespace btf
