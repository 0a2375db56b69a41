// analyzeCompressibility: nearest-neighbour distances, the greedy texel codebook and the singular
// values of a BTF's luminance (definitions and caveats in compress/compressibility.h).
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "btf/compress/compressibility.h"
#include "btf/core/error.h"
#include "btf/core/progress.h"
#include "btf/core/rng.h"

namespace btf {
namespace {

using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Rows whose products with all texels are held at once (kOuterRows x T floats: 16 MiB at 16384
// texels), and rows per parallel task. Both fixed, so Eigen sees the same product shapes (hence
// the same summation order) whatever the thread count.
constexpr int kOuterRows = 256;
constexpr int kTaskRows = 32;

struct SampledPair {
  int view, light;
  auto operator<=>(const SampledPair&) const = default;
};

// The sampled (view, light) pairs, ascending: a partial Fisher-Yates shuffle of the pairs of the
// views held (each view with its own lights), driven by the seed.
std::vector<SampledPair> chooseDirections(const BtfViewSet& views, int directions, std::uint64_t seed) {
  std::vector<SampledPair> pairs;
  for (const int v : views.views())
    for (int l = 0; l < views.directions().lightCount(v); ++l) pairs.push_back({v, l});
  const int held = int(pairs.size());
  if (directions == 0 || directions >= held) return pairs;
  Rng rng(seed, 0x636f6d7072657373ULL);  // a stream of its own ("compress")
  for (int i = 0; i < directions; ++i) {
    const int j = i + int(rng.uniformInt(std::uint32_t(held - i)));
    std::swap(pairs[std::size_t(i)], pairs[std::size_t(j)]);
  }
  pairs.resize(std::size_t(directions));
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

// T x D luminance, views read in order, only those that hold a sampled pair.
RowMatrix readLuminance(const BtfSource& source, const std::vector<SampledPair>& pairs) {
  const auto texels = Eigen::Index(source.texelCount());
  RowMatrix x(texels, Eigen::Index(pairs.size()));
  int views_needed = 0;
  for (std::size_t c = 0; c < pairs.size(); ++c)
    if (c == 0 || pairs[c].view != pairs[c - 1].view) ++views_needed;
  Progress progress("compressibility: reading " + source.name(), std::uint64_t(views_needed));
  std::vector<Rgb> view;
  for (std::size_t c = 0; c < pairs.size();) {
    const int v = pairs[c].view;
    source.loadView(v, view);
    const std::size_t expected = source.viewValueCount(v);
    if (view.size() != expected)
      throw Error(source.name() + ": view " + std::to_string(v) + " has " + std::to_string(view.size()) +
                  " values, expected " + std::to_string(expected));
    for (; c < pairs.size() && pairs[c].view == v; ++c) {
      const Rgb* light = view.data() + std::size_t(pairs[c].light) * std::size_t(texels);
      for (Eigen::Index t = 0; t < texels; ++t) x(t, Eigen::Index(c)) = light[t].luminance();
    }
    progress.advance();
  }
  return x;
}

// The data of the search: the matrix, squared row norms in double (fixed order).
struct Texels {
  const RowMatrix& x;
  std::vector<double> norm2;

  explicit Texels(const RowMatrix& matrix) : x(matrix), norm2(std::size_t(matrix.rows())) {
    for (Eigen::Index t = 0; t < x.rows(); ++t) {
      double s = 0;
      for (Eigen::Index c = 0; c < x.cols(); ++c) s += double(x(t, c)) * double(x(t, c));
      norm2[std::size_t(t)] = s;
    }
  }

  // cos^2 from a float dot product: only to rank candidates (0 against a zero texel).
  double score(int i, int j, float dot) const {
    const double n = norm2[std::size_t(i)] * norm2[std::size_t(j)];
    return n > 0 ? double(dot) * double(dot) / n : 0.0;
  }

  // d(x_i, x_j) = |x_i - s x_j| / |x_i| at the optimal s, from the residual itself in double (no
  // 1 - cos^2 cancellation): 0 for a zero x_i (scale 0 reproduces it), 1 against a zero x_j.
  double distance(int i, int j) const {
    const double ni = norm2[std::size_t(i)], nj = norm2[std::size_t(j)];
    if (!(ni > 0)) return 0.0;
    if (!(nj > 0)) return 1.0;
    const auto a = x.row(i), b = x.row(j);
    double dot = 0;
    for (Eigen::Index c = 0; c < x.cols(); ++c) dot += double(a(c)) * double(b(c));
    const double s = dot / nj;
    double residual = 0;
    for (Eigen::Index c = 0; c < x.cols(); ++c) {
      const double r = double(a(c)) - s * double(b(c));
      residual += r * r;
    }
    return std::min(1.0, std::sqrt(residual / ni));
  }
};

struct GreedyState {
  double epsilon = 0;
  std::vector<int> entries;
  double error2 = 0;  // sum of |x|^2 d^2 over reused texels
};

// Quantile by linear interpolation between order statistics (h = (n - 1) p) of sorted values.
double quantile(const std::vector<double>& sorted, double p) {
  const double h = double(sorted.size() - 1) * p;
  const auto lo = std::size_t(std::floor(h));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (h - double(lo)) * (sorted[hi] - sorted[lo]);
}

// Nearest neighbours and the greedy codebooks in one pass over blocks of rows: each block's dot
// products with all texels are computed in parallel (fixed tasks), then the nearest neighbour of
// each row (parallel, per row) and the greedy decisions (sequential over rows, parallel over
// epsilons) read them.
void searchTexels(const Texels& data, CompressibilityReport& report, std::vector<GreedyState>& greedy,
                  const std::string& name) {
  const int texels = int(data.x.rows());
  report.nearest_distance.assign(std::size_t(texels), 0.0);
  report.nearest_texel.assign(std::size_t(texels), -1);
  RowMatrix dots(kOuterRows, texels);
  Progress progress("compressibility: nearest texels of " + name, std::uint64_t(texels));
  for (int start = 0; start < texels; start += kOuterRows) {
    const int rows = std::min(kOuterRows, texels - start);
    const int tasks = (rows + kTaskRows - 1) / kTaskRows;
    tbb::parallel_for(0, tasks, [&](int task) {
      const int r0 = task * kTaskRows, n = std::min(kTaskRows, rows - r0);
      dots.middleRows(r0, n).noalias() = data.x.middleRows(start + r0, n) * data.x.transpose();
    });
    tbb::parallel_for(0, rows, [&](int r) {
      const int i = start + r;
      int best = -1;
      double best_score = -1;
      for (int j = 0; j < texels; ++j) {
        if (j == i) continue;
        const double s = data.score(i, j, dots(r, j));
        if (s > best_score) best_score = s, best = j;  // ties: the lowest index
      }
      report.nearest_texel[std::size_t(i)] = best;
      report.nearest_distance[std::size_t(i)] = data.distance(i, best);
    });
    tbb::parallel_for(std::size_t(0), greedy.size(), [&](std::size_t e) {
      GreedyState& g = greedy[e];
      for (int r = 0; r < rows; ++r) {
        const int i = start + r;
        int best = -1;
        double best_score = -1;
        for (int j : g.entries) {
          const double s = data.score(i, j, dots(r, j));
          if (s > best_score) best_score = s, best = j;
        }
        const double d = best < 0 ? 2.0 : data.distance(i, best);
        if (d <= g.epsilon)
          g.error2 += data.norm2[std::size_t(i)] * d * d;
        else
          g.entries.push_back(i);
      }
    });
    progress.advance(std::uint64_t(rows));
  }
}

// Squared singular values of the T x D matrix, largest first, as the eigenvalues of the smaller
// Gram matrix (X X^T or X^T X) accumulated in double blocks.
//
// Why the Gram matrix and not Eigen's BDCSVD of X: only singular values are needed, and they enter
// only as squares through tail sums sum_{i>k} s_i^2 / sum s_i^2 compared against epsilon^2 >= ~1e-6.
// The eigenvalues of a double Gram matrix carry absolute errors ~1e-16 * n * s_1^2, many orders
// below that, so the loss of accuracy for tiny singular values (the usual objection to squaring)
// does not touch any rank we report. In exchange the Gram matrix is one blocked symmetric product
// plus an eigenvalues-only tridiagonal solve of size min(T, D), several times faster than a
// bidiagonalization of the whole T x D matrix.
std::vector<double> squaredSingularValues(const RowMatrix& x) {
  const Eigen::Index texels = x.rows(), dims = x.cols();
  constexpr Eigen::Index kBlock = 1024;
  const Eigen::Index n = std::min(texels, dims);
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(n, n);
  if (texels <= dims) {
    for (Eigen::Index c = 0; c < dims; c += kBlock) {
      const Eigen::MatrixXd block = x.middleCols(c, std::min(kBlock, dims - c)).cast<double>();
      gram.selfadjointView<Eigen::Lower>().rankUpdate(block);
    }
  } else {
    for (Eigen::Index r = 0; r < texels; r += kBlock) {
      const Eigen::MatrixXd block = x.middleRows(r, std::min(kBlock, texels - r)).cast<double>();
      gram.selfadjointView<Eigen::Lower>().rankUpdate(block.transpose());
    }
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(gram, Eigen::EigenvaluesOnly);
  if (solver.info() != Eigen::Success) throw Error("compressibility: the eigen-decomposition of the Gram matrix failed");
  std::vector<double> values(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) values[std::size_t(i)] = std::max(0.0, solver.eigenvalues()(n - 1 - i));
  return values;
}

void checkOptions(const BtfSource& source, const CompressibilityOptions& options) {
  const std::size_t texels = source.texelCount();
  if (texels < 2)
    throw Error(source.name() + ": compressibility needs at least 2 texels, the BTF has " + std::to_string(texels));
  if (texels > std::size_t(kMaxCompressibilityTexels))
    throw Error(source.name() + ": " + std::to_string(texels) + " texels is beyond the compressibility analysis (at most " +
                std::to_string(kMaxCompressibilityTexels) + ", e.g. 128 x 128; its cost grows as texels^2): use a smaller BTF");
  if (options.directions < 0)
    throw Error("compressibility: the direction count must be >= 0 (0 for all pairs), got " +
                std::to_string(options.directions));
  for (double e : options.epsilons)
    if (!(e > 0 && e < 1)) throw Error("compressibility: every epsilon must lie in (0, 1), got " + std::to_string(e));
}

}  // namespace

double rankRatioU8Bound(int texels, int rank, int pairs) {
  if (rank <= 0) return std::numeric_limits<double>::infinity();
  return double(texels) * pairs * 3.0 / (2.0 * double(rank) * (double(texels) + pairs));
}

CompressibilityReport analyzeCompressibility(const BtfSource& source, const CompressibilityOptions& options) {
  checkOptions(source, options);
  const std::vector<SampledPair> pairs = chooseDirections(source.views(), options.directions, options.seed);
  const int held_pairs = int(source.entryCount() / source.texelCount());
  const RowMatrix x = readLuminance(source, pairs);
  const Texels data(x);
  const double energy = std::accumulate(data.norm2.begin(), data.norm2.end(), 0.0);
  if (!(energy > 0))
    throw Error(source.name() + ": the luminance is zero at every sampled direction; relative errors are undefined");

  CompressibilityReport report;
  report.texels = int(x.rows());
  report.directions = int(x.cols());
  std::vector<GreedyState> greedy;
  for (double e : options.epsilons) greedy.push_back({e, {}, 0.0});
  searchTexels(data, report, greedy, source.name());

  std::vector<double> sorted = report.nearest_distance;
  std::sort(sorted.begin(), sorted.end());
  report.nn_p10 = quantile(sorted, 0.10);
  report.nn_p25 = quantile(sorted, 0.25);
  report.nn_p50 = quantile(sorted, 0.50);
  report.nn_p75 = quantile(sorted, 0.75);
  report.nn_p90 = quantile(sorted, 0.90);
  report.nn_max = sorted.back();
  double nn_error2 = 0;
  for (int t = 0; t < report.texels; ++t) {
    const double d = report.nearest_distance[std::size_t(t)];
    nn_error2 += data.norm2[std::size_t(t)] * d * d;
  }
  report.nn_rel_error = std::sqrt(nn_error2 / energy);

  const std::vector<double> squared = squaredSingularValues(x);
  // tail[k] = sum_{i >= k} s_i^2 (0-based: the energy a rank-k model leaves), summed smallest first.
  std::vector<double> tail(squared.size() + 1, 0.0);
  for (std::size_t i = squared.size(); i-- > 0;) tail[i] = tail[i + 1] + squared[i];
  const double total = tail[0] > 0 ? tail[0] : 1.0;
  for (double s2 : squared) report.singular_values.push_back(std::sqrt(s2));
  for (double t : tail) report.rank_rel_error.push_back(std::sqrt(t / total));

  for (const GreedyState& g : greedy) {
    CompressibilityAtEpsilon a;
    a.epsilon = g.epsilon;
    a.greedy_entries = int(g.entries.size());
    a.greedy_rel_error = std::sqrt(g.error2 / energy);
    int k = 0;
    while (std::size_t(k) < squared.size() && report.rank_rel_error[std::size_t(k)] > g.epsilon) ++k;
    a.rank = k;
    a.rank_rel_error = report.rank_rel_error[std::size_t(k)];
    a.ratio_u8_bound = rankRatioU8Bound(report.texels, k, held_pairs);
    report.at_epsilon.push_back(a);
  }
  return report;
}

}  // namespace btf
