// The range of values libbtf accepts from files and options, and promises of what it writes: every
// number is checked in the type it is stored in (a double that passes as finite may become inf as a
// float), and every value it writes is finite.
#pragma once

#include <cmath>
#include <limits>
#include <span>

#include "btf/core/rgb.h"

namespace btf {

// The largest reflectance (f in 1/sr, or a BTF's apparent BRDF) libbtf holds in float. Compression
// distances, statistics and renders add squares of many values in float; values up to 1e10 keep
// sums of billions of squares finite. Measured reflectance lies many orders of magnitude below
// (a near-mirror lobe of a measured table peaks in the thousands).
inline constexpr float kMaxReflectance = 1e10f;
// The largest radiance or intensity of a light: a render sums radiance times reflectance over
// paths, so both bounds together keep a pixel finite.
inline constexpr float kMaxRadiance = 1e10f;

// The index of the first value that is not finite, or values.size() when all are.
inline std::size_t firstNonFinite(std::span<const float> values) {
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!std::isfinite(values[i])) return i;
  return values.size();
}

}  // namespace btf
