// Per-view PCA of a BTF: the baseline that the multi-level VQ compressor is charted against
// ("PCA at equal storage"), in the style of the per-view factorization of measured BTFs
// of Sattler, Sarlette & Klein (2003).
//
// For each of the 81 views, the matrix texels x (81 lights x 3 channels) = T x 243 is approximated
// by its mean row plus k principal components: row_t ~ mean + sum_j c_tj b_j. The basis b_j is the
// top-k eigenvectors of the 243 x 243 covariance accumulated (in double) over the texels.
//
// What a file holds (storedBytes), and why:
//   16-byte header (u32 width, height, components, precision), then per view:
//     mean            243 x float32  (one row per view: negligible, kept exact)
//     basis           k x 243 x float16 (Half) or float32 (Float); entries of unit vectors, |b| <= 1,
//                     where float16's 11-bit mantissa gives ~5e-4 relative precision
//     component scale k x float32: the largest |c_tj| of the component, so the stored coefficients
//                     are in [-1, 1] and cannot overflow float16 (BTF peaks reach thousands 1/sr)
//     coefficients    T x k x float16 (Half) or float32 (Float)
//   Half is what PCA/factorization BTF codecs commonly store (coefficients and basis as 16-bit
//   floats) and makes the baseline as strong as it honestly can be at a given size; Float exists
//   for exactness tests. Coefficients are computed for the *rounded* basis (least squares) and the
//   object decodes from the rounded values, so compareBtf measures the error a reader of the file
//   would get. No entropy coding is applied or counted.
//
// Streaming: compression reads one view at a time (BtfSource::loadView, serially, as image readers
// need) and factorizes views in parallel with TBB; each view's arithmetic is single-threaded and
// independent of the others, so the result is the same for any thread count.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "btf/io/btf_data.h"

namespace btf {

struct PcaViewFactorizer;  // pca_compress.cpp

enum class PcaPrecision : std::uint32_t { Half = 0, Float = 1 };

// Values per texel and view on the 81-direction set (81 lights x RGB); on another set a view has
// 3 x its light count.
inline constexpr int kPcaDimension = kBtfDirectionCount * 3;
inline constexpr std::uint64_t kPcaHeaderBytes = 16;

class PcaBtf final : public BtfSource, public BtfLookup {
 public:
  int width() const override { return width_; }
  int height() const override { return height_; }
  std::string name() const override { return name_; }
  const BtfViewSet& views() const override { return view_set_; }
  // Decodes the whole view: T x 243 from k components per texel (a matrix product).
  void loadView(int view, std::vector<Rgb>& out) const override;
  int lookupWidth() const override { return width_; }
  int lookupHeight() const override { return height_; }
  const BtfViewSet& lookupViews() const override { return view_set_; }
  // One entry: mean + k multiply-adds per channel. No bounds checks (hot path).
  Rgb value(int x, int y, int view, int light) const override;

  int components() const { return components_; }
  PcaPrecision precision() const { return precision_; }
  // Bytes a file of this factorization holds (format above).
  std::uint64_t storedBytes() const { return storedBytesFor(width_, height_, components_, precision_, view_set_); }
  // The same for a BTF of `views` views of the 81-direction set (each view is factorized on its
  // own), and for the views of any set. Throws btf::Error for a size < 1 or k outside 0 .. the
  // smallest view's dimension (3 x its lights).
  static std::uint64_t storedBytesFor(int width, int height, int components, PcaPrecision precision,
                                      int views = kBtfDirectionCount);
  static std::uint64_t storedBytesFor(int width, int height, int components, PcaPrecision precision,
                                      const BtfViewSet& views);
  // Fraction of the (mean-removed) variance that the kept components explain, over all views:
  // sum of the top-k eigenvalues / trace of the covariance (1 for a constant BTF).
  double explainedVariance() const { return explained_variance_; }

 private:
  friend PcaBtf compressPca(const BtfSource& source, int components, PcaPrecision precision);
  friend struct PcaViewFactorizer;
  PcaBtf() = default;
  struct View {
    std::vector<float> mean;          // dimension (3 x the view's lights; 243 on the 81 set)
    std::vector<float> basis;         // dimension x k, row-major [d][j], the component scale folded in
    std::vector<float> coefficients;  // T x k, row-major [t][j], as decoded from storage
  };
  int width_ = 0, height_ = 0, components_ = 0;
  PcaPrecision precision_ = PcaPrecision::Half;
  std::string name_;
  double explained_variance_ = 1.0;
  BtfViewSet view_set_;
  std::vector<View> views_;  // by slot in view_set_
};

// Factorizes with k components per view (0 <= k <= 3 x the fewest lights of a view: 243 on the
// 81-direction set; k = 0 keeps only the mean), on any direction set. Throws btf::Error for a bad
// k and passes on the source's errors. Reports progress per view.
PcaBtf compressPca(const BtfSource& source, int components, PcaPrecision precision = PcaPrecision::Half);

// The largest k whose storedBytes fit in byte_budget (at most the smallest view's dimension), or -1
// if not even the mean fits; for `views` views of the 81-direction set, or the views of any set.
int pcaComponentsForBudget(int width, int height, std::uint64_t byte_budget,
                           PcaPrecision precision = PcaPrecision::Half, int views = kBtfDirectionCount);
int pcaComponentsForBudget(int width, int height, std::uint64_t byte_budget, PcaPrecision precision,
                           const BtfViewSet& views);
// compressPca with pcaComponentsForBudget's k, for "equal storage" comparisons; throws btf::Error
// if the budget cannot hold even the per-view means.
PcaBtf compressPcaToBytes(const BtfSource& source, std::uint64_t byte_budget,
                          PcaPrecision precision = PcaPrecision::Half);

}  // namespace btf
