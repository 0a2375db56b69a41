// Scene files: JSON (nlohmann-json) naming a camera, materials, meshes and lights. Relative paths
// resolve against the scene file's folder. Every error names the file, the JSON path (as a JSON
// pointer, e.g. /materials/gold/file) and the problem. The format, by example:
//
// {
//   "camera": {"position": [0, 1, 3.9], "look_at": [0, 1, 0], "up": [0, 1, 0], "fov_deg": 39.3,
//              "resolution": [256, 256]},
//   "render": {"spp": 64, "max_depth": 16, "rr_min_depth": 3},
//   "materials": {
//     "white": {"type": "lambert", "albedo": [0.73, 0.71, 0.68]},
//     "gold":  {"type": "merl", "file": "gold.binary", "lookup": "interpolated", "sampler": "dp-cdf"},
//     "paper": {"type": "rgl", "file": "paper_white_rgb.bsdf"},
//     "paint": {"type": "merl-fit", "name": "gold-metallic-paint", "model": "sgd"},
//     "cloth": {"type": "btf", "file": "fabric.btfz", "mapping": "box", "uv_scale": 2},
//     "plastic": {"type": "ggx", "diffuse": [0.2, 0.02, 0.02], "f0": [0.04, 0.04, 0.04], "alpha": 0.2}
//   },
//   "shapes": [
//     {"file": "CornellBox-Original.obj", "material": "mtl", "part_materials": {"tallBox": "gold"}},
//     {"file": "bun_zipper.ply", "material": "paint",
//      "transform": {"scale": 3, "rotate": {"axis": [0, 1, 0], "deg": 30}, "translate": [0, -0.1, 0]}},
//     {"type": "sphere", "center": [0, 0.3, 0], "radius": 0.3, "material": "gold"},
//     {"type": "quad", "corner": [-1, 0, -1], "edge_u": [2, 0, 0], "edge_v": [0, 0, 2], "material": "white"}
//   ],
//   "lights": [
//     {"type": "point", "position": [0, 1.9, 0], "intensity": [2, 2, 2]},
//     {"type": "environment", "radiance": [1, 1, 1]}  (or "file": "sky.exr", "scale": 1)
//   ]
// }
//
// Materials: each entry is the parameter set of a registered material type (btf/material/
// registry.h builds it; `btf info --types` lists the types and their keys): lambert, phong, ggx,
// ward, lafortune, merl, rgl, octree, fitted, merl-fit, btf (a .btfz file or an image folder; the
// scene reads its mapping uv | planar | box, uv_scale and axis for planar). Each entry also takes
// "sampler": material | cosine | uniform | tabulated | dp-cdf | quadtree, and an octree also
// octree-bound (a BTF varies over the surface, so only its own sampler and the warps apply).
// Shapes: meshes from OBJ (with .mtl: "material": "mtl" gives every part a Lambert of its Kd and an
// emission of its Ke; "part_materials" overrides parts and "skip_parts" leaves them out, by their
// .mtl material name first, else their group name) and PLY
// (also .ply.gz); "shading": smooth (default) | flat, "crease_deg" (default 60) for smooth
// normals where the file has none; "emission" (radiance) makes a shape an area light,
// "two_sided" lets it emit from both sides. Lights: point (position, intensity in W/sr) and one
// environment (constant radiance, or a lat-long EXR with a scale).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "btf/render/scene.h"
#include "btf/render/scene_document.h"

namespace btf::render {

struct SceneLoadOptions {
  // Replaces every material's "sampler" when not empty (the command line's --sampler).
  std::string sampler_override;
  // What a scene leaves to defaults (a mesh's missing material library, an unknown usemtl) is a
  // warning through btf::log naming the scene entry; strict makes it a FileError.
  bool strict = false;
};

// Reads and checks a scene file. Throws FileError naming the scene file, the JSON path and the
// problem; errors of the files it names (meshes, materials, maps) name those files.
SceneDescription loadSceneDescription(const std::filesystem::path& file, const SceneLoadOptions& options = {});
SceneDescription loadSceneDescription(const SceneDocument& document, const SceneLoadOptions& options = {});

}  // namespace btf::render
