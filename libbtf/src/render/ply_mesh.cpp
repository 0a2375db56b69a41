#include "ply_mesh.h"

// Read by hand: the one PLY reader in Debian 12 outside large geometry libraries (CGAL, Open3D,
// PCL, VTK) is Assimp's, and under fuzz_mesh it looped for ever, read past the data, aborted,
// allocated without bound and wrote past a heap block (docs/design-notes.md#readers-under-fuzzing).
// PLY is a short format: a header of elements and their properties, then the instances of each
// element in order, as words or as binary scalars.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "btf/core/error.h"
#include "file_normal.h"

namespace btf::render {
namespace {

struct ScalarType {
  int size = 0;  // bytes; 0 for an unknown type name
  bool is_signed = false;
  bool integer = true;
};

ScalarType scalarType(const std::string& name) {
  if (name == "char" || name == "int8") return {1, true, true};
  if (name == "uchar" || name == "uint8") return {1, false, true};
  if (name == "short" || name == "int16") return {2, true, true};
  if (name == "ushort" || name == "uint16") return {2, false, true};
  if (name == "int" || name == "int32") return {4, true, true};
  if (name == "uint" || name == "uint32") return {4, false, true};
  if (name == "float" || name == "float32") return {4, true, false};
  if (name == "double" || name == "float64") return {8, true, false};
  return {};
}

struct Property {
  std::string name;
  ScalarType type;        // of the value, or of a list's items
  ScalarType count_type;  // of a list's count; size 0 for a scalar
  bool isList() const { return count_type.size > 0; }
};

struct Element {
  std::string name;
  unsigned long long count = 0;
  std::vector<Property> properties;
};

enum class Format { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct Header {
  Format format = Format::Ascii;
  std::vector<Element> elements;
  std::size_t body = 0;  // offset of the first byte after "end_header\n"
};

Header readHeader(const std::filesystem::path& path, std::string_view bytes) {
  auto fail = [&](const std::string& problem) { throw FileError(path, problem); };
  Header header;
  std::string format;
  std::size_t pos = 0, line_number = 0;
  bool ended = false;
  while (!ended) {
    const std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string_view::npos) fail("truncated PLY header (no end_header line)");
    std::string line(bytes.substr(pos, eol - pos));
    pos = eol + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    // Words are separated by spaces and tabs only (a vertical tab or a form feed, which istream
    // counts as space, would make "end_header\v" read as the end of the header).
    if (std::any_of(line.begin(), line.end(), [](char c) { return (static_cast<unsigned char>(c) < 0x20 && c != '\t') || c == 0x7f; }))
      fail("malformed PLY header: a control character in line " + std::to_string(line_number));
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    auto malformed = [&] { fail("malformed PLY header line '" + line + "'"); };
    if (line_number == 1) {
      if (keyword != "ply") fail("not a PLY file (it does not start with \"ply\")");
    } else if (keyword == "format") {
      words >> format;
    } else if (keyword == "element") {
      Element e;
      std::string count, extra;
      words >> e.name >> count >> extra;
      const auto [end, ec] = std::from_chars(count.data(), count.data() + count.size(), e.count);
      if (e.name.empty() || ec != std::errc() || end != count.data() + count.size() || !extra.empty()) malformed();
      for (const Element& other : header.elements)
        if (other.name == e.name) fail("PLY element '" + e.name + "' declared twice");
      header.elements.push_back(std::move(e));
    } else if (keyword == "property") {
      if (header.elements.empty()) fail("malformed PLY header: a property before any element");
      std::string type;
      words >> type;
      Property p;
      if (type == "list") {
        std::string count_type, item_type;
        words >> count_type >> item_type >> p.name;
        p.count_type = scalarType(count_type);
        p.type = scalarType(item_type);
        if (!p.count_type.integer) malformed();  // a list's length is a whole number
      } else {
        p.type = scalarType(type);
        words >> p.name;
      }
      if (p.type.size == 0 || p.name.empty() || (type == "list" && p.count_type.size == 0)) malformed();
      header.elements.back().properties.push_back(std::move(p));
    } else if (keyword == "end_header") {
      ended = true;
    } else if (keyword != "comment" && keyword != "obj_info" && !keyword.empty()) {
      malformed();
    }
  }
  header.body = pos;
  if (format == "ascii") header.format = Format::Ascii;
  else if (format == "binary_little_endian") header.format = Format::BinaryLittleEndian;
  else if (format == "binary_big_endian") header.format = Format::BinaryBigEndian;
  else fail("unknown PLY format '" + format + "'");
  return header;
}

// The values of the body, one at a time, as doubles (every PLY scalar fits one exactly).
class BodyReader {
 public:
  BodyReader(const std::filesystem::path& path, std::string_view bytes, std::size_t start, Format format)
      : path_(path), at_(bytes.data() + start), end_(bytes.data() + bytes.size()), format_(format) {}

  // False when the data has ended.
  bool read(const ScalarType& type, double& value) {
    if (format_ == Format::Ascii) return readWord(value);
    if (end_ - at_ < type.size) return false;
    std::uint64_t bits = 0;
    for (int b = 0; b < type.size; ++b) {
      const int shift = 8 * (format_ == Format::BinaryBigEndian ? type.size - 1 - b : b);
      bits |= std::uint64_t(static_cast<unsigned char>(at_[b])) << shift;
    }
    at_ += type.size;
    if (!type.integer) {
      if (type.size == 4) {
        float f;
        const auto u = std::uint32_t(bits);
        std::memcpy(&f, &u, 4);
        value = f;
      } else {
        std::memcpy(&value, &bits, 8);
      }
    } else if (type.is_signed) {
      const int unused = 64 - 8 * type.size;  // sign extension from the value's top bit
      value = double(static_cast<std::int64_t>(bits << unused) >> unused);
    } else {
      value = double(bits);
    }
    return true;
  }

 private:
  bool readWord(double& value) {
    while (at_ < end_ && std::isspace(static_cast<unsigned char>(*at_))) ++at_;
    const char* start = at_;
    while (at_ < end_ && !std::isspace(static_cast<unsigned char>(*at_))) ++at_;
    if (start == at_) return false;
    const char* digits = *start == '+' ? start + 1 : start;  // from_chars takes no plus sign
    const auto [stop, ec] = std::from_chars(digits, at_, value);
    if (ec != std::errc() || stop != at_)
      throw FileError(path_, "malformed PLY data: '" + std::string(start, at_) + "' is not a number");
    return true;
  }

  const std::filesystem::path& path_;
  const char* at_;
  const char* end_;
  Format format_;
};

// A double as float: out of float's range it is infinite (a cast would be undefined), and the
// triangles it touches are dropped later as non-finite.
float toFloat(double d) {
  if (std::isnan(d)) return std::numeric_limits<float>::quiet_NaN();
  constexpr float kInfinity = std::numeric_limits<float>::infinity();
  if (std::abs(d) > double(std::numeric_limits<float>::max())) return d > 0 ? kInfinity : -kInfinity;
  return static_cast<float>(d);
}

// The index of the scalar property `name` of `e`, or -1.
int scalarIndex(const Element& e, const char* name) {
  for (std::size_t j = 0; j < e.properties.size(); ++j)
    if (e.properties[j].name == name && !e.properties[j].isList()) return int(j);
  return -1;
}

}  // namespace

TriangleMesh readPlyMesh(const std::filesystem::path& path, std::string_view bytes) {
  auto fail = [&](const std::string& problem) { throw FileError(path, problem); };
  const Header header = readHeader(path, bytes);

  const Element* vertex = nullptr;
  for (const Element& e : header.elements)
    if (e.name == "vertex") vertex = &e;
  const unsigned long long vertex_count = vertex ? vertex->count : 0;
  if (vertex_count > std::numeric_limits<std::uint32_t>::max())
    fail("PLY with " + std::to_string(vertex_count) + " vertices (at most 2^32 - 1 are read)");
  int position[3] = {-1, -1, -1}, normal[3] = {-1, -1, -1}, uv[2] = {-1, -1};
  if (vertex && vertex_count > 0) {
    const char* axes[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) {
      position[a] = scalarIndex(*vertex, axes[a]);
      if (position[a] < 0) fail(std::string("PLY vertices without the position property '") + axes[a] + "'");
    }
    const char* normal_names[3] = {"nx", "ny", "nz"};
    for (int a = 0; a < 3; ++a) normal[a] = scalarIndex(*vertex, normal_names[a]);
    if (std::min({normal[0], normal[1], normal[2]}) < 0) normal[0] = -1;
    for (const auto& [u, v] : {std::pair{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}, {"texture_s", "texture_t"}}) {
      uv[0] = scalarIndex(*vertex, u);
      uv[1] = scalarIndex(*vertex, v);
      if (uv[0] >= 0 && uv[1] >= 0) break;
      uv[0] = -1;
    }
  }

  TriangleMesh mesh;
  mesh.name = path.string();
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec2> uvs;
  BodyReader body(path, bytes, header.body, header.format);
  std::vector<double> scalars;
  std::vector<std::uint32_t> corners;
  for (const Element& e : header.elements) {
    // The face element's polygons: its first list named vertex_indices (or vertex_index).
    int face_list = -1;
    if (e.name == "face")
      for (std::size_t j = 0; j < e.properties.size() && face_list < 0; ++j)
        if (e.properties[j].isList() && (e.properties[j].name == "vertex_indices" || e.properties[j].name == "vertex_index"))
          face_list = int(j);
    if (e.name == "face" && e.count > 0 && face_list < 0) fail("PLY faces without a vertex_indices list");
    // An element without properties takes no bytes: there is nothing to read of it, however many.
    if (e.properties.empty()) continue;
    scalars.assign(e.properties.size(), 0.0);
    for (unsigned long long i = 0; i < e.count; ++i) {
      auto truncated = [&] {
        fail("truncated PLY: the data ends in element '" + e.name + "' " + std::to_string(i) + " of " + std::to_string(e.count));
      };
      for (std::size_t j = 0; j < e.properties.size(); ++j) {
        const Property& p = e.properties[j];
        if (!p.isList()) {
          if (!body.read(p.type, scalars[j])) truncated();
          continue;
        }
        double n = 0;
        if (!body.read(p.count_type, n)) truncated();
        if (!(n >= 0)) fail("malformed PLY data: a list of negative length");
        const bool polygon = int(j) == face_list;
        if (polygon) {
          if (n < 3)
            fail("PLY " + e.name + " " + std::to_string(i) + " has " + std::to_string(static_cast<long long>(n)) +
                 " vertices (a face needs 3 or more)");
          corners.clear();
        }
        // Each item takes a byte or a word at least, so a long list ends with the data.
        for (double k = 0; k < n; ++k) {
          double item = 0;
          if (!body.read(p.type, item)) truncated();
          if (!polygon) continue;
          if (!(item >= 0) || item != std::floor(item) || item >= double(vertex_count))
            fail("PLY " + e.name + " " + std::to_string(i) + ": vertex index " + std::to_string(static_cast<long long>(item)) +
                 " out of range (there are " + std::to_string(vertex_count) + " vertices)");
          corners.push_back(std::uint32_t(item));
        }
        // A polygon as a fan around its first corner.
        if (polygon)
          for (std::size_t k = 1; k + 1 < corners.size(); ++k) mesh.triangles.push_back({corners[0], corners[k], corners[k + 1]});
      }
      if (&e == vertex) {
        positions.push_back({toFloat(scalars[std::size_t(position[0])]), toFloat(scalars[std::size_t(position[1])]),
                             toFloat(scalars[std::size_t(position[2])])});
        if (normal[0] >= 0) {
          normals.push_back(fileNormal({toFloat(scalars[std::size_t(normal[0])]), toFloat(scalars[std::size_t(normal[1])]),
                                        toFloat(scalars[std::size_t(normal[2])])}));
        }
        if (uv[0] >= 0) uvs.push_back({toFloat(scalars[std::size_t(uv[0])]), toFloat(scalars[std::size_t(uv[1])])});
      }
    }
  }
  if (mesh.triangles.empty()) fail("the mesh has no faces");

  // Only the vertices faces use, in the file's order.
  std::vector<bool> used(positions.size(), false);
  for (const glm::uvec3& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) used[t[k]] = true;
  std::vector<std::uint32_t> renumbered(positions.size(), 0);
  for (std::size_t v = 0; v < positions.size(); ++v) {
    if (!used[v]) continue;
    renumbered[v] = std::uint32_t(mesh.positions.size());
    mesh.positions.push_back(positions[v]);
    if (!normals.empty()) mesh.normals.push_back(normals[v]);
    if (!uvs.empty()) mesh.uvs.push_back(uvs[v]);
  }
  for (glm::uvec3& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) t[k] = renumbered[t[k]];
  return mesh;
}

}  // namespace btf::render
