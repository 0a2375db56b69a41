#include "btf/core/frame.h"

#include <cmath>

namespace btf {

Frame Frame::fromNormal(const glm::vec3& n) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  return {glm::vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x),
          glm::vec3(b, sign + n.y * n.y * a, -n.y), n};
}

Frame Frame::fromNormalTangent(const glm::vec3& n, const glm::vec3& tangent) {
  const glm::vec3 s = tangent - glm::dot(tangent, n) * n;
  const float len = glm::length(s);
  if (!(len > 1e-6f)) return fromNormal(n);
  const glm::vec3 s_unit = s / len;
  return {s_unit, glm::cross(n, s_unit), n};
}

}  // namespace btf
