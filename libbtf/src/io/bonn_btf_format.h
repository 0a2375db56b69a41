// Constants and colour transforms of Bonn .btf files (btf/io/bonn_btf.h), shared by the reader and
// the writer so that what one encodes the other decodes with the same numbers.
#pragma once

#include <array>
#include <cmath>
#include <string_view>

#include "btf/core/rgb.h"
#include "btf/io/bonn_btf.h"

namespace btf::bonn {

struct Signature {
  std::string_view text;
  BonnBtfLayout layout;
  bool extended_header;  // FMF12FCER: a header version byte after the common header
};
// Longest first: "!FMF06FCR" must win over "!FMF06FC", as btflib takes the longest match.
inline constexpr std::array<Signature, 6> kSignatures{{{"!DFMF08FCR", BonnBtfLayout::Dfmf, false},
                                                       {"!FMF12FCER", BonnBtfLayout::Fmf, true},
                                                       {"!FMF06FCR", BonnBtfLayout::Fmf, false},
                                                       {"!PVF06FCR", BonnBtfLayout::Pvf, false},
                                                       {"!FMF06FC", BonnBtfLayout::Fmf, false},
                                                       {"!PVF06FC", BonnBtfLayout::Pvf, false}}};
inline constexpr std::size_t kLongestSignature = 10;
inline constexpr std::int32_t kLegacyPvfMagic = 301074;
inline constexpr std::size_t kMetaStringBytes = 80;

// The offset the log colour models and the dynamic-range reduction add before the logarithm
// (btflib's drr_eps; no file stores it).
inline constexpr float kLogEpsilon = 1e-5f;

// btflib's YUV -> RGB matrix (rows: R, G, B), and its inverse for the writer.
inline constexpr float kYuvToRgb[3][3] = {{1.0f, 0.0f, 1.13983f}, {1.0f, -0.39465f, -0.5806f}, {1.0f, 2.03211f, 0.0f}};

inline Rgb yuvToRgb(float y, float u, float v) {
  return Rgb(kYuvToRgb[0][0] * y + kYuvToRgb[0][1] * u + kYuvToRgb[0][2] * v,
             kYuvToRgb[1][0] * y + kYuvToRgb[1][1] * u + kYuvToRgb[1][2] * v,
             kYuvToRgb[2][0] * y + kYuvToRgb[2][1] * u + kYuvToRgb[2][2] * v);
}

// The colour models btflib's undecorrelate handles (5 and 6 are multispectral).
inline bool knownColorModel(int model) { return (model >= 0 && model <= 4) || (model >= 9 && model <= 12); }
inline bool spectralColorModel(int model) { return model == 5 || model == 6; }

}  // namespace btf::bonn
