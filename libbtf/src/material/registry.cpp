#include "btf/material/registry.h"

#include <algorithm>
#include <fstream>
#include <map>
#include <mutex>

#include "btf/core/btf_directions.h"
#include "btf/core/error.h"

namespace btf {
namespace {

// Function-local, so that registrations from static initialisers in any order find it built.
struct Registry {
  std::mutex mutex;
  std::map<std::string, MaterialType> types;
};
Registry& registry() {
  static Registry r;
  return r;
}

std::string knownNames() {
  std::string list;
  for (const MaterialType* t : materialTypes()) list += (list.empty() ? "" : ", ") + t->name;
  return list;
}

std::vector<unsigned char> readHead(const std::filesystem::path& path) {
  std::vector<unsigned char> head(kFormatSniffBytes);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path, "cannot open the file");
  in.read(reinterpret_cast<char*>(head.data()), std::streamsize(head.size()));
  head.resize(std::size_t(in.gcount()));
  return head;
}

std::string formatList() {
  std::string list;
  for (const MaterialType* t : materialTypes())
    for (const MaterialFileFormat& f : t->formats) {
      std::string where = f.folder ? "a folder" : "";
      for (const std::string& e : f.extensions) where += (where.empty() ? "" : " or ") + e;
      list += (list.empty() ? "" : "; ") + f.description + " (" + where + ")";
    }
  return list;
}

// A spec "type:A:B" whose type declares spec keys, or nothing.
std::optional<IdentifiedMaterial> identifySpec(const std::string& spec) {
  const std::size_t colon = spec.find(':');
  if (colon == std::string::npos || colon == 0) return std::nullopt;
  const std::string name = spec.substr(0, colon);
  const MaterialType* type = nullptr;
  for (const MaterialType* t : materialTypes())
    if (t->name == name && !t->spec_keys.empty()) type = t;
  if (!type) return std::nullopt;
  std::vector<std::string> parts;
  std::size_t start = colon + 1;
  while (true) {
    const std::size_t next = spec.find(':', start);
    parts.push_back(spec.substr(start, next == std::string::npos ? std::string::npos : next - start));
    if (next == std::string::npos) break;
    start = next + 1;
  }
  std::string form = name;
  for (const std::string& k : type->spec_keys) form += ":" + k;
  if (parts.size() != type->spec_keys.size() ||
      std::any_of(parts.begin(), parts.end(), [](const std::string& p) { return p.empty(); }))
    throw Error("'" + spec + "': expected " + form);
  MaterialParams params(name);
  for (std::size_t i = 0; i < parts.size(); ++i) params.set(type->spec_keys[i], parts[i]);
  params.setOrigin(spec, {});
  return IdentifiedMaterial{std::move(params), type, nullptr, type->summary};
}

// The type of a set, its keys checked as createMaterial checks them.
const MaterialType& checkedType(const MaterialParams& params, const std::vector<std::string>& extra_keys = {}) {
  if (!params.has("type")) params.fail("missing \"type\" (expected one of: " + knownNames() + ")");
  const MaterialType* type = nullptr;
  try {
    type = &materialType(params.type());
  } catch (const Error& e) {
    params.fail("type", e.what());
  }
  std::vector<std::string> allowed = {"type"};
  allowed.insert(allowed.end(), type->keys.begin(), type->keys.end());
  allowed.insert(allowed.end(), extra_keys.begin(), extra_keys.end());
  params.allowOnly(allowed);
  return *type;
}

// Calls `build`, giving a plain Error the set's origin (a FileError names its file already).
template <class F>
auto withOrigin(const MaterialParams& params, F&& build) -> decltype(build()) {
  try {
    return build();
  } catch (const FileError&) {
    throw;
  } catch (const Error& e) {
    params.fail(e.what());
  }
}

bool takesKey(const MaterialType& type, const std::string& key) {
  return std::find(type.keys.begin(), type.keys.end(), key) != type.keys.end();
}

}  // namespace

bool registerMaterialType(MaterialType type) {
  if (type.name.empty() || !type.create) throw Error("a material type needs a name and a create function");
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  const std::string name = type.name;
  if (!r.types.emplace(name, std::move(type)).second) throw Error("the material type '" + name + "' is registered twice");
  return true;
}

const MaterialType& materialType(const std::string& name) {
  Registry& r = registry();
  {
    const std::lock_guard lock(r.mutex);
    const auto it = r.types.find(name);
    if (it != r.types.end()) return it->second;
  }
  throw Error("unknown material type '" + name + "' (expected one of: " + knownNames() + ")");
}

std::vector<const MaterialType*> materialTypes() {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  std::vector<const MaterialType*> out;
  for (const auto& [name, type] : r.types) out.push_back(&type);
  return out;
}

bool isBtfType(const MaterialType& type) { return bool(type.btf); }

std::string materialLabel(const IdentifiedMaterial& material) {
  if (material.type->label) return material.type->label(material.params);
  if (material.params.has("file")) return material.params.path("file").stem().string();
  return material.type->name;
}

std::shared_ptr<const Material> createMaterial(const MaterialParams& params, const std::vector<std::string>& extra_keys) {
  const MaterialType& type = checkedType(params, extra_keys);
  return withOrigin(params, [&] { return type.create(params); });
}

std::shared_ptr<const BtfSource> createBtf(const MaterialParams& params) {
  const MaterialType& type = checkedType(params);
  if (type.btf) return withOrigin(params, [&] { return type.btf(params); });
  const auto brdf = withOrigin(params, [&] { return type.create(params); });
  const IdentifiedMaterial identified{params, &type, nullptr, type.summary};
  return std::make_shared<BtfData>(brdfAsBtf(*brdf, materialLabel(identified)));
}

MerlTable createTable(const MaterialParams& params) {
  const MaterialType& type = checkedType(params);
  if (type.table) return withOrigin(params, [&] { return type.table(params); });
  return tabulate(*withOrigin(params, [&] { return type.create(params); }));
}

IdentifiedMaterial identifyMaterial(const std::string& path_or_spec, const OpenOptions& options) {
  if (path_or_spec.empty()) throw Error("expected a material file, folder or spec; got an empty name");
  const std::filesystem::path path(path_or_spec);
  std::error_code ec;
  std::optional<IdentifiedMaterial> found;
  if (!std::filesystem::exists(path, ec)) {
    found = identifySpec(path_or_spec);
    if (!found) throw FileError(path, "no such file or folder");
  } else {
    const bool folder = std::filesystem::is_directory(path, ec);
    // A folder named like a file of a format (folder.binary) is a mistake to name, not a BTF folder.
    if (folder && !path.extension().empty())
      for (const MaterialType* t : materialTypes())
        for (const MaterialFileFormat& f : t->formats)
          if (std::find(f.extensions.begin(), f.extensions.end(), path.extension().string()) != f.extensions.end())
            throw FileError(path, "is a directory, not a " + f.description + " file");
    const std::vector<unsigned char> head = folder ? std::vector<unsigned char>() : readHead(path);
    const std::uintmax_t size = folder ? 0 : std::filesystem::file_size(path, ec);
    const std::string ext = path.extension().string();
    const MaterialType* by_content = nullptr;
    const MaterialType* by_extension = nullptr;
    const MaterialFileFormat* content_format = nullptr;
    const MaterialFileFormat* extension_format = nullptr;
    for (const MaterialType* t : materialTypes())
      for (const MaterialFileFormat& f : t->formats) {
        if (f.folder != folder) continue;
        if (!folder && f.sniff && !by_content && f.sniff(head, size)) by_content = t, content_format = &f;
        const bool ext_match = folder || std::find(f.extensions.begin(), f.extensions.end(), ext) != f.extensions.end();
        if (ext_match && !by_extension) by_extension = t, extension_format = &f;
      }
    // Content first: a file named .json that is an RGL tensor opens as one. The extension decides
    // only when no format recognises the bytes; its reader then reports what is wrong.
    const MaterialType* type = by_content ? by_content : by_extension;
    const MaterialFileFormat* format = by_content ? content_format : extension_format;
    if (!type) {
      const std::string what = folder ? "is a folder that is no BTF format"
                               : ext.empty() ? "has no extension and no known content"
                                             : "is of no known format (extension '" + ext + "')";
      throw FileError(path, what + "; expected " + formatList());
    }
    MaterialParams params(type->name);
    params.set("file", path_or_spec);
    params.setOrigin(path, {});
    found = IdentifiedMaterial{std::move(params), type, format, format->description};
  }
  if (options.lookup && takesKey(*found->type, "lookup")) found->params.set("lookup", tableLookupName(*options.lookup));
  if (!options.database_material.empty()) {
    if (!takesKey(*found->type, "material"))
      throw FileError(path, "a material name ('" + options.database_material +
                                "') selects a material of a .btfz database; this is not one");
    found->params.set("material", options.database_material);
  }
  return std::move(*found);
}

std::shared_ptr<const Material> openMaterial(const std::string& path_or_spec, const OpenOptions& options) {
  return createMaterial(identifyMaterial(path_or_spec, options).params);
}

std::shared_ptr<const BtfSource> materialBtf(const IdentifiedMaterial& material) { return createBtf(material.params); }
MerlTable materialTable(const IdentifiedMaterial& material) { return createTable(material.params); }

std::shared_ptr<const BtfSource> openBtf(const std::string& path_or_spec, const OpenOptions& options) {
  return materialBtf(identifyMaterial(path_or_spec, options));
}

MerlTable openTable(const std::string& path_or_spec, const OpenOptions& options) {
  return materialTable(identifyMaterial(path_or_spec, options));
}

BtfData brdfAsBtf(const Material& material, const std::string& name) {
  BtfData data(1, 1, name);
  const auto& directions = btfDirections();
  for (int view = 0; view < kBtfDirectionCount; ++view)
    for (int light = 0; light < kBtfDirectionCount; ++light) {
      const Rgb f = material.eval(directions[std::size_t(light)].w, directions[std::size_t(view)].w);
      if (!f.isFinite() || f.minComponent() < 0.0f)
        throw Error(name + ": the material gives an invalid value at view " + std::to_string(view) + ", light " +
                    std::to_string(light));
      data.at(0, 0, view, light) = f;
    }
  return data;
}

}  // namespace btf
