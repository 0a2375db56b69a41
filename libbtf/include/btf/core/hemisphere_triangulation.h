// Measured directions on the upper hemisphere as a spherical Delaunay triangulation: barycentric
// interpolation between them and piecewise-constant sampling over its triangles. What BTF
// materials use on direction sets without rings of constant elevation (the Bonn dome, scattered
// and view-dependent lists; material/btf_material.h).
//
// The triangulation is the convex hull of the unit vectors (on a sphere, the hull's faces are the
// Delaunay triangles), computed by Qhull (Debian libqhull-dev). The hull also takes a ring of
// virtual directions on the horizon and the south pole, so that its upper faces cover the whole
// hemisphere: a virtual horizon direction stands for the measured direction nearest to it, which
// extends the data to the horizon as a constant along the elevation, as the 81-direction rings
// do beyond their last ring.
//
// Interpolation: w lies in the cone of one triangle (A, B, C); its weights are the solution of
// w = a A + b B + c C, normalized to sum 1 (the gnomonic barycentric coordinates: linear on the
// triangle's plane, exactly 1 at a vertex, so measured directions return the data exactly).
#pragma once

#include <array>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace btf {

class HemisphereTriangulation {
 public:
  // Virtual directions on the horizon (every 360 / kHorizonPoints degrees).
  static constexpr int kHorizonPoints = 36;

  // Unit directions with z > 0. Throws btf::Error when there are none or Qhull fails.
  explicit HemisphereTriangulation(std::span<const glm::vec3> directions);

  // Interpolation weights of w (z > 0): up to three measured directions and weights summing to 1.
  struct Stencil {
    std::array<int, 3> index{};
    std::array<float, 3> weight{};
    int count = 0;
  };
  Stencil stencil(const glm::vec3& w) const;

  // The triangles over the upper hemisphere (the sampling cells): their measured directions (a
  // virtual one given as the measured direction it stands for) and solid angles, which sum to 2 pi.
  int triangleCount() const { return int(triangles_.size()); }
  const std::array<int, 3>& triangleDirections(int t) const { return triangles_[std::size_t(t)].direction; }
  float triangleSolidAngle(int t) const { return triangles_[std::size_t(t)].solid_angle; }
  // cos theta at the triangle's centroid direction (for f cos weights).
  float triangleCosTheta(int t) const { return triangles_[std::size_t(t)].cos_theta; }
  // The triangle whose cone holds w (z > 0); -1 for no triangle (w below the horizon).
  int locate(const glm::vec3& w) const;
  // A direction uniformly distributed (in solid angle) in triangle t (Arvo 1995, "Stratified
  // sampling of spherical triangles"), u in [0, 1)^2.
  glm::vec3 sampleTriangle(int t, glm::vec2 u) const;
  // The measured direction nearest to w.
  int nearest(const glm::vec3& w) const;
  int directionCount() const { return int(directions_.size()); }

 private:
  struct Triangle {
    std::array<glm::vec3, 3> vertex;  // unit vectors (virtual ones included)
    std::array<int, 3> direction;     // measured direction of each vertex
    glm::mat3 inverse;                // of the matrix of columns vertex[0..2]
    float solid_angle, cos_theta;
  };
  bool inside(int t, const glm::vec3& w) const;
  // locate()'s search grid: cells equal in cos theta and phi, each with the triangles that may
  // meet it (ascending).
  static constexpr int kZCells = 16, kPhiCells = 32;
  static int cellOf(const glm::vec3& w);
  void buildCells();

  std::vector<glm::vec3> directions_;
  std::vector<Triangle> triangles_;
  std::vector<std::vector<int>> cells_;
};

}  // namespace btf
