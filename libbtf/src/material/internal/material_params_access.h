// The JSON behind a MaterialParams, for the library's own JSON readers and writers (the scene
// loader and writer): a set made from an entry of a parsed document, and its value back.
#pragma once

#include <filesystem>
#include <string>

#include "btf/material/material_params.h"
#include "json_node.h"

namespace btf {

struct MaterialParamsAccess {
  // A copy of `value`, which sits at `pointer` in `file`; relative names resolve against `base`.
  static MaterialParams fromJson(const detail::json& value, std::string pointer, const std::filesystem::path& file,
                                 const std::filesystem::path& base);
  static const detail::json& value(const MaterialParams& params);
  // The folder relative file names of the set resolve against.
  static const std::filesystem::path& base(const MaterialParams& params);
};

}  // namespace btf
