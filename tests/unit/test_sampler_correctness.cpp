// Correctness of the tabulated samplers (reference tables, DP-CDFs at several epsilon, quadtree;
// over the incident direction and, for one setting of each, over the half vector): the
// chi-square harness accepts each on six materials from Lambert to a near-mirror GGX
// (anisotropic Ward and a MERL-layout table included), at a near-normal or a grazing view (they
// alternate over materials and samplers, so each sampler meets both); the pdf integrates to 1
// within 1% (half-vector tables: to 1 minus the fraction of draws lost below the horizon);
// sample() and pdf() agree on every draw.
// Significance: the 49 chi-square tests of this file form one family with family-wise
// alpha = 0.01 (Sidak: each test uses 1 - 0.99^(1/49) = 2.1e-4), so that a correct sampler fails
// somewhere in the file with probability 1%, not 1 - 0.99^49 = 39%. p-values are printed; a wrong
// normalization or a misplaced lobe gives p < 1e-10. 40 x 40 cells, 100,000 draws per test, fixed
// seeds: every outcome is deterministic.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numeric>

#include "support/tier.h"
#include "btf/core/math.h"
#include "btf/core/rng.h"
#include "btf/sampling/chi2.h"
#include "sampler_test_materials.h"

namespace {

struct SamplerConfig {
  std::string label;
  btf::SamplerKind kind;
  float epsilon = 1e-3f;
  btf::CdfReduction reduction = btf::CdfReduction::DouglasPeucker;
  btf::Parameterization parameterization = btf::Parameterization::Incident;
};

const std::vector<SamplerConfig> kConfigs = {
    {"tabulated", btf::SamplerKind::Tabulated},
    {"dp_eps1e-3", btf::SamplerKind::DpCdf, 1e-3f},
    {"dp_fewest_eps1e-2", btf::SamplerKind::DpCdf, 1e-2f, btf::CdfReduction::Fewest},
    {"dp_eps0.2", btf::SamplerKind::DpCdf, 0.2f},
    {"quadtree", btf::SamplerKind::Quadtree},
    {"half_tabulated", btf::SamplerKind::Tabulated, 1e-3f, btf::CdfReduction::Fewest, btf::Parameterization::Half},
    {"half_dp_eps1e-3", btf::SamplerKind::DpCdf, 1e-3f, btf::CdfReduction::Fewest, btf::Parameterization::Half},
    {"half_quadtree", btf::SamplerKind::Quadtree, 1e-3f, btf::CdfReduction::Fewest, btf::Parameterization::Half},
};

struct Case {
  std::size_t material;
  std::size_t config;
};

std::string caseName(const testing::TestParamInfo<Case>& info) {
  std::string s = btf::test::samplerTestMaterials()[info.param.material].label + "_" + kConfigs[info.param.config].label;
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return s;
}

std::vector<Case> allCases() {
  std::vector<Case> cases;
  for (std::size_t m = 0; m < 6; ++m)
    for (std::size_t c = 0; c < kConfigs.size(); ++c) cases.push_back({m, c});
  return cases;
}

class SamplerCorrectness : public testing::TestWithParam<Case> {
 protected:
  std::unique_ptr<btf::BinnedSampler> makeSampler() const {
    const SamplerConfig& config = kConfigs[GetParam().config];
    btf::SamplerOptions options = btf::test::coarseSamplerOptions(config.parameterization);
    options.epsilon = config.epsilon;
    options.reduction = config.reduction;
    return btf::makeSampler(config.kind, btf::test::samplerTestMaterials()[GetParam().material].material, options);
  }
};

constexpr int kChi2TestsInFile = 6 * 8 + 1;
const double kPerTestSignificance = 1.0 - std::pow(1.0 - 0.01, 1.0 / kChi2TestsInFile);

// A near-normal and a grazing view, off the theta_o bin centres. Isotropic materials are viewed
// at phi_o = 0 (see coarseSamplerOptions); the rotation about the normal is covered by the
// agreement test below and by RotatedViewOfAnIsotropicTable.
std::vector<glm::vec3> viewsFor(const btf::Material& m) {
  if (m.isAnisotropic()) return {btf::sphericalDirection(0.25f, 0.7f), btf::sphericalDirection(1.38f, 4.1f)};
  return {btf::sphericalDirection(0.25f, 0.0f), btf::sphericalDirection(1.38f, 0.0f)};
}
const std::vector<glm::vec3> kAgreementViews = {btf::sphericalDirection(0.25f, 0.7f), btf::sphericalDirection(0.95f, 2.3f),
                                                btf::sphericalDirection(1.38f, 4.1f)};

btf::Chi2Result runChi2(const btf::Material& sampler, const glm::vec3& wo, std::uint64_t seed) {
  btf::Chi2Options options;
  options.sample_count = 100'000;
  options.seed = seed;
  options.theta_bins = btf::test::kSamplerChi2ThetaBins;
  options.phi_bins = btf::test::kSamplerChi2PhiBins;
  options.significance = kPerTestSignificance;
  return btf::chi2TestMaterial(sampler, wo, {}, options);
}

BTF_STATISTICAL_TEST_P(SamplerCorrectness, ChiSquareAcceptsAndPdfIntegratesToOne) {
  const auto sampler = makeSampler();
  const std::size_t v = (GetParam().material + GetParam().config) % 2;
  const btf::Chi2Result r = runChi2(*sampler, viewsFor(*sampler)[v], 17 + v);
  EXPECT_TRUE(r.accepted) << sampler->name() << " view " << v << ": " << r.message;
  const double integral = std::accumulate(r.expected.begin(), r.expected.end(), 0.0) / double(r.sample_count);
  if (sampler->parameterization() == btf::Parameterization::Incident) {
    EXPECT_EQ(r.failed_samples, 0u) << sampler->name() << " view " << v;
    EXPECT_NEAR(integral, 1.0, 0.01) << sampler->name() << " view " << v;
  } else {
    // Half-vector tables lose the draws reflected below the horizon: the pdf integrates to the
    // probability of a direction, so the lost fraction is 1 - integral, within 4 standard errors
    // of a binomial count plus the quadrature's 1e-3.
    const double lost = double(r.failed_samples) / double(r.sample_count);
    const double se = std::sqrt(std::max(lost * (1.0 - lost), 1e-6) / double(r.sample_count));
    EXPECT_NEAR(lost, 1.0 - integral, 4.0 * se + 1e-3) << sampler->name() << " view " << v;
    EXPECT_LT(lost, 0.2) << sampler->name() << " view " << v;
  }
  std::printf("[ p-value ] %-45s view %zu: p = %.4f, int pdf = %.5f\n", sampler->name().c_str(), v, r.p_value,
              integral);
}

TEST_P(SamplerCorrectness, SampleAndPdfAgreeOnEveryDraw) {
  // Incident tables draw a direction every time; half-vector tables lose the draws whose
  // reflection falls below the horizon (a sizeable share at the grazing view of these coarse tables, 8
  // theta_o bins of 11 degrees: see binned_sampler.cpp, target()).
  const auto sampler = makeSampler();
  const bool half = sampler->parameterization() == btf::Parameterization::Half;
  btf::Rng rng(99);
  for (const glm::vec3& wo : kAgreementViews) {
    int lost = 0;
    for (int k = 0; k < 2000; ++k) {
      const std::optional<btf::BsdfSample> s = sampler->sample(wo, {}, rng.uniform2D());
      if (half && !s) {
        ++lost;
        continue;
      }
      ASSERT_TRUE(s) << sampler->name();
      ASSERT_GT(s->pdf, 0.0f);
      ASSERT_EQ(s->pdf, sampler->pdf(s->wi, wo)) << sampler->name() << " draw " << k;
      ASSERT_NEAR(glm::length(s->wi), 1.0f, 1e-5f);
      const btf::Rgb expected = sampler->eval(s->wi, wo) * (s->wi.z / s->pdf);
      ASSERT_EQ(s->weight, expected);
    }
    EXPECT_LE(lost, 400) << sampler->name() << " wo.z " << wo.z;
  }
}

INSTANTIATE_TEST_SUITE_P(AllMaterials, SamplerCorrectness, testing::ValuesIn(allCases()), caseName);

TEST(SamplerCorrectness, RotatedViewOfAnIsotropicTable) {
  // phi_o = 2.3: the bin's table is rotated about the normal; its jumps no longer align with the
  // chi-square cells, so this one test pays for the slower quadrature.
  const auto sampler = btf::makeSampler(btf::SamplerKind::DpCdf, btf::test::samplerTestMaterials()[5].material,
                                        btf::test::coarseSamplerOptions());
  const btf::Chi2Result r = runChi2(*sampler, btf::sphericalDirection(0.95f, 2.3f), 5);
  EXPECT_TRUE(r.accepted) << sampler->name() << ": " << r.message;
  std::printf("[ p-value ] %-45s rotated view: p = %.4f\n", sampler->name().c_str(), r.p_value);
}

TEST(SamplerCorrectness, EvalForwardsToTheWrappedMaterial) {
  const auto& m = btf::test::samplerTestMaterials()[3];
  const auto sampler = btf::makeSampler(btf::SamplerKind::DpCdf, m.material, btf::test::coarseSamplerOptions());
  const glm::vec3 wi = btf::sphericalDirection(0.6f, 1.0f), wo = btf::sphericalDirection(0.4f, 4.0f);
  EXPECT_EQ(sampler->eval(wi, wo), m.material->eval(wi, wo));
  EXPECT_TRUE(sampler->isAnisotropic());
  EXPECT_EQ(sampler->binCount(), 8u * 6u);
  EXPECT_NE(sampler->name().find("dp-cdf("), std::string::npos);
}

}  // namespace
