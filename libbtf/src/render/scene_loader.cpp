#include "btf/render/scene_loader.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>

#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/progress.h"
#include "btf/core/value_limits.h"
#include "btf/material/lambert.h"
#include "btf/material/registry.h"
#include "btf/sampling/sampler_choice.h"
#include "json_node.h"
#include "material_params_access.h"
#include "scene_document_impl.h"

namespace btf::render {
namespace {

using detail::json;
using detail::pointerToken;
using Node = detail::JsonNode;

SceneMaterial loadMaterial(const std::string& name, const Node& m, const SceneLoadOptions& options) {
  SceneMaterial out;
  out.name = name;
  const std::string type = m["type"].string();
  const MaterialParams params = MaterialParamsAccess::fromJson(m.value(), m.pointer(), m.file(), m.file().parent_path());
  out.material = createMaterial(params, {"sampler"});
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
  out.sampler = !options.sampler_override.empty() ? options.sampler_override
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
    if (options.sampler_override.empty())
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

// A light's radiance or intensity: a colour within the range a render keeps finite.
Rgb radiance(const Node& node) {
  const Rgb v = node.rgb();
  static_assert(kMaxRadiance == 1e10f, "the message below names the bound");
  if (v.maxComponent() > kMaxRadiance)
    node.fail("a radiance or intensity must be at most 1e10 (kMaxRadiance), got " + node.value().dump());
  return v;
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
    m = glm::rotate(m, r["deg"].floatNumber() * (kPi / 180.0f), glm::normalize(axis));
  }
  if (t.has("scale")) {
    const Node s = t["scale"];
    glm::vec3 v;
    if (s.value().is_number()) v = glm::vec3(s.floatNumber());
    else v = s.vec3();
    if (!(std::abs(v.x * v.y * v.z) > 0) || !std::isfinite(v.x * v.y * v.z)) s.fail("a scale must not be zero or overflow");
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

void loadShapes(const Node& list, SceneDescription& scene, std::map<std::string, int>& material_index,
                const SceneLoadOptions& options) {
  list.requireArray();
  if (list.size() == 0) list.fail("the scene has no shape");
  for (std::size_t i = 0; i < list.size(); ++i) {
    const Node s = list.at(i);
    const std::string type = s.has("type") ? s["type"].string() : std::string("mesh");
    std::vector<TriangleMesh> meshes;
    if (type == "mesh") {
      s.allowOnly({"type", "file", "material", "part_materials", "skip_parts", "transform", "shading", "crease_deg", "emission",
                   "two_sided"});
      std::vector<std::string> warnings;
      meshes = loadTriangleMeshes(s["file"].existingPath(), &warnings);
      for (const std::string& w : warnings) {
        if (options.strict) s["file"].fail(w + " (--strict)");
        log(LogLevel::Warning, s.file().string() + ": " + s.pointer() + ": " + w);
      }
    } else if (type == "sphere") {
      s.allowOnly({"type", "center", "radius", "rings", "material", "transform", "emission", "two_sided"});
      try {
        meshes.push_back(makeSphere(s["center"].vec3(), s["radius"].positiveFloat(),
                                    s.has("rings") ? s["rings"].integer(3, 4096) : 64, s.pointer()));
      } catch (const FileError&) {
        throw;
      } catch (const Error& e) {
        s.fail(e.what());
      }
    } else if (type == "quad") {
      s.allowOnly({"type", "corner", "edge_u", "edge_v", "material", "transform", "emission", "two_sided"});
      const glm::vec3 u = s["edge_u"].vec3(), v = s["edge_v"].vec3();
      if (!(glm::length(glm::cross(u, v)) > 0) || !std::isfinite(glm::length(glm::cross(u, v))))
        s.fail("the quad's edges span no area, or one beyond float range (a zero-area light or surface, or edges too long)");
      try {
        meshes.push_back(makeQuad(s["corner"].vec3(), u, v, s.pointer()));
      } catch (const FileError&) {
        throw;
      } catch (const Error& e) {
        s.fail(e.what());
      }
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
    const Rgb emission = s.has("emission") ? radiance(s["emission"]) : Rgb(0.0f);
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
      try {
        transformMesh(mesh, transform);
      } catch (const Error& e) {  // the mesh's problem comes from the scene's transform
        s["transform"].fail(e.what());
      }
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
      const Rgb intensity = radiance(l["intensity"]);
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
        scene.environment_radiance = radiance(l["radiance"]);
        if (scene.environment_radiance.isBlack()) l["radiance"].fail("an environment of zero radiance");
      }
    } else {
      l["type"].fail("unknown light type '" + type + "' (expected point or environment; area lights are shapes with an \"emission\")");
    }
  }
}

}  // namespace

SceneDescription loadSceneDescription(const std::filesystem::path& file, const SceneLoadOptions& options) {
  return loadSceneDescription(SceneDocument::read(file), options);
}

SceneDescription loadSceneDescription(const SceneDocument& document, const SceneLoadOptions& options) {
  const std::filesystem::path& file = document.file();
  const Node root(document.impl().root, "", file);
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
    // A render libbtf cannot read back (btf compare, an environment map) is not one to make.
    const ImageSizeLimits limits = imageSizeLimits();
    if (scene.camera.width > limits.max_side || scene.camera.height > limits.max_side ||
        std::uint64_t(scene.camera.width) * std::uint64_t(scene.camera.height) > limits.max_pixels)
      r.fail("a " + std::to_string(scene.camera.width) + " x " + std::to_string(scene.camera.height) +
             " render is beyond the images libbtf reads back (" + std::to_string(limits.max_pixels) +
             " pixels; btf --max-image-pixels raises it)");
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

  std::map<std::string, int> material_index;
  if (root.has("materials"))
    for (const auto& [name, value] : root["materials"].object()) {
      const Node m(value, "/materials/" + pointerToken(name), file);
      if (name == "mtl") m.fail("the name 'mtl' is reserved (it stands for an OBJ file's own .mtl colours)");
      material_index[name] = int(scene.materials.size());
      scene.materials.push_back(loadMaterial(name, m, options));
    }
  loadShapes(root["shapes"], scene, material_index, options);
  if (root.has("lights")) loadLights(root["lights"], scene);
  return scene;
}

}  // namespace btf::render
