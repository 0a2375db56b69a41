// The half-vector parameterization of the tabulated samplers (sampling/parameterization.h): its
// map and inverse, its Jacobian, the choice between it and the incident one (Auto), and the
// samplers built on it over the shared RGL files (chi-square, sample/pdf agreement).
//
// Statistical tests use fixed seeds (deterministic outcomes); counts and levels are stated per test.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "support/tier.h"
#include "btf/core/math.h"
#include "btf/core/rng.h"
#include "btf/material/rgl_brdf.h"
#include "btf/sampling/binned_sampler.h"
#include "btf/sampling/chi2.h"
#include "sampler_test_materials.h"
#include "support/test_support.h"

namespace {

using btf::Parameterization;

float concentricRadius(glm::vec2 st) { return std::max(std::abs(2.0f * st.x - 1.0f), std::abs(2.0f * st.y - 1.0f)); }

TEST(HalfVectorMap, InverseRecoversTheSquarePointAndRadius) {
  // 100,000 random points, plus the centre's neighbourhood and the octant borders, where the map
  // switches branches: the inverse is within 2e-6 of the point (a few ulps of the square).
  btf::Rng rng(3);
  std::vector<glm::vec2> points = {{0.5f, 0.5f + 1e-6f}, {0.5f + 1e-6f, 0.5f}, {0.75f, 0.75f}, {0.25f, 0.75f},
                                   {0.25f, 0.25f},       {0.75f, 0.25f},       {0.999f, 0.5f}, {0.5f, 0.001f}};
  for (int i = 0; i < 100'000; ++i) points.push_back(rng.uniform2D());
  for (const glm::vec2 st : points) {
    const glm::vec3 h = btf::squareToHalfVector(st);
    ASSERT_NEAR(glm::length(h), 1.0f, 2e-6f) << st.x << " " << st.y;
    ASSERT_GE(h.z, 0.0f);
    const btf::HalfVectorSquare back = btf::halfVectorToSquare(h);
    ASSERT_NEAR(back.st.x, st.x, 2e-6f) << st.x << " " << st.y;
    ASSERT_NEAR(back.st.y, st.y, 2e-6f) << st.x << " " << st.y;
    ASSERT_NEAR(back.r, concentricRadius(st), 2e-6f) << st.x << " " << st.y;
  }
  EXPECT_EQ(btf::squareToHalfVector({0.5f, 0.5f}), glm::vec3(0.0f, 0.0f, 1.0f));
}

TEST(HalfVectorMap, JacobianIsFourPiRSquared) {
  // The solid angle of the small parallelogram spanned by the map's partial derivatives (central
  // differences, step 1e-3) against 4 pi r^2 at 2,000 random points away from the octant borders
  // and the centre (where the derivatives jump or vanish): within 1% (the step's error).
  btf::Rng rng(5);
  int checked = 0;
  while (checked < 2000) {
    const glm::vec2 st = rng.uniform2D();
    const float a = 2.0f * st.x - 1.0f, b = 2.0f * st.y - 1.0f;
    if (std::abs(std::abs(a) - std::abs(b)) < 0.01f || concentricRadius(st) < 0.05f || concentricRadius(st) > 0.99f)
      continue;
    constexpr float d = 1e-3f;
    const glm::vec3 hs = (btf::squareToHalfVector(st + glm::vec2(d, 0)) - btf::squareToHalfVector(st - glm::vec2(d, 0))) / (2 * d);
    const glm::vec3 ht = (btf::squareToHalfVector(st + glm::vec2(0, d)) - btf::squareToHalfVector(st - glm::vec2(0, d))) / (2 * d);
    const float r = concentricRadius(st);
    EXPECT_NEAR(glm::length(glm::cross(hs, ht)) / (4.0f * btf::kPi * r * r), 1.0f, 0.01f) << st.x << " " << st.y;
    ++checked;
  }
}

TEST(AutoParameterization, ChoosesByMeasuredVarianceAndIsDeterministic) {
  // A near-mirror GGX (alpha 0.02) needs the half vector: its incident tables spread the lobe
  // over a few cells. Whatever is chosen, it is the parameterization with the smaller measured
  // variance, and the same on a second build.
  const auto& materials = btf::test::samplerTestMaterials();
  for (const std::size_t m : {std::size_t(0), std::size_t(4)}) {
    btf::SamplerOptions options = btf::test::coarseSamplerOptions(Parameterization::Auto);
    const auto a = btf::makeSampler(btf::SamplerKind::DpCdf, materials[m].material, options);
    const auto b = btf::makeSampler(btf::SamplerKind::DpCdf, materials[m].material, options);
    const btf::SamplerStats s = a->stats();
    ASSERT_TRUE(std::isfinite(s.auto_variance_incident) && std::isfinite(s.auto_variance_half)) << materials[m].label;
    EXPECT_EQ(a->parameterization(), s.auto_variance_half < s.auto_variance_incident ? Parameterization::Half
                                                                                   : Parameterization::Incident);
    EXPECT_EQ(a->parameterization(), b->parameterization());
    EXPECT_EQ(s.auto_variance_half, b->stats().auto_variance_half);
    EXPECT_EQ(s.parameterization, std::string(btf::toString(a->parameterization())));
    std::printf("[ auto     ] %-24s incident %.4g half %.4g -> %s\n", materials[m].label.c_str(), s.auto_variance_incident,
                s.auto_variance_half, s.parameterization.c_str());
  }
  const btf::SamplerOptions options = btf::test::coarseSamplerOptions(Parameterization::Auto);
  EXPECT_EQ(btf::makeSampler(btf::SamplerKind::DpCdf, materials[4].material, options)->parameterization(),
            Parameterization::Half);
  // Given parameterizations are kept, with no measurement.
  const auto given = btf::makeSampler(btf::SamplerKind::Tabulated, materials[4].material,
                                      btf::test::coarseSamplerOptions(Parameterization::Incident));
  EXPECT_EQ(given->parameterization(), Parameterization::Incident);
  EXPECT_TRUE(std::isnan(given->stats().auto_variance_half));
}

TEST(AutoParameterization, NamesParseBothWays) {
  for (const Parameterization p : {Parameterization::Auto, Parameterization::Incident, Parameterization::Half})
    EXPECT_EQ(btf::parseParameterization(btf::toString(p)), p);
  EXPECT_FALSE(btf::parseParameterization("halfway").has_value());
}

// The shared RGL files with the library's default half-vector DP tables (128 x 128, 32 bins, eps
// 1e-3): chi-square at a near-normal and a grazing view (300,000 draws, 20 x 40 cells, alpha 0.01
// per test: 6 tests), sample() and pdf() agreeing on every draw.
class HalfVectorRgl : public testing::TestWithParam<std::string> {};

btf::SamplerOptions halfVectorOptions() {
  btf::SamplerOptions options;
  options.parameterization = Parameterization::Half;
  return options;
}

std::shared_ptr<const btf::Material> halfVectorDpSampler(const std::string& file, const btf::SamplerOptions& options) {
  const auto material = std::make_shared<btf::RglBrdf>(btf::test::sharedDataDir() / "rgl_bsdf" / (file + ".bsdf"));
  return btf::makeSampler(btf::SamplerKind::DpCdf, material, options);
}

BTF_STATISTICAL_TEST_P(HalfVectorRgl, ChiSquareAcceptsAndSampleAgreesWithPdf) {
  const btf::SamplerOptions options = halfVectorOptions();
  const auto sampler = halfVectorDpSampler(GetParam(), options);
  for (const float theta_deg : {12.0f, 80.0f}) {
    const glm::vec3 wo = btf::sphericalDirection(glm::radians(theta_deg), 0.4f);
    btf::Chi2Options chi2;
    chi2.sample_count = 300'000;
    const btf::Chi2Result r = btf::chi2TestMaterial(*sampler, wo, {}, chi2);
    EXPECT_TRUE(r.accepted) << GetParam() << " theta_o " << theta_deg << ": " << r.message;
    std::printf("[ chi2     ] %s half dp-cdf theta_o %.0f: p = %.4f (%llu draws, %llu without a direction)\n",
                GetParam().c_str(), theta_deg, r.p_value, static_cast<unsigned long long>(r.sample_count),
                static_cast<unsigned long long>(r.failed_samples));
    btf::Rng rng(21);
    for (int k = 0; k < 5000; ++k) {
      const auto s = sampler->sample(wo, {}, rng.uniform2D());
      if (!s) continue;
      ASSERT_EQ(s->pdf, sampler->pdf(s->wi, wo)) << GetParam() << " draw " << k;
    }
  }
}

// A bin's half-vector tables are made at its central wo; directions reflected below the horizon
// there but above it at a bin edge must keep mass, or queries near that edge draw them only by the
// defensive share (weights hundreds of times the mean on paper_white before both edges were
// consulted). Just inside both sides of every bin edge up to 80 degrees (grazing
// views beyond it are limited by the bin width instead), 50,000 draws each: no weight f cos / pdf
// above 100x the mean weight.
TEST_P(HalfVectorRgl, NoRunawayWeightsNearBinEdges) {
  const btf::SamplerOptions options = halfVectorOptions();
  const auto sampler = halfVectorDpSampler(GetParam(), options);
  for (int edge = 0; edge <= options.theta_o_bins; ++edge)
    for (const float side : {-0.02f, 0.02f}) {
      const float theta_deg = float(edge) * 90.0f / float(options.theta_o_bins) + side;
      if (theta_deg < 0.0f || theta_deg > 80.0f) continue;
      const glm::vec3 wo = btf::sphericalDirection(glm::radians(theta_deg), 0.0f);
      btf::Rng rng(7, std::uint64_t(edge));
      constexpr int kDraws = 50'000;
      double sum = 0, largest = 0;
      for (int k = 0; k < kDraws; ++k)
        if (const auto s = sampler->sample(wo, {}, rng.uniform2D())) {
          sum += s->weight.luminance();
          largest = std::max(largest, double(s->weight.luminance()));
        }
      EXPECT_LT(largest, 100.0 * sum / kDraws) << GetParam() << " theta_o " << theta_deg;
    }
}

INSTANTIATE_TEST_SUITE_P(SharedFiles, HalfVectorRgl,
                         testing::Values("cc_ibiza_sunset_rgb", "paper_white_rgb", "vch_golden_yellow_rgb"));

}  // namespace
