// The YUV of Bonn .btf files (btflib's matrix), shared by their reader and writer (io/) and by the
// factor form of the compress layer, which codes log-luminance as Bonn's DFMF does.
#pragma once

#include "btf/core/rgb.h"

namespace btf::bonn {

// The offset the log colour models and the dynamic-range reduction add before the logarithm
// (btflib's drr_eps; no file stores it).
inline constexpr float kLogEpsilon = 1e-5f;

// btflib's YUV -> RGB matrix (rows: R, G, B).
inline constexpr float kYuvToRgb[3][3] = {{1.0f, 0.0f, 1.13983f}, {1.0f, -0.39465f, -0.5806f}, {1.0f, 2.03211f, 0.0f}};

inline Rgb yuvToRgb(float y, float u, float v) {
  return Rgb(kYuvToRgb[0][0] * y + kYuvToRgb[0][1] * u + kYuvToRgb[0][2] * v,
             kYuvToRgb[1][0] * y + kYuvToRgb[1][1] * u + kYuvToRgb[1][2] * v,
             kYuvToRgb[2][0] * y + kYuvToRgb[2][1] * u + kYuvToRgb[2][2] * v);
}

}  // namespace btf::bonn
