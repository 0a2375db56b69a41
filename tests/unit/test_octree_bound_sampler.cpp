// The octree-bound sampler (sampling/octree_bound_sampler.h): its bound holds for every lookup of
// lossless and lossy trees, its exact mode passes chi-square (alpha = 0.01, 300,000 draws per test,
// 20 x 40 cells) with sample() and pdf() agreeing bit for bit and weights within 4 Z, and its
// rejection mode draws luminance(f) cos exactly (on a Lambertian table, where that density is
// known) at the acceptance rate the bound implies (albedo / (4 Z), on glossy tables).
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "support/tier.h"
#include "btf/compress/octree_table.h"
#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/rng.h"
#include "btf/material/ggx.h"
#include "btf/material/lambert.h"
#include "btf/material/octree_brdf.h"
#include "btf/material/rgl_brdf.h"
#include "btf/material/tabulated_brdf.h"
#include "btf/sampling/chi2.h"
#include "btf/sampling/octree_bound_sampler.h"
#include "btf/core/warp.h"
#include "support/test_support.h"

namespace btf {
namespace {

using ::testing::HasSubstr;

struct Case {
  const char* label;
  std::shared_ptr<const OctreeBrdf> material;
};

std::shared_ptr<const OctreeBrdf> octreeOf(const Material& m, double tolerance, TableLookup lookup) {
  const MerlTable table = tabulate(m);
  return std::make_shared<OctreeBrdf>(std::make_shared<OctreeTable>(OctreeTable::build(table, tolerance)), lookup);
}

// Diffuse, plastic and near-mirror tables, lossless and lossy, both lookups.
const std::vector<Case>& cases() {
  static const std::vector<Case> c = [] {
    const Lambert lambert(Rgb(0.5f, 0.6f, 0.7f));
    const Ggx plastic(Rgb(0.3f, 0.1f, 0.1f), Rgb(0.04f), 0.1f, 0.1f);
    const Ggx mirror(Rgb(0.0f), Rgb(0.9f, 0.7f, 0.5f), 0.03f, 0.03f);
    return std::vector<Case>{
        {"lambert t=0 interpolated", octreeOf(lambert, 0.0, TableLookup::Interpolated)},
        {"plastic t=0 interpolated", octreeOf(plastic, 0.0, TableLookup::Interpolated)},
        {"plastic t=0.05 nearest", octreeOf(plastic, 0.05, TableLookup::Nearest)},
        {"near-mirror t=0.02 interpolated", octreeOf(mirror, 0.02, TableLookup::Interpolated)},
    };
  }();
  return c;
}

float maxChannel(Rgb f) { return std::max({f.r, f.g, f.b}); }

TEST(OctreeBoundSampler, TheBoundHoldsForEveryChannelAtRandomPairs) {
  Rng rng(5);
  // Besides the generated tables, a measured one with spikes at grazing angles (the RGL file's
  // values tabulated into the MERL layout), where a bound that ignored phi_d would be far looser
  // and one that cut corners would be broken.
  std::vector<Case> all = cases();
  const RglBrdf measured(test::sharedDataDir() / "rgl_bsdf" / "cc_ibiza_sunset_rgb.bsdf");
  all.push_back({"cc_ibiza_sunset t=0.02 interpolated", octreeOf(measured, 0.02, TableLookup::Interpolated)});
  for (const Case& c : all) {
    const OctreeBoundSampler sampler(c.material, 45);
    int violations = 0;
    for (int n = 0; n < 200'000; ++n) {
      const glm::vec3 wo = squareToUniformHemisphere(rng.uniform2D());
      const glm::vec3 wi = squareToUniformHemisphere(rng.uniform2D());
      // The bound the sampler uses for this pair, from its exact pdf: pdf = (B / Z) / (4 wo.h).
      const glm::vec3 h = glm::normalize(wi + wo);
      const float cos_d = glm::dot(wo, h);
      const double b = double(sampler.pdf(wi, wo)) * 4.0 * cos_d * sampler.normalization(sampler.thetaOBin(wo));
      const double value = double(maxChannel(c.material->eval(wi, wo))) * cos_d;
      // Every pair above the horizon is a reflection about its h, so b == 0 must mean f == 0.
      if (value > b * (1 + 1e-4)) ++violations;
    }
    EXPECT_EQ(violations, 0) << c.label;
  }
}

BTF_STATISTICAL_TEST(OctreeBoundSampler, ExactModeChiSquareAccepts) {
  for (const Case& c : cases()) {
    const OctreeBoundSampler sampler(c.material);
    for (const float theta_deg : {0.0f, 33.0f, 62.0f, 81.0f}) {
      const glm::vec3 wo = sphericalDirection(glm::radians(theta_deg), 0.7f);
      Chi2Options options;
      options.sample_count = 300'000;
      const Chi2Result r = chi2TestMaterial(sampler, wo, {}, options);
      EXPECT_TRUE(r.accepted) << c.label << " theta_o " << theta_deg << ": " << r.message;
      std::printf("[ chi2     ] %-32s theta_o %2.0f: p = %.4f (%llu without a direction)\n", c.label, theta_deg,
                  r.p_value, static_cast<unsigned long long>(r.failed_samples));
    }
  }
}

TEST(OctreeBoundSampler, SampleAgreesWithPdfAndWeightsStayWithinFourZ) {
  for (const Case& c : cases()) {
    const OctreeBoundSampler sampler(c.material);
    for (const float theta_deg : {0.0f, 33.0f, 62.0f, 81.0f}) {
      const glm::vec3 wo = sphericalDirection(glm::radians(theta_deg), 0.7f);
      // sample() returns pdf() of its draw, the weight is f cos / pdf, and no weight exceeds 4 Z.
      const double z = sampler.normalization(sampler.thetaOBin(wo));
      Rng rng(11);
      for (int n = 0; n < 20'000; ++n) {
        const auto s = sampler.sample(wo, {}, rng.uniform2D());
        if (!s) continue;
        ASSERT_EQ(s->pdf, sampler.pdf(s->wi, wo)) << c.label;
        const Rgb f = sampler.eval(s->wi, wo);
        ASSERT_EQ(s->weight.g, f.g * (s->wi.z / s->pdf));
        ASSERT_LE(maxChannel(s->weight), 4 * z * (1 + 1e-4)) << c.label << " theta_o " << theta_deg;
      }
    }
  }
}

BTF_STATISTICAL_TEST(OctreeBoundSampler, RejectionModeChiSquareAcceptsOnALambertianTable) {
  const OctreeBoundSampler sampler(cases()[0].material);
  for (const float theta_deg : {10.0f, 70.0f}) {
    const glm::vec3 wo = sphericalDirection(glm::radians(theta_deg), 0.2f);
    // Each draw gets its own stream from the harness's u, so the test stays a function of u.
    const DirectionSampler draw = [&](glm::vec2 u) -> std::optional<glm::vec3> {
      Rng rng(std::uint64_t(u.x * 0x1p24f) * 0x1000000ull + std::uint64_t(u.y * 0x1p24f), 3);
      int tries = 0;
      return sampler.sampleByRejection(wo, rng, 1000, tries);
    };
    const DirectionPdf cosine = [](const glm::vec3& w) { return w.z > 0 ? double(w.z) / kPi : 0.0; };
    Chi2Options options;
    options.sample_count = 300'000;
    const Chi2Result r = chi2Test(draw, cosine, options);
    EXPECT_TRUE(r.accepted) << "theta_o " << theta_deg << ": " << r.message;
    EXPECT_EQ(r.failed_samples, 0u);
  }
}

BTF_STATISTICAL_TEST(OctreeBoundSampler, AlbedoAcceptanceIsTheAlbedoOverFourZ) {
  // E[accept] = (1/Z) int lum f cos_i cos_d d omega_h = albedo_lum / (4 Z); albedo_lum from the
  // exact mode's weights. Both sides estimated from 200,000 draws; 5 standard errors apart at most.
  for (const Case& c : cases()) {
    const OctreeBoundSampler sampler(c.material);
    const glm::vec3 wo = sphericalDirection(glm::radians(40.0f), 1.1f);
    Rng rng(17);
    double weight_sum = 0, weight_sq = 0;
    const int n = 200'000;
    for (int k = 0; k < n; ++k) {
      const auto s = sampler.sample(wo, {}, rng.uniform2D());
      if (!s) continue;
      const double w = s->weight.luminance();
      weight_sum += w, weight_sq += w * w;
    }
    const double z = sampler.normalization(sampler.thetaOBin(wo));
    const double albedo = weight_sum / n, albedo_se = std::sqrt((weight_sq / n - albedo * albedo) / n);
    Rng rrng(23);
    std::uint64_t accepted = 0, proposals = 0;
    for (int k = 0; k < n; ++k) {
      int tries = 0;
      if (sampler.sampleByRejection(wo, rrng, 1, tries)) ++accepted;
      proposals += std::uint64_t(tries);
    }
    const double a = double(accepted) / double(proposals), a_se = std::sqrt(a * (1 - a) / double(proposals));
    const double expected = albedo / (4 * z), expected_se = albedo_se / (4 * z);
    std::printf("[ accept   ] %-32s acceptance %.4f, albedo / 4Z %.4f\n", c.label, a, expected);
    EXPECT_NEAR(a, expected, 5 * std::hypot(a_se, expected_se)) << c.label;
  }
}

TEST(OctreeBoundSampler, TablesDoNotDependOnTheThreadCount) {
  const OctreeBoundSampler parallel(cases()[1].material, 30);
  std::unique_ptr<OctreeBoundSampler> serial;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    serial = std::make_unique<OctreeBoundSampler>(cases()[1].material, 30);
  }
  for (int b = 0; b < 30; ++b) {
    EXPECT_EQ(parallel.normalization(b), serial->normalization(b));
    for (int i = 0; i < OctreeBoundSampler::kSlabs; ++i) ASSERT_EQ(parallel.bound(b, i), serial->bound(b, i));
  }
}

TEST(OctreeBoundSampler, RefusesWhatItCannotSample) {
  EXPECT_THROW(OctreeBoundSampler(nullptr), Error);
  EXPECT_THROW(OctreeBoundSampler(cases()[0].material, 0), Error);
  const Lambert black(Rgb(0.0f));
  try {
    OctreeBoundSampler sampler(octreeOf(black, 0.0, TableLookup::Interpolated));
    ADD_FAILURE() << "a table of zeros was accepted";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("no measured cell with f > 0"));
  }
  const OctreeBoundSampler sampler(cases()[1].material);
  EXPECT_FALSE(sampler.sample(glm::vec3(0, 0, -1), {}, {0.5f, 0.5f}).has_value());
  EXPECT_EQ(sampler.pdf(glm::vec3(0, 0, 1), glm::vec3(0, 0, -1)), 0.0f);
}

}  // namespace
}  // namespace btf
