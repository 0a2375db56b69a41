// Named materials of btf-datagen (and the generator materials of `btf bench sampling`), from
// diffuse to near-mirror. Each builds the isotropic material that a MERL table of it represents
// (anisotropic models are averaged over phi_h, see azimuthal_average.h).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "btf/material/material.h"

namespace btf::datagen {

struct Preset {
  std::string name;
  std::string description;  // one line: model and parameters
  std::function<std::shared_ptr<const Material>()> make;
};

// In order from diffuse to near-mirror.
const std::vector<Preset>& presets();

// Throws btf::Error naming the unknown preset and listing the known ones.
const Preset& findPreset(const std::string& name);

}  // namespace btf::datagen
