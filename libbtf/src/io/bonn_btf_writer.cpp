// Writes Bonn .btf files (btf/io/bonn_btf.h): DFMF and FMF by a randomised truncated SVD that
// streams the source view by view, PVF by a per-view PCA.
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <Imath/half.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include "bonn_btf_format.h"
#include "btf/core/error.h"
#include "btf/core/progress.h"
#include "btf/core/rng.h"
#include "btf/core/value_limits.h"
#include "btf/io/atomic_file.h"
#include "btf/io/bonn_btf.h"

namespace btf {
namespace fs = std::filesystem;
namespace {

using MatrixF = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using MatrixD = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

constexpr float kEps = bonn::kLogEpsilon;
constexpr int kOversampling = 10;      // extra columns of the randomised range finder (Halko et al.: 5 to 10)
constexpr std::size_t kRowChunk = 64;  // rows per parallel task: fixed, so sums do not depend on threads
constexpr std::size_t kProjectTexels = 4096;

// RGB -> the stored channels of a colour model (the inverse of the reader's decoding).
struct ColorEncoder {
  int model = 0;
  std::array<float, 3> mean{};
  std::array<float, 9> transform{};  // orthonormal rows for model 3
  float rgb_to_yuv[3][3];

  explicit ColorEncoder(int m) : model(m) {
    // The exact inverse of btflib's YUV -> RGB matrix, so that a round trip returns the values.
    const Eigen::Matrix3d to_rgb{{bonn::kYuvToRgb[0][0], bonn::kYuvToRgb[0][1], bonn::kYuvToRgb[0][2]},
                                 {bonn::kYuvToRgb[1][0], bonn::kYuvToRgb[1][1], bonn::kYuvToRgb[1][2]},
                                 {bonn::kYuvToRgb[2][0], bonn::kYuvToRgb[2][1], bonn::kYuvToRgb[2][2]}};
    const Eigen::Matrix3d inverse = to_rgb.inverse();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) rgb_to_yuv[i][j] = float(inverse(i, j));
    // Model 3: an orthonormal luminance / opponent basis (rows), so the inverse is the transpose.
    const float s3 = 1.0f / std::sqrt(3.0f), s2 = 1.0f / std::sqrt(2.0f), s6 = 1.0f / std::sqrt(6.0f);
    transform = {s3, s3, s3, s2, 0.0f, -s2, s6, -2.0f * s6, s6};
  }

  std::array<float, 3> yuv(const Rgb& c) const {
    std::array<float, 3> out;
    for (int i = 0; i < 3; ++i) out[std::size_t(i)] = rgb_to_yuv[i][0] * c.r + rgb_to_yuv[i][1] * c.g + rgb_to_yuv[i][2] * c.b;
    return out;
  }

  std::array<float, 3> operator()(const Rgb& c) const {
    switch (model) {
      case 0: return {c.r, c.g, c.b};
      case 1: return yuv(c);
      case 2: return lab(c);
      case 3: {
        // decode: rgb_j = sum_i v_i T[i][j] + mean_j, T orthonormal -> v_i = sum_j T[i][j] (rgb_j - mean_j)
        const float d[3] = {c.r - mean[0], c.g - mean[1], c.b - mean[2]};
        std::array<float, 3> v{};
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) v[std::size_t(i)] += transform[std::size_t(i * 3 + j)] * d[j];
        return v;
      }
      case 4: return {0.25f * c.r + 0.5f * c.g + 0.25f * c.b, 0.5f * c.r - 0.5f * c.b, -0.25f * c.r + 0.5f * c.g - 0.25f * c.b};
      case 9: {
        const std::array<float, 3> y = yuv(c);
        return {std::log(std::max(y[0], 0.0f) + kEps), y[1], y[2]};
      }
      case 10: {
        const std::array<float, 3> y = yuv(c);
        const auto squeeze = [](float x) { return std::abs(x) <= kEps ? 0.0f : std::copysign(std::log(std::abs(x) / kEps), x); };
        return {std::log(std::max(y[0], 0.0f) + kEps), squeeze(y[1]), squeeze(y[2])};
      }
      case 11: {
        const std::array<float, 3> y = yuv(c);
        const float luminance = std::max(y[0], 0.0f);
        return {std::log(luminance + kEps), y[1] / (luminance + kEps), y[2] / (luminance + kEps)};
      }
      case 12: return {std::log(c.r + kEps), std::log(c.g + kEps), std::log(c.b + kEps)};
      default: return {c.r, c.g, c.b};
    }
  }

  // Linear Rec.709 -> CIE Lab (D65 white, L in 0..100), the reader's model 2.
  static std::array<float, 3> lab(const Rgb& c) {
    const Rgb xyz = linearRec709ToXyz(c);
    const float x = xyz.r / 0.95047f, y = xyz.g, z = xyz.b / 1.08883f;
    const auto f = [](float t) {
      constexpr float d = 6.0f / 29.0f;
      return t > d * d * d ? std::cbrt(t) : t / (3.0f * d * d) + 4.0f / 29.0f;
    };
    return {116.0f * f(y) - 16.0f, 500.0f * (f(x) - f(y)), 200.0f * (f(y) - f(z))};
  }
};

// The matrices a layout factorises, filled one view at a time: DFMF three (one per stored
// channel, rows = the view's lights), FMF one (rows = the view's (light, channel) pairs, channel
// fastest). Columns are texels (x fastest).
struct ViewMatrices {
  std::vector<MatrixF> a;
};

class MatrixSource {
 public:
  MatrixSource(const BtfSource& source, const BonnBtfWriteOptions& options, const ColorEncoder& encoder)
      : source_(source), options_(options), encoder_(encoder) {
    const BtfDirectionSet& set = source.directions();
    std::size_t offset = 0;
    for (int v = 0; v < set.viewCount(); ++v) {
      row_offset_.push_back(offset);
      offset += rowsOf(v);
    }
    rows_ = offset;
  }
  int matrixCount() const { return options_.layout == BonnBtfLayout::Dfmf ? 3 : 1; }
  std::size_t rows() const { return rows_; }
  std::size_t columns() const { return source_.texelCount(); }
  std::size_t rowsOf(int view) const {
    const std::size_t lights = std::size_t(source_.directions().lightCount(view));
    return options_.layout == BonnBtfLayout::Dfmf ? lights : 3 * lights;
  }
  std::size_t rowOffset(int view) const { return row_offset_[std::size_t(view)]; }

  void load(int view, ViewMatrices& out) const {
    source_.loadView(view, values_);
    const std::size_t texels = source_.texelCount(), lights = std::size_t(source_.directions().lightCount(view));
    if (values_.size() != lights * texels)
      throw Error(source_.name() + ": view " + std::to_string(view) + " has " + std::to_string(values_.size()) +
                  " values, expected " + std::to_string(lights * texels));
    out.a.resize(std::size_t(matrixCount()));
    for (MatrixF& m : out.a) m.resize(Eigen::Index(rowsOf(view)), Eigen::Index(texels));
    // Checked in order first, so that the error named is the first bad value whatever the threads.
    for (std::size_t i = 0; i < values_.size(); ++i) {
      const Rgb& c = values_[i];
      if (!std::isfinite(c.r) || !std::isfinite(c.g) || !std::isfinite(c.b) || c.r < 0 || c.g < 0 || c.b < 0 ||
          c.r > kMaxReflectance || c.g > kMaxReflectance || c.b > kMaxReflectance)
        throw Error(source_.name() + ": view " + std::to_string(view) + ", light " + std::to_string(i / texels) +
                    ", texel " + std::to_string(i % texels) + " holds (" + std::to_string(c.r) + ", " +
                    std::to_string(c.g) + ", " + std::to_string(c.b) +
                    "); a Bonn file stores finite reflectances in [0, 1e10]");
    }
    tbb::parallel_for(std::size_t(0), lights, [&](std::size_t l) {
      for (std::size_t t = 0; t < texels; ++t) {
        const Rgb& c = values_[l * texels + t];
        if (options_.layout == BonnBtfLayout::Dfmf) {
          const std::array<float, 3> s = encoder_(c);
          for (std::size_t k = 0; k < 3; ++k) out.a[k](Eigen::Index(l), Eigen::Index(t)) = s[k];
        } else {
          const float rgb[3] = {c.r, c.g, c.b};
          for (std::size_t k = 0; k < 3; ++k)
            out.a[0](Eigen::Index(l * 3 + k), Eigen::Index(t)) =
                options_.dynamic_range_reduction ? std::log(rgb[k] + kEps) : rgb[k];
        }
      }
    });
  }

 private:
  const BtfSource& source_;
  const BonnBtfWriteOptions& options_;
  const ColorEncoder& encoder_;
  std::vector<std::size_t> row_offset_;
  std::size_t rows_ = 0;
  mutable std::vector<Rgb> values_;
};

// Orthonormal columns spanning those of m (thin QR).
MatrixD orthonormalColumns(const MatrixD& m) {
  Eigen::HouseholderQR<MatrixD> qr(m);
  return qr.householderQ() * MatrixD::Identity(m.rows(), m.cols());
}

struct Truncation {
  std::vector<double> sigma;
  MatrixD u, sv;  // rows x r, columns x r
  double relative_error = 0;
};

// The randomised truncated SVD of every matrix of `matrices`, streaming the source:
// 2 + 2 * power_iterations passes, memory ~ (rows + columns) x (rank + oversampling) per matrix.
// Every product is split into fixed chunks of rows or texels computed whole by one task, so the
// result does not depend on the thread count.
std::vector<Truncation> randomisedSvd(const BtfSource& source, const MatrixSource& matrices,
                                      const BonnBtfWriteOptions& options) {
  const std::size_t rows = matrices.rows(), texels = matrices.columns();
  const std::size_t k = std::min({std::size_t(options.max_components), rows, texels});
  const std::size_t width = std::min({k + std::size_t(kOversampling), rows, texels});
  const int count = matrices.matrixCount();
  const int views = source.directions().viewCount();
  const Eigen::Index w = Eigen::Index(width);

  std::vector<MatrixD> y(std::size_t(count), MatrixD::Zero(Eigen::Index(rows), w));
  std::vector<double> frob2(std::size_t(count), 0.0);
  std::vector<MatrixF> right(std::size_t(count), MatrixF(Eigen::Index(texels), w));  // Omega, later Z
  tbb::parallel_for(std::size_t(0), texels, [&](std::size_t t) {
    for (int m = 0; m < count; ++m) {
      Rng rng(options.seed, std::uint64_t(m) * texels + t);
      for (Eigen::Index j = 0; j < w; j += 2) {  // Box-Muller pairs
        const double u1 = 1.0 - rng.uniformDouble(), u2 = rng.uniformDouble();
        const double r = std::sqrt(-2.0 * std::log(u1));
        right[std::size_t(m)](Eigen::Index(t), j) = float(r * std::cos(6.283185307179586 * u2));
        if (j + 1 < w) right[std::size_t(m)](Eigen::Index(t), j + 1) = float(r * std::sin(6.283185307179586 * u2));
      }
    }
  });

  const int passes = 2 + 2 * options.power_iterations;
  Progress progress("factorising " + source.name(), std::uint64_t(passes) * std::uint64_t(views));
  ViewMatrices a;
  // Y = A * right, view block by view block (rows split into fixed chunks).
  const auto rangePass = [&](bool norms) {
    for (int v = 0; v < views; ++v) {
      matrices.load(v, a);
      const Eigen::Index off = Eigen::Index(matrices.rowOffset(v)), n = Eigen::Index(matrices.rowsOf(v));
      for (int m = 0; m < count; ++m) {
        const MatrixF& av = a.a[std::size_t(m)];
        const std::size_t chunks = (std::size_t(n) + kRowChunk - 1) / kRowChunk;
        tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
          const Eigen::Index r0 = Eigen::Index(c * kRowChunk), rn = std::min<Eigen::Index>(Eigen::Index(kRowChunk), n - r0);
          const MatrixF block = av.middleRows(r0, rn) * right[std::size_t(m)];
          y[std::size_t(m)].middleRows(off + r0, rn) = block.cast<double>();
        });
        if (norms)
          for (Eigen::Index r = 0; r < n; ++r)
            for (Eigen::Index t = 0; t < Eigen::Index(texels); ++t) frob2[std::size_t(m)] += double(av(r, t)) * double(av(r, t));
      }
      progress.advance();
    }
  };
  // Returns Q^T A (width x texels) for q = the orthonormalised Y, or (transposed) A^T Q.
  const auto projectPass = [&](const std::vector<MatrixD>& q, std::vector<MatrixD>& out) {
    out.assign(std::size_t(count), MatrixD::Zero(w, Eigen::Index(texels)));
    for (int v = 0; v < views; ++v) {
      matrices.load(v, a);
      const Eigen::Index off = Eigen::Index(matrices.rowOffset(v)), n = Eigen::Index(matrices.rowsOf(v));
      for (int m = 0; m < count; ++m) {
        const MatrixF qv = q[std::size_t(m)].middleRows(off, n).cast<float>().transpose();  // width x n
        const MatrixF& av = a.a[std::size_t(m)];
        const std::size_t chunks = (texels + kProjectTexels - 1) / kProjectTexels;
        tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
          const Eigen::Index t0 = Eigen::Index(c * kProjectTexels);
          const Eigen::Index tn = std::min<Eigen::Index>(Eigen::Index(kProjectTexels), Eigen::Index(texels) - t0);
          const MatrixF block = qv * av.middleCols(t0, tn);
          out[std::size_t(m)].middleCols(t0, tn) += block.cast<double>();
        });
      }
      progress.advance();
    }
  };

  rangePass(true);
  std::vector<MatrixD> q(static_cast<std::size_t>(count)), b;
  for (int it = 0; it < options.power_iterations; ++it) {
    for (int m = 0; m < count; ++m) q[std::size_t(m)] = orthonormalColumns(y[std::size_t(m)]);
    projectPass(q, b);
    for (int m = 0; m < count; ++m)
      right[std::size_t(m)] = orthonormalColumns(b[std::size_t(m)].transpose()).cast<float>();
    rangePass(false);
  }
  for (int m = 0; m < count; ++m) q[std::size_t(m)] = orthonormalColumns(y[std::size_t(m)]);
  projectPass(q, b);

  std::vector<Truncation> result(static_cast<std::size_t>(count));
  for (int m = 0; m < count; ++m) {
    const MatrixD& bm = b[std::size_t(m)];
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Eigen::MatrixXd(bm * bm.transpose()));
    // Descending order.
    Eigen::MatrixXd vectors = eig.eigenvectors().rowwise().reverse();
    Eigen::VectorXd values = eig.eigenvalues().reverse();
    Truncation& out = result[std::size_t(m)];
    // U_r^T A = S.V_r^T exactly (S.V = B^T W = A^T Q W), so the error of the kept rank is the norm
    // left over: |A|^2 - sum of the kept sigma^2.
    std::size_t rank = k;
    double kept = 0;
    const double total = frob2[std::size_t(m)];
    const auto errorAt = [&](double kept_energy) { return total > 0 ? std::sqrt(std::max(0.0, total - kept_energy) / total) : 0.0; };
    if (options.relative_error) {
      for (std::size_t r = 0; r < k; ++r) {
        kept += std::max(0.0, values(Eigen::Index(r)));
        if (errorAt(kept) <= *options.relative_error) {
          rank = r + 1;
          break;
        }
      }
    }
    kept = 0;
    for (std::size_t r = 0; r < rank; ++r) {
      out.sigma.push_back(std::sqrt(std::max(0.0, values(Eigen::Index(r)))));
      kept += std::max(0.0, values(Eigen::Index(r)));
    }
    out.relative_error = errorAt(kept);
    const Eigen::MatrixXd wr = vectors.leftCols(Eigen::Index(rank));
    out.u = q[std::size_t(m)] * wr;
    out.sv = bm.transpose() * wr;
  }
  return result;
}

// --- writing ----------------------------------------------------------------------------------

class BinaryWriter {
 public:
  BinaryWriter(std::ofstream& out, int scalar_bytes) : out_(out), scalar_bytes_(scalar_bytes) {}
  template <class T>
  void value(T v) {
    out_.write(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void text(const std::string& s, std::size_t bytes) {
    std::string padded = s.substr(0, bytes - 1);
    padded.resize(bytes, '\0');
    out_.write(padded.data(), std::streamsize(bytes));
  }
  void scalar(double v) {
    if (scalar_bytes_ == 2) {
      value(Imath::half(float(v)).bits());
    } else if (scalar_bytes_ == 4) {
      value(float(v));
    } else {
      value(v);
    }
  }
  void matrix(const MatrixD& m) {  // row-major
    for (Eigen::Index r = 0; r < m.rows(); ++r)
      for (Eigen::Index c = 0; c < m.cols(); ++c) scalar(m(r, c));
  }

 private:
  std::ofstream& out_;
  int scalar_bytes_;
};

constexpr float kRadiansPerDegree = 0.017453292519943295f;

void writeCommonHeader(BinaryWriter& out, std::string_view signature, const BtfSource& source,
                       const BonnBtfWriteOptions& options) {
  for (const char c : signature) out.value(c);
  // Meta data, version 3: cosine flag and an (empty) XML block; three channels implied.
  constexpr std::uint32_t kMetaBytes = 4 + 4 + 3 * bonn::kMetaStringBytes + 4 + 12 + 4 + 4;
  out.value<std::uint32_t>(kMetaBytes);
  out.value<std::uint32_t>(3);
  out.text(options.measurement_setup, bonn::kMetaStringBytes);
  out.text(options.image_sensor, bonn::kMetaStringBytes);
  out.text(options.light_source, bonn::kMetaStringBytes);
  out.value<float>(0.0f);  // pixels per mm: unknown
  for (int c = 0; c < 3; ++c) out.value<float>(1.0f);
  out.value<std::uint32_t>(0);  // the values are f, not f cos(theta_l)
  out.value<std::uint32_t>(0);  // XML bytes
  const BtfDirectionSet& set = source.directions();
  out.value<std::uint32_t>(std::uint32_t(set.viewCount()));
  for (int v = 0; v < set.viewCount(); ++v) {
    out.value<float>(set.viewAngles(v).theta_deg * kRadiansPerDegree);
    out.value<float>(set.viewAngles(v).phi_deg * kRadiansPerDegree);
    out.value<std::uint32_t>(std::uint32_t(set.lightCount(v)));
    for (const BtfAngles& l : set.lights(v)) {
      out.value<float>(l.theta_deg * kRadiansPerDegree);
      out.value<float>(l.phi_deg * kRadiansPerDegree);
    }
  }
  out.value<std::uint32_t>(std::uint32_t(source.width()));
  out.value<std::uint32_t>(std::uint32_t(source.height()));
  if (signature.back() == 'R') out.value<std::uint32_t>(0);  // no rotations
}

void checkScalarRange(const std::vector<Truncation>& factors, int scalar_bytes, const std::string& name) {
  const double limit = scalar_bytes == 2 ? 65504.0 : scalar_bytes == 4 ? double(std::numeric_limits<float>::max())
                                                                       : std::numeric_limits<double>::max();
  for (const Truncation& t : factors) {
    const double largest = std::max(t.u.cwiseAbs().maxCoeff(), t.sv.cwiseAbs().maxCoeff());
    if (!(largest <= limit))
      throw Error(name + ": a factor reaches " + std::to_string(largest) + ", beyond what " +
                  std::to_string(scalar_bytes) + "-byte scalars hold; write 4-byte scalars");
  }
}

void checkWriteOptions(const BtfSource& source, const BonnBtfWriteOptions& o) {
  const std::string what = "writing " + source.name() + " as a Bonn " + bonnBtfLayoutName(o.layout) + " file";
  if (o.layout == BonnBtfLayout::Pvf) throw Error(what + ": use writeBonnBtfPvf for the per-view layout");
  if (o.max_components < 1 || o.max_components > 4096)
    throw Error(what + ": components " + std::to_string(o.max_components) + " is outside 1 .. 4096");
  if (o.relative_error && !(*o.relative_error > 0.0 && *o.relative_error < 1.0))
    throw Error(what + ": the relative error must lie in (0, 1)");
  if (o.scalar_bytes != 2 && o.scalar_bytes != 4 && o.scalar_bytes != 8)
    throw Error(what + ": scalar size " + std::to_string(o.scalar_bytes) + " is not 2, 4 or 8");
  if (o.layout == BonnBtfLayout::Dfmf && !bonn::knownColorModel(o.color_model))
    throw Error(what + ": colour model " + std::to_string(o.color_model) + " is not one of 0 to 4, 9 to 12");
  if (o.dynamic_range_reduction != 0 && o.dynamic_range_reduction != 1)
    throw Error(what + ": the dynamic-range reduction is 0 (none) or 1 (log)");
  if (o.power_iterations < 0 || o.power_iterations > 8) throw Error(what + ": power iterations must lie in 0 .. 8");
  if (!source.views().complete())
    throw Error(what + ": the format stores every view of the set; this BTF holds " + source.views().describe());
}

}  // namespace

BonnBtfWriteReport writeBonnBtf(const BtfSource& source, const fs::path& path, const BonnBtfWriteOptions& options) {
  checkWriteOptions(source, options);
  ColorEncoder encoder(options.layout == BonnBtfLayout::Dfmf ? options.color_model : 0);
  const MatrixSource matrices(source, options, encoder);
  const std::vector<Truncation> factors = randomisedSvd(source, matrices, options);
  checkScalarRange(factors, options.scalar_bytes, source.name());

  BonnBtfWriteReport report;
  for (const Truncation& t : factors) {
    report.components.push_back(std::uint32_t(t.sigma.size()));
    report.relative_error.push_back(t.relative_error);
  }
  writeFileAtomically(path, [&](std::ofstream& stream) {
    BinaryWriter out(stream, options.scalar_bytes);
    if (options.layout == BonnBtfLayout::Dfmf) {
      writeCommonHeader(out, "!DFMF08FCR", source, options);
      out.value<std::uint32_t>(*std::max_element(report.components.begin(), report.components.end()));
      out.value<std::int32_t>(options.color_model);
      for (int c = 0; c < 3; ++c) out.value<float>(encoder.mean[std::size_t(c)]);
      for (const float t : encoder.transform) out.value<float>(t);
    } else {
      writeCommonHeader(out, "!FMF12FCER", source, options);
      out.value<std::uint8_t>(1);  // FMF header version: the dynamic-range reduction follows
      out.value<std::uint32_t>(std::uint32_t(options.dynamic_range_reduction));
      out.value<std::uint32_t>(report.components[0]);
    }
    for (const Truncation& t : factors) {
      out.value<std::uint8_t>(std::uint8_t(options.scalar_bytes));
      out.value<std::uint32_t>(std::uint32_t(t.sigma.size()));
      out.value<std::uint32_t>(std::uint32_t(t.u.rows()));
      out.value<std::uint32_t>(std::uint32_t(t.sv.rows()));
      for (const double s : t.sigma) out.scalar(s);
      out.matrix(t.u);
      out.matrix(t.sv);
    }
  });
  report.bytes = fs::file_size(path);
  return report;
}

void writeBonnBtfPvf(const BtfSource& source, const fs::path& path, int components, int scalar_bytes) {
  BonnBtfWriteOptions options;
  options.scalar_bytes = scalar_bytes;
  options.layout = BonnBtfLayout::Dfmf;  // for the checks shared with the other layouts
  checkWriteOptions(source, options);
  if (components < 1) throw Error("writing " + source.name() + " as a PVF file: components must be >= 1");
  const BtfDirectionSet& set = source.directions();
  const std::size_t texels = source.texelCount();
  writeFileAtomically(path, [&](std::ofstream& stream) {
    BinaryWriter out(stream, scalar_bytes);
    writeCommonHeader(out, "!PVF06FCR", source, options);
    out.value<std::uint32_t>(std::uint32_t(components));
    out.value<std::uint32_t>(std::uint32_t(set.viewCount()));
    std::vector<Rgb> values;
    Progress progress("writing " + path.filename().string(), std::uint64_t(set.viewCount()));
    for (int v = 0; v < set.viewCount(); ++v) {
      source.loadView(v, values);
      const std::size_t lights = std::size_t(set.lightCount(v)), dimension = 3 * lights;
      // Rows: texels; columns: (light, channel), channel fastest.
      MatrixD x(static_cast<Eigen::Index>(texels), static_cast<Eigen::Index>(dimension));
      for (std::size_t l = 0; l < lights; ++l)
        for (std::size_t t = 0; t < texels; ++t) {
          const Rgb& c = values[l * texels + t];
          x(Eigen::Index(t), Eigen::Index(3 * l)) = c.r;
          x(Eigen::Index(t), Eigen::Index(3 * l + 1)) = c.g;
          x(Eigen::Index(t), Eigen::Index(3 * l + 2)) = c.b;
        }
      const Eigen::RowVectorXd mean = x.colwise().mean();
      x.rowwise() -= mean;
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Eigen::MatrixXd(x.transpose() * x));
      const Eigen::Index k = std::min<Eigen::Index>(components, Eigen::Index(std::min(dimension, texels)));
      const MatrixD basis = eig.eigenvectors().rowwise().reverse().leftCols(k);  // dimension x k
      const MatrixD weights = x * basis;                                        // texels x k
      out.value<std::uint8_t>(std::uint8_t(scalar_bytes));
      out.value<std::uint32_t>(std::uint32_t(k));
      out.value<std::uint32_t>(std::uint32_t(texels));
      out.value<std::uint32_t>(std::uint32_t(dimension));
      const Eigen::VectorXd eigenvalues = eig.eigenvalues().reverse();
      for (Eigen::Index i = 0; i < k; ++i) out.scalar(eigenvalues(i));
      for (Eigen::Index i = 0; i < mean.size(); ++i) out.scalar(mean(i));
      out.matrix(basis);
      out.matrix(weights);
      progress.advance();
    }
  });
}

}  // namespace btf
