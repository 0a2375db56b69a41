#include "btf/sampling/chi2.h"

#include <boost/math/distributions/chi_squared.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <numeric>
#include <sstream>

#include "btf/core/error.h"
#include "btf/core/rng.h"

namespace btf {

namespace {

constexpr double kPiD = std::numbers::pi;
// Draws per work unit; fixed so that the RNG streams do not depend on the thread count.
constexpr std::uint64_t kSampleChunk = 1 << 16;

struct ChunkResult {
  std::vector<std::uint64_t> histogram;
  std::uint64_t failed = 0;
  std::uint64_t bad_index = UINT64_MAX;  // first invalid draw of the chunk, if any
  std::string bad_message;
};

// ---- Quadrature of the pdf over one cell, in (theta, phi) where dw = sin(theta) dtheta dphi.
// Parametrizing by theta rather than cos(theta) keeps a narrow lobe narrow in parameter space even
// at the pole, so the fixed minimum subdivision below cannot step over it.

constexpr std::array<double, 5> kGaussNodes{-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                            0.9061798459386640};
constexpr std::array<double, 5> kGaussWeights{0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                              0.4786286704993665, 0.2369268850561891};
constexpr int kMinDepth = 3;   // every cell is split into at least 8 x 8 rectangles of 5 x 5 nodes
constexpr int kMaxDepth = 8;   // cell / 256: resolves lobes far narrower than alpha = 0.02, bounds the work

struct Rect {
  double theta0, theta1, phi0, phi1;
};

double gaussRect(const DirectionPdf& pdf, const Rect& r) {
  const double ht = 0.5 * (r.theta1 - r.theta0), ct = 0.5 * (r.theta1 + r.theta0);
  const double hp = 0.5 * (r.phi1 - r.phi0), cp = 0.5 * (r.phi1 + r.phi0);
  std::array<double, 5> cos_phi, sin_phi;
  for (int j = 0; j < 5; ++j) {
    const double phi = cp + hp * kGaussNodes[j];
    cos_phi[j] = std::cos(phi);
    sin_phi[j] = std::sin(phi);
  }
  double sum = 0.0;
  for (int i = 0; i < 5; ++i) {
    const double theta = ct + ht * kGaussNodes[i];
    const double st = std::sin(theta), z = std::cos(theta);
    double row = 0.0;
    for (int j = 0; j < 5; ++j) {
      const glm::vec3 w{static_cast<float>(st * cos_phi[j]), static_cast<float>(st * sin_phi[j]), static_cast<float>(z)};
      row += kGaussWeights[j] * pdf(w);
    }
    sum += kGaussWeights[i] * st * row;
  }
  return sum * ht * hp;
}

// Float pdfs of sharp lobes carry a relative rounding noise near 1e-4 (cos^n with n in the
// thousands), which no refinement removes; refining only until the quarters agree with their
// parent to this relative level keeps the work bounded, and its effect on a count E (1e-5 E) stays
// far below the sqrt(E) scatter of the histogram.
constexpr double kRelativeTolerance = 1e-5;
// Relative uncertainty allowed in the integral of the pdf over the sphere (see step 3).
constexpr double kNormalizationSlack = 1e-4;

// Adaptive refinement: compare the rectangle's estimate with the sum over its four quarters.
double integrateRect(const DirectionPdf& pdf, const Rect& r, double whole, int depth, double tolerance) {
  const double tm = 0.5 * (r.theta0 + r.theta1), pm = 0.5 * (r.phi0 + r.phi1);
  const std::array<Rect, 4> quarters{Rect{r.theta0, tm, r.phi0, pm}, Rect{r.theta0, tm, pm, r.phi1},
                                     Rect{tm, r.theta1, r.phi0, pm}, Rect{tm, r.theta1, pm, r.phi1}};
  std::array<double, 4> parts;
  for (int k = 0; k < 4; ++k) parts[k] = gaussRect(pdf, quarters[k]);
  const double fine = parts[0] + parts[1] + parts[2] + parts[3];
  const double error = std::abs(fine - whole);
  if (depth >= kMaxDepth || (depth >= kMinDepth && (error <= tolerance || error <= kRelativeTolerance * std::abs(fine))))
    return fine;
  double sum = 0.0;
  for (int k = 0; k < 4; ++k) sum += integrateRect(pdf, quarters[k], parts[k], depth + 1, 0.5 * tolerance);
  return sum;
}

void validate(const Chi2Options& o) {
  if (o.theta_bins < 1 || o.phi_bins < 1)
    throw Error("chi2Test: bin counts must be positive, got " + std::to_string(o.theta_bins) + " x " +
                std::to_string(o.phi_bins));
  if (o.sample_count < 1) throw Error("chi2Test: sample_count must be positive");
  if (!(o.min_expected > 0.0)) throw Error("chi2Test: min_expected must be > 0");
  if (!(o.significance > 0.0 && o.significance < 1.0))
    throw Error("chi2Test: significance must be in (0, 1), got " + std::to_string(o.significance));
}

std::string describeDirection(const glm::vec3& w) {
  std::ostringstream out;
  out << '(' << w.x << ", " << w.y << ", " << w.z << ')';
  return out.str();
}

}  // namespace

Chi2Result chi2Test(const DirectionSampler& sampler, const DirectionPdf& pdf, const Chi2Options& options) {
  validate(options);
  const int nt = options.theta_bins, np = options.phi_bins, cells = nt * np;
  const std::uint64_t n = options.sample_count;
  Chi2Result result;
  result.sample_count = n;
  result.theta_bins = nt;
  result.phi_bins = np;

  // 1. Histogram of draws. Theta rows run from +z (row 0) down to -z, as cos(theta) decreases.
  const std::uint64_t chunks = (n + kSampleChunk - 1) / kSampleChunk;
  std::vector<ChunkResult> partial(chunks);
  tbb::parallel_for(std::uint64_t{0}, chunks, [&](std::uint64_t chunk) {
    ChunkResult& out = partial[chunk];
    out.histogram.assign(cells, 0);
    Rng rng(options.seed, chunk);
    const std::uint64_t end = std::min(n, (chunk + 1) * kSampleChunk);
    for (std::uint64_t i = chunk * kSampleChunk; i < end; ++i) {
      const std::optional<glm::vec3> w = sampler(rng.uniform2D());
      if (!w) {
        ++out.failed;
        continue;
      }
      const float len2 = glm::dot(*w, *w);
      std::string problem;
      if (!std::isfinite(len2) || std::abs(len2 - 1.0f) > 1e-3f) {
        problem = "is not a finite unit vector";
      } else {
        const double p = pdf(*w);
        if (!(p > 0.0) || !std::isfinite(p)) problem = "has pdf " + std::to_string(p) + " (must be finite and > 0)";
      }
      if (!problem.empty()) {
        out.bad_index = i;
        out.bad_message = "sample " + std::to_string(i) + " at " + describeDirection(*w) + " " + problem;
        return;
      }
      const double z = std::clamp(static_cast<double>(w->z), -1.0, 1.0);
      const int row = std::min(nt - 1, static_cast<int>((1.0 - z) * 0.5 * nt));
      double phi = std::atan2(static_cast<double>(w->y), static_cast<double>(w->x));
      if (phi < 0.0) phi += 2.0 * kPiD;
      const int col = std::min(np - 1, static_cast<int>(phi / (2.0 * kPiD) * np));
      ++out.histogram[row * np + col];
    }
  });
  result.observed.assign(cells, 0.0);
  for (const ChunkResult& c : partial) {
    if (c.bad_index != UINT64_MAX) {  // chunks are in sample order, so this is the first bad draw
      result.message = "chi2: rejected: " + c.bad_message;
      return result;
    }
    result.failed_samples += c.failed;
    for (int k = 0; k < cells; ++k) result.observed[k] += static_cast<double>(c.histogram[k]);
  }

  // 2. Expected counts: N times the pdf integrated over each cell. The tolerance is a hundredth of
  // a draw per cell, far below the sqrt(expected) scatter the statistic measures.
  const double tolerance = std::clamp(0.01 / static_cast<double>(n), 1e-14, 1e-6);
  result.expected.assign(cells, 0.0);
  tbb::parallel_for(0, cells, [&](int k) {
    const int row = k / np, col = k % np;
    const double z_top = 1.0 - 2.0 * row / nt, z_bottom = 1.0 - 2.0 * (row + 1) / nt;
    const Rect r{std::acos(std::clamp(z_top, -1.0, 1.0)), std::acos(std::clamp(z_bottom, -1.0, 1.0)),
                 2.0 * kPiD * col / np, 2.0 * kPiD * (col + 1) / np};
    result.expected[k] = static_cast<double>(n) * integrateRect(pdf, r, gaussRect(pdf, r), 1, tolerance);
  });

  // 3. Pool sparse cells, then the statistic over the direction cells.
  const std::vector<double>& obs = result.observed;
  const std::vector<double>& exp = result.expected;
  std::vector<int> order(cells);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return exp[a] < exp[b]; });
  double pooled_obs = 0.0, pooled_exp = 0.0;
  int next = 0;
  // Every cell below min_expected goes into the pool; if the pool is still below min_expected the
  // next-smallest cells join it, so that no cell of the statistic expects too few draws.
  while (next < cells && (exp[order[next]] < options.min_expected || (next > 0 && pooled_exp < options.min_expected))) {
    pooled_obs += obs[order[next]];
    pooled_exp += exp[order[next]];
    ++next;
  }
  result.pooled_cells = next;
  if (pooled_exp == 0.0 && pooled_obs > 0.0) {
    result.message = "chi2: rejected: " + std::to_string(static_cast<std::uint64_t>(pooled_obs)) +
                     " draws landed in cells where the pdf integrates to zero";
    return result;
  }
  double statistic = 0.0;
  int used_cells = 0;
  for (int k = next; k < cells; ++k) {
    const double d = obs[order[k]] - exp[order[k]];
    statistic += d * d / exp[order[k]];
    ++used_cells;
  }
  if (pooled_exp > 0.0) {
    statistic += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
    ++used_cells;
  }
  // The draws without a direction: expected n (1 - int pdf). Its expectation is a difference of
  // two large numbers, uncertain by the pdf's normalization error (kNormalizationSlack, the float
  // precision of sharp lobes), which is added to its variance; it counts as a degree of freedom
  // only when it expects min_expected draws. A pdf that does not integrate to the probability of
  // a sample by much more than that slack is rejected through this term.
  const double expected_none = static_cast<double>(n) - std::accumulate(exp.begin(), exp.end(), 0.0);
  const double slack = kNormalizationSlack * static_cast<double>(n);
  const double d_none = static_cast<double>(result.failed_samples) - expected_none;
  statistic += d_none * d_none / (std::max(expected_none, 0.0) + slack * slack);
  if (expected_none >= options.min_expected) ++used_cells;
  result.statistic = statistic;
  result.degrees_of_freedom = used_cells - 1;
  if (result.degrees_of_freedom < 1) {
    result.message = "chi2: rejected: fewer than two cells expect " + std::to_string(options.min_expected) +
                     " draws; use more samples or fewer bins";
    return result;
  }
  const boost::math::chi_squared_distribution<double> distribution(result.degrees_of_freedom);
  result.p_value = boost::math::cdf(boost::math::complement(distribution, statistic));
  result.accepted = result.p_value >= options.significance;
  std::ostringstream summary;
  summary << "chi2: " << (result.accepted ? "accepted" : "rejected") << ": statistic " << statistic << ", dof "
          << result.degrees_of_freedom << ", p-value " << result.p_value << " (significance " << options.significance
          << "), " << n << " draws, " << result.failed_samples << " without a direction, " << result.pooled_cells
          << " cells pooled";
  result.message = summary.str();
  return result;
}

Chi2Result chi2TestMaterial(const Material& material, const glm::vec3& wo, glm::vec2 uv, const Chi2Options& options) {
  const DirectionSampler sampler = [&](glm::vec2 u) -> std::optional<glm::vec3> {
    const std::optional<BsdfSample> s = material.sample(wo, uv, u);
    if (!s) return std::nullopt;
    return s->wi;
  };
  const DirectionPdf pdf = [&](const glm::vec3& wi) { return static_cast<double>(material.pdf(wi, wo, uv)); };
  Chi2Result result = chi2Test(sampler, pdf, options);
  result.message = material.name() + ": " + result.message;
  return result;
}

}  // namespace btf
