// The check of an OBJ file before tinyobjloader reads it (obj_mesh.cpp), and the statements it
// is given. tinyobjloader reads what it cannot parse as zeros, indexes with atoi, and skips a face
// that indexes past its lists with a warning; so every face (f) is checked here first: at least 3
// vertices, every vertex, texture-coordinate and normal index a number within its list (positive:
// 1 to the file's count; negative: relative, within the entries defined before the face; never
// 0), and every v, vt and vn entry finite numbers, as many as the statement takes. Control
// characters other than tab and carriage return are refused: a line read here must be the line
// tinyobjloader reads, and an OBJ is text.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace btf::render {

// Throws FileError naming the file, the line and the problem. Returns the text tinyobjloader is
// to read: the file's lines, each ended by '\n' (lines end at "\n", "\r\n" or "\r", as
// tinyobjloader ends them), with every statement a mesh does not need blanked: only v, vt, vn, f,
// g, o, usemtl and mtllib are kept. The others (lines, points, curves, tinyobjloader's own tags
// and skin weights) are not modelled, and tinyobjloader copies its tags into every group that
// follows them, so memory and time grow as tags x groups: a few kilobytes of file can exhaust both.
std::string checkedObjStatements(const std::filesystem::path& path, std::string_view text);

}  // namespace btf::render
