#include "presets.h"

#include "btf/core/error.h"
#include "btf/material/ggx.h"
#include "btf/material/lafortune.h"
#include "btf/material/lambert.h"
#include "btf/material/phong.h"
#include "btf/material/ward.h"
#include "azimuthal_average.h"

namespace btf::datagen {

const std::vector<Preset>& presets() {
  // Parameters are chosen to look like their names; gold's f0 is its measured normal reflectance.
  static const std::vector<Preset> list = {
      {"white-diffuse", "Lambert, albedo 0.8 (a white reference tile)",
       [] { return std::make_shared<Lambert>(Rgb(0.8f)); }},
      {"matte-clay", "Lambert clay (0.50, 0.32, 0.22) + faint very rough GGX sheen (f0 0.03, alpha 0.7)",
       [] { return std::make_shared<Ggx>(Rgb(0.50f, 0.32f, 0.22f), Rgb(0.03f), 0.7f, 0.7f); }},
      {"satin-paint", "Lafortune: cream diffuse + broad specular lobe (n 6) + glossier one (n 40)",
       [] {
         return std::make_shared<Lafortune>(
             Rgb(0.55f, 0.50f, 0.38f),
             std::vector<LafortuneLobe>{{Rgb(0.12f), glm::vec3(-1.0f, -1.0f, 1.0f), 6.0f},
                                        {Rgb(0.08f), glm::vec3(-1.0f, -1.0f, 1.0f), 40.0f}});
       }},
      {"plastic-red", "GGX: red diffuse (0.55, 0.05, 0.04), f0 0.04, alpha 0.1",
       [] { return std::make_shared<Ggx>(Rgb(0.55f, 0.05f, 0.04f), Rgb(0.04f), 0.1f, 0.1f); }},
      {"glossy-blue-plastic", "energy-normalized Phong: blue diffuse (0.05, 0.10, 0.45), ks 0.2, exponent 200",
       [] { return std::make_shared<Phong>(Rgb(0.05f, 0.10f, 0.45f), Rgb(0.2f), 200.0f); }},
      {"brushed-metal",
       "anisotropic Ward (ks 0.75, alpha 0.06 x 0.25) averaged over phi_h: MERL tables are isotropic "
       "(randomly oriented brushing; see azimuthal_average.h)",
       [] {
         return std::make_shared<AzimuthalAverage>(
             std::make_shared<Ward>(Rgb(0.02f), Rgb(0.75f, 0.75f, 0.77f), 0.06f, 0.25f));
       }},
      {"rough-gold", "GGX metal: gold f0 (1.00, 0.71, 0.29), alpha 0.3",
       [] { return std::make_shared<Ggx>(Rgb(0.0f), Rgb(1.00f, 0.71f, 0.29f), 0.3f, 0.3f); }},
      {"chrome", "GGX metal, near-mirror: f0 (0.55, 0.56, 0.55), alpha 0.02",
       [] { return std::make_shared<Ggx>(Rgb(0.0f), Rgb(0.55f, 0.56f, 0.55f), 0.02f, 0.02f); }},
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
