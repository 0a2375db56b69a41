#include "btf/render/triangle_mesh.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <utility>

#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/progress.h"
#include "obj_mesh.h"
#include "ply_mesh.h"

namespace btf::render {
namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::string readFileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path, "cannot open the mesh file");
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// zlib's gzip stream decoder: the readers read from memory and do not unpack .gz themselves.
std::string gunzip(const std::filesystem::path& path, const std::string& packed) {
  z_stream z{};
  if (inflateInit2(&z, 15 + 32) != Z_OK) throw FileError(path, "cannot start the gzip decoder");
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(packed.data()));
  z.avail_in = static_cast<uInt>(packed.size());
  std::string out;
  char buffer[1 << 16];
  int rc = Z_OK;
  while (rc != Z_STREAM_END) {
    z.next_out = reinterpret_cast<Bytef*>(buffer);
    z.avail_out = sizeof(buffer);
    rc = inflate(&z, Z_NO_FLUSH);
    if (rc != Z_OK && rc != Z_STREAM_END) {
      inflateEnd(&z);
      throw FileError(path, "corrupt gzip data");
    }
    out.append(buffer, sizeof(buffer) - z.avail_out);
    if (rc == Z_OK && z.avail_in == 0 && z.avail_out != 0) {
      inflateEnd(&z);
      throw FileError(path, "truncated gzip data");
    }
  }
  inflateEnd(&z);
  return out;
}

std::string lowercase(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

}  // namespace

std::vector<TriangleMesh> loadTriangleMeshes(const std::filesystem::path& path, std::vector<std::string>* warnings) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw FileError(path, "no such mesh file");
  if (!std::filesystem::is_regular_file(path, ec))
    throw FileError(path, "is not a regular file (a folder, FIFO or device), not a mesh file");
  // The format by the name, before anything is read.
  const bool gzipped = lowercase(path.extension().string()) == ".gz";
  const std::string extension = lowercase((gzipped ? path.stem() : path).extension().string());
  if (extension != ".obj" && extension != ".ply")
    throw FileError(path, "unknown mesh format '" + extension + "' (expected .obj, .ply, or either gzipped)");
  std::string bytes = readFileBytes(path);
  if (gzipped) bytes = gunzip(path, bytes);
  if (bytes.empty()) throw FileError(path, "empty mesh file");

  if (extension == ".obj") {
    std::vector<std::string> found;
    std::vector<TriangleMesh> meshes = readObjMeshes(path, bytes, found);
    if (meshes.empty()) throw FileError(path, "the mesh has no faces");
    for (const std::string& w : found) {
      if (warnings) warnings->push_back(w);
      else log(LogLevel::Warning, path.string() + ": " + w);
    }
    return meshes;
  }

  std::vector<TriangleMesh> meshes;
  meshes.push_back(readPlyMesh(path, bytes));
  return meshes;
}

MeshCleanup removeInvalidTriangles(TriangleMesh& mesh) {
  MeshCleanup counts;
  const std::size_t n = mesh.positions.size();
  std::vector<glm::uvec3> kept;
  kept.reserve(mesh.triangles.size());
  for (const glm::uvec3& t : mesh.triangles) {
    if (t.x >= n || t.y >= n || t.z >= n) {
      ++counts.out_of_range;
      continue;
    }
    const glm::vec3 &a = mesh.positions[t.x], &b = mesh.positions[t.y], &c = mesh.positions[t.z];
    if (!finite(a) || !finite(b) || !finite(c)) {
      ++counts.non_finite;
      continue;
    }
    // Zero area in float: the cross product of the edges vanishes (repeated or collinear corners).
    const glm::vec3 cross = glm::cross(b - a, c - a);
    if (!(glm::dot(cross, cross) > 0.0f)) {
      ++counts.degenerate;
      continue;
    }
    kept.push_back(t);
  }
  mesh.triangles = std::move(kept);
  return counts;
}

MeshCleanup removeInvalidTrianglesWithWarning(TriangleMesh& mesh) {
  const MeshCleanup dropped = removeInvalidTriangles(mesh);
  const std::size_t total = dropped.degenerate + dropped.non_finite + dropped.out_of_range;
  if (total > 0)
    log(LogLevel::Warning, mesh.name + ": dropped " + std::to_string(total) + " triangles (" +
                               std::to_string(dropped.degenerate) + " of zero area, " +
                               std::to_string(dropped.non_finite) + " with NaN or infinite vertices, " +
                               std::to_string(dropped.out_of_range) + " with vertex indices out of range)");
  return dropped;
}

void computeVertexNormals(TriangleMesh& mesh, float crease_deg) {
  const std::size_t nf = mesh.triangles.size();
  // Faces meet at a position, not at a vertex index: a file splits a vertex wherever its UVs jump
  // (a texture seam), and averaging per index would crease the surface along every such seam.
  std::vector<std::uint32_t> position_id(mesh.positions.size());
  std::uint32_t positions_seen = 0;
  {
    std::map<std::array<float, 3>, std::uint32_t> id_of;
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
      const glm::vec3 p = mesh.positions[v];
      if (!finite(p)) {
        position_id[v] = positions_seen++;  // NaN does not compare: never merged
        continue;
      }
      const auto [it, inserted] = id_of.try_emplace(std::array<float, 3>{p.x, p.y, p.z}, positions_seen);
      if (inserted) ++positions_seen;
      position_id[v] = it->second;
    }
  }
  std::vector<glm::vec3> face_normal(nf);
  std::vector<std::vector<std::uint32_t>> faces_of(positions_seen);
  for (std::size_t f = 0; f < nf; ++f) {
    const glm::uvec3 t = mesh.triangles[f];
    face_normal[f] = glm::normalize(glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]));
    for (int k = 0; k < 3; ++k) faces_of[position_id[t[k]]].push_back(std::uint32_t(f));
  }
  auto openingAngle = [&](std::size_t f, std::uint32_t position) {
    const glm::uvec3 t = mesh.triangles[f];
    const int k = position_id[t.x] == position ? 0 : (position_id[t.y] == position ? 1 : 2);
    const glm::vec3 p = mesh.positions[t[k]];
    const glm::vec3 e1 = glm::normalize(mesh.positions[t[(k + 1) % 3]] - p);
    const glm::vec3 e2 = glm::normalize(mesh.positions[t[(k + 2) % 3]] - p);
    return std::acos(std::clamp(glm::dot(e1, e2), -1.0f, 1.0f));
  };
  const float cos_crease = std::cos(std::clamp(crease_deg, 0.0f, 180.0f) * kPi / 180.0f);

  // Corners whose normals come out equal share one vertex again (exactly equal floats: the same
  // set of faces was averaged), so a smooth mesh keeps its vertex count.
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec2> uvs;
  const bool has_uvs = mesh.uvs.size() == mesh.positions.size();
  std::map<std::pair<std::uint32_t, std::array<float, 3>>, std::uint32_t> vertex_of;
  std::vector<glm::uvec3> triangles(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = mesh.triangles[f][k];
      glm::vec3 sum(0.0f);
      for (const std::uint32_t g : faces_of[position_id[v]])
        if (glm::dot(face_normal[g], face_normal[f]) >= cos_crease) sum += openingAngle(g, position_id[v]) * face_normal[g];
      const float len = glm::length(sum);
      const glm::vec3 n = len > 0 ? sum / len : face_normal[f];
      const auto key = std::make_pair(v, std::array<float, 3>{n.x, n.y, n.z});
      auto [it, inserted] = vertex_of.try_emplace(key, std::uint32_t(positions.size()));
      if (inserted) {
        positions.push_back(mesh.positions[v]);
        normals.push_back(n);
        if (has_uvs) uvs.push_back(mesh.uvs[v]);
      }
      triangles[f][k] = it->second;
    }
  }
  mesh.positions = std::move(positions);
  mesh.normals = std::move(normals);
  mesh.uvs = std::move(uvs);
  mesh.triangles = std::move(triangles);
}

void transformMesh(TriangleMesh& mesh, const glm::mat4& transform) {
  const glm::mat3 linear(transform);
  if (!(std::abs(glm::determinant(linear)) > 0.0f)) throw Error(mesh.name + ": the transform is singular");
  const glm::mat3 normal_matrix = glm::transpose(glm::inverse(linear));
  for (glm::vec3& p : mesh.positions) p = glm::vec3(transform * glm::vec4(p, 1.0f));
  for (glm::vec3& n : mesh.normals)
    if (n != glm::vec3(0.0f)) n = glm::normalize(normal_matrix * n);
  // A mirroring transform flips the winding's normal; swapping two corners keeps the geometric
  // normal on the side of the transformed vertex normals.
  if (glm::determinant(linear) < 0.0f)
    for (glm::uvec3& t : mesh.triangles) std::swap(t.y, t.z);
}

TriangleMesh makeQuad(const glm::vec3& corner, const glm::vec3& edge_u, const glm::vec3& edge_v, std::string name) {
  TriangleMesh mesh;
  mesh.name = std::move(name);
  mesh.positions = {corner, corner + edge_u, corner + edge_u + edge_v, corner + edge_v};
  mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const glm::vec3 n = glm::cross(edge_u, edge_v);
  if (!(glm::length(n) > 0.0f) || !finite(n)) throw Error(mesh.name + ": the quad's edges span no area");
  mesh.normals.assign(4, glm::normalize(n));
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

TriangleMesh makeSphere(const glm::vec3& center, float radius, int rings, std::string name) {
  TriangleMesh mesh;
  mesh.name = std::move(name);
  if (!(radius > 0.0f) || !std::isfinite(radius)) throw Error(mesh.name + ": the sphere's radius must be positive and finite");
  if (!finite(center)) throw Error(mesh.name + ": the sphere's center must be finite");
  rings = std::max(rings, 3);
  const int segments = 2 * rings;
  // Vertices on a (rings + 1) x (segments + 1) grid: the seam and the poles repeat positions so that
  // UVs stay continuous; the pole rows make degenerate triangles, which are not emitted.
  for (int i = 0; i <= rings; ++i) {
    const float theta = kPi * float(i) / float(rings);
    for (int j = 0; j <= segments; ++j) {
      const float phi = kTwoPi * float(j) / float(segments);
      const glm::vec3 n{std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)};
      mesh.positions.push_back(center + radius * n);
      mesh.normals.push_back(n);
      mesh.uvs.push_back({float(j) / float(segments), float(i) / float(rings)});
    }
  }
  auto at = [&](int i, int j) { return std::uint32_t(i * (segments + 1) + j); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      // Counter-clockwise seen from outside: the normal of the winding points out.
      if (i > 0) mesh.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j)});
      if (i + 1 < rings) mesh.triangles.push_back({at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)});
    }
  return mesh;
}

}  // namespace btf::render
