#include "btf/core/half_diff.h"

#include "btf/core/math.h"

namespace btf {
namespace {

// Rotation about +z by angle a (right-handed).
glm::vec3 rotateZ(const glm::vec3& v, float a) {
  const float c = std::cos(a), s = std::sin(a);
  return {c * v.x - s * v.y, s * v.x + c * v.y, v.z};
}
// Rotation about +y by angle a (right-handed).
glm::vec3 rotateY(const glm::vec3& v, float a) {
  const float c = std::cos(a), s = std::sin(a);
  return {c * v.x + s * v.z, v.y, -s * v.x + c * v.z};
}

}  // namespace

HalfDiff toHalfDiff(const glm::vec3& wi, const glm::vec3& wo) {
  const glm::vec3 h = glm::normalize(wi + wo);
  HalfDiff hd;
  hd.theta_h = sphericalTheta(h);
  hd.phi_h = sphericalPhi(h);
  const glm::vec3 d = rotateY(rotateZ(wi, -hd.phi_h), -hd.theta_h);
  hd.theta_d = sphericalTheta(d);
  hd.phi_d = sphericalPhi(d);
  return hd;
}

DirectionPair fromHalfDiff(const HalfDiff& hd) {
  const glm::vec3 h = sphericalDirection(hd.theta_h, hd.phi_h);
  const glm::vec3 d = sphericalDirection(hd.theta_d, hd.phi_d);
  const glm::vec3 wi = rotateZ(rotateY(d, hd.theta_h), hd.phi_h);
  return {wi, reflect(wi, h)};
}

}  // namespace btf
