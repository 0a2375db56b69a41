#include "btf/material/model_family.h"

#include <string>

#include "btf/core/error.h"

namespace btf {

const char* modelFamilyName(ModelFamily family) {
  switch (family) {
    case ModelFamily::Lambert: return "lambert";
    case ModelFamily::Phong: return "phong";
    case ModelFamily::Ggx: return "ggx";
    case ModelFamily::Ward: return "ward";
    case ModelFamily::Lafortune: return "lafortune";
    case ModelFamily::Sgd: return "sgd";
    case ModelFamily::Abc: return "abc";
    case ModelFamily::Ggx2: return "ggx2";
  }
  return "unknown";
}

ModelFamily parseModelFamily(std::string_view text, std::span<const ModelFamily> allowed) {
  std::string names;
  for (std::size_t i = 0; i < allowed.size(); ++i) {
    if (text == modelFamilyName(allowed[i])) return allowed[i];
    names += std::string(i == 0 ? "" : i + 1 == allowed.size() ? " or " : ", ") + modelFamilyName(allowed[i]);
  }
  throw Error("unknown model '" + std::string(text) + "' (expected " + names + ")");
}

}  // namespace btf
