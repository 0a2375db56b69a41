#include "btf/material/material.h"

#include <string>

#include "btf/core/error.h"

namespace btf {

void Material::checkEvalManySizes(std::span<const glm::vec3> wi, std::span<const Rgb> out) {
  if (wi.size() != out.size())
    throw Error("evalMany: " + std::to_string(wi.size()) + " directions but " + std::to_string(out.size()) + " outputs");
}

void Material::evalMany(const glm::vec3& wo, std::span<const glm::vec3> wi, std::span<Rgb> out, glm::vec2 uv) const {
  checkEvalManySizes(wi, out);
  for (std::size_t k = 0; k < wi.size(); ++k) out[k] = eval(wi[k], wo, uv);
}

}  // namespace btf
