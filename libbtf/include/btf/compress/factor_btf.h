// A BTF as a quantized low-rank factorisation: transform coding of the full BTF matrix, the form a
// Bonn .btf file (DFMF, FMF) already is, made smaller by coding both factors to the error asked for.
//
// The data: per colour channel c, the matrix A_c of texels x (view, light) pairs held, its values
// the RGB entries in one of two colour models:
//   - Linear: turned by an orthonormal 3 x 3 colour transform K (the principal axes of the RGB
//     values' second moments, largest first: channel 0 carries nearly all the energy, 1 and 2 the
//     colour). Since K is orthonormal, the squared error of the RGB values is the sum of the
//     channels' squared errors, so the error is accounted in the transformed channels exactly.
//   - LogLuminance: Bonn's DFMF model (log Y, U / Y, V / Y in btflib's YUV), with the offset
//     log(Y + o), o = kFactorLogOffset x the RMS luminance: a coefficient's error is then a relative
//     error of the value, which suits materials whose highlights stand orders of magnitude above
//     their body (a linear basis needs many components for a sharp peak, a log basis few), while
//     values far below o (shadows), which add nothing to the error, take no resolution of their own.
//     The RGB error is not a sum of the channels' errors here: it is estimated on kFactorErrorSamples
//     entries drawn by importance (their values recorded in the last pass) and decoded from the
//     codes, then measured on every entry, the step shrinking until that measure meets epsilon.
//
// Factorisation: A_c ~ C_c B_c^T, B_c (pairs x k_c) with orthonormal columns, C_c = A_c B_c (texels
// x k_c), found by a randomised range finder on the pair side (Halko, Martinsson and Tropp 2011): a
// pass over the source sketches Y_c = A_c^T Omega_c (Omega_c Gaussian, texels x r_c), Q_c = orth(Y_c);
// `power_iterations` extra pairs of passes refine Q_c; a last pass projects G_c = A_c Q_c, and the
// SVD of the small G_c rotates Q_c into B_c, largest singular value first. Truncation error:
// |A_c|^2 - |G_c|^2, exact for the kept space (accumulated in double). Every pass reads the source
// view by view, so memory is (texels + pairs) x r plus one view, never the matrix.
//
// Quantization (the error budget epsilon^2 |A|^2 shared by truncation, coefficients and basis):
//   - coefficients: one uniform step for every channel and component (for an orthonormal basis the
//     MSE-optimal allocation at high rate: each coefficient's error counts the same); a component
//     whose coefficients all round to 0 is dropped. The step is the largest whose error meets the
//     budget: Linear, truncation + the exact sum of the coefficients' rounding errors + the basis
//     term below; LogLuminance, the sampled RGB error of the decoded codes.
//   - basis: column j on a grid of its own, fine enough that |C_j|^2 |dB_j|^2 (its error, since
//     the columns' errors are uncorrelated) is an equal share of kFactorBasisErrorShare of the
//     coefficients' rounding error (in the channels' own units).
//   Stored as integers: each plane (one component over the texels in row order, one basis column
//   over the pairs) as zigzag LEB128 varints, raw or as differences to the previous value, whichever
//   is shorter, in zstd sections.
// The estimate is the error against the source before the decoder clamps negative values to 0
// (Linear; clamping only brings a value closer to a non-negative source) or of the decoded samples
// (LogLuminance): `btf compress` measures the written file against its input after writing.
//
// Decoding: value() is k_c multiply-adds per channel (float, in component order) and the inverse
// colour transform, clamped at 0; loadView() runs the same arithmetic, so both return the same bits.
// Deterministic: the random sketch is counter-based, passes are cut into fixed texel chunks summed in
// order, so the file is the same for any thread count.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "btf/io/btf_data.h"

namespace btf {

// Share of the coefficients' squared rounding error allowed to the basis's rounding.
inline constexpr double kFactorBasisErrorShare = 0.05;
// LogLuminance: the offset before the logarithm, in RMS luminances of the data.
inline constexpr double kFactorLogOffset = 0.01;
// LogLuminance: entries drawn uniformly, and among them those drawn by importance whose decoded
// error estimates the step's (factor_compress.cpp).
inline constexpr std::size_t kFactorErrorCandidates = std::size_t(1) << 20;
inline constexpr std::size_t kFactorErrorSamples = std::size_t(1) << 18;

enum class FactorColorModel { Linear = 0, LogLuminance = 1 };
std::string factorColorModelName(FactorColorModel model);  // "linear", "log-luminance"

struct FactorOptions {
  float epsilon = 0.02f;       // target rel_rmse of the RGB values (RMSE over RMS of the source), in (0, 1)
  FactorColorModel color_model = FactorColorModel::Linear;
  int max_components = 96;     // sketch size of channel 0 (the rank it can keep at most)
  int max_chroma_components = 32;  // sketch size of channels 1 and 2
  int power_iterations = 0;    // each adds two passes; 0 suits the fast-decaying spectra of BTFs
  std::uint64_t seed = 1;      // of the random sketch
  int threads = 0;             // 0: TBB's default; the output does not depend on it
};

struct FactorStats {
  std::array<int, 3> components{};          // kept per channel
  double coefficient_step = 0;              // the uniform step of the coefficients
  double truncation_rel_rmse = 0;           // of the sketched space's truncation alone (kept components)
  double estimated_rel_rmse = 0;            // truncation + quantization, before clamping (LogLuminance: sampled)
  double measured_rel_rmse = -1;            // LogLuminance: of every entry decoded from the codes (-1: not measured)
  int refinements = 0;                      // LogLuminance: step reductions after the measurement
  std::uint64_t compressed_bytes = 0;       // payload as stored in .btfz (after write or read)
  bool from_source_factors = false;         // a Bonn DFMF file's own factors were coded (below)
  double seconds = 0;                       // compression wall time
};

class FactorBtf final : public BtfSource, public BtfLookup {
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

  const FactorOptions& options() const;
  const FactorStats& stats() const;
  // Linear: the colour transform K (rows: channels, applied to RGB); LogLuminance: unused (identity).
  const std::array<float, 9>& colorTransform() const;

  // .btfz (io/container.h), format "libbtf-factor". write() fills stats().compressed_bytes and
  // writes atomically; read() throws FileError naming the file and what is wrong.
  void write(const std::filesystem::path& path) const;
  static FactorBtf read(const std::filesystem::path& path);

  struct Impl;  // factors as decoded (src/compress/factor_impl.h)
  explicit FactorBtf(std::shared_ptr<const Impl> impl);
  const Impl& impl() const { return *impl_; }

 private:
  std::shared_ptr<const Impl> impl_;
};

// Factorises and quantizes `source` (any direction set; the views it holds) with progress reported
// per pass and view. Throws btf::Error for options out of range, a source that is zero everywhere,
// and negative, NaN or infinite values (naming the source, view and light).
// A Bonn DFMF file in colour model 11 (log Y, U/Y, V/Y, as UBO2014 ships them) compressed in the
// log-luminance model is not factorised again: its own factors are the model's (its offset 1e-5,
// its cosine flag a pair offset), rotated to singular vectors exactly and quantized, so nothing is
// lost to a new truncation and no pass over the decoded values is made (the step's error is
// measured on entries the file decodes one by one).
FactorBtf compressFactor(const BtfSource& source, const FactorOptions& options = {});
// True when compressFactor takes the source's own factors (above).
bool factorFromSourceFactors(const BtfSource& source, const FactorOptions& options);

}  // namespace btf
