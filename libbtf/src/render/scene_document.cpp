#include "btf/render/scene_document.h"

#include <fstream>

#include "btf/core/error.h"
#include "btf/io/atomic_file.h"
#include "material_params_access.h"
#include "scene_document_impl.h"

namespace btf::render {
namespace fs = std::filesystem;
using detail::json;

namespace {

fs::path folderOf(const fs::path& file) { return file.parent_path().empty() ? fs::path(".") : file.parent_path(); }

// A relative name that resolves against `from`, rewritten to resolve against `to`.
void rebase(json& value, const fs::path& from, const fs::path& to) {
  if (!value.is_string()) return;
  const fs::path p(value.get<std::string>());
  if (p.empty() || p.is_absolute()) return;
  value = fs::absolute(from / p).lexically_normal().lexically_relative(fs::absolute(to).lexically_normal()).string();
}

// Every file name of a material's parameter set, nested sets included.
void rebaseMaterial(json& params, const fs::path& from, const fs::path& to) {
  if (params.is_array()) {
    for (json& item : params) rebaseMaterial(item, from, to);
    return;
  }
  if (!params.is_object()) return;
  for (auto& [key, value] : params.items()) {
    if (key == "file" || key == "fits_dir") rebase(value, from, to);
    else rebaseMaterial(value, from, to);
  }
}

}  // namespace

SceneDocument::SceneDocument(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
SceneDocument::~SceneDocument() = default;
SceneDocument::SceneDocument(const SceneDocument& other) : impl_(std::make_unique<Impl>(*other.impl_)) {}
SceneDocument& SceneDocument::operator=(const SceneDocument& other) {
  if (this != &other) *impl_ = *other.impl_;
  return *this;
}
SceneDocument::SceneDocument(SceneDocument&&) noexcept = default;
SceneDocument& SceneDocument::operator=(SceneDocument&&) noexcept = default;

SceneDocument SceneDocument::read(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) throw FileError(file, "no such scene file");
  std::ifstream in(file);
  if (!in) throw FileError(file, "cannot open the scene file");
  auto impl = std::make_unique<Impl>();
  impl->file = file;
  try {
    impl->root = json::parse(in);
  } catch (const json::exception& e) {  // parse_error, and out_of_range for numbers beyond a double
    throw FileError(file, std::string("malformed JSON: ") + e.what());
  }
  return SceneDocument(std::move(impl));
}

const fs::path& SceneDocument::file() const { return impl_->file; }

std::vector<std::string> SceneDocument::materialNames() const {
  std::vector<std::string> names;
  const json& root = impl_->root;
  if (root.is_object() && root.contains("materials") && root["materials"].is_object())
    for (const auto& item : root["materials"].items()) names.push_back(item.key());
  return names;
}

bool SceneDocument::hasMaterial(const std::string& name) const {
  const json& root = impl_->root;
  return root.is_object() && root.contains("materials") && root["materials"].is_object() &&
         root["materials"].contains(name);
}

MaterialParams SceneDocument::material(const std::string& name) const {
  if (!hasMaterial(name)) throw FileError(impl_->file, "/materials: no material '" + name + "'");
  return MaterialParamsAccess::fromJson(impl_->root["materials"][name], "/materials/" + detail::pointerToken(name),
                                        impl_->file, folderOf(impl_->file));
}

void SceneDocument::setMaterial(const std::string& name, const MaterialParams& params) {
  json value = MaterialParamsAccess::value(params);
  rebaseMaterial(value, MaterialParamsAccess::base(params), folderOf(impl_->file));
  impl_->root["materials"][name] = std::move(value);
}

void SceneDocument::setComment(const std::string& comment) { impl_->root["comment"] = comment; }

void SceneDocument::write(const fs::path& path) const {
  json out = impl_->root;
  const fs::path from = folderOf(impl_->file), to = folderOf(path);
  if (out.contains("materials")) rebaseMaterial(out["materials"], from, to);
  for (const char* list : {"shapes", "lights"})
    if (out.contains(list) && out[list].is_array())
      for (json& item : out[list])
        if (item.is_object() && item.contains("file")) rebase(item["file"], from, to);
  writeFileAtomically(path, [&](std::ofstream& stream) { stream << out.dump(2) << "\n"; });
}

}  // namespace btf::render
