// The analytic model families that several parts of libbtf name: the fitter's (btf/fit/
// analytic_fit.h: ggx, ward, lafortune) and the published MERL fits' (btf/fit/merl_fits.h: sgd,
// abc, lafortune). One naming for all: a family's name is also the "type" under which its material
// registers (btf/material/registry.h), so "ggx" in `btf fit --model`, in a fit file and in a scene
// is one word.
#pragma once

#include <span>
#include <string_view>

namespace btf {

enum class ModelFamily { Lambert, Phong, Ggx, Ward, Lafortune, Sgd, Abc, Ggx2 };

// "lambert", "phong", "ggx", "ward", "lafortune", "sgd", "abc", "ggx2" (two GGX lobes).
const char* modelFamilyName(ModelFamily family);
// The family of that name among `allowed`; throws btf::Error naming the allowed ones.
ModelFamily parseModelFamily(std::string_view text, std::span<const ModelFamily> allowed);

}  // namespace btf
