// Triangle meshes of the renderer: smooth vertex normals (angle weighting, creases, vertex sharing),
// cleaning, transforms, the built-in shapes, and reading OBJ / PLY files and their gzips with one clear
// FileError per kind of bad file.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "btf/core/error.h"
#include "btf/render/triangle_mesh.h"
#include "support/test_support.h"

namespace btf::render {
namespace {
namespace fs = std::filesystem;

void writeFile(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

glm::vec3 windingNormal(const TriangleMesh& mesh, const glm::uvec3& t) {
  return glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]);
}

float angleDeg(const glm::dvec3& a, const glm::dvec3& b) {
  return float(std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)) * 180.0 / std::numbers::pi);
}

// ---------------------------------------------------------------------------------------------
// computeVertexNormals

// One vertex (the origin) shared by a wide face (120 degrees at the vertex, in the plane z = 0) and
// three thin faces (10 degrees each) tilted in different directions. The angle-weighted normal is
// dominated by the wide face; a count-weighted one by the thin faces.
struct FanAtOrigin {
  TriangleMesh mesh;
  std::vector<glm::dvec3> face_normals;  // exact, unit
  std::vector<double> angles;            // opening angles at the origin (radians)
  std::vector<double> areas;
};

FanAtOrigin fanAtOrigin() {
  FanAtOrigin fan;
  fan.mesh.name = "fan";
  fan.mesh.positions.push_back({0, 0, 0});
  auto addFace = [&](const glm::dvec3& n, const glm::dvec3& d, double angle, double len1, double len2) {
    // Edges d and e = cos(angle) d + sin(angle) (n x d): the winding's normal is n.
    const glm::dvec3 e = std::cos(angle) * d + std::sin(angle) * glm::cross(n, d);
    const auto base = std::uint32_t(fan.mesh.positions.size());
    fan.mesh.positions.push_back(glm::vec3(len1 * d));
    fan.mesh.positions.push_back(glm::vec3(len2 * e));
    fan.mesh.triangles.push_back({0, base, base + 1});
    fan.face_normals.push_back(n);
    fan.angles.push_back(angle);
    fan.areas.push_back(0.5 * len1 * len2 * std::sin(angle));
  };
  const double deg = std::numbers::pi / 180.0;
  addFace({0, 0, 1}, {1, 0, 0}, 120 * deg, 1.0, 1.0);
  const std::array<glm::dvec3, 3> tilts = {glm::dvec3(0.0, -0.8, 1.0), glm::dvec3(0.7, -0.6, 1.0), glm::dvec3(-0.5, -0.9, 1.0)};
  for (std::size_t i = 0; i < tilts.size(); ++i) {
    const glm::dvec3 n = glm::normalize(tilts[i]);
    const glm::dvec3 d = glm::normalize(glm::cross(n, glm::dvec3(1, 0, 0)));  // any direction in the face's plane
    addFace(n, d, 10 * deg, 2.0 + double(i), 1.5);
  }
  return fan;
}

TEST(TriangleMeshNormals, AngleWeightedAtASharedVertex) {
  FanAtOrigin fan = fanAtOrigin();
  glm::dvec3 by_angle(0.0), by_area(0.0), by_count(0.0);
  for (std::size_t f = 0; f < fan.face_normals.size(); ++f) {
    by_angle += fan.angles[f] * fan.face_normals[f];
    by_area += fan.areas[f] * fan.face_normals[f];
    by_count += fan.face_normals[f];
  }
  // The three weightings must be told apart by the test, else it proves nothing.
  ASSERT_GT(angleDeg(by_angle, by_area), 1.0f);
  ASSERT_GT(angleDeg(by_angle, by_count), 5.0f);

  computeVertexNormals(fan.mesh, 180.0f);
  ASSERT_EQ(fan.mesh.triangles.size(), 4u);
  ASSERT_EQ(fan.mesh.normals.size(), fan.mesh.positions.size());
  const glm::dvec3 want = glm::normalize(by_angle);
  std::set<std::uint32_t> origin_vertices;
  for (const glm::uvec3& t : fan.mesh.triangles) {
    ASSERT_EQ(fan.mesh.positions[t.x], glm::vec3(0.0f));  // the corner order is kept
    origin_vertices.insert(t.x);
    const glm::vec3 n = fan.mesh.normals[t.x];
    EXPECT_NEAR(n.x, want.x, 1e-5);
    EXPECT_NEAR(n.y, want.y, 1e-5);
    EXPECT_NEAR(n.z, want.z, 1e-5);
  }
  // Every corner at the origin averaged the same faces: one vertex.
  EXPECT_EQ(origin_vertices.size(), 1u);
  // The outer vertices belong to one face each: their normal is the face's.
  for (std::size_t f = 0; f < fan.mesh.triangles.size(); ++f) {
    const glm::vec3 n = fan.mesh.normals[fan.mesh.triangles[f].y];
    EXPECT_LT(angleDeg(glm::dvec3(n), fan.face_normals[f]), 1e-3f);
  }
}

// The unit cube [0, 1]^3, 8 vertices, 12 triangles wound outwards. Each face is split along a
// diagonal, so a corner touches one or two triangles of each face (a count-weighted average
// would not be the diagonal), but always 90 degrees of each.
TriangleMesh cube() {
  TriangleMesh mesh;
  mesh.name = "cube";
  for (int i = 0; i < 8; ++i) mesh.positions.push_back({float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)});
  for (int i = 0; i < 8; ++i) mesh.uvs.push_back({0.1f * float(i), 1.0f - 0.1f * float(i)});
  // Quads (a, b, c, d) counter-clockwise seen from outside.
  const std::array<std::array<std::uint32_t, 4>, 6> quads = {{
      {0, 2, 3, 1},  // z = 0, normal -z
      {4, 5, 7, 6},  // z = 1, +z
      {0, 1, 5, 4},  // y = 0, -y
      {2, 6, 7, 3},  // y = 1, +y
      {0, 4, 6, 2},  // x = 0, -x
      {1, 3, 7, 5},  // x = 1, +x
  }};
  for (const auto& q : quads) {
    mesh.triangles.push_back({q[0], q[1], q[2]});
    mesh.triangles.push_back({q[0], q[2], q[3]});
  }
  return mesh;
}

TEST(TriangleMeshNormals, CubeIsOutwardWound) {
  const TriangleMesh mesh = cube();
  for (const glm::uvec3& t : mesh.triangles) {
    const glm::vec3 centroid = (mesh.positions[t.x] + mesh.positions[t.y] + mesh.positions[t.z]) / 3.0f;
    EXPECT_GT(glm::dot(windingNormal(mesh, t), centroid - glm::vec3(0.5f)), 0.0f);
  }
}

TEST(TriangleMeshNormals, CreaseKeepsTheCubesFacesFlat) {
  TriangleMesh mesh = cube();
  computeVertexNormals(mesh, 60.0f);
  ASSERT_EQ(mesh.triangles.size(), 12u);
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  // Each of the 8 corners splits into one vertex per face: 3 x 8.
  EXPECT_EQ(mesh.positions.size(), 24u);
  for (const glm::uvec3& t : mesh.triangles) {
    const glm::vec3 face = glm::normalize(windingNormal(mesh, t));
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 n = mesh.normals[t[k]];
      EXPECT_NEAR(n.x, face.x, 1e-6);
      EXPECT_NEAR(n.y, face.y, 1e-6);
      EXPECT_NEAR(n.z, face.z, 1e-6);
    }
  }
}

TEST(TriangleMeshNormals, NoCreaseGivesTheCubesCornersTheDiagonal) {
  TriangleMesh mesh = cube();
  computeVertexNormals(mesh, 180.0f);
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  EXPECT_EQ(mesh.positions.size(), 8u);
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::vec3 diagonal = glm::normalize(mesh.positions[v] - glm::vec3(0.5f));
    EXPECT_NEAR(mesh.normals[v].x, diagonal.x, 1e-6) << v;
    EXPECT_NEAR(mesh.normals[v].y, diagonal.y, 1e-6) << v;
    EXPECT_NEAR(mesh.normals[v].z, diagonal.z, 1e-6) << v;
  }
}

TEST(TriangleMeshNormals, UvsFollowTheirVerticesWhenCornersSplit) {
  const TriangleMesh original = cube();
  TriangleMesh mesh = original;
  computeVertexNormals(mesh, 30.0f);
  ASSERT_EQ(mesh.uvs.size(), mesh.positions.size());
  ASSERT_EQ(mesh.triangles.size(), original.triangles.size());
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t before = original.triangles[f][k], after = mesh.triangles[f][k];
      EXPECT_EQ(mesh.positions[after], original.positions[before]);
      EXPECT_EQ(mesh.uvs[after], original.uvs[before]);
    }
}

// z = 0.3 sin(x) cos(y) on an n x n grid over [-1, 1]^2: smooth everywhere.
TriangleMesh heightfield(int n) {
  TriangleMesh mesh;
  mesh.name = "heightfield";
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const float x = -1.0f + 2.0f * float(i) / float(n - 1), y = -1.0f + 2.0f * float(j) / float(n - 1);
      mesh.positions.push_back({x, y, 0.3f * std::sin(x) * std::cos(y)});
      mesh.uvs.push_back({float(i) / float(n - 1), float(j) / float(n - 1)});
    }
  auto at = [n](int i, int j) { return std::uint32_t(j * n + i); };
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return mesh;
}

TEST(TriangleMeshNormals, SmoothMeshKeepsItsVertices) {
  const TriangleMesh original = heightfield(17);
  TriangleMesh mesh = original;
  computeVertexNormals(mesh, 60.0f);
  // Vertices may be renumbered, but none is split: one per original vertex, and each corner still
  // refers to the same position and UV.
  EXPECT_EQ(mesh.positions.size(), original.positions.size());
  ASSERT_EQ(mesh.uvs.size(), mesh.positions.size());
  ASSERT_EQ(mesh.triangles.size(), original.triangles.size());
  std::map<std::uint32_t, std::uint32_t> renumbered;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t before = original.triangles[f][k], after = mesh.triangles[f][k];
      EXPECT_EQ(mesh.positions[after], original.positions[before]);
      EXPECT_EQ(mesh.uvs[after], original.uvs[before]);
      const auto [it, inserted] = renumbered.try_emplace(before, after);
      EXPECT_EQ(it->second, after) << "vertex " << before << " was split";
    }
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  // Close to the surface's own normal (-dz/dx, -dz/dy, 1); the two grid corners with a single
  // triangle see only that triangle.
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::vec3 p = mesh.positions[v];
    const glm::dvec3 exact(-0.3 * std::cos(p.x) * std::cos(p.y), 0.3 * std::sin(p.x) * std::sin(p.y), 1.0);
    EXPECT_NEAR(glm::length(mesh.normals[v]), 1.0f, 1e-5f);
    EXPECT_LT(angleDeg(glm::dvec3(mesh.normals[v]), exact), 2.0f) << v;
  }
}

// A file splits a vertex where its UVs jump; the surface must stay smooth across the seam.
TEST(TriangleMeshNormals, UvSeamDoesNotCreaseTheSurface) {
  const int n = 9, seam = 4;
  const TriangleMesh whole = heightfield(n);
  TriangleMesh split = whole;
  // Copies of the seam column with their own UVs, used by the triangles right of the seam.
  std::map<std::uint32_t, std::uint32_t> copy_of;
  for (int j = 0; j < n; ++j) {
    const auto v = std::uint32_t(j * n + seam);
    copy_of[v] = std::uint32_t(split.positions.size());
    split.positions.push_back(split.positions[v]);
    split.uvs.push_back(split.uvs[v] + glm::vec2(7.0f, 0.0f));
  }
  for (glm::uvec3& t : split.triangles) {
    const float cx = (split.positions[t.x].x + split.positions[t.y].x + split.positions[t.z].x) / 3.0f;
    if (cx > split.positions[seam].x)
      for (int k = 0; k < 3; ++k)
        if (copy_of.count(t[k])) t[k] = copy_of[t[k]];
  }
  TriangleMesh smooth_whole = whole;
  computeVertexNormals(smooth_whole, 60.0f);
  computeVertexNormals(split, 60.0f);
  EXPECT_EQ(split.positions.size(), whole.positions.size() + std::size_t(n));  // the seam stays, no new split
  ASSERT_EQ(split.triangles.size(), smooth_whole.triangles.size());
  for (std::size_t f = 0; f < split.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 a = split.normals[split.triangles[f][k]], b = smooth_whole.normals[smooth_whole.triangles[f][k]];
      EXPECT_EQ(a, b) << "triangle " << f << " corner " << k;
    }
}

TEST(TriangleMeshNormals, ReplacesNormalsTheMeshHad) {
  TriangleMesh mesh = cube();
  mesh.normals.assign(mesh.positions.size(), glm::vec3(1, 0, 0));
  computeVertexNormals(mesh, 180.0f);
  ASSERT_EQ(mesh.normals.size(), 8u);
  EXPECT_NEAR(mesh.normals[0].x, -1.0f / std::sqrt(3.0f), 1e-6);
}

// ---------------------------------------------------------------------------------------------
// removeInvalidTriangles

TEST(TriangleMeshCleanup, CountsEachKindAndKeepsTheRest) {
  constexpr float kNan = std::numeric_limits<float>::quiet_NaN();
  constexpr float kInf = std::numeric_limits<float>::infinity();
  TriangleMesh mesh;
  mesh.name = "dirty";
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 0, 0}, {kNan, 0, 0}, {0, kInf, 0}};
  mesh.triangles = {
      {0, 1, 2},  // kept
      {0, 0, 2},  // degenerate: a repeated corner
      {1, 3, 2},  // kept
      {0, 1, 4},  // degenerate: collinear
      {0, 1, 5},  // NaN
      {6, 1, 2},  // infinite
      {0, 1, 7},  // out of range
      {9, 8, 7},  // out of range
      {3, 1, 4},  // kept
  };
  const MeshCleanup counts = removeInvalidTriangles(mesh);
  EXPECT_EQ(counts.degenerate, 2u);
  EXPECT_EQ(counts.non_finite, 2u);
  EXPECT_EQ(counts.out_of_range, 2u);
  const std::vector<glm::uvec3> kept = {{0, 1, 2}, {1, 3, 2}, {3, 1, 4}};
  EXPECT_EQ(mesh.triangles, kept);
  EXPECT_EQ(mesh.positions.size(), 7u);  // vertices stay

  // A clean mesh is left alone.
  const MeshCleanup again = removeInvalidTriangles(mesh);
  EXPECT_EQ(again.degenerate + again.non_finite + again.out_of_range, 0u);
  EXPECT_EQ(mesh.triangles, kept);
}

// ---------------------------------------------------------------------------------------------
// transformMesh

TEST(TriangleMeshTransform, NormalsByTheInverseTranspose) {
  // A tilted triangle whose vertex normals are its face normal.
  TriangleMesh mesh;
  mesh.name = "tilted";
  mesh.positions = {{0, 0, 0}, {1, 0, 1}, {0, 1, 0.5f}};
  mesh.triangles = {{0, 1, 2}};
  mesh.normals.assign(3, glm::normalize(windingNormal(mesh, mesh.triangles[0])));
  const glm::mat4 transform = glm::scale(glm::translate(glm::mat4(1.0f), {1, 2, 3}), {3.0f, 1.0f, 0.5f});
  transformMesh(mesh, transform);
  EXPECT_NEAR(mesh.positions[1].x, 1.0f + 3.0f, 1e-6);
  EXPECT_NEAR(mesh.positions[1].z, 3.0f + 0.5f, 1e-6);
  const glm::vec3 face = glm::normalize(windingNormal(mesh, mesh.triangles[0]));
  for (const glm::vec3& n : mesh.normals) {
    EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
    // Still perpendicular to the (transformed) surface: a plain M * n would not be.
    EXPECT_NEAR(n.x, face.x, 1e-5);
    EXPECT_NEAR(n.y, face.y, 1e-5);
    EXPECT_NEAR(n.z, face.z, 1e-5);
  }
}

TEST(TriangleMeshTransform, MirroringFlipsTheWinding) {
  TriangleMesh mesh = makeQuad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, "quad");  // normal +z
  transformMesh(mesh, glm::scale(glm::mat4(1.0f), {1.0f, 1.0f, -1.0f}));
  for (const glm::vec3& n : mesh.normals) EXPECT_NEAR(n.z, -1.0f, 1e-6);
  for (const glm::uvec3& t : mesh.triangles) {
    const glm::vec3 w = glm::normalize(windingNormal(mesh, t));
    EXPECT_NEAR(w.z, -1.0f, 1e-6);  // the winding agrees with the normals again
  }
  // A mirror in x keeps z but reverses the order of the corners.
  TriangleMesh other = makeQuad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, "quad");
  transformMesh(other, glm::scale(glm::mat4(1.0f), {-2.0f, 1.0f, 1.0f}));
  for (const glm::uvec3& t : other.triangles) EXPECT_GT(windingNormal(other, t).z, 0.0f);
  for (const glm::vec3& n : other.normals) EXPECT_NEAR(n.z, 1.0f, 1e-6);
}

TEST(TriangleMeshTransform, SingularTransformThrows) {
  TriangleMesh mesh = makeQuad({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, "flattened");
  try {
    transformMesh(mesh, glm::scale(glm::mat4(1.0f), {1.0f, 0.0f, 1.0f}));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("flattened"), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------------------------------------
// makeQuad, makeSphere

TEST(TriangleMeshShapes, QuadWindingAgreesWithItsNormals) {
  const glm::vec3 edge_u{2, 0, 0}, edge_v{0, 0, -3};
  const TriangleMesh mesh = makeQuad({1, 1, 1}, edge_u, edge_v, "quad");
  ASSERT_EQ(mesh.triangles.size(), 2u);
  ASSERT_EQ(mesh.normals.size(), 4u);
  ASSERT_EQ(mesh.uvs.size(), 4u);
  const glm::vec3 want = glm::normalize(glm::cross(edge_u, edge_v));
  EXPECT_NEAR(want.y, 1.0f, 1e-6);  // cross((2,0,0), (0,0,-3)) points up
  float area = 0;
  for (const glm::uvec3& t : mesh.triangles) {
    const glm::vec3 w = windingNormal(mesh, t);
    area += 0.5f * glm::length(w);
    for (int k = 0; k < 3; ++k) EXPECT_GT(glm::dot(glm::normalize(w), mesh.normals[t[k]]), 0.999999f);
  }
  EXPECT_NEAR(area, 6.0f, 1e-5);
  for (const glm::vec2& uv : mesh.uvs) {
    EXPECT_GE(std::min(uv.x, uv.y), 0.0f);
    EXPECT_LE(std::max(uv.x, uv.y), 1.0f);
  }
  EXPECT_THROW(makeQuad({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, "line"), Error);
}

TEST(TriangleMeshShapes, SphereIsClosedOutwardAndOfTheRightArea) {
  const glm::vec3 center{1, -2, 0.5f};
  const float radius = 0.75f;
  TriangleMesh mesh = makeSphere(center, radius, 32, "sphere");
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  ASSERT_EQ(mesh.uvs.size(), mesh.positions.size());
  double area = 0;
  for (const glm::uvec3& t : mesh.triangles) {
    const glm::vec3 w = windingNormal(mesh, t);
    ASSERT_GT(glm::length(w), 0.0f) << "degenerate triangle";
    area += 0.5 * glm::length(glm::dvec3(w));
    for (int k = 0; k < 3; ++k) EXPECT_GT(glm::dot(glm::normalize(w), mesh.normals[t[k]]), 0.9f);
    const glm::vec3 centroid = (mesh.positions[t.x] + mesh.positions[t.y] + mesh.positions[t.z]) / 3.0f;
    EXPECT_GT(glm::dot(w, centroid - center), 0.0f);
  }
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    EXPECT_NEAR(glm::length(mesh.positions[v] - center), radius, 1e-5f);
    EXPECT_NEAR(glm::dot(mesh.normals[v], glm::normalize(mesh.positions[v] - center)), 1.0f, 1e-5f);
  }
  // 32 rings and 64 segments: 2 * 32 * 64 - 2 * 64 (no triangles collapse at the poles).
  EXPECT_EQ(mesh.triangles.size(), std::size_t(2 * 32 * 64 - 2 * 64));
  const double exact = 4.0 * std::numbers::pi * radius * radius;
  EXPECT_LT(area, exact);  // an inscribed polyhedron
  EXPECT_NEAR(area, exact, 0.005 * exact);
  // Nothing for the cleanup to drop.
  const MeshCleanup c = removeInvalidTriangles(mesh);
  EXPECT_EQ(c.degenerate + c.non_finite + c.out_of_range, 0u);
  EXPECT_THROW(makeSphere(center, 0.0f, 8, "flat"), Error);
  EXPECT_THROW(makeSphere(center, std::numeric_limits<float>::quiet_NaN(), 8, "nan"), Error);
}

// ---------------------------------------------------------------------------------------------
// loadTriangleMeshes: files written by the tests

// A little-endian binary PLY: 5 vertices, two triangles and a quad (which is triangulated).
std::string binaryPly() {
  std::string s =
      "ply\n"
      "format binary_little_endian 1.0\n"
      "comment written by test_triangle_mesh\n"
      "element vertex 5\n"
      "property float x\nproperty float y\nproperty float z\n"
      "element face 3\n"
      "property list uchar int vertex_indices\n"
      "end_header\n";
  const float v[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 0.5f, 1}};
  for (const auto& p : v) s.append(reinterpret_cast<const char*>(p), sizeof(p));
  auto face = [&](std::initializer_list<std::int32_t> idx) {
    s.push_back(char(idx.size()));
    for (std::int32_t i : idx) s.append(reinterpret_cast<const char*>(&i), 4);
  };
  face({0, 1, 4});
  face({1, 2, 4});
  face({0, 3, 2, 1});
  return s;
}

const char* kAsciiPly =
    "ply\n"
    "format ascii 1.0\n"
    "element vertex 4\n"
    "property float x\nproperty float y\nproperty float z\n"
    "element face 2\n"
    "property list uchar int vertex_indices\n"
    "end_header\n"
    "0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
    "3 0 1 2\n3 0 2 3\n";

// gzip with stored (uncompressed) deflate blocks: enough to test .gz reading without zlib here.
std::uint32_t crc32(const std::string& data) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (unsigned char c : data) {
    crc ^= c;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

std::string gzipStored(const std::string& data) {
  std::string out = {'\x1f', '\x8b', '\x08', '\0', '\0', '\0', '\0', '\0', '\0', '\x03'};
  std::size_t pos = 0;
  do {
    const std::size_t n = std::min<std::size_t>(data.size() - pos, 65535);
    const bool last = pos + n == data.size();
    out.push_back(last ? '\x01' : '\x00');
    const auto len = std::uint16_t(n), nlen = std::uint16_t(~len);
    out.append(reinterpret_cast<const char*>(&len), 2);
    out.append(reinterpret_cast<const char*>(&nlen), 2);
    out.append(data, pos, n);
    pos += n;
  } while (pos < data.size());
  const std::uint32_t crc = crc32(data), size = std::uint32_t(data.size());
  out.append(reinterpret_cast<const char*>(&crc), 4);
  out.append(reinterpret_cast<const char*>(&size), 4);
  return out;
}

std::multiset<std::array<float, 9>> trianglesAsPositions(const TriangleMesh& mesh) {
  // Each triangle as its corners starting from the smallest (a rotation keeps the winding).
  std::multiset<std::array<float, 9>> out;
  for (const glm::uvec3& t : mesh.triangles) {
    std::array<std::array<float, 3>, 3> c;
    for (int k = 0; k < 3; ++k) c[k] = {mesh.positions[t[k]].x, mesh.positions[t[k]].y, mesh.positions[t[k]].z};
    const auto first = std::size_t(std::min_element(c.begin(), c.end()) - c.begin());
    std::array<float, 9> a;
    for (std::size_t k = 0; k < 3; ++k)
      for (std::size_t j = 0; j < 3; ++j) a[3 * k + j] = c[(first + k) % 3][j];
    out.insert(a);
  }
  return out;
}

TEST(TriangleMeshFiles, BinaryPlyLoads) {
  test::TempDir dir;
  writeFile(dir / "tiny.ply", binaryPly());
  const std::vector<TriangleMesh> meshes = loadTriangleMeshes(dir / "tiny.ply");
  ASSERT_EQ(meshes.size(), 1u);
  const TriangleMesh& mesh = meshes[0];
  EXPECT_NE(mesh.name.find("tiny.ply"), std::string::npos) << mesh.name;
  EXPECT_TRUE(mesh.normals.empty());  // the file has none
  // No material in a PLY file: the defaults.
  EXPECT_TRUE(mesh.file_material.empty()) << mesh.file_material;
  EXPECT_EQ(mesh.file_diffuse, TriangleMesh{}.file_diffuse);
  EXPECT_EQ(mesh.file_emission, Rgb(0.0f));
  ASSERT_EQ(mesh.triangles.size(), 4u);
  for (const glm::uvec3& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ASSERT_LT(t[k], mesh.positions.size());
  // The two triangles exactly, the quad as two triangles with its own winding (normal -z).
  const auto tris = trianglesAsPositions(mesh);
  EXPECT_EQ(tris.count({0, 0, 0, 1, 0, 0, 0.5f, 0.5f, 1}), 1u);
  EXPECT_EQ(tris.count({0.5f, 0.5f, 1, 1, 0, 0, 1, 1, 0}), 1u);
  int quad_halves = 0;
  for (const glm::uvec3& t : mesh.triangles) {
    const glm::vec3 w = windingNormal(mesh, t);
    if (mesh.positions[t.x].z == 0 && mesh.positions[t.y].z == 0 && mesh.positions[t.z].z == 0) {
      ++quad_halves;
      EXPECT_LT(w.z, 0.0f);
      EXPECT_NEAR(0.5f * glm::length(w), 0.5f, 1e-6);
    }
  }
  EXPECT_EQ(quad_halves, 2);
}

TEST(TriangleMeshFiles, AsciiPlyAndItsGzipLoadTheSame) {
  test::TempDir dir;
  writeFile(dir / "quad.ply", kAsciiPly);
  writeFile(dir / "quad.PLY.gz", gzipStored(kAsciiPly));  // extensions in any case
  const auto plain = loadTriangleMeshes(dir / "quad.ply");
  const auto unpacked = loadTriangleMeshes(dir / "quad.PLY.gz");
  ASSERT_EQ(plain.size(), 1u);
  ASSERT_EQ(unpacked.size(), 1u);
  EXPECT_EQ(plain[0].triangles.size(), 2u);
  EXPECT_EQ(trianglesAsPositions(plain[0]), trianglesAsPositions(unpacked[0]));
}

// Expects loadTriangleMeshes(path) to throw FileError whose message names the file and contains `problem`.
void expectLoadError(const fs::path& path, const std::string& problem) {
  try {
    loadTriangleMeshes(path);
    ADD_FAILURE() << "no error for " << path;
  } catch (const FileError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path.string()), std::string::npos) << what;
    EXPECT_EQ(e.path(), path) << what;
    EXPECT_NE(what.find(problem), std::string::npos) << "expected '" << problem << "' in: " << what;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not a FileError: " << e.what();
  }
}

// Normals and texture coordinates of the vertex element, a pentagon as a fan, a vertex no face
// uses left out, and elements and properties a mesh does not need skipped.
TEST(TriangleMeshFiles, PlyNormalsTextureCoordinatesAndPolygons) {
  test::TempDir dir;
  writeFile(dir / "pentagon.ply",
            "ply\nformat ascii 1.0\ncomment made by hand\nelement camera 1\nproperty float view_px\n"
            "element vertex 6\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\n"
            "property float ny\nproperty float nz\nproperty uchar red\nproperty float s\nproperty float t\n"
            "element face 1\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord\nend_header\n"
            "7.5\n"
            "0 0 0 0 0 2 255 0 0\n1 0 0 0 0 2 255 1 0\n1.5 1 0 0 0 2 255 1 1\n"
            "9 9 9 0 0 2 255 0.5 0.5\n0.5 1.5 0 0 0 2 255 0.5 1\n-0.5 1 0 0 0 2 255 0 1\n"
            "5 0 1 2 4 5 2 0.5 0.5\n");
  const auto meshes = loadTriangleMeshes(dir / "pentagon.ply");
  ASSERT_EQ(meshes.size(), 1u);
  const TriangleMesh& mesh = meshes[0];
  EXPECT_EQ(mesh.triangles.size(), 3u);
  ASSERT_EQ(mesh.positions.size(), 5u);  // vertex 3 is used by no face
  for (const glm::vec3& p : mesh.positions) EXPECT_NE(p, glm::vec3(9.0f));
  ASSERT_EQ(mesh.normals.size(), 5u);
  EXPECT_EQ(mesh.normals[0], glm::vec3(0, 0, 1));  // unit length
  ASSERT_EQ(mesh.uvs.size(), 5u);
  EXPECT_EQ(mesh.uvs[2], glm::vec2(1, 1));
  float area = 0;
  for (const glm::uvec3& t : mesh.triangles) area += 0.5f * windingNormal(mesh, t).z;
  EXPECT_NEAR(area, 2.0f, 1e-6);  // counter-clockwise, the pentagon's area (shoelace formula)

  // An element declared twice, and more vertices than 32-bit indices address, are refused.
  writeFile(dir / "twice.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nelement vertex 1\n"
                               "property float x\nend_header\n0\n0\n");
  expectLoadError(dir / "twice.ply", "PLY element 'vertex' declared twice");
  writeFile(dir / "huge.ply", "ply\nformat ascii 1.0\nelement vertex 4294967296\nproperty float x\nproperty float y\n"
                              "property float z\nend_header\n");
  expectLoadError(dir / "huge.ply", "4294967296 vertices");
}

TEST(TriangleMeshFiles, MissingFile) {
  test::TempDir dir;
  expectLoadError(dir / "nothing.ply", "no such mesh file");
  expectLoadError(dir.path(), "is not a regular file");  // a folder is not a mesh
}

TEST(TriangleMeshFiles, EmptyFile) {
  test::TempDir dir;
  writeFile(dir / "empty.ply", "");
  writeFile(dir / "empty.obj", "");
  expectLoadError(dir / "empty.ply", "empty");
  expectLoadError(dir / "empty.obj", "empty");
}

TEST(TriangleMeshFiles, UnknownExtension) {
  test::TempDir dir;
  writeFile(dir / "mesh.stl", kAsciiPly);
  writeFile(dir / "mesh", kAsciiPly);
  writeFile(dir / "mesh.txt.gz", gzipStored(kAsciiPly));
  expectLoadError(dir / "mesh.stl", "unknown mesh format");
  expectLoadError(dir / "mesh", "unknown mesh format");
  expectLoadError(dir / "mesh.txt.gz", "unknown mesh format");
}

TEST(TriangleMeshFiles, GzippedObjFindsTheMtlBesideIt) {
  test::TempDir dir;
  writeFile(dir / "lamp.mtl", "newmtl lamp\nKd 0.25 0.5 0.75\nKe 4 4 4\n");
  writeFile(dir / "mesh.obj.GZ", gzipStored("mtllib lamp.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl lamp\nf 1 2 3\n"));
  const auto meshes = loadTriangleMeshes(dir / "mesh.obj.GZ");
  ASSERT_EQ(meshes.size(), 1u);
  EXPECT_EQ(meshes[0].triangles.size(), 1u);
  EXPECT_EQ(meshes[0].file_material, "lamp");
  EXPECT_EQ(meshes[0].file_diffuse, Rgb(0.25f, 0.5f, 0.75f));
  EXPECT_EQ(meshes[0].file_emission, Rgb(4.0f));
}

TEST(TriangleMeshFiles, CorruptGzip) {
  test::TempDir dir;
  writeFile(dir / "garbage.ply.gz", "this is not gzip data at all, just text");
  expectLoadError(dir / "garbage.ply.gz", "gzip");
  // A valid stream cut short.
  const std::string packed = gzipStored(kAsciiPly);
  writeFile(dir / "cut.ply.gz", packed.substr(0, packed.size() / 2));
  expectLoadError(dir / "cut.ply.gz", "gzip");
  // Intact deflate data, wrong checksum.
  std::string bad_crc = packed;
  bad_crc[bad_crc.size() - 6] ^= 0x5a;
  writeFile(dir / "crc.ply.gz", bad_crc);
  expectLoadError(dir / "crc.ply.gz", "gzip");
  writeFile(dir / "empty.ply.gz", "");
  expectLoadError(dir / "empty.ply.gz", "");
}

TEST(TriangleMeshFiles, PlyWithoutFaces) {
  test::TempDir dir;
  writeFile(dir / "points.ply",
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
            "end_header\n0 0 0\n1 0 0\n0 1 0\n");
  expectLoadError(dir / "points.ply", "");
  writeFile(dir / "zero.ply",
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 0\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n");
  expectLoadError(dir / "zero.ply", "");
}

// A file cut anywhere is an error naming the element where its data ends.
TEST(TriangleMeshFiles, TruncatedPly) {
  test::TempDir dir;
  const std::string binary = binaryPly();
  writeFile(dir / "cut-binary.ply", binary.substr(0, binary.size() - 20));
  expectLoadError(dir / "cut-binary.ply", "truncated PLY: the data ends in element 'face' 1 of 3");
  writeFile(dir / "no-body.ply", binary.substr(0, binary.find("end_header\n") + 11));
  expectLoadError(dir / "no-body.ply", "truncated PLY: the data ends in element 'vertex' 0 of 5");
  const std::string ascii = kAsciiPly;
  writeFile(dir / "cut-ascii-vertices.ply", ascii.substr(0, ascii.find("1 1 0")));
  expectLoadError(dir / "cut-ascii-vertices.ply", "truncated PLY: the data ends in element 'vertex' 2 of 4");
  writeFile(dir / "cut-ascii-faces.ply", ascii.substr(0, ascii.find("3 0 2 3")));
  expectLoadError(dir / "cut-ascii-faces.ply", "truncated PLY: the data ends in element 'face' 1 of 2");
  writeFile(dir / "cut-ascii-list.ply", ascii.substr(0, ascii.size() - 3));
  expectLoadError(dir / "cut-ascii-list.ply", "truncated PLY");
  writeFile(dir / "header-only.ply", ascii.substr(0, ascii.find("end_header")));
  expectLoadError(dir / "header-only.ply", "no end_header");
  writeFile(dir / "header-cut.ply", ascii.substr(0, ascii.find("property")));
  expectLoadError(dir / "header-cut.ply", "no end_header");
}

TEST(TriangleMeshFiles, MalformedPly) {
  test::TempDir dir;
  std::string ascii = kAsciiPly;
  writeFile(dir / "word.ply", ascii.replace(ascii.find("1 1 0"), 5, "1 x 0"));
  expectLoadError(dir / "word.ply", "'x' is not a number");
  ascii = kAsciiPly;
  writeFile(dir / "type.ply", ascii.replace(ascii.find("float z"), 7, "quad z"));
  expectLoadError(dir / "type.ply", "malformed PLY header line 'property quad z'");
  ascii = kAsciiPly;
  writeFile(dir / "format.ply", ascii.replace(ascii.find("ascii"), 5, "utf-8"));
  expectLoadError(dir / "format.ply", "unknown PLY format 'utf-8'");
  ascii = kAsciiPly;
  writeFile(dir / "index.ply", ascii.replace(ascii.find("3 0 2 3"), 7, "3 0 2 9"));
  expectLoadError(dir / "index.ply", "out of range");
}

// The same tiny mesh in big-endian byte order, a ushort list count and a double coordinate.
TEST(TriangleMeshFiles, BigEndianPly) {
  std::string s =
      "ply\r\nformat binary_big_endian 1.0\r\nelement vertex 3\r\n"
      "property double x\r\nproperty float y\r\nproperty float z\r\n"
      "element face 1\r\nproperty list ushort uint vertex_indices\r\nend_header\r\n";
  auto put = [&](const void* p, std::size_t n) {
    const auto* b = static_cast<const char*>(p);
    for (std::size_t i = 0; i < n; ++i) s.push_back(b[n - 1 - i]);  // this machine is little-endian
  };
  const float yz[3][2] = {{0, 0}, {0, 0}, {1, 0}};
  const double x[3] = {0, 1, 0};
  for (int v = 0; v < 3; ++v) {
    put(&x[v], 8);
    put(&yz[v][0], 4);
    put(&yz[v][1], 4);
  }
  const std::uint16_t n = 3;
  put(&n, 2);
  for (std::uint32_t i : {0u, 1u, 2u}) put(&i, 4);
  test::TempDir dir;
  writeFile(dir / "big.ply", s);
  const auto meshes = loadTriangleMeshes(dir / "big.ply");
  ASSERT_EQ(meshes.size(), 1u);
  ASSERT_EQ(meshes[0].triangles.size(), 1u);
  EXPECT_EQ(trianglesAsPositions(meshes[0]).count({0, 0, 0, 1, 0, 0, 0, 1, 0}), 1u);
  writeFile(dir / "big-cut.ply", s.substr(0, s.size() - 1));
  expectLoadError(dir / "big-cut.ply", "truncated PLY: the data ends in element 'face' 0 of 1");
}

TEST(TriangleMeshFiles, NotAMeshAtAll) {
  test::TempDir dir;
  writeFile(dir / "noise.ply", std::string("\x01\x02\x03 binary noise \xff\xfe", 20));
  expectLoadError(dir / "noise.ply", "");
}

TEST(TriangleMeshFiles, ObjWithoutMtl) {
  test::TempDir dir;
  writeFile(dir / "plain.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\n");
  const auto meshes = loadTriangleMeshes(dir / "plain.obj");
  ASSERT_EQ(meshes.size(), 1u);
  EXPECT_EQ(meshes[0].triangles.size(), 2u);
  EXPECT_TRUE(meshes[0].file_material.empty()) << meshes[0].file_material;
  EXPECT_EQ(meshes[0].file_diffuse, TriangleMesh{}.file_diffuse);
  EXPECT_TRUE(meshes[0].uvs.empty());
}

TEST(TriangleMeshFiles, ObjWithMaterialsAndGroups) {
  test::TempDir dir;
  writeFile(dir / "two.mtl",
            "newmtl red\nKd 0.8 0.1 0.1\nKe 0 0 0\n\n"
            "newmtl lamp\nKd 0.5 0.5 0.5\nKe 3 2 1\n");
  writeFile(dir / "two.obj",
            "mtllib two.mtl\n"
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\n"
            "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
            "g floor\nusemtl red\nf 1/1 2/2 3/3 4/4\n"
            "g lamp\nusemtl lamp\nf 5/1 6/2 7/3\n");
  const auto meshes = loadTriangleMeshes(dir / "two.obj");
  ASSERT_EQ(meshes.size(), 2u);
  std::map<std::string, const TriangleMesh*> by_material;
  for (const TriangleMesh& m : meshes) by_material[m.file_material] = &m;
  ASSERT_TRUE(by_material.count("red") && by_material.count("lamp"));
  const TriangleMesh& floor = *by_material["red"];
  EXPECT_EQ(floor.triangles.size(), 2u);
  EXPECT_NE(floor.name.find("two.obj"), std::string::npos);
  EXPECT_NE(floor.name.find("floor"), std::string::npos) << floor.name;
  EXPECT_EQ(floor.file_diffuse, Rgb(0.8f, 0.1f, 0.1f));
  EXPECT_EQ(floor.file_emission, Rgb(0.0f));
  ASSERT_EQ(floor.uvs.size(), floor.positions.size());
  const TriangleMesh& lamp = *by_material["lamp"];
  EXPECT_EQ(lamp.triangles.size(), 1u);
  EXPECT_EQ(lamp.file_emission, Rgb(3.0f, 2.0f, 1.0f));
}

TEST(TriangleMeshFiles, ObjGroupChangingMaterialSplitsAndALibraryIsReadOnce) {
  test::TempDir dir;
  writeFile(dir / "two.mtl", "newmtl red\nKd 0.8 0.1 0.1\nnewmtl blue\nKd 0.1 0.1 0.8\n");
  // The library named three times, two of them under other names: its materials are read once.
  writeFile(dir / "split.obj",
            "mtllib two.mtl ./two.mtl\nmtllib .//two.mtl\n"
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
            "o panel\nusemtl red\nf 1 2 3\nusemtl blue\nf 1 3 4\nusemtl red\nf 2 3 4\n");
  const auto meshes = loadTriangleMeshes(dir / "split.obj");
  ASSERT_EQ(meshes.size(), 2u);
  EXPECT_EQ(meshes[0].file_material, "red");
  EXPECT_EQ(meshes[0].triangles.size(), 2u);
  EXPECT_EQ(meshes[1].file_material, "blue");
  EXPECT_EQ(meshes[1].file_diffuse, Rgb(0.1f, 0.1f, 0.8f));
  EXPECT_NE(meshes[1].name.find("split.obj:panel"), std::string::npos) << meshes[1].name;
}

// Statements a mesh does not need are not read: tinyobjloader copies its subdivision tags ("t")
// into every group that follows them, so these 5 KB would take it gigabytes.
TEST(TriangleMeshFiles, ObjStatementsBeyondAMeshAreNotRead) {
  test::TempDir dir;
  std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvw 0 0 0.5\ns 1\nl 1 2\np 3\ncurv 0 1 1 2\n";
  for (int i = 0; i < 300; ++i) text += "t a 0/0/8192\n";
  for (int i = 0; i < 100; ++i) text += "f 1 2 3\ng part" + std::to_string(i) + "\n";
  writeFile(dir / "tags.obj", text);
  const auto meshes = loadTriangleMeshes(dir / "tags.obj");
  EXPECT_EQ(meshes.size(), 100u);
}

// ---------------------------------------------------------------------------------------------
// loadTriangleMeshes: the shared data

fs::path sharedMeshes() { return test::sharedDataDir() / "meshes"; }

// The shared data sits beside the checkout for every test run (as for the rest of the suite): a
// missing folder is a failure, not a skip.
#define SKIP_WITHOUT_SHARED_MESHES() \
  ASSERT_TRUE(fs::is_directory(sharedMeshes())) << "no shared data at " << sharedMeshes()

std::size_t unusedVertices(const TriangleMesh& mesh) {
  std::vector<bool> used(mesh.positions.size(), false);
  for (const glm::uvec3& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) used[t[k]] = true;
  return std::size_t(std::count(used.begin(), used.end(), false));
}

TEST(TriangleMeshSharedData, StanfordBunnyAsciiPly) {
  SKIP_WITHOUT_SHARED_MESHES();
  const auto meshes = loadTriangleMeshes(sharedMeshes() / "bunny/bun_zipper.ply");
  ASSERT_EQ(meshes.size(), 1u);
  const TriangleMesh& bunny = meshes[0];
  EXPECT_EQ(bunny.triangles.size(), 69451u);
  // Vertices no face uses are left out; none is invented.
  EXPECT_LE(bunny.positions.size(), 35947u);
  EXPECT_GE(bunny.positions.size(), 34000u);
  for (const glm::uvec3& t : bunny.triangles)
    for (int k = 0; k < 3; ++k) ASSERT_LT(t[k], bunny.positions.size());
  EXPECT_EQ(unusedVertices(bunny), 0u);
}

TEST(TriangleMeshSharedData, StanfordDragonGzippedPly) {
  SKIP_WITHOUT_SHARED_MESHES();
  const fs::path path = sharedMeshes() / "dragon/dragon_vrip_res4.ply.gz";
  const auto meshes = loadTriangleMeshes(path);
  ASSERT_EQ(meshes.size(), 1u);
  EXPECT_EQ(meshes[0].triangles.size(), 11102u);
  EXPECT_LE(meshes[0].positions.size(), 5205u);
  EXPECT_GE(meshes[0].positions.size(), 5000u);
  EXPECT_NE(meshes[0].name.find("dragon_vrip_res4.ply.gz"), std::string::npos);

  // The same file cut short is an error naming it.
  test::TempDir dir;
  const std::string packed = readFile(path);
  writeFile(dir / "cut.ply.gz", packed.substr(0, packed.size() / 3));
  expectLoadError(dir / "cut.ply.gz", "gzip");
}

TEST(TriangleMeshSharedData, CornellBoxObjWithItsMtl) {
  SKIP_WITHOUT_SHARED_MESHES();
  const auto meshes = loadTriangleMeshes(sharedMeshes() / "cornell_box/CornellBox-Original.obj");
  // 18 quads: one each for the walls, floor, ceiling and light, six per box.
  std::map<std::string, std::size_t> triangles_of;
  std::size_t total = 0;
  for (const TriangleMesh& m : meshes) {
    triangles_of[m.file_material] += m.triangles.size();
    total += m.triangles.size();
  }
  EXPECT_EQ(total, 36u);
  const std::map<std::string, std::size_t> want = {{"floor", 2},    {"ceiling", 2},  {"backWall", 2}, {"rightWall", 2},
                                                   {"leftWall", 2}, {"shortBox", 12}, {"tallBox", 12}, {"light", 2}};
  EXPECT_EQ(triangles_of, want);
  for (const TriangleMesh& m : meshes) {
    if (m.file_material == "light") {
      EXPECT_EQ(m.file_emission, Rgb(17.0f, 12.0f, 4.0f));
      EXPECT_NEAR(m.file_diffuse.r, 0.78f, 1e-6);
    } else {
      EXPECT_EQ(m.file_emission, Rgb(0.0f)) << m.file_material;
    }
    if (m.file_material == "leftWall") {
      EXPECT_EQ(m.file_diffuse, Rgb(0.63f, 0.065f, 0.05f));
    }
    if (m.file_material == "rightWall") {
      EXPECT_EQ(m.file_diffuse, Rgb(0.14f, 0.45f, 0.091f));
    }
  }
}

}  // namespace
}  // namespace btf::render
