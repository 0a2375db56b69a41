// Orthonormal shading frame: converts between world space and the local frame where +z = normal.
#pragma once

#include <glm/glm.hpp>

namespace btf {

struct Frame {
  glm::vec3 s{1, 0, 0};  // tangent (local +x)
  glm::vec3 t{0, 1, 0};  // bitangent (local +y)
  glm::vec3 n{0, 0, 1};  // normal (local +z)

  Frame() = default;
  Frame(const glm::vec3& s_, const glm::vec3& t_, const glm::vec3& n_) : s(s_), t(t_), n(n_) {}

  // A frame around a unit normal, continuous except at one pole (Duff et al. 2017, "Building an
  // Orthonormal Basis, Revisited").
  static Frame fromNormal(const glm::vec3& n);
  // A frame whose tangent is the part of `tangent` orthogonal to n (for anisotropic materials).
  static Frame fromNormalTangent(const glm::vec3& n, const glm::vec3& tangent);

  glm::vec3 toLocal(const glm::vec3& w) const { return {glm::dot(w, s), glm::dot(w, t), glm::dot(w, n)}; }
  glm::vec3 toWorld(const glm::vec3& w) const { return w.x * s + w.y * t + w.z * n; }
};

}  // namespace btf
