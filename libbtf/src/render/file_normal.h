// A normal as a mesh file gives it, for TriangleMesh::normals: unit length, or zero where the file's
// vector has no direction (zero, NaN or infinite). A zero normal adds nothing to the interpolated
// shading normal (scene.cpp), which falls back to the geometric one where all three are zero.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

namespace btf::render {

inline glm::vec3 fileNormal(const glm::vec3& n) {
  const float length = glm::length(n);
  return length > 0 && std::isfinite(length) ? n / length : glm::vec3(0.0f);
}

}  // namespace btf::render
