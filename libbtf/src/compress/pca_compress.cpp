// compressPca: per-view eigen-decomposition of the 243 x 243 covariance, storage rounding, and
// least-squares coefficients for the rounded basis (format and rationale in compress/pca.h).
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "btf/compress/pca.h"
#include "btf/core/error.h"
#include "btf/core/progress.h"

namespace btf {
namespace {

// Texels per block when accumulating the covariance in double: 4096 x 243 doubles = 8 MiB.
constexpr Eigen::Index kCovarianceBlock = 4096;

// The value a reader of the file gets back for a stored float.
float roundToStorage(float value, PcaPrecision precision) {
  return precision == PcaPrecision::Half ? float(Eigen::half(value)) : value;
}

struct PcaViewStats {
  double total_variance = 0, kept_variance = 0;
};

// The top-k eigenvectors of the covariance X^T X (dims x dims, accumulated in double blocks).
Eigen::MatrixXd principalAxesFromCovariance(const Eigen::MatrixXf& x, Eigen::Index k, PcaViewStats& stats) {
  const Eigen::Index texels = x.rows(), dims = x.cols();
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(dims, dims);
  for (Eigen::Index start = 0; start < texels; start += kCovarianceBlock) {
    const Eigen::Index rows = std::min(kCovarianceBlock, texels - start);
    const Eigen::MatrixXd block = x.middleRows(start, rows).cast<double>();
    covariance.selfadjointView<Eigen::Lower>().rankUpdate(block.transpose());
  }
  covariance = covariance.selfadjointView<Eigen::Lower>();
  stats.total_variance = covariance.trace();
  if (k == 0) return Eigen::MatrixXd(dims, 0);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(covariance);
  if (solver.info() != Eigen::Success) throw Error("PCA: the eigen-decomposition of a view's covariance failed");
  // Eigenvalues come in increasing order: the last k columns, largest first.
  for (Eigen::Index j = 0; j < k; ++j) stats.kept_variance += std::max(0.0, solver.eigenvalues()(dims - 1 - j));
  return solver.eigenvectors().rightCols(k).rowwise().reverse();
}

// Fewer texels than dimensions: the same axes from the smaller T x T Gram matrix X X^T (the
// "snapshot" method): if X X^T u = lambda u then X^T u is an eigenvector of X^T X with the same
// eigenvalue. Axes beyond the rank (lambda ~ 0, or k > T) are left zero: they carry no variance,
// so their coefficients would be zero anyway.
Eigen::MatrixXd principalAxesFromGram(const Eigen::MatrixXf& x, Eigen::Index k, PcaViewStats& stats) {
  const Eigen::Index texels = x.rows(), dims = x.cols();
  const Eigen::MatrixXd xd = x.cast<double>();
  const Eigen::MatrixXd gram = xd * xd.transpose();
  stats.total_variance = gram.trace();
  Eigen::MatrixXd basis = Eigen::MatrixXd::Zero(dims, k);
  if (k == 0) return basis;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(gram);
  if (solver.info() != Eigen::Success) throw Error("PCA: the eigen-decomposition of a view's Gram matrix failed");
  const double largest = std::max(0.0, solver.eigenvalues()(texels - 1));
  for (Eigen::Index j = 0; j < std::min(k, texels); ++j) {
    const double lambda = solver.eigenvalues()(texels - 1 - j);
    // Below ~1e-12 of the largest, X^T u is dominated by rounding: not a meaningful axis.
    if (!(lambda > largest * 1e-12)) break;
    const Eigen::VectorXd axis = xd.transpose() * solver.eigenvectors().col(texels - 1 - j);
    basis.col(j) = axis.normalized();
    stats.kept_variance += lambda;
  }
  return basis;
}

}  // namespace

// Friend of PcaBtf: factorizes one view's values (light-major, as loadView gives them).
struct PcaViewFactorizer {
  using Stats = PcaViewStats;
  static PcaBtf::View factorize(std::vector<Rgb>& data, Eigen::Index texels, Eigen::Index lights, int components,
                                PcaPrecision precision, Stats& stats) {
    const Eigen::Index dims = 3 * lights, k = components;
    // X(t, 3 light + channel), column-major: each column is one (light, channel) over the texels.
    Eigen::MatrixXf x(texels, dims);
    for (Eigen::Index light = 0; light < lights; ++light)
      for (Eigen::Index t = 0; t < texels; ++t) {
        const Rgb& v = data[std::size_t(light * texels + t)];
        x(t, 3 * light) = v.r;
        x(t, 3 * light + 1) = v.g;
        x(t, 3 * light + 2) = v.b;
      }
    std::vector<Rgb>().swap(data);  // X holds the view now: free its first copy early

    PcaBtf::View view;
    view.mean.resize(std::size_t(dims));
    for (Eigen::Index d = 0; d < dims; ++d) {
      double sum = 0;
      for (Eigen::Index t = 0; t < texels; ++t) sum += x(t, d);
      // Stored as float32, and the data is centred on exactly that float so decoding adds it back.
      view.mean[std::size_t(d)] = float(sum / double(texels));
      x.col(d).array() -= view.mean[std::size_t(d)];
    }

    Eigen::MatrixXd basis;  // dims x k, orthonormal columns, largest variance first
    if (texels >= dims)
      basis = principalAxesFromCovariance(x, k, stats);
    else
      basis = principalAxesFromGram(x, k, stats);
    if (k == 0) return view;

    // The basis as a reader gets it back, then the least-squares coefficients for that basis:
    // C = X Bq (Bq^T Bq)^-1 over its non-zero (leading) columns. Bq^T Bq is the identity up to the
    // rounding, so this is well posed.
    Eigen::MatrixXf rounded(dims, k);
    for (Eigen::Index j = 0; j < k; ++j)
      for (Eigen::Index d = 0; d < dims; ++d) rounded(d, j) = roundToStorage(float(basis(d, j)), precision);
    Eigen::Index used = 0;
    while (used < k && rounded.col(used).squaredNorm() > 0) ++used;
    Eigen::MatrixXf coefficients = Eigen::MatrixXf::Zero(texels, k);
    if (used > 0) {
      const Eigen::MatrixXd rounded_d = rounded.leftCols(used).cast<double>();
      const Eigen::MatrixXd gram = rounded_d.transpose() * rounded_d;
      const Eigen::MatrixXf projector = gram.ldlt().solve(rounded_d.transpose()).cast<float>();  // used x dims
      coefficients.leftCols(used).noalias() = x * projector.transpose();
    }

    // Per-component scale so that the stored coefficients are in [-1, 1] (no float16 overflow).
    view.basis.resize(std::size_t(dims * k));
    view.coefficients.resize(std::size_t(texels * k));
    for (Eigen::Index j = 0; j < k; ++j) {
      float scale = coefficients.col(j).cwiseAbs().maxCoeff();
      if (!(scale > 0) || !std::isfinite(scale)) scale = 1.0f;
      for (Eigen::Index d = 0; d < dims; ++d) view.basis[std::size_t(d * k + j)] = rounded(d, j) * scale;
      for (Eigen::Index t = 0; t < texels; ++t)
        view.coefficients[std::size_t(t * k + j)] = roundToStorage(coefficients(t, j) / scale, precision);
    }
    return view;
  }
};

PcaBtf compressPca(const BtfSource& source, int components, PcaPrecision precision) {
  PcaBtf pca;
  const BtfViewSet& views = source.views();
  const int view_count = views.count();
  PcaBtf::storedBytesFor(source.width(), source.height(), components, precision, views);  // validates
  pca.width_ = source.width();
  pca.height_ = source.height();
  pca.components_ = components;
  pca.precision_ = precision;
  pca.name_ = source.name() + " (pca k=" + std::to_string(components) + ")";
  pca.view_set_ = views;
  pca.views_.resize(std::size_t(view_count));
  std::vector<PcaViewFactorizer::Stats> stats(std::size_t(view_count), PcaViewFactorizer::Stats{});
  const auto texels = Eigen::Index(source.texelCount());

  // Views are read one at a time in order (readers need not be thread-safe) and factorized in
  // parallel; at most one view per worker is in memory.
  struct Job {
    int slot;
    std::vector<Rgb> data;
  };
  Progress progress("PCA of " + source.name(), view_count);
  int next_slot = 0;
  const auto tokens = std::size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
  tbb::parallel_pipeline(
      tokens,
      tbb::make_filter<void, std::shared_ptr<Job>>(
          tbb::filter_mode::serial_in_order,
          [&](tbb::flow_control& control) -> std::shared_ptr<Job> {
            if (next_slot == view_count) {
              control.stop();
              return nullptr;
            }
            auto job = std::make_shared<Job>();
            job->slot = next_slot++;
            source.loadView(views.view(job->slot), job->data);
            const std::size_t expected = source.viewValueCount(views.view(job->slot));
            if (job->data.size() != expected)
              throw Error(source.name() + ": view " + std::to_string(views.view(job->slot)) + " has " +
                          std::to_string(job->data.size()) + " values, expected " + std::to_string(expected));
            return job;
          }) &
          tbb::make_filter<std::shared_ptr<Job>, void>(tbb::filter_mode::parallel, [&](std::shared_ptr<Job> job) {
            const Eigen::Index lights = source.directions().lightCount(views.view(job->slot));
            pca.views_[std::size_t(job->slot)] = PcaViewFactorizer::factorize(
                job->data, texels, lights, components, precision, stats[std::size_t(job->slot)]);
            progress.advance();
          }));

  double total = 0, kept = 0;
  for (const auto& s : stats) {
    total += s.total_variance;
    kept += s.kept_variance;
  }
  pca.explained_variance_ = total > 0 ? std::min(1.0, kept / total) : 1.0;
  return pca;
}

}  // namespace btf
