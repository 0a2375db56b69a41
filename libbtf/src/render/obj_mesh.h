// OBJ files (with the colours of their .mtl) read through tinyobjloader, for loadTriangleMeshes.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "btf/render/triangle_mesh.h"

namespace btf::render {

// One mesh per group (g, o) and material (usemtl) of the OBJ text of `path`, polygons
// triangulated; material libraries (mtllib) are looked for beside `path`. Throws FileError naming
// the file for a malformed file (obj_check.h says what is checked). What falls back to defaults
// (a material library not found, a usemtl of an unknown material) is added to `warnings`.
std::vector<TriangleMesh> readObjMeshes(const std::filesystem::path& path, std::string_view text,
                                        std::vector<std::string>& warnings);

}  // namespace btf::render
