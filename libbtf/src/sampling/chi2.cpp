#include "btf/sampling/chi2.h"

#include <boost/math/distributions/chi_squared.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
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
//
// Two kinds of pdf must be integrated to a small fraction of a draw per cell: smooth lobes, which
// Gauss-Legendre resolves once rectangles are small, and the piecewise-constant densities of
// tabulated samplers, whose jumps lie on lines of constant theta or phi (grid rows in cos(theta),
// columns in phi, rotated about the normal). A jump inside a rectangle costs a Gauss rule an error
// proportional to the rectangle's width, so refining every rectangle into quarters to a fixed depth
// left errors far above the tolerance in the sharpest cells of a near-mirror table (rejecting
// correct samplers ever more surely as draws grew). Each rectangle therefore also probes the pdf
// next to its borders and
// records in which directions it varies: a rectangle that is constant is exact as it is, one that
// varies along theta only (a jump line of constant theta) is halved along theta only, and so on.
// A jump line is then followed by a bisection that costs two rectangles per level instead of four
// times as many per level, which allows far deeper refinement (kMaxDepth) at bounded work; smooth
// pdfs, which vary both ways, are quartered exactly as before (at most kMaxQuarterDepth times).

constexpr std::array<double, 5> kGaussNodes{-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                            0.9061798459386640};
constexpr std::array<double, 5> kGaussWeights{0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                              0.4786286704993665, 0.2369268850561891};
// The probe grid: the Gauss nodes plus a point just inside each border. A jump between the border
// and that point goes unseen, so it sits a millionth of the width inside (at 0.999 the strips
// missed this way still cost 2e-4 of a sharp cell's count); not on the border itself, where float
// rounding of the direction would often land across a jump that coincides with the border.
constexpr double kBorderProbe = 1.0 - 1e-6;
constexpr std::array<double, 7> kProbes{-kBorderProbe,  kGaussNodes[0], kGaussNodes[1], kGaussNodes[2],
                                        kGaussNodes[3], kGaussNodes[4], kBorderProbe};
constexpr int kMinDepth = 3;         // every cell is split into at least 8 x 8 rectangles
constexpr int kMaxQuarterDepth = 8;  // quarters: cell / 256, lobes far narrower than alpha = 0.02
constexpr int kMaxDepth = 30;        // halvings along a jump line: cell / 2^30, below float resolution
// Values within this relative difference count as equal (a tabulated pdf repeats its float exactly).
constexpr double kConstantTolerance = 1e-6;

struct Rect {
  double theta0, theta1, phi0, phi1;
};

struct RectEstimate {
  double integral = 0;
  double low = 0, high = 0;  // least and largest probed pdf value
  bool varies_theta = false, varies_phi = false;
  bool constant() const { return !varies_theta && !varies_phi; }
};

double solidAngle(const Rect& r) { return (r.phi1 - r.phi0) * (std::cos(r.theta0) - std::cos(r.theta1)); }

RectEstimate gaussRect(const DirectionPdf& pdf, const Rect& r) {
  const double ht = 0.5 * (r.theta1 - r.theta0), ct = 0.5 * (r.theta1 + r.theta0);
  const double hp = 0.5 * (r.phi1 - r.phi0), cp = 0.5 * (r.phi1 + r.phi0);
  std::array<double, 7> cos_phi, sin_phi;
  for (int j = 0; j < 7; ++j) {
    const double phi = cp + hp * kProbes[j];
    cos_phi[j] = std::cos(phi);
    sin_phi[j] = std::sin(phi);
  }
  std::array<std::array<double, 7>, 7> v;  // [theta][phi]
  double sum = 0.0, largest = 0.0, low = std::numeric_limits<double>::infinity(), high = -low;
  for (int i = 0; i < 7; ++i) {
    const double theta = ct + ht * kProbes[i];
    const double st = std::sin(theta), z = std::cos(theta);
    double row = 0.0;
    for (int j = 0; j < 7; ++j) {
      const glm::vec3 w{static_cast<float>(st * cos_phi[j]), static_cast<float>(st * sin_phi[j]), static_cast<float>(z)};
      v[i][j] = pdf(w);
      largest = std::max(largest, std::abs(v[i][j]));
      low = std::min(low, v[i][j]);
      high = std::max(high, v[i][j]);
      if (j >= 1 && j <= 5) row += kGaussWeights[j - 1] * v[i][j];
    }
    if (i >= 1 && i <= 5) sum += kGaussWeights[i - 1] * st * row;
  }
  RectEstimate e;
  e.integral = sum * ht * hp;
  e.low = low;
  e.high = high;
  const double limit = kConstantTolerance * largest;
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 7; ++j) {
      if (std::abs(v[i][j] - v[i][0]) > limit) e.varies_phi = true;
      if (std::abs(v[i][j] - v[0][j]) > limit) e.varies_theta = true;
    }
  return e;
}

// Float pdfs of sharp lobes carry a relative rounding noise near 1e-4 (cos^n with n in the
// thousands), which no refinement removes; refining only until the parts agree with their
// parent to this relative level keeps the work bounded, and its effect on a count E (1e-5 E) stays
// far below the sqrt(E) scatter of the histogram.
constexpr double kRelativeTolerance = 1e-5;
// Error bound, relative to the cell, below which a rectangle is final (see integrateRect).
constexpr double kJumpFloor = 1e-7;
// Relative uncertainty allowed in the integral of the pdf over the sphere (see step 3).
constexpr double kNormalizationSlack = 1e-4;

// Adaptive refinement. A rectangle is final when it is constant (exact), when the spread of its
// probes times its solid angle bounds its error below `tolerance` or below `floor` (a fixed
// fraction of the whole cell, so that a jump line is followed only as deep as the cell's count
// needs), or, for smooth parts, when its estimate agrees with the sum over its parts (quarters, or
// halves across the one direction in which the pdf varies). That agreement is not trusted across a
// jump (one part constant, another not): Gauss rules of parent and parts can miss a step by the
// same amount, which left 2e-4 of a sharp cell's count behind. `quarterings` counts the quarter
// splits above this rectangle.
double integrateRect(const DirectionPdf& pdf, const Rect& r, const RectEstimate& whole, int depth, int quarterings,
                     double tolerance, double floor) {
  const bool past_minimum = depth >= kMinDepth;
  if (past_minimum && whole.constant()) return whole.integral;
  if (past_minimum && (whole.high - whole.low) * solidAngle(r) <= std::max(tolerance, floor)) return whole.integral;
  const bool split_theta = !past_minimum || whole.varies_theta;
  const bool split_phi = !past_minimum || whole.varies_phi;
  const bool quarters = split_theta && split_phi;
  const double tm = 0.5 * (r.theta0 + r.theta1), pm = 0.5 * (r.phi0 + r.phi1);
  std::array<Rect, 4> parts_rect;
  int count = 0;
  if (quarters) {
    parts_rect = {Rect{r.theta0, tm, r.phi0, pm}, Rect{r.theta0, tm, pm, r.phi1}, Rect{tm, r.theta1, r.phi0, pm},
                  Rect{tm, r.theta1, pm, r.phi1}};
    count = 4;
  } else if (split_theta) {
    parts_rect[0] = Rect{r.theta0, tm, r.phi0, r.phi1};
    parts_rect[1] = Rect{tm, r.theta1, r.phi0, r.phi1};
    count = 2;
  } else {
    parts_rect[0] = Rect{r.theta0, r.theta1, r.phi0, pm};
    parts_rect[1] = Rect{r.theta0, r.theta1, pm, r.phi1};
    count = 2;
  }
  std::array<RectEstimate, 4> parts;
  double fine = 0.0;
  int constant_parts = 0;
  for (int k = 0; k < count; ++k) {
    parts[k] = gaussRect(pdf, parts_rect[k]);
    fine += parts[k].integral;
    if (parts[k].constant()) ++constant_parts;
  }
  const bool jump = constant_parts > 0 && constant_parts < count;
  const double error = std::abs(fine - whole.integral);
  const int next_quarterings = quarterings + (quarters ? 1 : 0);
  const bool exhausted = depth >= kMaxDepth || (quarters && next_quarterings >= kMaxQuarterDepth);
  if (exhausted || (past_minimum && !jump && (error <= tolerance || error <= kRelativeTolerance * std::abs(fine))))
    return fine;
  // A half keeps most of the tolerance: along a jump line only one half goes on varying.
  const double part_tolerance = tolerance * (quarters ? 0.5 : 0.7);
  double sum = 0.0;
  for (int k = 0; k < count; ++k)
    sum += integrateRect(pdf, parts_rect[k], parts[k], depth + 1, next_quarterings, part_tolerance, floor);
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
    const RectEstimate cell = gaussRect(pdf, r);
    // Errors below 1e-7 of the cell's count are far below its sqrt(count) scatter.
    const double floor = kJumpFloor * std::abs(cell.integral);
    result.expected[k] = static_cast<double>(n) * integrateRect(pdf, r, cell, 0, 0, tolerance, floor);
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
