// OBJ files (with the colours of their .mtl) read through tinyobjloader, for loadTriangleMeshes.
#pragma once

#include <filesystem>
#include <string_view>
#include <vector>

#include "btf/render/triangle_mesh.h"

namespace btf::render {

// One mesh per group (g, o) and material (usemtl) of the OBJ text of `path`, polygons
// triangulated; material libraries (mtllib) are looked for beside `path`. Throws FileError naming
// the file for a malformed file (obj_check.h says what is checked).
std::vector<TriangleMesh> readObjMeshes(const std::filesystem::path& path, std::string_view text);

}  // namespace btf::render
