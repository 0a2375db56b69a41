// The chi-square goodness-of-fit harness: it must accept correct samplers and reject wrong ones.
// Every test uses fixed seeds, 20 x 40 cells and significance 0.01, so each outcome is
// deterministic; the draw counts are stated per test.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <vector>

#include "btf/core/error.h"
#include "btf/sampling/chi2.h"
#include "btf/core/warp.h"

namespace {

const btf::DirectionSampler kCosineSampler = [](glm::vec2 u) {
  return std::optional(btf::squareToCosineHemisphere(u));
};
const btf::DirectionPdf kCosinePdf = [](const glm::vec3& w) { return double(btf::cosineHemispherePdf(w)); };

btf::DirectionSampler phongLobeSampler(float exponent) {
  return [exponent](glm::vec2 u) { return std::optional(btf::squareToCosinePowerHemisphere(u, exponent)); };
}
btf::DirectionPdf phongLobePdf(float exponent) {
  return [exponent](const glm::vec3& w) { return double(btf::cosinePowerHemispherePdf(w, exponent)); };
}

}  // namespace

TEST(Chi2, AcceptsACorrectSamplerAndReportsItsCells) {
  const btf::Chi2Options options;  // 1e6 draws
  const btf::Chi2Result r = btf::chi2Test(kCosineSampler, kCosinePdf, options);
  EXPECT_TRUE(r.accepted) << r.message << " (1e6 draws, alpha = 0.01)";
  EXPECT_GE(r.p_value, 0.01);
  EXPECT_EQ(r.sample_count, options.sample_count);
  EXPECT_EQ(r.failed_samples, 0u);
  ASSERT_EQ(r.observed.size(), std::size_t(options.theta_bins * options.phi_bins));
  ASSERT_EQ(r.expected.size(), r.observed.size());
  EXPECT_EQ(std::accumulate(r.observed.begin(), r.observed.end(), 0.0), double(options.sample_count));
  EXPECT_NEAR(std::accumulate(r.expected.begin(), r.expected.end(), 0.0), double(options.sample_count), 1.0);
  // The lower hemisphere expects nothing, so its 400 cells are pooled; the rest are tested.
  EXPECT_GE(r.pooled_cells, options.theta_bins * options.phi_bins / 2);
  EXPECT_GT(r.degrees_of_freedom, 300);
  EXPECT_NE(r.message.find("accepted"), std::string::npos) << r.message;
}

TEST(Chi2, RejectsCosineDrawsAgainstAUniformPdf) {
  const btf::Chi2Result r =
      btf::chi2Test(kCosineSampler, [](const glm::vec3& w) { return double(btf::uniformHemispherePdf(w)); });
  EXPECT_FALSE(r.accepted) << r.message << " (1e6 draws, alpha = 0.01)";
  EXPECT_LT(r.p_value, 1e-10);
  EXPECT_NE(r.message.find("rejected"), std::string::npos) << r.message;
}

TEST(Chi2, RejectsAPhongLobeWhosePdfExponentIs20PercentOff) {
  // Draws from cos^20, pdf claims cos^24: the lobes differ only slightly in width.
  const btf::Chi2Result right = btf::chi2Test(phongLobeSampler(20.0f), phongLobePdf(20.0f));
  const btf::Chi2Result wrong = btf::chi2Test(phongLobeSampler(20.0f), phongLobePdf(24.0f));
  EXPECT_TRUE(right.accepted) << right.message << " (1e6 draws, alpha = 0.01)";
  EXPECT_FALSE(wrong.accepted) << wrong.message << " (1e6 draws, alpha = 0.01)";
}

TEST(Chi2, RejectsAPdfThatIsZeroWhereASampleLanded) {
  // Uniform sphere draws, hemisphere pdf: the first draw below the horizon fails the test at once.
  const btf::Chi2Result r = btf::chi2Test([](glm::vec2 u) { return std::optional(btf::squareToUniformSphere(u)); },
                                          [](const glm::vec3& w) { return double(btf::uniformHemispherePdf(w)); });
  EXPECT_FALSE(r.accepted);
  EXPECT_NE(r.message.find("pdf 0"), std::string::npos) << r.message;
}

TEST(Chi2, RejectsADirectionThatIsNotAUnitVector) {
  const btf::Chi2Result r = btf::chi2Test([](glm::vec2) { return std::optional(glm::vec3(0.0f, 0.0f, 2.0f)); },
                                          kCosinePdf);
  EXPECT_FALSE(r.accepted);
  EXPECT_NE(r.message.find("not a finite unit vector"), std::string::npos) << r.message;
}

// A sampler that returns nothing for 30% of the draws and is uniform on the hemisphere otherwise.
const btf::DirectionSampler kLossySampler = [](glm::vec2 u) -> std::optional<glm::vec3> {
  if (u.x < 0.3f) return std::nullopt;
  return btf::squareToUniformHemisphere({(u.x - 0.3f) / 0.7f, u.y});
};

TEST(Chi2, AcceptsDrawsWithoutDirectionWhenThePdfIntegratesToTheirComplement) {
  const btf::Chi2Result r =
      btf::chi2Test(kLossySampler, [](const glm::vec3& w) { return 0.7 * btf::uniformHemispherePdf(w); });
  EXPECT_TRUE(r.accepted) << r.message << " (1e6 draws, alpha = 0.01)";
  EXPECT_NEAR(double(r.failed_samples), 0.3e6, 5 * std::sqrt(0.3 * 0.7 * 1e6));
}

TEST(Chi2, RejectsAPdfThatIgnoresTheDrawsWithoutDirection) {
  // The right shape but normalized to 1: every cell expects 1/0.7 times too many draws.
  const btf::Chi2Result r =
      btf::chi2Test(kLossySampler, [](const glm::vec3& w) { return double(btf::uniformHemispherePdf(w)); });
  EXPECT_FALSE(r.accepted) << r.message << " (1e6 draws, alpha = 0.01)";
}

TEST(Chi2, IsDeterministicForASeedAndChangesWithIt) {
  btf::Chi2Options options;
  options.sample_count = 200'000;
  const btf::Chi2Result a = btf::chi2Test(kCosineSampler, kCosinePdf, options);
  const btf::Chi2Result b = btf::chi2Test(kCosineSampler, kCosinePdf, options);
  options.seed = 2;
  const btf::Chi2Result c = btf::chi2Test(kCosineSampler, kCosinePdf, options);
  EXPECT_EQ(a.observed, b.observed);
  EXPECT_EQ(a.statistic, b.statistic);
  EXPECT_NE(a.observed, c.observed);
}

TEST(Chi2, DoesNotDependOnTheThreadCount) {
  btf::Chi2Options options;
  options.sample_count = 200'000;
  btf::Chi2Result one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = btf::chi2Test(kCosineSampler, kCosinePdf, options);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = btf::chi2Test(kCosineSampler, kCosinePdf, options);
  }
  EXPECT_EQ(one.observed, two.observed);
  EXPECT_EQ(one.expected, two.expected);
  EXPECT_EQ(one.statistic, two.statistic);
}

TEST(Chi2, RejectsTooFewDrawsForTheCells) {
  btf::Chi2Options options;
  options.sample_count = 10;  // 800 cells, each expecting far fewer than 5 draws
  const btf::Chi2Result r = btf::chi2Test(kCosineSampler, kCosinePdf, options);
  EXPECT_FALSE(r.accepted);
  EXPECT_NE(r.message.find("fewer than two cells"), std::string::npos) << r.message;
}

TEST(Chi2, ThrowsOnInvalidOptions) {
  btf::Chi2Options options;
  options.theta_bins = 0;
  EXPECT_THROW(btf::chi2Test(kCosineSampler, kCosinePdf, options), btf::Error);
  options = {};
  options.significance = 1.5;
  EXPECT_THROW(btf::chi2Test(kCosineSampler, kCosinePdf, options), btf::Error);
  options = {};
  options.sample_count = 0;
  EXPECT_THROW(btf::chi2Test(kCosineSampler, kCosinePdf, options), btf::Error);
}

namespace {

// A density constant on each cell of a 64 x 128 grid over (cos theta, phi) of the upper hemisphere,
// as the tabulated samplers' densities are, with a near-mirror lobe: 15 cells hold most of the
// mass and their values jump by up to 4 orders of magnitude. The grid lines do not coincide with
// the harness's 20 x 40 cells, so jumps cross the cells. `peak` scales the two brightest cells.
struct GridDensity {
  static constexpr int kRows = 64, kCols = 128;
  std::vector<double> value, cdf;  // per cell, row-major; cdf over cells
  double total = 0;

  explicit GridDensity(double peak = 3e4) {
    value.assign(kRows * kCols, 1.0);
    for (int i = 54; i <= 56; ++i)
      for (int j : {126, 127, 0, 1, 2}) value[i * kCols + j] = (i == 55 && (j == 0 || j == 127)) ? peak : 3e3;
    cdf.assign(value.size() + 1, 0.0);
    for (std::size_t k = 0; k < value.size(); ++k) cdf[k + 1] = cdf[k] + value[k];
    total = cdf.back();
  }
  std::optional<glm::vec3> sample(glm::vec2 u) const {
    const double x = double(u.x) * total;
    const std::size_t k = std::min<std::size_t>(value.size() - 1, std::upper_bound(cdf.begin(), cdf.end(), x) - cdf.begin() - 1);
    const double frac = std::clamp((x - cdf[k]) / value[k], 0.0, 1.0);
    const double s = (double(k / kCols) + frac) / kRows, t = (double(k % kCols) + double(u.y)) / kCols;
    const double r = std::sqrt(std::max(0.0, 1.0 - s * s)), phi = 2.0 * std::numbers::pi * t;
    return glm::vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(s));
  }
  double pdf(const glm::vec3& w) const {
    if (w.z <= 0.0f) return 0.0;
    double t = std::atan2(double(w.y), double(w.x)) / (2.0 * std::numbers::pi);
    if (t < 0.0) t += 1.0;
    const int i = std::min(kRows - 1, int(double(w.z) * kRows)), j = std::min(kCols - 1, int(t * kCols));
    return value[i * kCols + j] / total * (kRows * kCols) / (2.0 * std::numbers::pi);
  }
  // Exact probability of the harness cell [z0, z1] x [t0, t1] (t = phi / 2 pi): sum of overlaps.
  double cellProbability(double z0, double z1, double t0, double t1) const {
    double p = 0.0;
    for (int i = 0; i < kRows; ++i) {
      const double ds = std::min(z1, (i + 1.0) / kRows) - std::max(z0, double(i) / kRows);
      if (ds <= 0.0) continue;
      for (int j = 0; j < kCols; ++j) {
        const double dt = std::min(t1, (j + 1.0) / kCols) - std::max(t0, double(j) / kCols);
        if (dt > 0.0) p += value[i * kCols + j] / total * (kRows * kCols) * ds * dt;
      }
    }
    return p;
  }
};

}  // namespace

// Regression: the harness integrated every cell by Gauss rules refined into quarters to a fixed
// depth, which left errors far above a hundredth of a draw in cells crossed by the jumps of a sharp
// piecewise-constant density, and it rejected this correct sampler at 1e6 draws (seed 1); a wrong sampler
// gets worse with more draws, a quadrature error does too, so the counts are checked directly.
TEST(Chi2, IntegratesASharpPiecewiseConstantDensityExactlyAndAcceptsItsSampler) {
  const GridDensity grid;
  btf::Chi2Options options;  // 20 x 40 cells, 1e6 draws, alpha = 0.01
  const btf::Chi2Result r = btf::chi2Test([&](glm::vec2 u) { return grid.sample(u); },
                                          [&](const glm::vec3& w) { return grid.pdf(w); }, options);
  EXPECT_TRUE(r.accepted) << r.message << " (1e6 draws, alpha = 0.01)";
  ASSERT_EQ(r.expected.size(), std::size_t(options.theta_bins * options.phi_bins));
  double worst = 0.0;
  for (int row = 0; row < options.theta_bins / 2; ++row)  // the upper hemisphere
    for (int col = 0; col < options.phi_bins; ++col) {
      const double z1 = 1.0 - 2.0 * row / options.theta_bins, z0 = 1.0 - 2.0 * (row + 1) / options.theta_bins;
      const double exact = double(options.sample_count) *
                           grid.cellProbability(z0, z1, double(col) / options.phi_bins, (col + 1.0) / options.phi_bins);
      const double computed = r.expected[row * options.phi_bins + col];
      // Within 1e-5 of the count or a hundredth of a draw; the old integration missed by far more.
      EXPECT_NEAR(computed, exact, std::max(1e-5 * exact, 0.01)) << "cell " << row << ", " << col;
      worst = std::max(worst, std::abs(computed - exact) / exact);
    }
  RecordProperty("worst_relative_error", std::to_string(worst));
}

TEST(Chi2, RejectsAPiecewiseConstantDensityWhosePeakIs5PercentOff) {
  // Draws from the grid, pdf claims peak cells 5% dimmer (renormalized): the adaptive refinement
  // that makes constant cells exact must not blunt the test.
  const GridDensity drawn, claimed(0.95 * 3e4);
  const btf::Chi2Result r = btf::chi2Test([&](glm::vec2 u) { return drawn.sample(u); },
                                          [&](const glm::vec3& w) { return claimed.pdf(w); });
  EXPECT_FALSE(r.accepted) << r.message << " (1e6 draws, alpha = 0.01)";
}
