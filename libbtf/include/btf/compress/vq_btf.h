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

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "btf/io/btf_data.h"

namespace btf {

struct VqOptions {
  float epsilon = 0.02f;         // level-1 tolerance (relative, on the normalized 1D functions)
  float chroma_epsilon = 0.01f;  // tolerance of the chromaticity quantizer
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
