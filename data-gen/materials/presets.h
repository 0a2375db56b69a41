// Named materials of btf-datagen (and the generator materials of `btf bench sampling`), from
// diffuse to near-mirror. Each is a parameter set built through the material registry
// (btf/material/registry.h), as a scene would hold it; every one is isotropic, as the MERL table it
// is written into (the anisotropic one is averaged over phi_h, btf/material/azimuthal_average.h).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "btf/material/material.h"
#include "btf/material/material_params.h"

namespace btf::datagen {

struct Preset {
  std::string name;
  std::string description;  // one line: model and parameters
  std::string parameters;   // the material's parameter set, JSON
  MaterialParams params() const;
  std::shared_ptr<const Material> make() const;
};

// In order from diffuse to near-mirror.
const std::vector<Preset>& presets();

// Throws btf::Error naming the unknown preset and listing the known ones.
const Preset& findPreset(const std::string& name);

}  // namespace btf::datagen
