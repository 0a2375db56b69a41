// Multi-level vector quantization of BTFs (after Havran, Filip and Myszkowski 2010, "Bidirectional
// Texture Function Compression Based on Multi-Level Vector Quantization", the BTFBASE scheme).
//
// Level 1: the data is cut into small 1D functions over light azimuth (fixed texel, view and light
// ring; the rings of the BTF's direction set, core/btf_ring_layout.h: on the 81-direction set sizes
// 1, 6, 12, 18, 20, 24 as in btf_directions.h), each normalized by a stored scale
// and inserted one by one into a codebook searched with FLANN (compress/codebook.h): the nearest
// entry the search finds is reused when within the tolerance, else the function becomes a new
// entry. (The search is approximate, a bounded number of kd-tree visits, so that compression time
// grows about linearly with the texel count: it may miss a reusable entry, costing an extra entry,
// never accuracy: the tolerances below hold for every entry reused.)
// Level 2: the (index, scale) vectors of one 2D light slice (fixed texel and view) are quantized
// again; level 3: the vectors of a texel's slices over all views. Colour: luminance goes through
// the levels above; chromaticity (R/Y, B/Y) per light, as one 1D function per ring (2 x n values),
// goes through its own per-ring codebook (few materials: its functions repeat).
// TBB parallel where it does not change the result: the output is identical for any thread count.
//
// The compressed form decodes any entry on its own (value()), so BtfMaterial evaluates straight
// from the codebooks; loadView() decodes one view for comparisons and `btf decompress`.
#pragma once

#include <span>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "btf/core/btf_ring_layout.h"
#include "btf/io/btf_data.h"

namespace btf {

// Tolerances and their bounds (the exact rules are in src/compress/vq_compress.cpp):
// - Every level reuses a codebook entry only when the least-squares fit of the entry (scaled) to
//   what it replaces has an L2 error <= epsilon * max(|f|, energy_floor * R), where |f| is the
//   norm of what it replaces and R the RMS norm of its batch (one ring of one view at level 1, the
//   light slices of one view at level 2, all texels at level 3): relative for bright vectors, an
//   absolute floor for dark ones (shadowed, grazing), which a purely relative rule would give
//   entries of their own although they add almost nothing to the error. Level 1 fits the
//   luminance of a ring's 1D function, level 2 the level-1 reconstruction of a light slice (one
//   value per light), level 3 the level-2 reconstruction of a texel (views x lights values). Summed over a batch,
//   the squared error is <= epsilon^2 (1 + energy_floor^2) times the batch's energy, so each level
//   adds a relative RMS error <= e = epsilon sqrt(1 + energy_floor^2), and the luminance rel_rmse
//   is <= (1 + e + 2 q)^levels - 1, where q is the rounding of what is stored: new entries'
//   values and scales are rounded to a precision matched to the tolerance, each rounding within
//   q = max(epsilon / 16, 0.00034) relative (0.00034: the finest 16-bit log2 scale step's half;
//   src/compress/vq_impl.h). energy_floor = 0 makes the bound per vector.
// - Chromaticity c_a = (R / Y, B / Y) at each light azimuth a of a ring (where Y = 0, the ring's
//   mean; G follows from Y) forms a chroma function per ring; its codebook entry (one per ring,
//   carried by the level-1 code or the level-2 entry) is reused only when the luminance-weighted
//   error sum_a Y_a^2 |c'_a - c_a|^2 <= chroma_epsilon^2 max(sum_a Y_a^2, (energy_floor R)^2)
//   (absolute: c is already normalized; R is the RMS ring norm of the ring's batch, so dark rings,
//   whose colour adds little to the error, get the same floor as their luminance), checked
//   against the data at level 1 and 2. Level 3 tests the whole texel, as it does its luminance:
//   a texel may take another's entry when, summed over its views x lights samples, the luminance-weighted
//   squared difference between the entry's chroma and the texel's own verified chroma entries is
//   <= chroma_epsilon^2 max(|Y|^2, (energy_floor R)^2) (weights from the level-2 reconstruction;
//   rings where the entry keeps the texel's own or its slice's level-2 chroma add nothing), so by
//   the triangle inequality level 3 at most doubles the chroma term below. (A test per ring and
//   view, as level 2's, can never pass on camera data: one light's chroma noise exceeds any useful
//   tolerance, and on the 81-direction set 486 rings must all pass.) New entries are stored on a grid of step
//   chroma_epsilon / 4 (vq_impl.h), within their own tolerance. Since |dRGB|^2 <= 1.0986 Y^2
//   |dc|^2 and |RGB|^2 >= 1.7797 Y^2, the RGB rel_rmse is
//   <= kmax / 1.334 * L + 0.786 m chroma_epsilon sqrt(1 + energy_floor^2), with L the luminance
//   rel_rmse, kmax the largest |RGB| / Y of the decoded data, and m = 1 for 1 or 2 levels, 2 for 3.
// - Level 3 has a cheaper way to add an entry: a texel that no entry fits but one nearly does,
//   all but a few views (at most a tenth), gets that entry with its own level-2 codes in those
//   views. Its error, over the views kept, passes the same tests, and the views replaced add no
//   level-3 error, so the bounds above hold as they are; the file stores such an entry as its
//   parent and the views that differ (src/compress/vq_impl.h).
// - Entries that nothing references once the last level is done (a texel that takes another's
//   level-3 entry leaves its slices' level-2 entries, and the level-1 and chroma entries only they
//   used, behind) are dropped before the file is written (src/compress/vq_prune.h).
// Chromaticities are stored on a 16-bit grid of step chroma_epsilon / 4; since R/Y <= 4.7 and
// B/Y <= 13.9 for non-negative RGB, a tolerance of 0.001 or more keeps the grid within 16 bits.
inline constexpr float kVqMinChromaEpsilon = 0.001f;

struct VqOptions {
  float epsilon = 0.02f;         // relative L2 tolerance per level (see above); 0: near-lossless
  float chroma_epsilon = 0.01f;  // absolute tolerance of the chromaticity (R/Y, B/Y) (see above); >= 0.001
  float energy_floor = 1.0f;     // >= 0: the absolute floor of the tolerance, in batch RMS norms
  int levels = 3;                // 1, 2 or 3
  int threads = 0;               // 0: TBB's default; the output does not depend on it
  // Code level-1 entries in a principal basis of their ring learned from the first view, each cut
  // to the leading coefficients its tolerance needs (src/compress/vq_basis.h): on noisy measured
  // data the dropped tail is mostly noise and files shrink at equal error; on clean data the cut
  // moves entries off the data and the coefficients code worse than the values
  // (docs/design-notes.md#vq-level-1-basis-and-cut). Off:
  // entries are stored value by value, as files were before.
  bool level1_cut = false;
  // Level 3's derived entries (above): a texel that nearly matches an entry takes it with its own
  // codes in a few views. Smaller files at equal error on measured data, with more level-3 entries
  // in the decoded tables (docs/design-notes.md#vq-derived-level-3-entries). Off: every level-3
  // entry is matched or whole, as files were
  // before.
  bool level3_exceptions = true;
};

// The bound above on the luminance rel_rmse of a BTF compressed with these options against its
// input: (1 + e + 2 q)^levels - 1 (compareBtf's luminance_rel_rmse measures it).
double vqLuminanceBound(const VqOptions& options);

struct VqStats {
  std::vector<std::size_t> codebook_entries;  // per level
  std::uint64_t compressed_bytes = 0;         // payload as stored in .btfz (after zstd)
  double seconds = 0;                         // compression wall time
  double ratio_u8 = 0, ratio_f32 = 0;         // docs/design-notes.md#measures
};

class VqBtf final : public BtfSource, public BtfLookup {
 public:
  int width() const override;
  int height() const override;
  std::string name() const override;
  const BtfViewSet& views() const override;
  void loadView(int view, std::vector<Rgb>& out) const override;
  int lookupWidth() const override { return width(); }
  int lookupHeight() const override { return height(); }
  const BtfViewSet& lookupViews() const override { return views(); }
  Rgb value(int x, int y, int view, int light) const override;
  void values(std::span<const BtfSampleIndex> samples, std::span<Rgb> out) const override;

  const VqOptions& options() const;
  const VqStats& stats() const;
  // Bytes of the decoded tables random lookups (value, values, weightedSum) walk: the working set
  // that decides whether they run from cache (bench_btf.cpp measures the rate against it).
  std::size_t lookupTableBytes() const;

  // The rings its level 1 codes (core/btf_ring_layout.h): the direction set's, as compressed.
  const BtfRingLayout& ringLayout() const;
  // The light slice of texel (x, y) and a view as its rings, for samplers that work on the
  // compressed form (material/btf_material.h): ring r's level-1 entry as the normalized prefix
  // sums of its values (cdf, ringLayout().size(r) + 1 entries, as buildCdf1D writes them) and their
  // total (sum); the ring's luminance at place a is scale * sum * (cdf[a + 1] - cdf[a]), or
  // scale * values[a] / 65535 from the entry's stored values.
  // `rings` holds ringLayout().ringCount() entries. A few lookups.
  struct LightRing {
    const float* cdf;
    float sum;
    float scale;
    const std::uint16_t* values;
  };
  // The same prefix sums and totals of every level-1 entry with its values weighted per light:
  // value a of ring r's entry times light_weight[ringLayout().light(r, a)] (what a sampler that
  // weighs lights unequally, by the cells they stand for, draws from; the plain tables are those
  // of weight 1). With two or three levels, also per level-2 entry the marginal over its rings:
  // the CDF of (its ring code's scale x the weighted total of that code's entry) and their sum,
  // which a light slice scales by its own level-2 scale alone, so that choosing a ring reads one
  // record. Built once for a set of weights.
  struct WeightedRings {
    std::vector<std::vector<float>> cdf, sum;  // per ring: entries x (size + 1), entries
    std::vector<float> slice_cdf, slice_total;  // per level-2 entry: ringCount() + 1, 1
  };
  WeightedRings weightedRings(std::span<const float> light_weight) const;
  void lightRings(int x, int y, int view, std::span<LightRing> rings, const WeightedRings* weighted = nullptr) const;
  // One light slice (texel, view) for lookups of single rings and lights: its level-2 code
  // (levels >= 2) or where its level-1 codes start (levels 1).
  struct SliceCode {
    std::size_t texel;
    int view;
    std::uint32_t entry;  // level-2 entry (levels >= 2)
    float scale;          // its scale
  };
  SliceCode sliceCode(int x, int y, int view) const;
  // Asks the cache for the slice's ring codes (a hint: no result; for callers that will read the
  // slice after other work, so that the misses overlap with it).
  void prefetch(const SliceCode& slice) const;
  // Ring r of the slice, as lightRings gives it (from `weighted`'s tables).
  LightRing lightRing(const SliceCode& slice, int ring, const WeightedRings& weighted) const;
  // The marginal over the slice's rings from `weighted` (levels >= 2): the level-2 entry's CDF
  // (ringCount() + 1 entries) and the slice's total, its scale times the entry's.
  struct RingMarginal {
    const float* cdf;
    float total;
  };
  RingMarginal ringMarginal(const SliceCode& slice, const WeightedRings& weighted) const;
  // The luminance the codebook holds for a light of the slice (its ring code's scale x the
  // entry's value): what the samplers' ring masses sum.
  float luminance(const SliceCode& slice, int light) const;
  // Sum over k < count of weights[k] * value(x, y, views[k], lights[k]): BtfMaterial's
  // interpolation in one call per texel rather than one virtual call per entry.
  Rgb weightedSum(int x, int y, const int* views, const int* lights, const float* weights, int count) const;

  // .btfz (io/container.h). write() fills stats().compressed_bytes; read() throws FileError.
  // read() also takes a database of materials (compress/vq_database.h): `material` names the one
  // to read; it may be left empty for a single-material file or a database of one.
  void write(const std::filesystem::path& path) const;
  static VqBtf read(const std::filesystem::path& path, std::string_view material = {});

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
