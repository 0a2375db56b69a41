// The one way to build a material. Every material type registers itself once, in its own source
// file, under the name a scene's "type" uses:
//
//   BTF_REGISTER_MATERIAL(lambert, {.name = "lambert", .summary = "ideal diffuse", .keys = {"albedo"},
//                                   .create = [](const MaterialParams& p) { ... }});
//
// and everything that builds a material goes through the functions below: the scene loader, every
// `btf` verb, btf-datagen, and your program. A material comes from
//   - a typed parameter set (createMaterial): a scene's JSON object, or one made in code;
//   - a path or a spec (openMaterial): the file's format is recognised by its content first (magic
//     bytes, sizes), then by its extension, and opens as the parameter set {"type": T, "file":
//     PATH} of the type T that registered the format; a spec "T:A:B" is {"type": T} with A and B
//     as the type's spec keys (merl-fit:sgd:alum-bronze).
// docs/library.md#adding-a-material-type shows a new type end to end.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "btf/io/btf_data.h"
#include "btf/io/merl.h"
#include "btf/material/material.h"
#include "btf/material/material_params.h"
#include "btf/material/tabulated_brdf.h"

namespace btf {

// A file format a material type reads: a file in it opens as {"type": the type, "file": path}.
struct MaterialFileFormat {
  std::string description = {};              // e.g. "MERL binary (isotropic BRDF table)"
  std::vector<std::string> extensions = {};  // e.g. {".binary"}; empty for a folder format
  bool folder = false;                       // the "file" is a folder
  // True when the first bytes of a file (at most kFormatSniffBytes; fewer for a short file) and
  // its size are of this format. Null: recognised by extension only.
  std::function<bool(std::span<const unsigned char> head, std::uintmax_t size)> sniff = {};
};
inline constexpr std::size_t kFormatSniffBytes = 65536;

struct MaterialType {
  std::string name;          // the "type" of its parameter sets
  std::string summary = {};  // one line, for listings
  // Keys its parameter sets may hold besides "type"; any other key is an error naming these.
  std::vector<std::string> keys = {};
  // Keys that a spec "name:A:B" sets, in order (empty: no spec form).
  std::vector<std::string> spec_keys = {};
  std::vector<MaterialFileFormat> formats = {};
  // Builds the material. Throws btf::Error (FileError for a file's problems); the registry adds
  // where the parameters came from to a plain Error.
  std::function<std::shared_ptr<const Material>(const MaterialParams&)> create = {};
  // For types whose data is a BTF: the data itself, which the BTF verbs stream (compress, info)
  // without the material's copy of it. Null for a BRDF: openBtf samples the material instead.
  std::function<std::shared_ptr<const BtfSource>(const MaterialParams&)> btf = {};
  // For types whose data is a MERL-layout table: the table as stored. Null: openTable tabulates.
  std::function<MerlTable(const MaterialParams&)> table = {};
  // A short name for the material's data (a one-texel BTF's name, an entry of a database). Null:
  // the stem of its "file".
  std::function<std::string(const MaterialParams&)> label = {};
};

// Adds a type; throws btf::Error for an empty or taken name or no `create`. Returns true, so that a
// registration can initialise a static (BTF_REGISTER_MATERIAL).
bool registerMaterialType(MaterialType type);
// The type of that name; throws btf::Error listing the registered names.
const MaterialType& materialType(const std::string& name);
// Every registered type, by name.
std::vector<const MaterialType*> materialTypes();

#define BTF_REGISTER_MATERIAL(id, ...) \
  [[maybe_unused]] static const bool btf_registered_material_##id = ::btf::registerMaterialType(__VA_ARGS__)

// --- From a parameter set ----------------------------------------------------------------------
// The material of params["type"]. Keys outside the type's `keys` and `extra_keys` (what the
// caller itself reads, e.g. a scene's "sampler") are errors. Every error names the set's origin.
std::shared_ptr<const Material> createMaterial(const MaterialParams& params,
                                               const std::vector<std::string>& extra_keys = {});

// --- From a path or a spec ---------------------------------------------------------------------
struct OpenOptions {
  // The table lookup of types that take a "lookup" (tables, octrees); ignored by the others.
  std::optional<TableLookup> lookup;
  // Which material of a .btfz database; an error for a type that takes no "material".
  std::string database_material;
};

struct IdentifiedMaterial {
  MaterialParams params;             // what openMaterial builds
  const MaterialType* type;          // params' type
  const MaterialFileFormat* format;  // the file's format; null for a spec
  std::string description;           // the format's (a file) or the type's summary (a spec)
};

// How `path_or_spec` opens, without reading it beyond its first bytes. Throws FileError for a
// missing path, or one no format claims (listing the formats), and btf::Error for a bad spec.
IdentifiedMaterial identifyMaterial(const std::string& path_or_spec, const OpenOptions& options = {});
std::shared_ptr<const Material> openMaterial(const std::string& path_or_spec, const OpenOptions& options = {});
// The data as a BTF: a BTF type's own source, or a BRDF as a one-texel BTF (brdfAsBtf).
std::shared_ptr<const BtfSource> openBtf(const std::string& path_or_spec, const OpenOptions& options = {});
// The data as a MERL-layout table: a table type's own table, or the material tabulated.
MerlTable openTable(const std::string& path_or_spec, const OpenOptions& options = {});
// The same two for a parameter set (createMaterial's checks apply) and for an identified material.
std::shared_ptr<const BtfSource> createBtf(const MaterialParams& params);
MerlTable createTable(const MaterialParams& params);
std::shared_ptr<const BtfSource> materialBtf(const IdentifiedMaterial& material);
MerlTable materialTable(const IdentifiedMaterial& material);
// The type's label of the material (see MaterialType::label).
std::string materialLabel(const IdentifiedMaterial& material);
// True when the data is a BTF (varies over the surface).
bool isBtfType(const MaterialType& type);

// A BRDF as a one-texel BTF at the 81 x 81 directions: value(view, light) = f(light, view).
// Throws btf::Error naming `name` for a value that is negative or not finite.
BtfData brdfAsBtf(const Material& material, const std::string& name);

}  // namespace btf
