#include "btf/render/scene_loader.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>

#include "btf/compress/vq_btf.h"
#include "btf/core/error.h"
#include "btf/fit/fit_file.h"
#include "btf/core/math.h"
#include "btf/core/progress.h"
#include "btf/io/btf_images.h"
#include "btf/io/merl.h"
#include "btf/fit/merl_fits.h"
#include "btf/material/btf_material.h"
#include "btf/material/ggx.h"
#include "btf/material/lafortune.h"
#include "btf/material/lambert.h"
#include "btf/material/octree_brdf.h"
#include "btf/material/phong.h"
#include "btf/material/rgl_brdf.h"
#include "btf/material/tabulated_brdf.h"
#include "btf/material/ward.h"
#include "btf/sampling/sampler_choice.h"

namespace btf::render {
namespace {

using nlohmann::json;

// A key as a JSON pointer token (RFC 6901): "~" and "/" are escaped as "~0" and "~1".
std::string pointerToken(const std::string& key) {
  std::string out;
  for (const char c : key) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

// A JSON value with where it sits in the file, so that every problem names its JSON pointer.
class Node {
 public:
  Node(const json& value, std::string pointer, const std::filesystem::path& file)
      : value_(&value), pointer_(std::move(pointer)), file_(&file) {}

  [[noreturn]] void fail(const std::string& problem) const {
    throw FileError(*file_, (pointer_.empty() ? std::string("/") : pointer_) + ": " + problem);
  }
  const json& value() const { return *value_; }
  const std::string& pointer() const { return pointer_; }
  const std::filesystem::path& file() const { return *file_; }

  bool has(const std::string& key) const { return value_->is_object() && value_->contains(key); }
  Node operator[](const std::string& key) const {
    if (!value_->is_object()) fail("expected an object");
    const auto it = value_->find(key);
    if (it == value_->end()) fail("missing \"" + key + "\"");
    return Node(*it, pointer_ + "/" + pointerToken(key), *file_);
  }
  Node at(std::size_t i) const { return Node((*value_)[i], pointer_ + "/" + std::to_string(i), *file_); }
  std::size_t size() const { return value_->size(); }

  // Keys that are not in `known` are errors: a misspelt key would otherwise be silently ignored.
  void allowOnly(std::initializer_list<const char*> known) const {
    if (!value_->is_object()) fail("expected an object");
    for (const auto& [key, v] : value_->items()) {
      bool ok = false;
      for (const char* k : known) ok = ok || key == k;
      if (!ok) {
        std::string list;
        for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
        Node(v, pointer_ + "/" + pointerToken(key), *file_).fail("unknown key (expected one of: " + list + ")");
      }
    }
  }
  const json::object_t& object() const {
    if (!value_->is_object()) fail("expected an object");
    return value_->get_ref<const json::object_t&>();
  }
  void requireArray() const {
    if (!value_->is_array()) fail("expected an array");
  }

  double number() const {
    if (!value_->is_number()) fail("expected a number, got " + std::string(value_->type_name()));
    const double v = value_->get<double>();
    if (!std::isfinite(v)) fail("expected a finite number");
    return v;
  }
  double number(double lo, double hi, const char* range) const {
    const double v = number();
    if (!(v >= lo && v <= hi)) fail("expected a number " + std::string(range) + ", got " + value_->dump());
    return v;
  }
  double positive() const {
    const double v = number();
    if (!(v > 0)) fail("expected a positive number, got " + value_->dump());
    return v;
  }
  int integer(int lo, int hi) const {
    if (!value_->is_number_integer()) fail("expected an integer, got " + value_->dump());
    const long long v = value_->get<long long>();
    if (v < lo || v > hi) fail("expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + value_->dump());
    return int(v);
  }
  std::string string() const {
    if (!value_->is_string()) fail("expected a string, got " + std::string(value_->type_name()));
    return value_->get<std::string>();
  }
  bool boolean() const {
    if (!value_->is_boolean()) fail("expected true or false");
    return value_->get<bool>();
  }
  glm::vec3 vec3() const {
    if (!value_->is_array() || value_->size() != 3) fail("expected an array of 3 numbers");
    return {float(at(0).number()), float(at(1).number()), float(at(2).number())};
  }
  // A colour: 3 non-negative numbers, or one number for grey.
  Rgb rgb() const {
    if (value_->is_number()) {
      const float v = float(number());
      if (v < 0) fail("a colour must not be negative");
      return Rgb(v);
    }
    const glm::vec3 v = vec3();
    if (v.x < 0 || v.y < 0 || v.z < 0) fail("a colour must not be negative");
    return {v.x, v.y, v.z};
  }
  std::filesystem::path path() const {
    const std::filesystem::path p = string();
    if (p.empty()) fail("expected a file name");
    return p.is_absolute() ? p : file_->parent_path() / p;
  }
  std::filesystem::path existingPath() const {
    const std::filesystem::path p = path();
    std::error_code ec;
    if (!std::filesystem::exists(p, ec)) fail("no such file: " + p.string());
    return p;
  }

 private:
  const json* value_;
  std::string pointer_;
  const std::filesystem::path* file_;
};

// alpha as one number (isotropic) or [alpha_x, alpha_y].
glm::vec2 roughness(const Node& node) {
  const Node a = node["alpha"];
  if (a.value().is_array()) {
    if (a.size() != 2) a.fail("expected one number or [alpha_x, alpha_y]");
    return {float(a.at(0).positive()), float(a.at(1).positive())};
  }
  const float v = float(a.positive());
  return {v, v};
}

struct MaterialContext {
  const SceneLoadOptions& options;
};

std::shared_ptr<const Material> analyticOrMeasured(const Node& m, const std::string& type, const MaterialContext& context) {
  // Constructors of the models check their own ranges; their messages get the JSON path here.
  try {
    if (type == "lambert") {
      m.allowOnly({"type", "albedo", "sampler"});
      return std::make_shared<Lambert>(m["albedo"].rgb());
    }
    if (type == "phong") {
      m.allowOnly({"type", "diffuse", "specular", "exponent", "sampler"});
      return std::make_shared<Phong>(m["diffuse"].rgb(), m["specular"].rgb(), float(m["exponent"].number(0, 1e6, "in [0, 1e6]")));
    }
    if (type == "ggx") {
      m.allowOnly({"type", "diffuse", "f0", "alpha", "sampler"});
      const glm::vec2 a = roughness(m);
      return std::make_shared<Ggx>(m["diffuse"].rgb(), m["f0"].rgb(), a.x, a.y);
    }
    if (type == "ward") {
      m.allowOnly({"type", "diffuse", "specular", "alpha", "sampler"});
      const glm::vec2 a = roughness(m);
      return std::make_shared<Ward>(m["diffuse"].rgb(), m["specular"].rgb(), a.x, a.y);
    }
    if (type == "lafortune") {
      m.allowOnly({"type", "diffuse", "lobes", "sampler"});
      const Node lobes = m["lobes"];
      lobes.requireArray();
      std::vector<LafortuneLobe> list;
      for (std::size_t i = 0; i < lobes.size(); ++i) {
        const Node lobe = lobes.at(i);
        lobe.allowOnly({"rho", "c", "exponent"});
        list.push_back({lobe["rho"].rgb(), lobe["c"].vec3(), float(lobe["exponent"].number(0, 1e6, "in [0, 1e6]"))});
      }
      return std::make_shared<Lafortune>(m["diffuse"].rgb(), std::move(list));
    }
  } catch (const FileError&) {
    throw;
  } catch (const Error& e) {
    m.fail(e.what());
  }
  auto tableLookup = [&] {
    TableLookup lookup = TableLookup::Interpolated;
    if (m.has("lookup")) {
      const std::optional<TableLookup> named = parseTableLookup(m["lookup"].string());
      if (!named) m["lookup"].fail(std::string("expected ") + kTableLookupNames);
      lookup = *named;
    }
    return lookup;
  };
  if (type == "merl") {
    m.allowOnly({"type", "file", "lookup", "sampler"});
    const TableLookup lookup = tableLookup();
    return std::make_shared<TabulatedBrdf>(std::make_shared<const MerlTable>(readMerl(m["file"].existingPath())), lookup);
  }
  if (type == "octree") {  // a table written by `btf convert ... .octree` (compress/octree_table.h)
    m.allowOnly({"type", "file", "lookup", "sampler"});
    const TableLookup lookup = tableLookup();
    return std::make_shared<OctreeBrdf>(std::make_shared<const OctreeTable>(readOctreeFile(m["file"].existingPath())), lookup);
  }
  if (type == "rgl") {
    m.allowOnly({"type", "file", "sampler"});
    return std::make_shared<RglBrdf>(m["file"].existingPath());
  }
  if (type == "fitted") {  // a model written by `btf fit` (fit/fit_file.h)
    m.allowOnly({"type", "file", "sampler"});
    return makeAnalyticMaterial(readFitFile(m["file"].existingPath()));
  }
  if (type == "merl-fit") {
    m.allowOnly({"type", "name", "model", "fits_dir", "sampler"});
    std::vector<std::filesystem::path> folders;
    if (m.has("fits_dir")) folders.push_back(m["fits_dir"].existingPath());
    else folders = context.options.fits_folders;
    try {
      const MerlFits fits = MerlFits::load(findMerlFitsFolder(folders));
      const FitModel model = m.has("model") ? parseFitModel(m["model"].string()) : FitModel::Sgd;
      return std::shared_ptr<const Material>(makeMerlFitMaterial(fits, m["name"].string(), model));
    } catch (const FileError&) {
      throw;
    } catch (const Error& e) {
      m.fail(e.what());
    }
  }
  if (type == "btf") {
    m.allowOnly({"type", "file", "material", "mapping", "uv_scale", "axis", "filter", "sampler"});
    const std::filesystem::path file = m["file"].existingPath();
    // "material": which material of a .btfz database (compress/vq_database.h).
    const std::string material = m.has("material") ? m["material"].string() : std::string();
    BtfTexelFilter filter = BtfTexelFilter::Bilinear;
    if (m.has("filter")) {
      const std::string f = m["filter"].string();
      if (f == "nearest") filter = BtfTexelFilter::Nearest;
      else if (f != "bilinear") m["filter"].fail("expected bilinear or nearest");
    }
    if (!material.empty() && file.extension() != ".btfz") m["material"].fail("names a material of a .btfz database only");
    std::shared_ptr<const BtfLookup> lookup;
    std::error_code ec;
    if (std::filesystem::is_directory(file, ec)) lookup = std::make_shared<BtfData>(BtfData::copyOf(BtfImageFolder::open(file)));
    else if (file.extension() == ".btfz") lookup = std::make_shared<VqBtf>(VqBtf::read(file, material));
    else m["file"].fail("expected a .btfz file or a BTF image folder");
    const std::string label = file.filename().string() + (material.empty() ? "" : ":" + material);
    return std::make_shared<BtfMaterial>(std::move(lookup), filter, "btf(" + label + ")");
  }
  m["type"].fail("unknown material type '" + type + "'");
}

SceneMaterial loadMaterial(const std::string& name, const Node& m, const MaterialContext& context) {
  SceneMaterial out;
  out.name = name;
  const std::string type = m["type"].string();
  out.material = analyticOrMeasured(m, type, context);
  if (type == "btf") {
    if (m.has("mapping")) {
      const std::string mapping = m["mapping"].string();
      if (mapping == "uv") out.mapping = UvMapping::Mesh;
      else if (mapping == "planar") out.mapping = UvMapping::Planar;
      else if (mapping == "box") out.mapping = UvMapping::Box;
      else m["mapping"].fail("expected uv, planar or box");
    }
    if (m.has("uv_scale")) out.uv_scale = float(m["uv_scale"].positive());
    if (m.has("axis")) {
      const std::string axis = m["axis"].string();
      if (axis != "x" && axis != "y" && axis != "z") m["axis"].fail("expected x, y or z");
      out.planar_axis = axis[0] - 'x';
    }
  }
  out.sampler = !context.options.sampler_override.empty() ? context.options.sampler_override
                : m.has("sampler")                        ? m["sampler"].string()
                                                          : "material";
  const auto choice = parseSamplerChoice(out.sampler);
  if (!choice) {
    const std::string problem = "unknown sampler '" + out.sampler + "' (expected one of: " + samplerChoiceNames() + ")";
    if (m.has("sampler")) m["sampler"].fail(problem);
    m.fail(problem);
  }
  if (type == "btf" && tabulatesOneBrdf(*choice)) {
    // A BTF changes over the surface; the tabulated samplers hold one table per material.
    if (context.options.sampler_override.empty())
      m["sampler"].fail("sampler '" + out.sampler + "' tabulates one BRDF, but a BTF varies over the surface: use material, cosine or uniform");
    out.sampler = "material";
    out.sampled = out.material;
    return out;
  }
  try {
    out.sampled = withSampler(*choice, out.material, SamplerOptions{});
  } catch (const Error& e) {
    m.fail(e.what());
  }
  return out;
}

glm::mat4 loadTransform(const Node& t) {
  t.allowOnly({"scale", "rotate", "translate"});
  glm::mat4 m(1.0f);
  if (t.has("translate")) m = glm::translate(m, t["translate"].vec3());
  if (t.has("rotate")) {
    const Node r = t["rotate"];
    r.allowOnly({"axis", "deg"});
    const glm::vec3 axis = r["axis"].vec3();
    if (!(glm::length(axis) > 0)) r["axis"].fail("the rotation axis must not be zero");
    m = glm::rotate(m, float(r["deg"].number()) * (kPi / 180.0f), glm::normalize(axis));
  }
  if (t.has("scale")) {
    const Node s = t["scale"];
    glm::vec3 v;
    if (s.value().is_number()) v = glm::vec3(float(s.number()));
    else v = s.vec3();
    if (!(std::abs(v.x * v.y * v.z) > 0)) s.fail("a scale must not be zero");
    m = glm::scale(m, v);
  }
  return m;
}

int materialIndex(const Node& where, const std::string& name, const std::map<std::string, int>& index) {
  const auto it = index.find(name);
  if (it == index.end()) {
    std::string known;
    for (const auto& [n, i] : index) known += (known.empty() ? "" : ", ") + n;
    where.fail("unknown material '" + name + "'" + (known.empty() ? std::string(" (the scene defines none)") : " (defined: " + known + ")"));
  }
  return it->second;
}

void loadShapes(const Node& list, SceneDescription& scene, std::map<std::string, int>& material_index) {
  list.requireArray();
  if (list.size() == 0) list.fail("the scene has no shape");
  for (std::size_t i = 0; i < list.size(); ++i) {
    const Node s = list.at(i);
    const std::string type = s.has("type") ? s["type"].string() : std::string("mesh");
    std::vector<TriangleMesh> meshes;
    if (type == "mesh") {
      s.allowOnly({"type", "file", "material", "part_materials", "skip_parts", "transform", "shading", "crease_deg", "emission",
                   "two_sided"});
      meshes = loadTriangleMeshes(s["file"].existingPath());
    } else if (type == "sphere") {
      s.allowOnly({"type", "center", "radius", "rings", "material", "transform", "emission", "two_sided"});
      meshes.push_back(makeSphere(s["center"].vec3(), float(s["radius"].positive()),
                                  s.has("rings") ? s["rings"].integer(3, 4096) : 64, s.pointer()));
    } else if (type == "quad") {
      s.allowOnly({"type", "corner", "edge_u", "edge_v", "material", "transform", "emission", "two_sided"});
      const glm::vec3 u = s["edge_u"].vec3(), v = s["edge_v"].vec3();
      if (!(glm::length(glm::cross(u, v)) > 0)) s.fail("the quad's edges span no area (zero-area light or surface)");
      meshes.push_back(makeQuad(s["corner"].vec3(), u, v, s.pointer()));
    } else {
      s["type"].fail("unknown shape type '" + type + "' (expected mesh, sphere or quad)");
    }

    const bool flat = s.has("shading") && [&] {
      const std::string shading = s["shading"].string();
      if (shading != "flat" && shading != "smooth") s["shading"].fail("expected smooth or flat");
      return shading == "flat";
    }();
    const float crease = s.has("crease_deg") ? float(s["crease_deg"].number(0, 180, "in [0, 180]")) : 60.0f;
    const glm::mat4 transform = s.has("transform") ? loadTransform(s["transform"]) : glm::mat4(1.0f);
    const Rgb emission = s.has("emission") ? s["emission"].rgb() : Rgb(0.0f);
    const bool two_sided = s.has("two_sided") && s["two_sided"].boolean();

    const std::string material = s.has("material") ? s["material"].string() : std::string();
    std::map<std::string, std::string> part_materials;
    if (s.has("part_materials"))
      for (const auto& [part, value] : s["part_materials"].object())
        part_materials[part] = Node(value, s.pointer() + "/part_materials/" + pointerToken(part), s.file()).string();
    std::set<std::string> parts_used;
    std::set<std::string> file_materials;
    for (const TriangleMesh& mesh : meshes)
      if (!mesh.file_material.empty()) file_materials.insert(mesh.file_material);
    std::set<std::string> skip_parts;
    if (s.has("skip_parts")) {
      const Node list = s["skip_parts"];
      list.requireArray();
      for (std::size_t k = 0; k < list.size(); ++k) skip_parts.insert(list.at(k).string());
    }

    // The key of `keys` (part_materials or skip_parts) that names a part: its .mtl name, else its
    // group (the text after the file name). A key that is the .mtl name of some part of the file
    // selects by .mtl name only: OBJ groups and materials need not agree (CornellBox-Original.obj
    // keeps its tall box in group "shortBox"), and "shortBox" must not select the tall box too.
    auto partKey = [&](const TriangleMesh& mesh, const auto& keys) -> std::string {
      if (!mesh.file_material.empty() && keys.count(mesh.file_material)) return mesh.file_material;
      const std::string group = mesh.name.find(':') != std::string::npos ? mesh.name.substr(mesh.name.rfind(':') + 1) : "";
      if (!group.empty() && keys.count(group) && !file_materials.count(group)) return group;
      return {};
    };

    for (TriangleMesh& mesh : meshes) {
      if (const std::string skipped = partKey(mesh, skip_parts); !skipped.empty()) {
        parts_used.insert(skipped);
        continue;
      }
      if (flat) mesh.normals.clear();
      else if (mesh.normals.empty() && type == "mesh") {
        // Normals of degenerate faces are undefined, so they go now; the Scene, which warns about
        // what it drops, would find nothing left to count.
        removeInvalidTrianglesWithWarning(mesh);
        if (!mesh.triangles.empty()) computeVertexNormals(mesh, crease);
      }
      transformMesh(mesh, transform);
      SceneShape shape;
      shape.emission = emission;
      shape.two_sided_emission = two_sided;
      if (const std::string part_key = partKey(mesh, part_materials); !part_key.empty()) {
        parts_used.insert(part_key);
        shape.material = materialIndex(s["part_materials"][part_key], part_materials[part_key], material_index);
      } else if (material == "mtl") {
        const std::string name = s["file"].string() + ":" + (mesh.file_material.empty() ? "default" : mesh.file_material);
        auto [it, inserted] = material_index.try_emplace(name, int(scene.materials.size()));
        if (inserted) {
          SceneMaterial m;
          m.name = name;
          m.material = std::make_shared<Lambert>(mesh.file_diffuse);
          m.sampled = m.material;
          scene.materials.push_back(m);
        }
        shape.material = it->second;
        if (!s.has("emission")) shape.emission = mesh.file_emission;
      } else if (!material.empty()) {
        shape.material = materialIndex(s["material"], material, material_index);
      } else if (emission.isBlack()) {
        s.fail("a shape needs a \"material\" (or an \"emission\" to be a pure light)");
      }
      shape.mesh = std::move(mesh);
      scene.shapes.push_back(std::move(shape));
    }
    for (const auto& [part, m] : part_materials)
      if (!parts_used.count(part)) s["part_materials"][part].fail("the mesh has no part named '" + part + "'");
    for (const std::string& part : skip_parts)
      if (!parts_used.count(part)) s["skip_parts"].fail("the mesh has no part named '" + part + "'");
  }
}

void loadLights(const Node& list, SceneDescription& scene) {
  list.requireArray();
  bool environment = false;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const Node l = list.at(i);
    const std::string type = l["type"].string();
    if (type == "point") {
      l.allowOnly({"type", "position", "intensity"});
      const Rgb intensity = l["intensity"].rgb();
      if (intensity.isBlack()) l["intensity"].fail("a light of zero intensity");
      scene.point_lights.push_back({l["position"].vec3(), intensity});
    } else if (type == "environment") {
      l.allowOnly({"type", "radiance", "file", "scale"});
      if (environment) l.fail("a scene has at most one environment");
      environment = true;
      if (l.has("file") == l.has("radiance")) l.fail("an environment has either a \"radiance\" or a \"file\"");
      if (l.has("scale") && !l.has("file")) l["scale"].fail("\"scale\" applies to an environment map (\"file\")");
      if (l.has("file")) {
        const float scale = l.has("scale") ? float(l["scale"].positive()) : 1.0f;
        scene.environment_map = std::make_shared<EnvironmentMap>(EnvironmentMap::load(l["file"].existingPath(), scale));
      } else {
        scene.environment_radiance = l["radiance"].rgb();
        if (scene.environment_radiance.isBlack()) l["radiance"].fail("an environment of zero radiance");
      }
    } else {
      l["type"].fail("unknown light type '" + type + "' (expected point or environment; area lights are shapes with an \"emission\")");
    }
  }
}

}  // namespace

std::vector<std::string> sceneMaterialTypes() {
  return {"lambert", "phong", "ggx", "ward", "lafortune", "merl", "octree", "rgl", "fitted", "merl-fit", "btf"};
}

SceneDescription loadSceneDescription(const std::filesystem::path& file, const SceneLoadOptions& options) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) throw FileError(file, "no such scene file");
  std::ifstream in(file);
  if (!in) throw FileError(file, "cannot open the scene file");
  json document;
  try {
    document = json::parse(in);
  } catch (const json::exception& e) {  // parse_error, and out_of_range for numbers beyond a double
    throw FileError(file, std::string("malformed JSON: ") + e.what());
  }
  const Node root(document, "", file);
  root.allowOnly({"camera", "render", "materials", "shapes", "lights", "comment"});

  SceneDescription scene;
  scene.file = file;
  const Node camera = root["camera"];
  camera.allowOnly({"position", "look_at", "up", "fov_deg", "resolution"});
  scene.camera.position = camera["position"].vec3();
  scene.camera.look_at = camera["look_at"].vec3();
  if (camera.has("up")) scene.camera.up = camera["up"].vec3();
  if (camera.has("fov_deg")) scene.camera.fov_deg = float(camera["fov_deg"].number(1e-3, 179.9, "in (0, 180)"));
  if (camera.has("resolution")) {
    const Node r = camera["resolution"];
    if (!r.value().is_array() || r.size() != 2) r.fail("expected [width, height]");
    scene.camera.width = r.at(0).integer(1, 16384);
    scene.camera.height = r.at(1).integer(1, 16384);
  }
  try {
    PinholeCamera check(scene.camera);
  } catch (const Error& e) {
    camera.fail(e.what());
  }
  if (root.has("render")) {
    const Node r = root["render"];
    r.allowOnly({"spp", "max_depth", "rr_min_depth"});
    if (r.has("spp")) scene.render.spp = r["spp"].integer(1, 1 << 24);
    if (r.has("max_depth")) scene.render.max_depth = r["max_depth"].integer(1, 1024);
    if (r.has("rr_min_depth")) scene.render.rr_min_depth = r["rr_min_depth"].integer(1, 1024);
  }

  const MaterialContext context{options};
  std::map<std::string, int> material_index;
  if (root.has("materials"))
    for (const auto& [name, value] : root["materials"].object()) {
      const Node m(value, "/materials/" + pointerToken(name), file);
      if (name == "mtl") m.fail("the name 'mtl' is reserved (it stands for an OBJ file's own .mtl colours)");
      material_index[name] = int(scene.materials.size());
      scene.materials.push_back(loadMaterial(name, m, context));
    }
  loadShapes(root["shapes"], scene, material_index);
  if (root.has("lights")) loadLights(root["lights"], scene);
  return scene;
}

}  // namespace btf::render
