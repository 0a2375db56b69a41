#include "presets.h"

#include "btf/core/error.h"
#include "btf/material/registry.h"

namespace btf::datagen {

MaterialParams Preset::params() const { return MaterialParams::parse(parameters, "preset " + name); }
std::shared_ptr<const Material> Preset::make() const { return createMaterial(params()); }

const std::vector<Preset>& presets() {
  // Parameters are chosen to look like their names; gold's f0 is its measured normal reflectance.
  static const std::vector<Preset> list = {
      {"white-diffuse", "Lambert, albedo 0.8 (a white reference tile)", R"({"type": "lambert", "albedo": 0.8})"},
      {"matte-clay", "Lambert clay (0.50, 0.32, 0.22) + faint very rough GGX sheen (f0 0.03, alpha 0.7)",
       R"({"type": "ggx", "diffuse": [0.50, 0.32, 0.22], "f0": 0.03, "alpha": 0.7})"},
      {"satin-paint", "Lafortune: cream diffuse + broad specular lobe (n 6) + glossier one (n 40)",
       R"({"type": "lafortune", "diffuse": [0.55, 0.50, 0.38],
           "lobes": [{"rho": 0.12, "c": [-1, -1, 1], "exponent": 6}, {"rho": 0.08, "c": [-1, -1, 1], "exponent": 40}]})"},
      {"plastic-red", "GGX: red diffuse (0.55, 0.05, 0.04), f0 0.04, alpha 0.1",
       R"({"type": "ggx", "diffuse": [0.55, 0.05, 0.04], "f0": 0.04, "alpha": 0.1})"},
      {"glossy-blue-plastic", "energy-normalized Phong: blue diffuse (0.05, 0.10, 0.45), ks 0.2, exponent 200",
       R"({"type": "phong", "diffuse": [0.05, 0.10, 0.45], "specular": 0.2, "exponent": 200})"},
      {"brushed-metal",
       "anisotropic Ward (ks 0.75, alpha 0.06 x 0.25) averaged over phi_h: MERL tables are isotropic "
       "(randomly oriented brushing; see btf/material/azimuthal_average.h)",
       R"({"type": "azimuthal-average",
           "material": {"type": "ward", "diffuse": 0.02, "specular": [0.75, 0.75, 0.77], "alpha": [0.06, 0.25]}})"},
      {"rough-gold", "GGX metal: gold f0 (1.00, 0.71, 0.29), alpha 0.3",
       R"({"type": "ggx", "diffuse": 0, "f0": [1.00, 0.71, 0.29], "alpha": 0.3})"},
      {"chrome", "GGX metal, near-mirror: f0 (0.55, 0.56, 0.55), alpha 0.02",
       R"({"type": "ggx", "diffuse": 0, "f0": [0.55, 0.56, 0.55], "alpha": 0.02})"},
  };
  return list;
}

const Preset& findPreset(const std::string& name) {
  std::string known;
  for (const Preset& p : presets()) {
    if (p.name == name) return p;
    known += (known.empty() ? "" : ", ") + p.name;
  }
  throw Error("unknown preset '" + name + "' (known: " + known + ")");
}

}  // namespace btf::datagen
