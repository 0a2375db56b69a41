// Level-1 entries coded in a principal basis of their ring (private to src/compress/).
//
// A new level-1 entry is the unit luminance function of one ring of one texel: 6 to 24 values that,
// on measured data, carry camera and JPEG noise. Stored value by value, every entry costs its full
// noise in bits and zstd cannot shrink it.
// Rotated into the principal basis of the ring's functions (the eigenvectors of their second-moment
// matrix, strongest first), an entry's energy sits in its leading coefficients; the compressor then
// keeps only as many leading coefficients as the tolerance needs (the dropped tail's energy stays
// within the entry's own tolerance, less the quantization share) and rounds them to the value step
// of VqPrecision. The entry the codebook holds is the reconstruction of those coefficients, so every
// vector that later reuses it is judged against what the file will decode. This is transform coding
// of the codebook, as PCA codes the data, but per entry and only as deep as each entry needs.
//
// Used only with VqOptions::level1_cut: on clean data the coefficients code worse than the values
// and the cut moves entries off the data (docs/design-notes.md#vq-level-1-basis-and-cut), so by
// default entries stay value by value.
// The basis is learned from the first view the compressor sees and written to the file in float32
// ("level1/basis<r>"); the ring's section then holds coefficients instead of values. The codes a
// lookup reads are the same 16-bit values as before (decoded once, on reading), so decoding speed
// and the lookup tables do not change. Rings with few lit vectors (BRDFs as one-texel BTFs) and
// epsilon 0 keep the value-by-value form: a basis there would cost more bytes than it saves.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "btf/core/btf_ring_layout.h"
#include "btf/core/rgb.h"

namespace btf {

// A learned basis of one ring: n x n float32, row-major, column j the j-th principal direction
// (descending eigenvalue); empty when the ring stores values. `step` is the coefficient unit.
struct VqRingBasis {
  int n = 0;
  float step = 0.0f;
  std::vector<float> v;
  bool empty() const { return v.empty(); }
  bool operator==(const VqRingBasis&) const = default;
};

// A basis is learned for a ring only from at least this many lit vectors per basis value (n^2 of
// them): below that the float32 basis (4 n^2 bytes) is not repaid and the moments are poorly
// estimated.
inline constexpr int kVqBasisVectorsPerValue = 4;

// Learns the bases of the layout's rings from one view (texel-major by light: buffer[light * texels
// + t], as BtfSource::loadView gives it); a ring of one light never has one. Deterministic: sums in
// texel order, in double. `step` is the coefficient unit (VqPrecision's value step).
std::vector<VqRingBasis> learnVqRingBases(const std::vector<Rgb>& view, std::size_t texels, const BtfRingLayout& layout,
                                          float step);

// Coefficients of a unit function u (n values) in the basis: the leading ones whose dropped tail has
// energy <= budget^2, rounded to multiples of the step (integers, in units of the step); the rest 0.
void vqBasisCoefficients(const VqRingBasis& basis, std::span<const float> u, double budget, std::int32_t* coefficients);

// The 16-bit level-1 codes (encodeVqEntryValue) of the entry whose coefficients are given: the
// one reconstruction the compressor and every reader compute, bit for bit.
void vqBasisCodes(const VqRingBasis& basis, const std::int32_t* coefficients, std::uint16_t* codes);

}  // namespace btf
