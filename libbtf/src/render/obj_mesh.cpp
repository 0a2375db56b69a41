#include "obj_mesh.h"

// tinyobjloader is a single-header library: its implementation is compiled here, in libbtf, so
// that the sanitizer builds (the unit tests under ASan, the fuzz targets) instrument it as our
// own code: a write past a block inside a prebuilt library goes unseen until it corrupts the
// allocator, far from its cause (Assimp's PLY reader did so under fuzz_mesh).
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>

#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <tuple>
#include <utility>

#include "btf/core/error.h"
#include "file_normal.h"
#include "obj_check.h"

namespace btf::render {
namespace {

// Material libraries named by `mtllib`, looked for beside the OBJ (or where an absolute name
// points). Regular files only: a folder or a device such as /dev/zero (which would read for ever)
// is a library not found, which tinyobjloader warns of and reads on without. A file named again
// (under another name: "a.mtl", "./a.mtl") is read once: tinyobjloader would add its materials
// again each time, and one line of names can name a file hundreds of times.
class MaterialLibraryReader : public tinyobj::MaterialReader {
 public:
  explicit MaterialLibraryReader(std::filesystem::path folder) : folder_(std::move(folder)) {}
  bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                  std::map<std::string, int>* index_of, std::string* warning, std::string* error) override {
    const std::filesystem::path file = folder_ / name;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) {
      *warning += "the material library '" + name + "' " +
                  (std::filesystem::exists(file, ec) ? "is not a regular file" : "was not found") + " (" + file.string() +
                  "); its materials are grey\n";
      return false;
    }
    if (!read_.insert(std::filesystem::canonical(file, ec)).second) return true;
    // As many bytes as the file system says the file holds: the files of /proc say 0, and some
    // of them (/proc/kmsg) would block a read for ever.
    const std::uintmax_t size = std::filesystem::file_size(file, ec);
    if (ec) return false;
    std::string bytes(size, '\0');
    std::ifstream in(file, std::ios::binary);
    if (!in.read(bytes.data(), std::streamsize(size))) return false;
    std::istringstream text(std::move(bytes));
    tinyobj::LoadMtl(index_of, materials, &text, warning, error);
    return true;
  }

 private:
  std::filesystem::path folder_;
  std::set<std::filesystem::path> read_;
};

Rgb rgbOf(const tinyobj::real_t (&c)[3]) { return {float(c[0]), float(c[1]), float(c[2])}; }

}  // namespace

std::vector<TriangleMesh> readObjMeshes(const std::filesystem::path& path, std::string_view text,
                                        std::vector<std::string>& warnings) {
  std::istringstream statements(checkedObjStatements(path, text));
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warning, error;
  MaterialLibraryReader material_libraries(path.parent_path());
  if (!tinyobj::LoadObj(&attrib, &shapes, &materials, &warning, &error, &statements, &material_libraries,
                        /*triangulate=*/true, /*default_vcols_fallback=*/false))
    throw FileError(path, "cannot read the OBJ file: " + error);
  // tinyobjloader's warnings, a line each ("material [x] not found in .mtl", ...): what the file
  // left to defaults.
  std::istringstream lines(warning);
  for (std::string line; std::getline(lines, line);)
    if (!line.empty()) warnings.push_back(line);

  const std::size_t vertex_count = attrib.vertices.size() / 3;
  const std::size_t uv_count = attrib.texcoords.size() / 2;
  const std::size_t normal_count = attrib.normals.size() / 3;
  std::vector<TriangleMesh> meshes;
  for (const tinyobj::shape_t& shape : shapes) {
    // A shape is a group (g or o); its faces may change material (usemtl) along the way. One mesh
    // per material, in the order the materials first appear, so each can be given its own.
    std::vector<int> material_order;
    std::map<int, std::vector<std::size_t>> faces_of;  // first index of each triangle
    std::size_t offset = 0;
    for (std::size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
      const std::size_t corners = shape.mesh.num_face_vertices[f];
      if (corners == 3 && offset + 3 <= shape.mesh.indices.size()) {
        const int material = f < shape.mesh.material_ids.size() ? shape.mesh.material_ids[f] : -1;
        auto [it, inserted] = faces_of.try_emplace(material);
        if (inserted) material_order.push_back(material);
        it->second.push_back(offset);
      }
      offset += corners;
    }
    for (const int material : material_order) {
      const std::vector<std::size_t>& faces = faces_of[material];
      TriangleMesh out;
      out.name = path.string() + (shape.name.empty() ? "" : ":" + shape.name);
      // A vertex per distinct (position, texture coordinate, normal) of the corners, in the order
      // first used. Texture coordinates and normals are kept when every corner has one.
      bool all_uvs = true, all_normals = true;
      for (const std::size_t first : faces)
        for (std::size_t k = 0; k < 3; ++k) {
          const tinyobj::index_t& i = shape.mesh.indices[first + k];
          all_uvs = all_uvs && i.texcoord_index >= 0;
          all_normals = all_normals && i.normal_index >= 0;
        }
      std::map<std::tuple<int, int, int>, std::uint32_t> vertex_of;
      for (const std::size_t first : faces) {
        glm::uvec3 triangle;
        for (std::size_t k = 0; k < 3; ++k) {
          const tinyobj::index_t& i = shape.mesh.indices[first + k];
          // checkedObjStatements has bounded every index; this keeps a reader change from turning
          // into a read past a list.
          if (i.vertex_index < 0 || std::size_t(i.vertex_index) >= vertex_count ||
              (all_uvs && std::size_t(i.texcoord_index) >= uv_count) ||
              (all_normals && std::size_t(i.normal_index) >= normal_count))
            throw FileError(path, "a face indexes past the lists of the OBJ file");
          const auto key = std::make_tuple(i.vertex_index, all_uvs ? i.texcoord_index : -1, all_normals ? i.normal_index : -1);
          const auto [it, inserted] = vertex_of.try_emplace(key, std::uint32_t(out.positions.size()));
          if (inserted) {
            const tinyobj::real_t* p = &attrib.vertices[3 * std::size_t(i.vertex_index)];
            out.positions.push_back({p[0], p[1], p[2]});
            if (all_uvs) {
              const tinyobj::real_t* t = &attrib.texcoords[2 * std::size_t(i.texcoord_index)];
              out.uvs.push_back({t[0], t[1]});
            }
            if (all_normals) {
              const tinyobj::real_t* n = &attrib.normals[3 * std::size_t(i.normal_index)];
              out.normals.push_back(fileNormal({n[0], n[1], n[2]}));
            }
          }
          triangle[int(k)] = it->second;
        }
        out.triangles.push_back(triangle);
      }
      // A face without a material (none given, or a usemtl naming none of the libraries') keeps
      // the defaults of TriangleMesh.
      if (material >= 0 && std::size_t(material) < materials.size()) {
        out.file_material = materials[std::size_t(material)].name;
        out.file_diffuse = rgbOf(materials[std::size_t(material)].diffuse);
        out.file_emission = rgbOf(materials[std::size_t(material)].emission);
      }
      meshes.push_back(std::move(out));
    }
  }
  return meshes;
}

}  // namespace btf::render
