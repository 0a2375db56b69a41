#include "btf/render/triangle_mesh.h"

#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <utility>

#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/progress.h"
#include "obj_indices.h"

namespace btf::render {
namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::string readFileBytes(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw FileError(path, "no such mesh file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path, "cannot open the mesh file");
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// zlib's gzip stream decoder; Assimp reads PLY from memory but does not unpack .gz itself.
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

// Assimp's PLY reader loops forever on a header without "end_header", and reads a body that ends
// early as if it were complete (faces of garbage) or past its end. So the structure is checked
// first: a complete header, and a body holding every element the header declares.
void checkPlyStructure(const std::filesystem::path& path, const std::string& bytes) {
  auto fail = [&](const std::string& problem) { throw FileError(path, problem); };
  struct Property {
    int size = 0;        // bytes of a scalar, or of a list's items
    int count_size = 0;  // bytes of a list's count; 0 for a scalar
    bool count_signed = false;
    std::string name;
    bool item_signed = false, item_integer = true;  // of a list's items
  };
  struct Element {
    std::string name;
    unsigned long long count = 0;
    std::vector<Property> properties;
  };
  auto typeSize = [](const std::string& type) {
    if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
    if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
    if (type == "int" || type == "uint" || type == "int32" || type == "uint32" || type == "float" || type == "float32") return 4;
    if (type == "double" || type == "float64") return 8;
    return 0;
  };

  // The header: lines up to "end_header".
  std::size_t pos = 0;
  std::string format;
  std::vector<Element> elements;
  bool first = true, ended = false;
  while (!ended) {
    const std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) fail("truncated PLY header (no end_header line)");
    std::string line = bytes.substr(pos, eol - pos);
    pos = eol + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    // Words are separated by spaces and tabs only: Assimp's tokenizer takes a vertical tab or a
    // form feed (which istream counts as space) as part of a word, misses "end_header" followed
    // by one, and then reads the body as header for ever.
    if (std::any_of(line.begin(), line.end(), [](char c) { return (static_cast<unsigned char>(c) < 0x20 && c != '\t') || c == 0x7f; }))
      fail("malformed PLY header: a control character in line " + std::to_string(std::count(bytes.begin(), bytes.begin() + std::ptrdiff_t(pos), '\n')));
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (first) {
      if (keyword != "ply") fail("not a PLY file (it does not start with \"ply\")");
      first = false;
    } else if (keyword == "format") {
      words >> format;
    } else if (keyword == "element") {
      Element e;
      std::string count;
      std::string extra;
      words >> e.name >> count >> extra;
      const auto [end, ec] = std::from_chars(count.data(), count.data() + count.size(), e.count);
      if (ec != std::errc() || end != count.data() + count.size() || !extra.empty())
        fail("malformed PLY header line '" + line + "'");
      // Assimp reads the count of an element it has no meaning for (not vertex, face...) from the
      // start of its name, so a name of digits ("4444vertex 3") becomes billions of instances that
      // it allocates. Names are words that begin with a letter or an underscore.
      if (!std::isalpha(static_cast<unsigned char>(e.name[0])) && e.name[0] != '_')
        fail("malformed PLY header line '" + line + "': an element name begins with a letter");
      elements.push_back(std::move(e));
    } else if (keyword == "property") {
      if (elements.empty()) fail("malformed PLY header: a property before any element");
      std::string type;
      words >> type;
      Property p;
      if (type == "list") {
        std::string count_type, item_type;
        words >> count_type >> item_type;
        p.count_size = typeSize(count_type);
        p.count_signed = count_type == "char" || count_type == "short" || count_type.rfind("int", 0) == 0;
        p.size = typeSize(item_type);
        p.item_signed = item_type == "char" || item_type == "short" || item_type.rfind("int", 0) == 0;
        p.item_integer = item_type.find("float") == std::string::npos && item_type != "double";
        words >> p.name;
        if (p.count_size == 0 || count_type.find("float") != std::string::npos || count_type == "double")
          fail("malformed PLY header line '" + line + "'");
      } else {
        p.size = typeSize(type);
        words >> p.name;
      }
      if (p.size == 0) fail("malformed PLY header line '" + line + "'");
      elements.back().properties.push_back(p);
    } else if (keyword == "end_header") {
      ended = true;
    } else if (keyword != "comment" && keyword != "obj_info" && !keyword.empty()) {
      fail("malformed PLY header line '" + line + "'");
    }
  }
  // An element without properties takes no bytes, so the body walk below cannot bound its count;
  // Assimp would build every one of them (2^31 empty faces take minutes).
  for (const Element& e : elements)
    if (e.count > 0 && e.properties.empty())
      fail("PLY element '" + e.name + "' declares " + std::to_string(e.count) + " instances but no properties");
  const bool ascii = format == "ascii";
  const bool big_endian = format == "binary_big_endian";
  if (!ascii && !big_endian && format != "binary_little_endian") fail("unknown PLY format '" + format + "'");
  // Vertices need positions: Assimp reads a vertex element without x, y or z into a mesh that its
  // triangulation then aborts on (an assertion, not an error).
  for (const Element& e : elements) {
    if (e.name != "vertex" || e.count == 0) continue;
    for (const char* axis : {"x", "y", "z"})
      if (std::none_of(e.properties.begin(), e.properties.end(), [&](const Property& p) { return p.name == axis && p.count_size == 0; }))
        fail(std::string("PLY vertices without the position property '") + axis + "'");
  }

  // The body. Every element instance with a property takes at least one byte or one word, so the
  // walk ends within the file's size whatever counts the header declares.
  const char* const end = bytes.data() + bytes.size();
  const char* at = bytes.data() + pos;
  auto truncated = [&](const Element& e, unsigned long long i) {
    fail("truncated PLY: the data ends in element '" + e.name + "' " + std::to_string(i) + " of " + std::to_string(e.count));
  };
  auto nextWord = [&](double& value) {
    while (at < end && std::isspace(static_cast<unsigned char>(*at))) ++at;
    const char* start = at;
    while (at < end && !std::isspace(static_cast<unsigned char>(*at))) ++at;
    if (start == at) return false;
    const char* digits = *start == '+' ? start + 1 : start;  // from_chars takes no plus sign
    const auto [stop, ec] = std::from_chars(digits, at, value);
    if (ec != std::errc() || stop != at) fail("malformed PLY data: '" + std::string(start, at) + "' is not a number");
    return true;
  };
  auto readCount = [&](const Property& p) {
    unsigned char raw[4] = {};
    for (int b = 0; b < p.count_size; ++b) raw[big_endian ? p.count_size - 1 - b : b] = static_cast<unsigned char>(at[b]);
    std::uint32_t u = 0;
    for (int b = p.count_size - 1; b >= 0; --b) u = (u << 8) | raw[b];
    at += p.count_size;
    const bool negative = p.count_signed && (raw[p.count_size - 1] & 0x80u);
    return negative ? -1.0 : double(u);
  };
  // Face lists must index existing vertices and hold 3 or more: Assimp drops the indices past the
  // vertex list, and its triangulation aborts (an assertion) on faces of fewer than 3.
  unsigned long long vertex_count = 0;
  for (const Element& e : elements)
    if (e.name == "vertex") vertex_count = e.count;
  auto indexes_vertices = [](const Element& e, const Property& p) {
    return e.name == "face" && (p.name == "vertex_indices" || p.name == "vertex_index");
  };
  auto checkIndex = [&](double index, const Element& e, unsigned long long i) {
    if (!(index >= 0) || index != std::floor(index) || index >= double(vertex_count))
      fail("PLY " + e.name + " " + std::to_string(i) + ": vertex index " + std::to_string(static_cast<long long>(index)) +
           " out of range (there are " + std::to_string(vertex_count) + " vertices)");
  };
  auto checkFaceSize = [&](double n, const Element& e, unsigned long long i) {
    if (n < 3) fail("PLY " + e.name + " " + std::to_string(i) + " has " + std::to_string(static_cast<long long>(n)) +
                    " vertices (a face needs 3 or more)");
  };
  for (const Element& e : elements) {
    if (e.properties.empty()) continue;
    for (unsigned long long i = 0; i < e.count; ++i)
      for (const Property& p : e.properties) {
        double n = 1;
        if (ascii) {
          if (!nextWord(n)) truncated(e, i);
          if (p.count_size > 0) {
            if (!(n >= 0) || n != std::floor(n)) fail("malformed PLY data: a list of " + std::to_string(n) + " items");
            if (indexes_vertices(e, p)) checkFaceSize(n, e, i);
            for (double k = 0, v = 0; k < n; ++k) {
              if (!nextWord(v)) truncated(e, i);
              if (indexes_vertices(e, p)) checkIndex(v, e, i);
            }
          }
        } else {
          if (p.count_size > 0) {
            if (end - at < p.count_size) truncated(e, i);
            n = readCount(p);
            if (n < 0) fail("malformed PLY data: a list of negative length");
            if (indexes_vertices(e, p)) checkFaceSize(n, e, i);
          }
          if (double(end - at) < n * p.size) truncated(e, i);
          if (p.count_size > 0 && p.item_integer && indexes_vertices(e, p))
            for (double k = 0; k < n; ++k) {
              unsigned char raw[4] = {};
              for (int b = 0; b < p.size && b < 4; ++b) raw[big_endian ? p.size - 1 - b : b] = static_cast<unsigned char>(at[b]);
              std::uint32_t u = 0;
              for (int b = std::min(p.size, 4) - 1; b >= 0; --b) u = (u << 8) | raw[b];
              const bool negative = p.item_signed && (raw[std::min(p.size, 4) - 1] & 0x80u);
              checkIndex(negative ? -1.0 : double(u), e, i);
              at += p.size;
            }
          else
            at += std::ptrdiff_t(n) * p.size;
        }
      }
  }
}

Rgb colourOf(const aiMaterial* material, const char* key, unsigned type, unsigned index, Rgb fallback) {
  aiColor3D c;
  if (material && material->Get(key, type, index, c) == AI_SUCCESS) return {c.r, c.g, c.b};
  return fallback;
}

// The files Assimp opens besides the mesh (an OBJ's material libraries) must be regular files.
// An `mtllib` naming a folder opened, then failed to read, and Assimp's OBJ importer threw without
// closing it (a leak); one naming a device such as /dev/zero would read for ever. Refused here,
// they are material libraries not found, which Assimp reports and goes on without.
class RegularFilesIOSystem : public Assimp::DefaultIOSystem {
 public:
  bool Exists(const char* file) const override {
    std::error_code ec;
    return std::filesystem::is_regular_file(file, ec);
  }
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    return Exists(file) ? Assimp::DefaultIOSystem::Open(file, mode) : nullptr;
  }
};

}  // namespace

std::vector<TriangleMesh> loadTriangleMeshes(const std::filesystem::path& path) {
  std::string extension = lowercase(path.extension().string());
  std::string bytes = readFileBytes(path);
  if (extension == ".gz") {
    bytes = gunzip(path, bytes);
    extension = lowercase(path.stem().extension().string());
  }
  if (extension != ".obj" && extension != ".ply")
    throw FileError(path, "unknown mesh format '" + extension + "' (expected .obj, .ply or .ply.gz)");
  if (bytes.empty()) throw FileError(path, "empty mesh file");

  Assimp::Importer importer;
  importer.SetIOHandler(new RegularFilesIOSystem);  // the importer owns it
  // No normal generation, no vertex welding across parts: normals are ours (computeVertexNormals),
  // and an OBJ's parts stay separate meshes so each can get its own material.
  // ValidateDataStructure runs first: a truncated or corrupt file can leave faces indexing past the
  // vertex list, which the other steps would read without checking (a crash, not an error).
  const unsigned flags =
      aiProcess_ValidateDataStructure | aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType;
  const aiScene* scene = nullptr;
  if (extension == ".obj") {
    // From the file itself, so that the .mtl beside it is found.
    if (lowercase(path.extension().string()) == ".gz") throw FileError(path, "gzipped OBJ files are not read (their .mtl could not be found)");
    checkObjElements(path, bytes);
    scene = importer.ReadFile(path.string(), flags);
  } else {
    checkPlyStructure(path, bytes);
    scene = importer.ReadFileFromMemory(bytes.data(), bytes.size(), flags, "ply");
  }
  if (!scene || !scene->mRootNode) {
    const std::string why = importer.GetErrorString();
    throw FileError(path, "cannot read the mesh" + (why.empty() ? std::string() : ": " + why));
  }

  // Meshes are referenced by nodes with transforms; OBJ and PLY put them all at the root with the
  // identity, so meshes are taken as stored.
  std::vector<TriangleMesh> meshes;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* in = scene->mMeshes[m];
    if (!(in->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;  // points and lines
    TriangleMesh out;
    const std::string part = in->mName.length ? std::string(in->mName.C_Str()) : std::string();
    out.name = path.string() + (part.empty() ? "" : ":" + part);
    out.positions.resize(in->mNumVertices);
    for (unsigned v = 0; v < in->mNumVertices; ++v)
      out.positions[v] = {in->mVertices[v].x, in->mVertices[v].y, in->mVertices[v].z};
    if (in->HasNormals()) {
      out.normals.resize(in->mNumVertices);
      for (unsigned v = 0; v < in->mNumVertices; ++v) {
        const glm::vec3 n{in->mNormals[v].x, in->mNormals[v].y, in->mNormals[v].z};
        const float len = glm::length(n);
        out.normals[v] = len > 0 && std::isfinite(len) ? n / len : glm::vec3(0.0f);
      }
    }
    if (in->HasTextureCoords(0)) {
      out.uvs.resize(in->mNumVertices);
      for (unsigned v = 0; v < in->mNumVertices; ++v) out.uvs[v] = {in->mTextureCoords[0][v].x, in->mTextureCoords[0][v].y};
    }
    out.triangles.reserve(in->mNumFaces);
    for (unsigned f = 0; f < in->mNumFaces; ++f) {
      const aiFace& face = in->mFaces[f];
      if (face.mNumIndices == 3) out.triangles.push_back({face.mIndices[0], face.mIndices[1], face.mIndices[2]});
    }
    if (in->mMaterialIndex < scene->mNumMaterials) {
      const aiMaterial* material = scene->mMaterials[in->mMaterialIndex];
      aiString name;
      if (material->Get(AI_MATKEY_NAME, name) == AI_SUCCESS) out.file_material = name.C_Str();
      // Assimp gives a file without materials a stand-in (named AI_DEFAULT_MATERIAL_NAME for OBJ,
      // nameless for PLY); it carries no colours of the file (its own are 0.6 grey for OBJ, white
      // for PLY), so the mesh keeps the defaults of TriangleMesh.
      if (out.file_material.empty() || out.file_material == AI_DEFAULT_MATERIAL_NAME) {
        out.file_material.clear();
      } else {
        out.file_diffuse = colourOf(material, AI_MATKEY_COLOR_DIFFUSE, out.file_diffuse);
        out.file_emission = colourOf(material, AI_MATKEY_COLOR_EMISSIVE, out.file_emission);
      }
    }
    if (!out.triangles.empty()) meshes.push_back(std::move(out));
  }
  if (meshes.empty()) throw FileError(path, "the mesh has no faces");
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
