// A typed parameter set that builds one material: the JSON object a scene file holds under
// "materials" ({"type": "ggx", "diffuse": [0.5, 0.1, 0.1], "f0": 0.04, "alpha": 0.2}), the
// parameters a path or a spec opens as (btf/material/registry.h), or one made in code. What pbrt
// calls a ParameterDictionary and Mitsuba a Properties object.
//
// The readers check type and range, and every problem is a btf::FileError that names where the set
// came from and the key's JSON pointer: "scene.json: /materials/gold/alpha: expected a positive
// number, got -1". Relative file names resolve against the folder of the set's origin (a scene's
// folder), or against the current directory for a set made in code.
#pragma once

#include <filesystem>
#include <initializer_list>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "btf/core/rgb.h"

namespace btf {

class MaterialParams {
 public:
  MaterialParams();  // an empty set
  // {"type": type}
  explicit MaterialParams(std::string_view type);
  // A JSON object; `origin` names it in messages and its folder resolves relative file names.
  // Throws FileError for text that is not a JSON object.
  static MaterialParams parse(std::string_view json_text, const std::filesystem::path& origin = {});
  ~MaterialParams();
  MaterialParams(const MaterialParams&);
  MaterialParams& operator=(const MaterialParams&);
  MaterialParams(MaterialParams&&) noexcept;
  MaterialParams& operator=(MaterialParams&&) noexcept;

  // --- Building -------------------------------------------------------------------------------
  MaterialParams& set(const std::string& key, std::string_view value);
  MaterialParams& set(const std::string& key, const char* value) { return set(key, std::string_view(value)); }
  MaterialParams& set(const std::string& key, double value);
  MaterialParams& set(const std::string& key, bool value);
  MaterialParams& set(const std::string& key, const Rgb& value);  // [r, g, b]
  MaterialParams& set(const std::string& key, const glm::vec3& value);
  MaterialParams& set(const std::string& key, const MaterialParams& value);  // a nested set
  MaterialParams& set(const std::string& key, const std::vector<MaterialParams>& values);  // a list of sets
  MaterialParams& erase(const std::string& key);
  // Where the set came from and the folder relative file names resolve against (see above).
  MaterialParams& setOrigin(const std::filesystem::path& origin, const std::filesystem::path& base_folder);

  // --- Reading --------------------------------------------------------------------------------
  // "type", or empty when the set has none.
  std::string type() const;
  bool has(const std::string& key) const;
  std::vector<std::string> keys() const;
  // Throws FileError for a key outside `known`, listing them (a misspelt key is not ignored).
  void allowOnly(const std::vector<std::string>& known) const;

  double number(const std::string& key) const;  // finite
  double number(const std::string& key, double lo, double hi) const;
  double positive(const std::string& key) const;
  int integer(const std::string& key, int lo, int hi) const;
  bool boolean(const std::string& key) const;
  std::string string(const std::string& key) const;
  glm::vec3 vec3(const std::string& key) const;
  // A colour: three non-negative numbers, or one for grey.
  Rgb rgb(const std::string& key) const;
  // One positive number (isotropic) or [x, y].
  glm::vec2 positivePair(const std::string& key) const;
  // A file name, resolved (see above); existingPath also checks that it exists.
  std::filesystem::path path(const std::string& key) const;
  std::filesystem::path existingPath(const std::string& key) const;
  // A nested set, and a list of them; they keep the origin and the JSON pointer of the parent.
  MaterialParams child(const std::string& key) const;
  std::vector<MaterialParams> list(const std::string& key) const;

  // Throw FileError "<origin>: <pointer>: <problem>", for the whole set or one key of it.
  [[noreturn]] void fail(const std::string& problem) const;
  [[noreturn]] void fail(const std::string& key, const std::string& problem) const;

  const std::filesystem::path& origin() const;
  const std::string& pointer() const;
  // The set as JSON text (indent < 0: one line).
  std::string toJson(int indent = -1) const;

 private:
  struct Impl;
  explicit MaterialParams(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
  friend struct MaterialParamsAccess;
};

}  // namespace btf
