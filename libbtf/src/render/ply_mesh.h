// PLY files (ASCII and binary of either byte order), read by libbtf itself.
#pragma once

#include <filesystem>
#include <string_view>

#include "btf/render/triangle_mesh.h"

namespace btf::render {

// The mesh of the PLY data `bytes` of `path`: positions of the vertex element (x, y, z), its normals
// (nx, ny, nz) and texture coordinates (u, v or s, t) when it has all of them, and the polygons of
// the face element (vertex_indices or vertex_index) as triangle fans; vertices no face uses are
// left out. Other elements and properties are skipped. Throws FileError naming the file and the
// problem for a malformed or truncated file.
TriangleMesh readPlyMesh(const std::filesystem::path& path, std::string_view bytes);

}  // namespace btf::render
