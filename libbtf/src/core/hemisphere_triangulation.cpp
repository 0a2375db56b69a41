#include "btf/core/hemisphere_triangulation.h"

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>

#include "btf/core/error.h"
#include "btf/core/fast_atan.h"
#include "btf/core/math.h"

namespace btf {
namespace {

// Interior angle at vertex a of the spherical triangle (a, b, c): between the great circles a-b, a-c.
double cornerAngle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 nb = glm::cross(a, b), nc = glm::cross(a, c);
  const double lb = glm::length(nb), lc = glm::length(nc);
  if (!(lb > 0) || !(lc > 0)) return 0.0;
  return std::acos(std::clamp(glm::dot(nb, nc) / (lb * lc), -1.0, 1.0));
}

// The hull's faces as vertex index triples (Qhull, triangulated output).
std::vector<std::array<int, 3>> hullFaces(std::vector<double>& points) {
  qhT qh_storage;
  qhT* qh = &qh_storage;
  QHULL_LIB_CHECK
  qh_zero(qh, nullptr);
  // Qhull reports on a stream; a failure is reported below by its exit code alone.
  std::unique_ptr<FILE, int (*)(FILE*)> quiet(std::fopen("/dev/null", "w"), &std::fclose);
  char options[] = "qhull Qt";
  const int exit_code =
      qh_new_qhull(qh, 3, int(points.size() / 3), points.data(), False, options, nullptr, quiet.get());
  std::vector<std::array<int, 3>> faces;
  if (exit_code == 0) {
    facetT* facet;
    FORALLfacets {
      std::array<int, 3> f{};
      int k = 0;
      vertexT *vertex, **vertexp;
      FOREACHvertex_(facet->vertices) {
        if (k < 3) f[std::size_t(k)] = qh_pointid(qh, vertex->point);
        ++k;
      }
      if (k == 3) faces.push_back(f);
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong, totlong;
  qh_memfreeshort(qh, &curlong, &totlong);
  if (exit_code != 0) throw Error("the triangulation of the measured directions failed (Qhull exit code " +
                                  std::to_string(exit_code) + ")");
  return faces;
}

}  // namespace

HemisphereTriangulation::HemisphereTriangulation(std::span<const glm::vec3> directions)
    : directions_(directions.begin(), directions.end()) {
  if (directions_.empty()) throw Error("a direction triangulation needs at least one direction");
  // Hull points: the directions, the virtual horizon ring, the south pole.
  const int n = int(directions_.size());
  std::vector<glm::vec3> vertex(directions_);
  std::vector<int> stands_for(directions_.size());
  for (int i = 0; i < n; ++i) stands_for[std::size_t(i)] = i;
  for (int k = 0; k < kHorizonPoints; ++k) {
    const float phi = kTwoPi * (float(k) + 0.5f) / float(kHorizonPoints);
    const glm::vec3 h(std::cos(phi), std::sin(phi), 0.0f);
    vertex.push_back(h);
    stands_for.push_back(nearest(h));
  }
  vertex.emplace_back(0.0f, 0.0f, -1.0f);
  stands_for.push_back(-1);
  std::vector<double> points;
  for (const glm::vec3& v : vertex) points.insert(points.end(), {double(v.x), double(v.y), double(v.z)});
  for (const std::array<int, 3>& f : hullFaces(points)) {
    Triangle t;
    bool below = false;
    for (std::size_t k = 0; k < 3; ++k) {
      t.vertex[k] = vertex[std::size_t(f[k])];
      t.direction[k] = stands_for[std::size_t(f[k])];
      below = below || t.direction[k] < 0;
    }
    if (below) continue;  // a face of the south pole's cone
    const glm::dvec3 a(t.vertex[0]), b(t.vertex[1]), c(t.vertex[2]);
    const double area = cornerAngle(a, b, c) + cornerAngle(b, c, a) + cornerAngle(c, a, b) - std::numbers::pi;
    const glm::mat3 m(t.vertex[0], t.vertex[1], t.vertex[2]);
    if (!(area > 1e-12) || !(std::abs(glm::determinant(m)) > 1e-12f)) continue;  // degenerate sliver
    t.solid_angle = float(area);
    t.cos_theta = float(glm::normalize(a + b + c).z);
    t.density_factor = std::max(t.cos_theta, 0.0f) / 3.0f;
    t.corner_angle = cornerAngle(a, b, c);
    t.sin_corner = std::sin(t.corner_angle);
    t.cos_corner = std::cos(t.corner_angle);
    triangles_.push_back(t);
    inverse_.push_back(glm::inverse(m));
  }
  if (triangles_.empty()) throw Error("the triangulation of the measured directions has no triangle");
  buildCells();
  buildIncidence();
}

int HemisphereTriangulation::nearestOf(const glm::vec3& w, const int* candidates, std::size_t count) const {
  int best = candidates ? candidates[0] : 0;
  float best_dot = -2.0f;
  for (std::size_t k = 0; k < count; ++k) {
    const int i = candidates ? candidates[k] : int(k);
    const float d = glm::dot(directions_[std::size_t(i)], w);
    if (d > best_dot) best_dot = d, best = i;
  }
  return best;
}

int HemisphereTriangulation::nearest(const glm::vec3& w) const {
  // Among the cell's candidates, which hold every direction that can be nearest to a point of
  // the cell (buildCells), in index order: the full scan's answer. Below the horizon (and while
  // the cells are being built) the full scan.
  if (nearest_start_.empty() || !(w.z >= 0.0f)) return nearestOf(w, nullptr, directions_.size());
  const int c = cellOf(w);
  const int begin = nearest_start_[std::size_t(c)], end = nearest_start_[std::size_t(c) + 1];
  return nearestOf(w, nearest_directions_.data() + begin, std::size_t(end - begin));
}

int HemisphereTriangulation::cellOf(const glm::vec3& w) {
  const int iz = std::clamp(int(w.z * float(kZCells)), 0, kZCells - 1);
  // The fast arctangent's error (fast_atan.h) is far inside the cells' margins.
  float turns = fastAtan2Turns(w.y, w.x);
  if (turns < 0.0f) turns += 1.0f;
  const int ip = std::clamp(int(turns * float(kPhiCells)), 0, kPhiCells - 1);
  return iz * kPhiCells + ip;
}

void HemisphereTriangulation::buildCells() {
  // Each triangle lies in the cap around its centre that holds its corners (a spherical triangle
  // within a cap narrower than a hemisphere lies in it); each cell lies in the cap around its
  // centre that holds its corners and edge midpoints, widened a little for the curved edges. A
  // triangle is a candidate of every cell whose cap meets its own.
  struct Cap {
    glm::vec3 centre;
    float radius;
  };
  auto capOf = [](const std::vector<glm::vec3>& points) {
    glm::vec3 sum(0.0f);
    for (const glm::vec3& p : points) sum += p;
    Cap cap{glm::normalize(sum), 0.0f};
    for (const glm::vec3& p : points) cap.radius = std::max(cap.radius, std::acos(std::clamp(glm::dot(cap.centre, p), -1.0f, 1.0f)));
    return cap;
  };
  std::vector<Cap> triangle_caps;
  for (const Triangle& t : triangles_) triangle_caps.push_back(capOf({t.vertex[0], t.vertex[1], t.vertex[2]}));
  auto angle = [](const glm::vec3& a, const glm::vec3& b) { return std::acos(std::clamp(glm::dot(a, b), -1.0f, 1.0f)); };
  cell_start_.assign(1, 0);
  cell_triangles_.clear();
  std::vector<int> nearest_start(1, 0), nearest_directions;
  for (int iz = 0; iz < kZCells; ++iz)
    for (int ip = 0; ip < kPhiCells; ++ip) {
      std::vector<glm::vec3> points;
      for (const float fz : {0.0f, 0.5f, 1.0f})
        for (const float fp : {0.0f, 0.5f, 1.0f}) {
          const float z = std::min((float(iz) + fz) / float(kZCells), 1.0f), phi = kTwoPi * (float(ip) + fp) / float(kPhiCells);
          const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
          points.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
        }
      Cap cell = capOf(points);
      cell.radius += 0.02f;
      std::vector<int> candidates;
      for (int t = 0; t < triangleCount(); ++t) {
        const Cap& c = triangle_caps[std::size_t(t)];
        if (c.radius >= 0.5f * kPi || angle(c.centre, cell.centre) <= c.radius + cell.radius + 1e-3f) candidates.push_back(t);
      }
      // Most overlap first (counted on 8 x 8 points of the cell; then by index), so that locate
      // mostly stops at its first block of candidates.
      std::vector<int> overlap(candidates.size(), 0);
      for (int jz = 0; jz < 8; ++jz)
        for (int jp = 0; jp < 8; ++jp) {
          const float z = (float(iz) + (float(jz) + 0.5f) / 8.0f) / float(kZCells);
          const float phi = kTwoPi * (float(ip) + (float(jp) + 0.5f) / 8.0f) / float(kPhiCells);
          const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
          const glm::vec3 p(r * std::cos(phi), r * std::sin(phi), z);
          for (std::size_t k = 0; k < candidates.size(); ++k) overlap[k] += int(inside(candidates[k], p));
        }
      std::vector<std::size_t> order(candidates.size());
      for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
      std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return overlap[a] > overlap[b]; });
      for (const std::size_t k : order) cell_triangles_.push_back(candidates[k]);
      cell_start_.push_back(int(cell_triangles_.size()));
      // The direction n nearest to a point p of the cell is at most angle(p, m) <= radius + d from
      // p, with m nearest to the centre at angle d; so n is within d + 2 radius of the centre.
      float d = 4.0f;
      for (const glm::vec3& m : directions_) d = std::min(d, angle(m, cell.centre));
      for (int i = 0; i < directionCount(); ++i)
        if (angle(directions_[std::size_t(i)], cell.centre) <= d + 2.0f * cell.radius + 1e-3f) nearest_directions.push_back(i);
      nearest_start.push_back(int(nearest_directions.size()));
    }
  nearest_start_ = std::move(nearest_start);
  nearest_directions_ = std::move(nearest_directions);
}

void HemisphereTriangulation::buildIncidence() {
  const std::size_t n = directions_.size();
  // Per direction, its corners' triangles (a triangle twice where two of its corners stand for
  // it) and their weights, accumulated in double.
  std::vector<std::vector<std::pair<int, double>>> corners(n);
  for (int t = 0; t < triangleCount(); ++t) {
    const Triangle& tri = triangles_[std::size_t(t)];
    const double w = double(std::max(tri.cos_theta, 0.0f)) * double(tri.solid_angle) / 3.0;
    for (const int d : tri.direction) {
      auto& list = corners[std::size_t(d)];
      if (!list.empty() && list.back().first == t) list.back().second += w;
      else list.emplace_back(t, w);
    }
  }
  incident_start_.assign(1, 0);
  incident_triangle_.clear();
  incident_cdf_.clear();
  direction_weight_.assign(n, 0.0f);
  for (std::size_t d = 0; d < n; ++d) {
    double sum = 0;
    for (const auto& [t, w] : corners[d]) sum += w;
    direction_weight_[d] = float(sum);
    // The CDF of the shares (uniform where the direction has no weight: it is then never chosen).
    incident_cdf_.push_back(0.0f);
    double running = 0;
    for (std::size_t k = 0; k < corners[d].size(); ++k) {
      running += corners[d][k].second;
      incident_triangle_.push_back(corners[d][k].first);
      const bool last = k + 1 == corners[d].size();
      incident_cdf_.push_back(last ? 1.0f : sum > 0 ? float(running / sum) : float(double(k + 1) / double(corners[d].size())));
    }
    incident_start_.push_back(int(incident_triangle_.size()));
  }
}

bool HemisphereTriangulation::inside(int t, const glm::vec3& w) const {
  const glm::vec3 b = barycentric(t, w);
  // & rather than &&: no branch per comparison (which one fails is random for random w).
  return (b.x >= 0.0f) & (b.y >= 0.0f) & (b.z >= 0.0f) & (b.x + b.y + b.z > 0.0f);
}

int HemisphereTriangulation::locate(const glm::vec3& w) const {
  // The first triangle that holds w among its cell's candidates (in the cell's order: most
  // overlap first), else (a direction the caps' margins missed) the first in index order among
  // all. A function of w alone, the same on every thread and for every order of queries, so that
  // sample() and pdf() agree. The candidates are tested four at a time into a mask, whose first
  // bit is the answer: one branch per four tests, not one mispredicted exit per test.
  if (!(w.z >= 0.0f)) return -1;
  const int c = cellOf(w);
  const int* list = cell_triangles_.data();
  for (int k0 = cell_start_[std::size_t(c)], end = cell_start_[std::size_t(c) + 1]; k0 < end; k0 += 4) {
    const int n = std::min(4, end - k0);
    unsigned mask = 0;
    for (int j = 0; j < n; ++j) mask |= unsigned(inside(list[k0 + j], w)) << j;
    if (mask != 0) return list[k0 + std::countr_zero(mask)];
  }
  for (int t = 0; t < triangleCount(); ++t)
    if (inside(t, w)) return t;
  return -1;
}

bool HemisphereTriangulation::locatesIn(int t, const glm::vec3& w) const {
  const glm::vec3 b = barycentric(t, w);
  const float margin = 1e-3f * (b.x + b.y + b.z);
  if ((w.z > 0.0f) & (margin > 0.0f) & (b.x > margin) & (b.y > margin) & (b.z > margin)) return true;
  return locate(w) == t;
}

HemisphereTriangulation::Stencil HemisphereTriangulation::stencil(const glm::vec3& w) const {
  Stencil s;
  const int t = locate(w);
  if (t < 0) {  // below the horizon, or on a hair-line gap between rounded faces
    s.index[0] = nearest(w);
    s.weight[0] = 1.0f;
    s.count = 1;
    return s;
  }
  return stencilIn(t, w);
}

HemisphereTriangulation::Stencil HemisphereTriangulation::stencilIn(int t, const glm::vec3& w) const {
  Stencil s;
  const Triangle& tri = triangles_[std::size_t(t)];
  const glm::vec3 b = glm::max(barycentric(t, w), glm::vec3(0.0f));
  const float sum = b.x + b.y + b.z;
  for (std::size_t k = 0; k < 3; ++k) {
    const float weight = b[int(k)] / sum;
    if (weight == 0.0f) continue;
    // Two virtual vertices may stand for one direction: their weights add.
    int j = 0;
    while (j < s.count && s.index[std::size_t(j)] != tri.direction[k]) ++j;
    if (j == s.count) {
      s.index[std::size_t(s.count)] = tri.direction[k];
      s.weight[std::size_t(s.count++)] = weight;
    } else {
      s.weight[std::size_t(j)] += weight;
    }
  }
  return s;
}

glm::vec3 HemisphereTriangulation::sampleTriangle(int t, glm::vec2 u) const {
  const Triangle& tri = triangles_[std::size_t(t)];
  const glm::dvec3 a(tri.vertex[0]), b(tri.vertex[1]), c(tri.vertex[2]);
  // Arvo's construction: the sub-triangle (a, b, c') of area u.x times the whole, then a point on
  // the arc b-c' at the distance that makes the density uniform.
  const double alpha = tri.corner_angle;
  const double area = double(tri.solid_angle) * double(u.x);
  const double s = std::sin(area - alpha), cs = std::cos(area - alpha);
  const double p = cs - tri.cos_corner, q = s + tri.sin_corner * glm::dot(a, b);
  const double denominator = (q * s + p * cs) * tri.sin_corner;
  double cos_b = denominator != 0.0 ? ((q * cs - p * s) * tri.cos_corner - q) / denominator : 1.0;
  cos_b = std::clamp(cos_b, -1.0, 1.0);
  glm::dvec3 ca = c - glm::dot(c, a) * a;
  const double lca = glm::length(ca);
  ca = lca > 0 ? ca / lca : glm::dvec3(0.0);
  const glm::dvec3 c1 = cos_b * a + std::sqrt(std::max(0.0, 1.0 - cos_b * cos_b)) * ca;
  const double z = 1.0 - double(u.y) * (1.0 - glm::dot(c1, b));
  glm::dvec3 cb = c1 - glm::dot(c1, b) * b;
  const double lcb = glm::length(cb);
  cb = lcb > 0 ? cb / lcb : glm::dvec3(0.0);
  return glm::vec3(glm::normalize(z * b + std::sqrt(std::max(0.0, 1.0 - z * z)) * cb));
}

}  // namespace btf
