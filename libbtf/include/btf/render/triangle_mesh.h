// Triangle meshes: read from OBJ files (with their .mtl colours, through tinyobjloader) and PLY
// files, or built from simple shapes; cleaned of triangles that cannot be hit; smooth vertex normals.
#pragma once

#include <glm/glm.hpp>

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "btf/core/rgb.h"

namespace btf::render {

struct TriangleMesh {
  std::string name;  // "<file>" or "<file>:<part>", for messages
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // per vertex, unit length; empty: flat shading
  std::vector<glm::vec2> uvs;      // per vertex; empty when the file has none
  std::vector<glm::uvec3> triangles;
  // From the file's material (OBJ .mtl), if any: its name, diffuse colour Kd and emission Ke.
  std::string file_material;
  Rgb file_diffuse{0.5f};
  Rgb file_emission{0.0f};
};

// What loading and cleaning left out, counted for one warning per mesh rather than one per face.
struct MeshCleanup {
  std::size_t degenerate = 0;  // zero area (repeated or collinear vertices)
  std::size_t non_finite = 0;  // a NaN or infinite coordinate
  std::size_t out_of_range = 0;  // a vertex index past the vertex list
};

// Every part of an OBJ or PLY file (a .gz file is decompressed first, so `dragon.ply.gz` reads as a
// PLY), one mesh per part (an OBJ's group or object, and material), polygons triangulated, with the normals and UVs the file has. Throws
// FileError naming the file for a missing or unreadable file, a file with no triangle at all, or
// an unknown format. What the file leaves to defaults (an OBJ's material library that is missing
// or a folder, a usemtl of a material no library defines) is a warning: added to `warnings` when
// given, else logged through btf::log.
std::vector<TriangleMesh> loadTriangleMeshes(const std::filesystem::path& path,
                                             std::vector<std::string>* warnings = nullptr);

// Drops degenerate, non-finite and out-of-range triangles (and then unused vertices' effect on
// nothing: vertices stay), returning the counts.
MeshCleanup removeInvalidTriangles(TriangleMesh& mesh);
// The same, and one warning through btf::log that counts what was dropped (if anything).
MeshCleanup removeInvalidTrianglesWithWarning(TriangleMesh& mesh);

// Smooth vertex normals: each corner's normal is the average of the normals of the faces around its
// vertex, each weighted by the face's opening angle at the vertex (Thürmer and Wüthrich 1998; the
// weighting makes the result independent of how a surface is cut into triangles). Faces whose
// normals differ from the corner's face by more than crease_deg do not take part, so the edges of a
// box stay sharp while a scanned surface is smooth; corners that end up with different normals get
// vertices of their own. Replaces any normals the mesh had.
void computeVertexNormals(TriangleMesh& mesh, float crease_deg);

// Applies an affine transform to positions and (by the inverse transpose) normals. Throws
// btf::Error for a singular transform.
void transformMesh(TriangleMesh& mesh, const glm::mat4& transform);

// Simple shapes, with UVs in [0, 1]^2.
// A parallelogram corner, corner + edge_u, corner + edge_u + edge_v, corner + edge_v; its normal is
// cross(edge_u, edge_v).
TriangleMesh makeQuad(const glm::vec3& corner, const glm::vec3& edge_u, const glm::vec3& edge_v, std::string name);
// A UV sphere of `rings` latitude bands and 2 * rings longitude segments, with exact normals.
TriangleMesh makeSphere(const glm::vec3& center, float radius, int rings, std::string name);

}  // namespace btf::render
