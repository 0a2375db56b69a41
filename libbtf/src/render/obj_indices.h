// A check of an OBJ file's elements before Assimp reads it (triangle_mesh.cpp). Assimp's OBJ
// importer throws when an element indexes past the vertex list or has too few vertices, and when
// that happens after a group statement it leaks the meshes it had built (found by fuzz_mesh). So
// every face (f), line (l) and point (p) is checked first: at least 3, 2 and 1 vertices, and every
// vertex, texture-coordinate and normal index a number within its list (positive: 1 to the file's
// count; negative: relative, within the entries defined before the element; never 0). Control
// characters other than tab and carriage return are refused first: Assimp ends a line at NUL and
// form feed, so with them its lines would not be the lines checked here.
#pragma once

#include <filesystem>
#include <string_view>

namespace btf::render {

// Throws FileError naming the file, the line and the problem.
void checkObjElements(const std::filesystem::path& path, std::string_view text);

}  // namespace btf::render
