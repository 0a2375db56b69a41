// compressFactor (factor_btf.h): the randomised range finder over the source's views, the rotation
// to singular vectors, and the choice of the quantization steps within the error budget.
#include <Eigen/Dense>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "btf/core/error.h"
#include "btf/core/progress.h"
#include "btf/core/rng.h"
#include "btf/io/bonn_btf.h"
#include "bonn_color.h"
#include "factor_impl.h"

namespace btf {
namespace {

using RowMatrixF = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using MatrixD = Eigen::MatrixXd;

// Texels per task of every pass: fixed, so that each chunk's arithmetic and the order of the sums
// over chunks do not depend on the thread count.
constexpr std::size_t kFactorTexelChunk = 4096;
// Codes stay within +-2^30, far inside int32 (and their differences inside int32 too).
constexpr double kMaxFactorCode = 1073741824.0;

// Round half away from zero, as std::round does except for the one double below 0.5 that adding 0.5
// carries up; a truncating conversion rather than a libm call, since the step's trials round every
// sampled coefficient many times. Every code of the file is rounded by it too.
inline double roundCode(double x) { return double(std::int64_t(x + std::copysign(0.5, x))); }

struct Channels {
  // Per channel: the view's values A_c, row-major lights x texels.
  std::array<RowMatrixF, 3> a;
};

// The Bonn file whose own factors the factor form holds exactly (see runFromOwnFactors), or null.
const BonnBtf* ownFactorsOf(const BtfSource& source, const FactorOptions& options) {
  const auto* bonn = dynamic_cast<const BonnBtf*>(&source);
  if (!bonn || options.color_model != FactorColorModel::LogLuminance) return nullptr;
  const BonnBtfHeader& h = bonn->header();
  return h.layout == BonnBtfLayout::Dfmf && h.color_model == 11 && source.views().complete() ? bonn : nullptr;
}

class FactorCompressor {
 public:
  FactorCompressor(const BtfSource& source, const FactorOptions& options) : source_(source), o_(options) {
    T_ = source.texelCount();
    const BtfDirectionSet& set = source.directions();
    for (const int v : source.views().views()) {
      view_pair_.push_back(P_);
      P_ += std::size_t(set.lightCount(v));
    }
    const std::array<int, 3> limits{o_.max_components, o_.max_chroma_components, o_.max_chroma_components};
    for (int c = 0; c < 3; ++c) r_[std::size_t(c)] = int(std::min<std::size_t>({std::size_t(limits[std::size_t(c)]), T_, P_}));
  }

  FactorBtf run() {
    if (const auto* bonn = ownFactorsOf(source_, o_)) return runFromOwnFactors(*bonn);
    const auto start = std::chrono::steady_clock::now();
    const std::shared_ptr<FactorBtf::Impl> impl = newImpl();
    chooseColorTransform();
    impl->color = color_;
    impl->color_model = o_.color_model;
    impl->log_offset = log_offset_;

    const int passes = 2 + 2 * o_.power_iterations;
    Progress progress("factor compress " + source_.name() + ": views read", std::uint64_t(passes) * views().size());
    progress_ = &progress;
    // The sketch Y_c = A_c^T Omega_c, then Q_c = orth(Y_c).
    std::array<MatrixD, 3> q;
    {
      std::array<RowMatrixF, 3> omega;
      for (int c = 0; c < 3; ++c) omega[std::size_t(c)] = randomMatrix(c);
      q = orthonormal(sketchPass(omega));
    }
    for (int i = 0; i < o_.power_iterations; ++i) q = orthonormal(sketchPass(toFloat(projectPass(q))));
    if (o_.color_model == FactorColorModel::LogLuminance) drawSamples();
    record_ = o_.color_model == FactorColorModel::LogLuminance;
    const std::array<MatrixD, 3> g = projectPass(q);
    record_ = false;
    if (o_.color_model == FactorColorModel::LogLuminance) selectSamples();
    progress_ = nullptr;

    // G_c = U S W^T: B_c = Q_c W, C_c = G_c W, columns by decreasing singular value.
    double total_energy = 0, outside = 0;
    std::array<MatrixD, 3> coefficients, basis;
    for (int c = 0; c < 3; ++c) {
      const std::size_t ci = std::size_t(c);
      const MatrixD gram = gramOf(g[ci]);
      const Eigen::SelfAdjointEigenSolver<MatrixD> eig(gram);
      const Eigen::Index r = gram.rows();
      MatrixD w(r, r);
      for (Eigen::Index j = 0; j < r; ++j) w.col(j) = eig.eigenvectors().col(r - 1 - j);
      coefficients[ci] = g[ci] * w;
      basis[ci] = q[ci] * w;
      total_energy += energy_[ci];
      outside += std::max(0.0, energy_[ci] - gram.trace());
    }
    if (!(total_energy > 0))
      throw Error(source_.name() + ": every value is 0; there is nothing to factorise");
    quantize(*impl, coefficients, basis, total_energy, outside);
    impl->prepare();
    impl->stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return FactorBtf(std::move(impl));
  }

  // A DFMF file of colour model 11 is the log-luminance model already: its factors are rotated to
  // singular vectors exactly (QR of each side, SVD of the small core) and quantized, without a pass
  // over the decoded values; its cosine flag becomes the pair offset.
  FactorBtf runFromOwnFactors(const BonnBtf& bonn) {
    const auto start = std::chrono::steady_clock::now();
    const std::shared_ptr<FactorBtf::Impl> impl = newImpl();
    impl->color_model = FactorColorModel::LogLuminance;
    log_offset_ = bonn::kLogEpsilon;
    impl->log_offset = log_offset_;
    const BonnBtfHeader& h = bonn.header();
    if (h.cosine_flag) {
      impl->pair_offset.resize(P_);
      std::size_t p = 0;
      for (const int v : views())
        for (const glm::vec3& l : source_.directions().lightDirections(v)) impl->pair_offset[p++] = -std::log(l.z);
    }
    pair_offset_ = impl->pair_offset;
    const std::vector<BonnBtf::ChannelFactors> factors = bonn.dfmfFactors();
    std::array<MatrixD, 3> coefficients, basis;
    for (int c = 0; c < 3; ++c) {
      const BonnBtf::ChannelFactors& f = factors[std::size_t(c)];
      const Eigen::Index k = Eigen::Index(f.components);
      const MatrixD pairs = Eigen::Map<const RowMatrixF>(f.pair_side.data(), Eigen::Index(P_), k).cast<double>();
      const MatrixD texels = Eigen::Map<const RowMatrixF>(f.texel_side.data(), Eigen::Index(T_), k).cast<double>();
      const Eigen::HouseholderQR<MatrixD> qp(pairs), qt(texels);
      const Eigen::Index kp = std::min(k, pairs.rows()), kt = std::min(k, texels.rows());
      const MatrixD rp = qp.matrixQR().topRows(kp).triangularView<Eigen::Upper>();
      const MatrixD rt = qt.matrixQR().topRows(kt).triangularView<Eigen::Upper>();
      const Eigen::JacobiSVD<MatrixD> svd(rp * rt.transpose(), Eigen::ComputeThinU | Eigen::ComputeThinV);
      basis[std::size_t(c)] = (qp.householderQ() * MatrixD::Identity(pairs.rows(), kp)) * svd.matrixU();
      coefficients[std::size_t(c)] =
          (qt.householderQ() * MatrixD::Identity(texels.rows(), kt)) * svd.matrixV() * svd.singularValues().asDiagonal();
    }
    // The samples' values: the file's own decode, entry by entry.
    drawSamples();
    tbb::parallel_for(std::size_t(0), samples_.size(), [&](std::size_t i) {
      Sample& s = samples_[i];
      const std::size_t slot = std::size_t(std::upper_bound(view_pair_.begin(), view_pair_.end(), std::size_t(s.pair)) -
                                           view_pair_.begin()) - 1;
      const int w = source_.width();
      s.value = bonn.value(int(s.texel % std::uint32_t(w)), int(s.texel / std::uint32_t(w)), views()[slot],
                           int(s.pair - view_pair_[slot]));
    });
    selectSamples();
    quantize(*impl, coefficients, basis, 0.0, 0.0);
    impl->prepare();
    impl->stats.from_source_factors = true;
    impl->stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return FactorBtf(std::move(impl));
  }

 private:
  const std::vector<int>& views() const { return source_.views().views(); }

  // The factors' frame: the source's size, name, views and the options asked for.
  std::shared_ptr<FactorBtf::Impl> newImpl() const {
    auto impl = std::make_shared<FactorBtf::Impl>();
    impl->width = source_.width();
    impl->height = source_.height();
    impl->name = source_.name() + " (factor)";
    impl->views = source_.views();
    impl->options = o_;
    return impl;
  }

  // K: the eigenvectors of the RGB second-moment matrix of a few views (first, middle, last held),
  // largest eigenvalue first, each signed so that its largest component is positive.
  void chooseColorTransform() {
    const std::vector<int>& held = views();
    std::vector<int> probe{held.front(), held[held.size() / 2], held.back()};
    probe.erase(std::unique(probe.begin(), probe.end()), probe.end());
    Eigen::Matrix3d moments = Eigen::Matrix3d::Zero();
    std::vector<Rgb> values;
    std::size_t count = 0;
    for (const int v : probe) {
      source_.loadView(v, values);
      checkValues(values, v);
      count += values.size();
      for (const Rgb& x : values) {
        const Eigen::Vector3d e(x.r, x.g, x.b);
        moments += e * e.transpose();
      }
    }
    if (o_.color_model == FactorColorModel::LogLuminance) {
      // btflib's RGB -> YUV (the inverse of the decoder's matrix), and the offset o.
      Eigen::Matrix3d to_rgb;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) to_rgb(i, j) = bonn::kYuvToRgb[i][j];
      const Eigen::Matrix3d to_yuv = to_rgb.inverse();
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) color_[std::size_t(3 * i + j)] = float(to_yuv(i, j));
      const Eigen::Vector3d y_row = to_yuv.row(0).transpose();
      const double mean_y2 = y_row.dot(moments * y_row) / double(std::max<std::size_t>(count, 1));
      log_offset_ = float(kFactorLogOffset * std::sqrt(std::max(mean_y2, 0.0)));
      if (!(log_offset_ > 0)) log_offset_ = 1e-6f;
      return;
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(moments);
    for (int c = 0; c < 3; ++c) {
      Eigen::Vector3d axis = eig.eigenvectors().col(2 - c);
      Eigen::Index largest;
      axis.cwiseAbs().maxCoeff(&largest);
      if (axis(largest) < 0) axis = -axis;
      for (int i = 0; i < 3; ++i) color_[std::size_t(3 * c + i)] = float(axis(i));
    }
  }

  void checkValues(const std::vector<Rgb>& values, int v) const {
    for (std::size_t i = 0; i < values.size(); ++i)
      if (!values[i].isFinite() || values[i].minComponent() < 0.0f) {
        const std::size_t light = i / T_, t = i % T_, w = std::size_t(source_.width());
        throw Error(source_.name() + ": view " + std::to_string(v) + ", light " + std::to_string(light) + ", texel (" +
                    std::to_string(t % w) + ", " + std::to_string(t / w) + ") holds a negative, infinite or NaN value");
      }
  }

  // Texels x r_c, uniform in [-1, 1) (a sub-Gaussian test matrix serves the range finder as a
  // Gaussian does); one random stream per texel and channel.
  RowMatrixF randomMatrix(int c) const {
    RowMatrixF m(Eigen::Index(T_), r_[std::size_t(c)]);
    tbb::parallel_for(std::size_t(0), T_, [&](std::size_t t) {
      Rng rng(o_.seed, std::uint64_t(t) * 3 + std::uint64_t(c));
      for (Eigen::Index j = 0; j < m.cols(); ++j) m(Eigen::Index(t), j) = 2.0f * rng.uniform() - 1.0f;
    });
    return m;
  }

  // Loads view v and turns it into the channels (checks the values on the first pass).
  void loadChannels(std::size_t slot, Channels& ch) {
    const int v = views()[slot];
    source_.loadView(v, rgb_);
    if (first_pass_) checkValues(rgb_, v);
    const std::size_t lights = rgb_.size() / T_;
    for (int c = 0; c < 3; ++c) ch.a[std::size_t(c)].resize(Eigen::Index(lights), Eigen::Index(T_));
    const std::array<float, 9>& k = color_;
    const bool log = o_.color_model == FactorColorModel::LogLuminance;
    const float offset = log_offset_;
    tbb::parallel_for(std::size_t(0), lights, [&](std::size_t l) {
      for (std::size_t t = 0; t < T_; ++t) {
        const Rgb& x = rgb_[l * T_ + t];
        float a[3];
        for (int c = 0; c < 3; ++c)
          a[c] = k[std::size_t(3 * c)] * x.r + k[std::size_t(3 * c + 1)] * x.g + k[std::size_t(3 * c + 2)] * x.b;
        if (log) {
          const float scale = std::max(a[0], 0.0f) + offset;
          a[0] = std::log(scale);
          a[1] /= scale;
          a[2] /= scale;
        }
        for (int c = 0; c < 3; ++c) ch.a[std::size_t(c)](Eigen::Index(l), Eigen::Index(t)) = a[c];
      }
    });
    if (record_) recordSamples(slot, lights);
  }

  std::size_t chunks() const { return (T_ + kFactorTexelChunk - 1) / kFactorTexelChunk; }

  // One pass: Y_c (pairs x r) = A_c^T X_c, X_c texels x r. Each view's rows are the sum over texel
  // chunks, in chunk order. The first pass also sums |A_c|^2.
  std::array<MatrixD, 3> sketchPass(const std::array<RowMatrixF, 3>& x) {
    std::array<MatrixD, 3> y;
    for (int c = 0; c < 3; ++c) y[std::size_t(c)] = MatrixD::Zero(Eigen::Index(P_), x[std::size_t(c)].cols());
    Channels ch;
    std::vector<double> chunk_energy(chunks() * 3);
    for (std::size_t slot = 0; slot < views().size(); ++slot) {
      loadChannels(slot, ch);
      const Eigen::Index lights = ch.a[0].rows();
      for (int c = 0; c < 3; ++c) {
        const std::size_t ci = std::size_t(c);
        const Eigen::Index r = x[ci].cols();
        std::vector<RowMatrixF> partial(chunks());
        tbb::parallel_for(std::size_t(0), chunks(), [&](std::size_t k) {
          const Eigen::Index t0 = Eigen::Index(k * kFactorTexelChunk), n = Eigen::Index(std::min(kFactorTexelChunk, T_ - k * kFactorTexelChunk));
          const auto block = ch.a[ci].middleCols(t0, n);
          partial[k].noalias() = block * x[ci].middleRows(t0, n);
          if (first_pass_) chunk_energy[k * 3 + ci] = double(block.cast<double>().squaredNorm());
        });
        MatrixD sum = MatrixD::Zero(lights, r);
        for (std::size_t k = 0; k < chunks(); ++k) {
          sum += partial[k].cast<double>();
          if (first_pass_) energy_[ci] += chunk_energy[k * 3 + ci];
        }
        y[ci].middleRows(Eigen::Index(view_pair_[slot]), lights) = sum;
      }
      progress_->advance();
    }
    first_pass_ = false;
    return y;
  }

  // One pass: G_c (texels x r) = A_c Q_c, summed over views in order, per texel chunk.
  std::array<MatrixD, 3> projectPass(const std::array<MatrixD, 3>& q) {
    std::array<RowMatrixF, 3> qf = toFloat(q), g;
    for (int c = 0; c < 3; ++c) g[std::size_t(c)] = RowMatrixF::Zero(Eigen::Index(T_), qf[std::size_t(c)].cols());
    Channels ch;
    for (std::size_t slot = 0; slot < views().size(); ++slot) {
      loadChannels(slot, ch);
      const Eigen::Index lights = ch.a[0].rows();
      for (int c = 0; c < 3; ++c) {
        const std::size_t ci = std::size_t(c);
        const auto qv = qf[ci].middleRows(Eigen::Index(view_pair_[slot]), lights);
        tbb::parallel_for(std::size_t(0), chunks(), [&](std::size_t k) {
          const Eigen::Index t0 = Eigen::Index(k * kFactorTexelChunk), n = Eigen::Index(std::min(kFactorTexelChunk, T_ - k * kFactorTexelChunk));
          g[ci].middleRows(t0, n).noalias() += ch.a[ci].middleCols(t0, n).transpose() * qv;
        });
      }
      progress_->advance();
    }
    std::array<MatrixD, 3> out;
    for (int c = 0; c < 3; ++c) out[std::size_t(c)] = g[std::size_t(c)].cast<double>();
    return out;
  }

  static std::array<RowMatrixF, 3> toFloat(const std::array<MatrixD, 3>& m) {
    std::array<RowMatrixF, 3> out;
    for (int c = 0; c < 3; ++c) out[std::size_t(c)] = m[std::size_t(c)].cast<float>();
    return out;
  }

  static std::array<MatrixD, 3> orthonormal(const std::array<MatrixD, 3>& y) {
    std::array<MatrixD, 3> q;
    for (int c = 0; c < 3; ++c) {
      const MatrixD& m = y[std::size_t(c)];
      const Eigen::HouseholderQR<MatrixD> qr(m);
      q[std::size_t(c)] = qr.householderQ() * MatrixD::Identity(m.rows(), m.cols());
    }
    return q;
  }

  // G^T G, summed over texel chunks in order.
  MatrixD gramOf(const MatrixD& g) const {
    std::vector<MatrixD> partial(chunks());
    tbb::parallel_for(std::size_t(0), chunks(), [&](std::size_t k) {
      const Eigen::Index t0 = Eigen::Index(k * kFactorTexelChunk), n = Eigen::Index(std::min(kFactorTexelChunk, T_ - k * kFactorTexelChunk));
      partial[k] = g.middleRows(t0, n).transpose() * g.middleRows(t0, n);
    });
    MatrixD sum = MatrixD::Zero(g.cols(), g.cols());
    for (const MatrixD& p : partial) sum += p;
    return sum;
  }

  // Sum over all coefficients of (c - step round(c / step))^2; and which components keep a code.
  double coefficientError(const std::array<MatrixD, 3>& coefficients, double step, std::array<std::vector<bool>, 3>* kept) const {
    double total = 0;
    for (int c = 0; c < 3; ++c) {
      const MatrixD& m = coefficients[std::size_t(c)];
      std::vector<double> col_error(std::size_t(m.cols()));
      std::vector<char> col_kept(std::size_t(m.cols()));
      tbb::parallel_for(Eigen::Index(0), m.cols(), [&](Eigen::Index j) {
        double e = 0;
        bool any = false;
        for (Eigen::Index t = 0; t < m.rows(); ++t) {
          const double v = m(t, j), code = roundCode(v / step);
          any |= code != 0;
          e += (v - code * step) * (v - code * step);
        }
        col_error[std::size_t(j)] = e;
        col_kept[std::size_t(j)] = any;
      });
      for (Eigen::Index j = 0; j < m.cols(); ++j) total += col_error[std::size_t(j)];
      if (kept) (*kept)[std::size_t(c)].assign(col_kept.begin(), col_kept.end());
    }
    return total;
  }

  // Entries whose decoded error measures the step (LogLuminance). A uniform draw of candidates
  // (sorted by pair, so that each view's are one range; their values recorded in the last pass),
  // then an importance draw among them with probability q ~ |v|^2 + mean |v|^2, weighted 1/q: the
  // ratio estimate of the relative error then counts the few highlights that hold much of an HDR
  // material's energy, which a uniform draw misses, while the floor keeps the body represented.
  struct Sample {
    std::uint32_t pair, texel;
    Rgb value;
    double weight = 1;
  };
  void drawSamples() {
    const std::size_t count = std::min<std::size_t>(kFactorErrorCandidates, T_ * P_);
    samples_.resize(count);
    Rng rng(o_.seed, 0xfac7);
    for (Sample& s : samples_) {
      s.pair = std::uint32_t(rng.nextU64() % P_);
      s.texel = std::uint32_t(rng.nextU64() % T_);
    }
    std::sort(samples_.begin(), samples_.end(),
              [](const Sample& a, const Sample& b) { return a.pair != b.pair ? a.pair < b.pair : a.texel < b.texel; });
  }
  void selectSamples() {
    const std::size_t n = samples_.size(), keep = std::min(kFactorErrorSamples, n);
    std::vector<double> cdf(n);
    double sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const Rgb& v = samples_[i].value;
      sum += double(v.r) * v.r + double(v.g) * v.g + double(v.b) * v.b;
    }
    const double floor = std::max(sum / double(n), 1e-300);
    double running = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const Rgb& v = samples_[i].value;
      running += double(v.r) * v.r + double(v.g) * v.g + double(v.b) * v.b + floor;
      cdf[i] = running;
    }
    Rng rng(o_.seed, 0xfac8);
    std::vector<Sample> chosen(keep);
    for (Sample& s : chosen) {
      const double u = rng.uniform() * running;
      const std::size_t i = std::min(n - 1, std::size_t(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin()));
      s = samples_[i];
      s.weight = running / (cdf[i] - (i ? cdf[i - 1] : 0.0));
    }
    samples_ = std::move(chosen);
  }
  void recordSamples(std::size_t slot, std::size_t lights) {
    const std::uint32_t p0 = std::uint32_t(view_pair_[slot]), p1 = p0 + std::uint32_t(lights);
    auto it = std::lower_bound(samples_.begin(), samples_.end(), p0, [](const Sample& s, std::uint32_t p) { return s.pair < p; });
    for (; it != samples_.end() && it->pair < p1; ++it) it->value = rgb_[std::size_t(it->pair - p0) * T_ + it->texel];
  }

  // A coefficient step and what follows from it: the components kept, the basis grids, the errors.
  struct StepTrial {
    double step = 0;
    std::vector<std::pair<int, Eigen::Index>> columns;  // (channel, column) kept, in channel order
    std::vector<double> scales;                          // of the kept basis columns
    double coefficient_error = 0, basis_error = 0;      // squared, in the channels' units
    double error = 0;                                   // squared RGB error (Linear) or its sampled share (LogLuminance)
  };

  StepTrial trial(const std::array<MatrixD, 3>& coefficients, const std::array<MatrixD, 3>& basis, double step,
                  double outside) const {
    StepTrial t;
    t.step = step;
    std::array<std::vector<bool>, 3> kept;
    t.coefficient_error = coefficientError(coefficients, step, &kept);
    for (int c = 0; c < 3; ++c)
      for (Eigen::Index j = 0; j < coefficients[std::size_t(c)].cols(); ++j)
        if (kept[std::size_t(c)][std::size_t(j)]) t.columns.emplace_back(c, j);
    if (t.columns.empty()) t.columns.emplace_back(0, 0);  // all below the step: one component of zeros
    const std::size_t K = t.columns.size();
    const double basis_budget = kFactorBasisErrorShare * std::max(t.coefficient_error, 1e-300);
    t.scales.resize(K);
    std::vector<double> column_error(K);
    tbb::parallel_for(std::size_t(0), K, [&](std::size_t j) {
      const auto [c, col] = t.columns[j];
      const auto ccol = coefficients[std::size_t(c)].col(col);
      double code_energy = 0;
      for (Eigen::Index i = 0; i < ccol.size(); ++i) {
        const double q = roundCode(ccol(i) / step) * step;
        code_energy += q * q;
      }
      // The basis grid: |C_j|^2 P h^2 / 12 = basis_budget / K.
      const double h = std::sqrt(12.0 * basis_budget / (double(K) * double(P_) * std::max(code_energy, 1e-300)));
      const double scale = std::min(1.0 / h, kMaxFactorCode);
      t.scales[j] = scale;
      const auto bcol = basis[std::size_t(c)].col(col);
      double e = 0;
      for (Eigen::Index p = 0; p < bcol.size(); ++p) {
        const double d = bcol(p) - roundCode(bcol(p) * scale) / scale;
        e += d * d;
      }
      column_error[j] = code_energy * e;
    });
    for (const double e : column_error) t.basis_error += e;
    t.error = o_.color_model == FactorColorModel::Linear ? outside + t.coefficient_error + t.basis_error
                                                         : sampledError(t);
    return t;
  }

  // LogLuminance: the squared RGB error of the samples decoded from the trial's codes, over their
  // squared norm.
  double sampledError(const StepTrial& t) const {
    const std::size_t K = t.columns.size(), n = samples_.size();
    constexpr std::size_t kChunk = 65536;
    const std::size_t chunks = (n + kChunk - 1) / kChunk;
    std::vector<double> error(chunks), energy(chunks);
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t k) {
      double e = 0, w = 0;
      for (std::size_t i = k * kChunk; i < std::min(n, (k + 1) * kChunk); ++i) {
        const Sample& s = samples_[i];
        float a[3] = {0, 0, 0};
        for (std::size_t j = 0; j < K; ++j) {
          const auto [c, col] = t.columns[j];
          const float cv = float(roundCode(coefficient_rows_[std::size_t(c)](Eigen::Index(s.texel), col) / t.step) * t.step);
          const float bv = float(roundCode(basis_rows_[std::size_t(c)](Eigen::Index(s.pair), col) * t.scales[j]) / t.scales[j]);
          a[c] += cv * bv;
        }
        const float scale = std::exp(pair_offset_.empty() ? a[0] : a[0] + pair_offset_[s.pair]);
        const Rgb d = bonn::yuvToRgb(scale - log_offset_, a[1] * scale, a[2] * scale);
        const Rgb decoded(std::max(d.r, 0.0f), std::max(d.g, 0.0f), std::max(d.b, 0.0f));
        for (int c = 0; c < 3; ++c) {
          const double diff = double(decoded[c]) - double(s.value[c]);
          e += s.weight * diff * diff;
          w += s.weight * double(s.value[c]) * double(s.value[c]);
        }
      }
      error[k] = e;
      energy[k] = w;
    });
    double e = 0, w = 0;
    for (std::size_t k = 0; k < chunks; ++k) e += error[k], w += energy[k];
    return w > 0 ? e / w : 0.0;
  }

  // The steps (factor_btf.h): the largest coefficient step whose error meets the budget; the codes.
  // LogLuminance: the sampled error chooses the step, then the error of every entry decoded from the
  // codes is measured, and while it exceeds epsilon the step shrinks in proportion (the error is
  // nearly linear in the step), so that what is written meets epsilon whatever the samples missed.
  void quantize(FactorBtf::Impl& m, const std::array<MatrixD, 3>& coefficients, const std::array<MatrixD, 3>& basis,
                double total_energy, double outside) {
    const bool linear = o_.color_model == FactorColorModel::Linear;
    if (!linear)
      for (int c = 0; c < 3; ++c) {
        coefficient_rows_[std::size_t(c)] = coefficients[std::size_t(c)];
        basis_rows_[std::size_t(c)] = basis[std::size_t(c)];
      }
    // 0.97: room for the float rounding of what is decoded (and, sampled, for the sample's spread).
    const double target = std::pow(0.97 * double(o_.epsilon), 2);
    const double budget = linear ? target * total_energy : target;
    if (linear && outside >= budget)
      throw Error(source_.name() + ": epsilon " + std::to_string(o_.epsilon) + " needs more components than the " +
                  std::to_string(r_[0]) + " (colour channels: " + std::to_string(r_[1]) +
                  ") sketched: the rest alone has rel_rmse " + std::to_string(std::sqrt(outside / total_energy)) +
                  "; raise max_components or epsilon");
    double largest = 0;
    for (const MatrixD& c : coefficients) largest = std::max(largest, c.cwiseAbs().maxCoeff());
    double lo = largest / kMaxFactorCode, hi = 2.0 * largest;
    StepTrial best = trial(coefficients, basis, lo, outside);
    if (best.error > budget)
      throw Error(source_.name() + ": epsilon " + std::to_string(o_.epsilon) + " is out of reach of the " +
                  std::to_string(r_[0]) + " components sketched (at the finest step the error is rel_rmse " +
                  std::to_string(std::sqrt(linear ? best.error / total_energy : best.error)) +
                  "); raise max_components or epsilon");
    // Bisection on log(step) until the bracket's ratio is below 1.005: the bytes change smoothly
    // with the step, and the measured refinement below corrects the last part anyway.
    for (int i = 0; i < 60 && hi / lo > 1.005; ++i) {
      const double mid = std::sqrt(lo * hi);
      StepTrial t = trial(coefficients, basis, mid, outside);
      if (t.error <= budget) {
        lo = mid;
        best = std::move(t);
      } else {
        hi = mid;
      }
    }
    setCodes(m, best, coefficients, basis);
    m.stats.estimated_rel_rmse = std::sqrt(linear ? best.error / total_energy : best.error);
    if (linear) {
      m.stats.measured_rel_rmse = -1;
      return;
    }
    // The measured error steers the step: shrink while above epsilon; grow (once it is known to
    // pass) while well below, since the sampled estimate errs either way. The largest passing step
    // is kept.
    constexpr int kMaxMeasures = 5;
    std::optional<StepTrial> passing;
    double passing_error = 0, failing_step = 0;
    for (int round = 0;; ++round) {
      m.prepare();
      const double measured = measuredRelRmse(m);
      m.stats.refinements = round;
      const bool passes = measured <= 0.995 * double(o_.epsilon);
      if (passes && (!passing || best.step > passing->step)) {
        passing = best;
        passing_error = measured;
      }
      if (!passes && (failing_step == 0 || best.step < failing_step)) failing_step = best.step;
      const bool close = passes && measured >= 0.85 * double(o_.epsilon);
      if (close || round + 1 == kMaxMeasures) break;
      double step = best.step * std::clamp(0.97 * double(o_.epsilon) / std::max(measured, 1e-300), 0.25, 4.0);
      if (passing && failing_step > 0) step = std::clamp(step, passing->step, failing_step);
      if (passing && failing_step > 0 && failing_step / passing->step < 1.02) break;
      best = trial(coefficients, basis, step, outside);
      setCodes(m, best, coefficients, basis);
    }
    if (!passing)
      throw Error(source_.name() + ": epsilon " + std::to_string(o_.epsilon) + " not met after " +
                  std::to_string(kMaxMeasures) + " measured steps; raise max_components or epsilon");
    if (passing->step != best.step) {
      setCodes(m, *passing, coefficients, basis);
      m.prepare();
    }
    m.stats.measured_rel_rmse = passing_error;
  }

  void setCodes(FactorBtf::Impl& m, const StepTrial& best, const std::array<MatrixD, 3>& coefficients,
                const std::array<MatrixD, 3>& basis) const {
    m.coefficient_step = best.step;
    m.k = {0, 0, 0};
    for (const auto& [c, col] : best.columns) ++m.k[std::size_t(c)];
    const std::size_t K = best.columns.size();
    m.coefficient_codes.assign(K * T_, 0);
    m.basis_codes.assign(K * P_, 0);
    m.basis_scale = best.scales;
    double kept_energy = 0, total_energy = 0;
    for (int c = 0; c < 3; ++c) total_energy += energy_[std::size_t(c)];
    for (std::size_t j = 0; j < K; ++j) {
      const auto [c, col] = best.columns[j];
      const auto ccol = coefficients[std::size_t(c)].col(col);
      for (std::size_t t = 0; t < T_; ++t) m.coefficient_codes[j * T_ + t] = std::int32_t(roundCode(ccol(Eigen::Index(t)) / best.step));
      kept_energy += ccol.squaredNorm();
      const auto bcol = basis[std::size_t(c)].col(col);
      for (std::size_t p = 0; p < P_; ++p) m.basis_codes[j * P_ + p] = std::int32_t(roundCode(bcol(Eigen::Index(p)) * best.scales[j]));
    }
    m.stats.components = m.k;
    m.stats.coefficient_step = best.step;
    m.stats.truncation_rel_rmse = o_.color_model == FactorColorModel::Linear && total_energy > 0
                                      ? std::sqrt(std::max(0.0, total_energy - kept_energy) / total_energy)
                                      : 0.0;
  }

  // The rel_rmse of every entry decoded from m's codes against the source, view by view (texel
  // chunks summed in order: the same figure for any thread count).
  double measuredRelRmse(const FactorBtf::Impl& m) {
    const FactorBtf decoded(std::shared_ptr<const FactorBtf::Impl>(&m, [](const FactorBtf::Impl*) {}));
    Progress progress("factor compress " + source_.name() + ": error measured", views().size());
    std::vector<Rgb> a, b;
    double error = 0, energy = 0;
    for (const int v : views()) {
      source_.loadView(v, a);
      decoded.loadView(v, b);
      const std::size_t n = a.size(), chunk = 65536, count = (n + chunk - 1) / chunk;
      std::vector<double> e(count), w(count);
      tbb::parallel_for(std::size_t(0), count, [&](std::size_t k) {
        double se = 0, sw = 0;
        for (std::size_t i = k * chunk; i < std::min(n, (k + 1) * chunk); ++i)
          for (int c = 0; c < 3; ++c) {
            const double d = double(b[i][c]) - double(a[i][c]);
            se += d * d;
            sw += double(a[i][c]) * double(a[i][c]);
          }
        e[k] = se;
        w[k] = sw;
      });
      for (std::size_t k = 0; k < count; ++k) error += e[k], energy += w[k];
      progress.advance();
    }
    return energy > 0 ? std::sqrt(error / energy) : 0.0;
  }

  const BtfSource& source_;
  FactorOptions o_;
  std::size_t T_ = 0, P_ = 0;
  std::vector<std::size_t> view_pair_;  // by slot of the held views
  std::array<int, 3> r_{};
  std::array<float, 9> color_{};
  std::array<double, 3> energy_{};
  bool first_pass_ = true, record_ = false;
  float log_offset_ = 0;
  std::vector<Sample> samples_;
  // LogLuminance: the factors row-major, so that a sample reads its texel's and pair's rows.
  std::array<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>, 3> coefficient_rows_, basis_rows_;
  std::vector<float> pair_offset_;
  std::vector<Rgb> rgb_;
  Progress* progress_ = nullptr;
};

}  // namespace

bool factorFromSourceFactors(const BtfSource& source, const FactorOptions& options) {
  return ownFactorsOf(source, options) != nullptr;
}

FactorBtf compressFactor(const BtfSource& source, const FactorOptions& options) {
  if (!(options.epsilon > 0.0f) || !(options.epsilon < 1.0f))
    throw Error("factor compression: epsilon must be in (0, 1), not " + std::to_string(options.epsilon));
  if (options.max_components < 1 || options.max_chroma_components < 1)
    throw Error("factor compression: max_components and max_chroma_components must be at least 1");
  if (options.power_iterations < 0 || options.power_iterations > 8)
    throw Error("factor compression: power_iterations must be in 0..8");
  if (options.threads < 0) throw Error("factor compression: threads must be >= 0");
  if (source.texelCount() == 0 || source.views().count() == 0) throw Error(source.name() + ": the BTF holds no values");
  FactorBtf out = [&] {
    FactorCompressor compressor(source, options);
    if (options.threads == 0) return compressor.run();
    tbb::task_arena arena(options.threads);
    return arena.execute([&] { return compressor.run(); });
  }();
  return out;
}

}  // namespace btf
