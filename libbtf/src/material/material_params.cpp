#include "btf/material/material_params.h"

#include <algorithm>
#include <cstdio>

#include "btf/core/error.h"
#include "json_node.h"
#include "material_params_access.h"

namespace btf {

using detail::json;
using detail::JsonNode;

struct MaterialParams::Impl {
  json value = json::object();
  std::string pointer;           // of the value in its origin, "" for the root
  std::filesystem::path origin;  // named in messages
  std::filesystem::path base;    // relative file names resolve against it

  JsonNode node() const { return JsonNode(value, pointer, origin, &base); }
};

MaterialParams::MaterialParams() : impl_(std::make_unique<Impl>()) {}
MaterialParams::MaterialParams(std::string_view type) : MaterialParams() { set("type", type); }
MaterialParams::MaterialParams(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
MaterialParams::~MaterialParams() = default;
MaterialParams::MaterialParams(const MaterialParams& other) : impl_(std::make_unique<Impl>(*other.impl_)) {}
MaterialParams& MaterialParams::operator=(const MaterialParams& other) {
  if (this != &other) *impl_ = *other.impl_;
  return *this;
}
MaterialParams::MaterialParams(MaterialParams&&) noexcept = default;
MaterialParams& MaterialParams::operator=(MaterialParams&&) noexcept = default;

MaterialParams MaterialParams::parse(std::string_view json_text, const std::filesystem::path& origin) {
  auto impl = std::make_unique<Impl>();
  try {
    impl->value = json::parse(json_text);
  } catch (const json::exception& e) {
    throw FileError(origin, std::string("malformed JSON: ") + e.what());
  }
  impl->origin = origin;
  impl->base = origin.parent_path();
  if (!impl->value.is_object()) throw FileError(origin, "a material's parameters must be a JSON object");
  return MaterialParams(std::move(impl));
}

MaterialParams& MaterialParams::set(const std::string& key, std::string_view value) {
  impl_->value[key] = std::string(value);
  return *this;
}
MaterialParams& MaterialParams::set(const std::string& key, double value) {
  impl_->value[key] = value;
  return *this;
}
MaterialParams& MaterialParams::set(const std::string& key, bool value) {
  impl_->value[key] = value;
  return *this;
}
MaterialParams& MaterialParams::set(const std::string& key, const Rgb& value) {
  impl_->value[key] = json::array({value.r, value.g, value.b});
  return *this;
}
MaterialParams& MaterialParams::set(const std::string& key, const glm::vec3& value) {
  impl_->value[key] = json::array({value.x, value.y, value.z});
  return *this;
}
MaterialParams& MaterialParams::set(const std::string& key, const MaterialParams& value) {
  impl_->value[key] = value.impl_->value;
  return *this;
}
MaterialParams& MaterialParams::set(const std::string& key, const std::vector<MaterialParams>& values) {
  json list = json::array();
  for (const MaterialParams& v : values) list.push_back(v.impl_->value);
  impl_->value[key] = std::move(list);
  return *this;
}
MaterialParams& MaterialParams::erase(const std::string& key) {
  impl_->value.erase(key);
  return *this;
}
MaterialParams& MaterialParams::setOrigin(const std::filesystem::path& origin, const std::filesystem::path& base_folder) {
  impl_->origin = origin;
  impl_->base = base_folder;
  return *this;
}

std::string MaterialParams::type() const {
  return has("type") ? impl_->node()["type"].string() : std::string();
}
bool MaterialParams::has(const std::string& key) const { return impl_->node().has(key); }
std::vector<std::string> MaterialParams::keys() const {
  std::vector<std::string> out;
  for (const auto& item : impl_->node().object()) out.push_back(item.first);
  return out;
}
void MaterialParams::allowOnly(const std::vector<std::string>& known) const {
  const JsonNode node = impl_->node();
  for (const auto& item : node.object())
    if (std::find(known.begin(), known.end(), item.first) == known.end()) {
      std::string list;
      for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
      node[item.first].fail("unknown key (expected one of: " + list + ")");
    }
}

double MaterialParams::number(const std::string& key) const { return impl_->node()[key].number(); }
double MaterialParams::number(const std::string& key, double lo, double hi) const {
  char range[80];
  std::snprintf(range, sizeof range, "in [%g, %g]", lo, hi);
  return impl_->node()[key].number(lo, hi, range);
}
double MaterialParams::positive(const std::string& key) const { return impl_->node()[key].positive(); }
int MaterialParams::integer(const std::string& key, int lo, int hi) const { return impl_->node()[key].integer(lo, hi); }
bool MaterialParams::boolean(const std::string& key) const { return impl_->node()[key].boolean(); }
std::string MaterialParams::string(const std::string& key) const { return impl_->node()[key].string(); }
glm::vec3 MaterialParams::vec3(const std::string& key) const { return impl_->node()[key].vec3(); }
Rgb MaterialParams::rgb(const std::string& key) const { return impl_->node()[key].rgb(); }
glm::vec2 MaterialParams::positivePair(const std::string& key) const {
  const JsonNode a = impl_->node()[key];
  if (a.value().is_array()) {
    if (a.size() != 2) a.fail("expected one number or [x, y]");
    return {a.at(0).positiveFloat(), a.at(1).positiveFloat()};
  }
  const float v = a.positiveFloat();
  return {v, v};
}
std::filesystem::path MaterialParams::path(const std::string& key) const { return impl_->node()[key].path(); }
std::filesystem::path MaterialParams::existingPath(const std::string& key) const {
  return impl_->node()[key].existingPath();
}

MaterialParams MaterialParams::child(const std::string& key) const {
  const JsonNode c = impl_->node()[key];
  (void)c.object();  // an object, or the error names the key
  return MaterialParamsAccess::fromJson(c.value(), c.pointer(), impl_->origin, impl_->base);
}
std::vector<MaterialParams> MaterialParams::list(const std::string& key) const {
  const JsonNode l = impl_->node()[key];
  l.requireArray();
  std::vector<MaterialParams> out;
  for (std::size_t i = 0; i < l.size(); ++i) {
    const JsonNode item = l.at(i);
    (void)item.object();
    out.push_back(MaterialParamsAccess::fromJson(item.value(), item.pointer(), impl_->origin, impl_->base));
  }
  return out;
}

void MaterialParams::fail(const std::string& problem) const {
  // A set of its own (a spec, one made in code) has no place in a file to point at.
  if (impl_->pointer.empty()) {
    if (impl_->origin.empty()) throw Error(problem);
    throw FileError(impl_->origin, problem);
  }
  impl_->node().fail(problem);
}
void MaterialParams::fail(const std::string& key, const std::string& problem) const {
  const JsonNode node = impl_->node();
  if (node.has(key)) node[key].fail(problem);
  node.fail("\"" + key + "\": " + problem);
}

const std::filesystem::path& MaterialParams::origin() const { return impl_->origin; }
const std::string& MaterialParams::pointer() const { return impl_->pointer; }
std::string MaterialParams::toJson(int indent) const { return impl_->value.dump(indent); }

MaterialParams MaterialParamsAccess::fromJson(const json& value, std::string pointer, const std::filesystem::path& file,
                                              const std::filesystem::path& base) {
  auto impl = std::make_unique<MaterialParams::Impl>();
  impl->value = value;
  impl->pointer = std::move(pointer);
  impl->origin = file;
  impl->base = base;
  return MaterialParams(std::move(impl));
}

const json& MaterialParamsAccess::value(const MaterialParams& params) { return params.impl_->value; }
const std::filesystem::path& MaterialParamsAccess::base(const MaterialParams& params) { return params.impl_->base; }

}  // namespace btf
