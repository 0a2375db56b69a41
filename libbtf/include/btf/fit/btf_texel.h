// A BTF texel as data to fit (fit/analytic_fit.h): the texel's apparent BRDF at the measured
// direction pairs. Without a texel, the mean over all texels: the BRDF the material shows from far
// away, where one pixel covers many texels.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "btf/fit/analytic_fit.h"
#include "btf/io/btf_data.h"

namespace btf {

// Why `texel` is not a texel of `btf` ("texel (x, y) lies outside its w x h texels"), or nothing
// when it is one: for callers that name the file in their own error.
std::optional<std::string> texelOutside(const BtfSource& btf, glm::ivec2 texel);

// Texel (x, y) of `btf`, or the mean over its texels, as a one-texel BTF holding the same views.
// Streams the source one view at a time (progress per view). Throws btf::Error for a texel outside
// the BTF or a source whose views have the wrong size.
BtfData btfTexel(const BtfSource& btf, std::optional<glm::ivec2> texel);

// The entries of a one-texel BTF as measurements: wi the light, wo the view, f the value.
std::vector<MeasuredReflectance> texelMeasurements(const BtfData& texel);

}  // namespace btf
