// Multi-level vector quantization of BTFs (after Havran, Filip and Myszkowski 2010, "Bidirectional
// Texture Function Compression Based on Multi-Level Vector Quantization", the BTFBASE scheme).
//
// Level 1: the data is cut into small 1D functions over light azimuth (fixed texel, view and light
// ring; ring sizes 1, 6, 12, 18, 20, 24 as in btf_directions.h), each normalized by a stored scale
// and inserted one by one into a codebook searched with FLANN (compress/codebook.h): the nearest
// entry is reused when within the tolerance, else the function becomes a new entry.
// Level 2: the (index, scale) vectors of one 2D light slice (fixed texel and view) are quantized
// again; level 3: the vectors of a texel's slices over all views. Colour: luminance goes through
// the levels above; chromaticity is quantized separately and coarsely (it varies little).
// TBB parallel where it does not change the result: the output is identical for any thread count.
//
// The compressed form decodes any entry on its own (value()), so BtfMaterial evaluates straight
// from the codebooks; loadView() decodes one view for comparisons and `btf decompress`.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "btf/io/btf_data.h"

namespace btf {

// Tolerances and their bounds (the exact rules are in src/compress/vq_compress.cpp):
// - Every level reuses a codebook entry only when the least-squares fit of the entry (scaled) to
//   what it replaces has an L2 error <= epsilon * max(|f|, energy_floor * R), where |f| is the
//   norm of what it replaces and R the RMS norm of its batch (one ring of one view at level 1, the
//   light slices of one view at level 2, all texels at level 3): relative for bright vectors, an
//   absolute floor for dark ones (shadowed, grazing), which a purely relative rule would give
//   entries of their own although they add almost nothing to the error. Level 1 fits the
//   luminance of a ring's 1D function, level 2 the level-1 reconstruction of a light slice (81
//   values), level 3 the level-2 reconstruction of a texel (81 x 81 values). Summed over a batch,
//   the squared error is <= epsilon^2 (1 + energy_floor^2) times the batch's energy, so each level
//   adds a relative RMS error <= e = epsilon sqrt(1 + energy_floor^2), and the luminance rel_rmse
//   is <= (1 + e)^levels - 1, plus the quantization of new entries' values (16-bit) and of scales
//   (16-bit log2, step 1/1024: <= 0.034 %). energy_floor = 0 makes the bound per vector.
// - Chromaticity c = (R / Y, B / Y) of each ring's 1D function (the energy-weighted mean over the
//   ring) is quantized on a grid of step chroma_epsilon; G follows from Y. An entry of level 2 or
//   3 is reused only when each ring's chromaticity lies within one grid step (per component) of
//   the data's own quantized chromaticity: the error of c is <= 1.5 chroma_epsilon per component
//   (plus the variation of c within a ring, which this scheme does not represent).
struct VqOptions {
  float epsilon = 0.02f;         // relative L2 tolerance per level (see above); 0: near-lossless
  float chroma_epsilon = 0.01f;  // grid step of the chromaticity (R/Y, B/Y); > 0
  float energy_floor = 1.0f;     // >= 0: the absolute floor of the tolerance, in batch RMS norms
  int levels = 3;                // 1, 2 or 3
  int threads = 0;               // 0: TBB's default; the output does not depend on it
};

struct VqStats {
  std::vector<std::size_t> codebook_entries;  // per level
  std::uint64_t compressed_bytes = 0;         // payload as stored in .btfz (after zstd)
  double seconds = 0;                         // compression wall time
  double ratio_u8 = 0, ratio_f32 = 0;         // ARCHITECTURE.md measures
};

class VqBtf final : public BtfSource, public BtfLookup {
 public:
  int width() const override;
  int height() const override;
  std::string name() const override;
  void loadView(int view, std::vector<Rgb>& out) const override;
  int lookupWidth() const override { return width(); }
  int lookupHeight() const override { return height(); }
  Rgb value(int x, int y, int view, int light) const override;

  const VqOptions& options() const;
  const VqStats& stats() const;

  // The light slice of texel (x, y) and a view as its six rings, for samplers that work on the
  // compressed form (material/btf_material.h): ring r's luminance at light azimuth a is
  // scale * values[a] (a < btfRingSize(r)); cdf holds the normalized prefix sums of values
  // (btfRingSize(r) + 1 entries, as buildCdf1D writes them) and sum their total. A few lookups.
  struct LightRing {
    const float* values;
    const float* cdf;
    float sum;
    float scale;
  };
  void lightRings(int x, int y, int view, std::array<LightRing, kBtfRingCount>& rings) const;
  // Sum over k < count of weights[k] * value(x, y, views[k], lights[k]): BtfMaterial's
  // interpolation in one call per texel rather than one virtual call per entry.
  Rgb weightedSum(int x, int y, const int* views, const int* lights, const float* weights, int count) const;

  // .btfz (io/container.h). write() fills stats().compressed_bytes; read() throws FileError.
  void write(const std::filesystem::path& path) const;
  static VqBtf read(const std::filesystem::path& path);

  struct Impl;  // codebooks and index streams (src/compress/)
  explicit VqBtf(std::shared_ptr<Impl> impl);
  const Impl& impl() const { return *impl_; }

 private:
  std::shared_ptr<Impl> impl_;
};

// Compresses a BTF view by view (progress reported). Throws btf::Error for invalid options or
// data (NaN, infinite or negative values name the source, view and light).
VqBtf compressVq(const BtfSource& source, const VqOptions& options = {});

}  // namespace btf
