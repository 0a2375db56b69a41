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
  // The same for a w known to lie in triangle t (t = locate(w) >= 0): what stencil(w) returns.
  Stencil stencilIn(int t, const glm::vec3& w) const;

  // The triangles over the upper hemisphere (the sampling cells): their measured directions (a
  // virtual one given as the measured direction it stands for) and solid angles, which sum to 2 pi.
  int triangleCount() const { return int(triangles_.size()); }
  const std::array<int, 3>& triangleDirections(int t) const { return triangles_[std::size_t(t)].direction; }
  float triangleSolidAngle(int t) const { return triangles_[std::size_t(t)].solid_angle; }
  // cos theta at the triangle's centroid direction (for f cos weights).
  float triangleCosTheta(int t) const { return triangles_[std::size_t(t)].cos_theta; }
  // The triangle whose cone holds w (z > 0); -1 for no triangle (w below the horizon).
  int locate(const glm::vec3& w) const;
  // locate(w) == t, without the search when w lies well inside t (every barycentric coordinate
  // above a thousandth of their sum): a point that far from t's edges is in no other triangle's
  // cone even with the coordinates' float rounding, since the triangles' interiors are disjoint.
  // Nearer the edges, where rounding decides, it is locate(w) == t itself.
  bool locatesIn(int t, const glm::vec3& w) const;
  // A direction uniformly distributed (in solid angle) in triangle t (Arvo 1995, "Stratified
  // sampling of spherical triangles"), u in [0, 1)^2.
  glm::vec3 sampleTriangle(int t, glm::vec2 u) const;
  // The measured direction nearest to w (the first in index order among equals).
  int nearest(const glm::vec3& w) const;
  int directionCount() const { return int(directions_.size()); }

  // Sampling the triangles through their corners (btf_material.h). Triangle t has the weight
  // w_t = max(cos theta at its centre, 0) x solid angle / 3 per corner; a measured direction d
  // collects the weights of the corners it is (directionWeight(d) = W_d, a virtual corner counting
  // for the direction it stands for), and its triangles come with the CDF of their shares
  // (incidentTriangles(d), incidentCdf(d): count + 1 entries). Choosing d with probability
  // proportional to f_d W_d, then one of its triangles from that CDF, draws triangle t with
  // probability w_t (f_a + f_b + f_c) / sum_d f_d W_d over its corners a, b, c: the mean of its
  // corners times cos x solid angle, without a table per set of values f. The density in solid
  // angle of that draw is triangleDensityFactor(t) (f_a + f_b + f_c) / sum_d f_d W_d, with the
  // factor max(cos theta, 0) / 3.
  float directionWeight(int d) const { return direction_weight_[std::size_t(d)]; }
  std::span<const int> incidentTriangles(int d) const {
    return {incident_triangle_.data() + incident_start_[std::size_t(d)],
            std::size_t(incident_start_[std::size_t(d) + 1] - incident_start_[std::size_t(d)])};
  }
  std::span<const float> incidentCdf(int d) const {
    return {incident_cdf_.data() + incident_start_[std::size_t(d)] + std::size_t(d),
            std::size_t(incident_start_[std::size_t(d) + 1] - incident_start_[std::size_t(d)]) + 1};
  }
  float triangleDensityFactor(int t) const { return triangles_[std::size_t(t)].density_factor; }

 private:
  struct Triangle {
    std::array<glm::vec3, 3> vertex;  // unit vectors (virtual ones included)
    std::array<int, 3> direction;     // measured direction of each vertex
    float solid_angle, cos_theta, density_factor;
    double corner_angle, sin_corner, cos_corner;  // interior angle at vertex 0 (Arvo's alpha), its sin and cos
  };
  // w's coordinates in the cone of triangle t's vertices (unnormalised barycentrics): all
  // non-negative exactly when w lies in that cone. The one place inside(), locatesIn() and
  // stencilIn() read inverse_.
  glm::vec3 barycentric(int t, const glm::vec3& w) const { return inverse_[std::size_t(t)] * w; }
  bool inside(int t, const glm::vec3& w) const;
  // locate()'s and nearest()'s search grid: cells equal in cos theta and phi, each with the
  // triangles that may meet it and the directions that may be nearest to a point in it
  // (ascending; flat lists, cell c's from start[c] to start[c + 1]).
  static constexpr int kZCells = 32, kPhiCells = 64;
  static int cellOf(const glm::vec3& w);
  void buildCells();
  void buildIncidence();
  int nearestOf(const glm::vec3& w, const int* candidates, std::size_t count) const;

  std::vector<glm::vec3> directions_;
  std::vector<Triangle> triangles_;
  std::vector<glm::mat3> inverse_;  // per triangle, of the matrix of columns vertex[0..2] (locate's one read)
  std::vector<int> cell_start_, cell_triangles_, nearest_start_, nearest_directions_;
  std::vector<float> direction_weight_, incident_cdf_;
  std::vector<int> incident_start_, incident_triangle_;
};

}  // namespace btf
