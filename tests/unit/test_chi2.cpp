// The chi-square goodness-of-fit harness: it must accept correct samplers and reject wrong ones.
// Every test uses fixed seeds, 20 x 40 cells and significance 0.01, so each outcome is
// deterministic; the draw counts are stated per test.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <numbers>
#include <numeric>

#include "btf/core/error.h"
#include "btf/sampling/chi2.h"
#include "btf/sampling/warp.h"

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
