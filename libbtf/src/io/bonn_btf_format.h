// Constants and colour transforms of Bonn .btf files (btf/io/bonn_btf.h), shared by the reader and
// the writer so that what one encodes the other decodes with the same numbers.
#pragma once

#include <array>
#include <cmath>
#include <string_view>

#include "btf/core/rgb.h"
#include "btf/io/bonn_btf.h"
#include "bonn_color.h"

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

// The colour models btflib's undecorrelate handles (5 and 6 are multispectral).
inline bool knownColorModel(int model) { return (model >= 0 && model <= 4) || (model >= 9 && model <= 12); }
inline bool spectralColorModel(int model) { return model == 5 || model == 6; }

}  // namespace btf::bonn
