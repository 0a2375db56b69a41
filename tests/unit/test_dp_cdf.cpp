// Douglas-Peucker and fewest-vertex reduction of 1D CDFs (dp_cdf.h): tolerance kept, vertex
// counts ordered, extreme tolerances, sampling and pdf of the reduced polyline; the sampler's
// compact storage.
#include <gtest/gtest.h>

#include <vector>

#include "btf/core/error.h"
#include "btf/core/rng.h"
#include "btf/core/cdf1d.h"
#include "btf/core/dp_cdf.h"
#include "btf/sampling/dp_cdf_sampler.h"
#include "btf/core/warp.h"
#include "sampler_test_materials.h"

namespace {

// A peaked function over 256 cells with noise: a CDF with long flat runs and one steep climb.
std::vector<float> peakedCdf(std::uint64_t seed) {
  btf::Rng rng(seed);
  std::vector<float> f(256), cdf(257);
  for (std::size_t i = 0; i < f.size(); ++i) {
    const float x = (float(i) + 0.5f) / 256.0f - 0.6f;
    f[i] = 0.05f * rng.uniform() + std::exp(-x * x / 0.0008f);
  }
  btf::buildCdf1D(f, cdf);
  return cdf;
}

}  // namespace

TEST(DpCdf, BothReductionsStayWithinEpsilonAndFewestNeverKeepsMore) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const std::vector<float> cdf = peakedCdf(seed);
    for (float eps : {1e-4f, 1e-3f, 1e-2f, 0.1f}) {
      std::vector<btf::CdfVertex> dp, fewest;
      const std::size_t n_dp = btf::reduceCdf(cdf, eps, btf::CdfReduction::DouglasPeucker, dp);
      const std::size_t n_fewest = btf::reduceCdf(cdf, eps, btf::CdfReduction::Fewest, fewest);
      EXPECT_LE(btf::cdfDeviation(cdf, dp), eps * (1 + 1e-5) + 1e-7) << "eps " << eps;
      EXPECT_LE(btf::cdfDeviation(cdf, fewest), eps * (1 + 1e-5) + 1e-7) << "eps " << eps;
      EXPECT_LE(n_fewest, n_dp) << "eps " << eps;
      EXPECT_LT(n_dp, cdf.size()) << "eps " << eps;
      EXPECT_EQ(dp.front().cdf, 0.0f);
      EXPECT_EQ(dp.back().cdf, 1.0f);
    }
  }
}

TEST(DpCdf, ZeroEpsilonKeepsTheCurveAndHugeEpsilonKeepsOnlyEndpoints) {
  const std::vector<float> cdf = peakedCdf(7);
  std::vector<btf::CdfVertex> exact, endpoints;
  btf::reduceCdf(cdf, 0.0f, btf::CdfReduction::DouglasPeucker, exact);
  EXPECT_LE(btf::cdfDeviation(cdf, exact), 1e-7);
  EXPECT_EQ(btf::reduceCdf(cdf, 5.0f, btf::CdfReduction::DouglasPeucker, endpoints), 2u);
  EXPECT_FLOAT_EQ(btf::pdfVertexCdf(endpoints, 0.3f), 1.0f);  // uniform
  // A constant function: a straight CDF collapses to its endpoints even at epsilon 0.
  std::vector<float> line(65);
  for (std::size_t k = 0; k < line.size(); ++k) line[k] = float(k) / 64.0f;
  std::vector<btf::CdfVertex> collapsed;
  EXPECT_EQ(btf::reduceCdf(line, 0.0f, btf::CdfReduction::Fewest, collapsed), 2u);
}

TEST(DpCdf, SampleInvertsTheReducedPolylineAndPdfIsItsSlope) {
  const std::vector<float> cdf = peakedCdf(11);
  std::vector<btf::CdfVertex> v;
  btf::reduceCdf(cdf, 2e-3f, btf::CdfReduction::DouglasPeucker, v);
  btf::Rng rng(5);
  for (int k = 0; k < 10'000; ++k) {
    const float u = rng.uniform();
    const btf::VertexCdfSample s = btf::sampleVertexCdf(v, u);
    ASSERT_GE(s.x, v[s.segment].x);
    ASSERT_LT(s.x, v[s.segment + 1].x);
    ASSERT_EQ(s.pdf, btf::pdfVertexCdf(v, s.x));
    // The polyline's value at x is u (inversion), to float precision.
    const btf::CdfVertex a = v[s.segment];
    ASSERT_NEAR(a.cdf + (s.x - a.x) * s.pdf, u, 2e-5f);
  }
  EXPECT_EQ(btf::pdfVertexCdf(v, -0.1f), 0.0f);
  EXPECT_EQ(btf::pdfVertexCdf(v, 1.1f), 0.0f);
}

TEST(DpCdf, RejectsNegativeOrNanEpsilon) {
  const std::vector<float> cdf = peakedCdf(1);
  std::vector<btf::CdfVertex> v;
  EXPECT_THROW(btf::reduceCdf(cdf, -1.0f, btf::CdfReduction::DouglasPeucker, v), btf::Error);
  EXPECT_THROW(btf::reduceCdf(cdf, std::nanf(""), btf::CdfReduction::Fewest, v), btf::Error);
}

// The sampler's compact storage (dp_cdf_sampler.h): 16-bit CDF values from kNarrowEpsilon on,
// with the deviation measured on what is stored (within epsilon + half a quantum), floats below;
// sample()'s pdf (its shortcut or pdf()'s path) equals pdf() of the drawn direction on every draw,
// on an isotropic and an anisotropic material.
TEST(DpCdfSampler, StoredCdfsStayWithinEpsilonPlusHalfAQuantumAndSamplePdfIsPdf) {
  const auto& mats = btf::test::samplerTestMaterials();
  for (std::size_t m : {std::size_t(2), std::size_t(3)}) {
    for (float eps : {1e-4f, 1e-3f, 1e-2f}) {
      btf::SamplerOptions o = btf::test::coarseSamplerOptions();
      o.epsilon = eps;
      const btf::DpCdfSampler s(mats[m].material, o);
      EXPECT_EQ(s.cdfQuantum() > 0.0, eps >= btf::DpCdfSampler::kNarrowEpsilon) << "eps " << eps;
      EXPECT_LE(s.maxCdfDeviation(), eps + s.cdfQuantum() / 2 + 1e-6) << mats[m].label << " eps " << eps;
      btf::Rng rng(3);
      for (int k = 0; k < 5000; ++k) {
        const glm::vec3 wo = btf::squareToUniformHemisphere(rng.uniform2D());
        const auto d = s.sample(wo, {}, rng.uniform2D());
        ASSERT_TRUE(d);
        ASSERT_EQ(d->pdf, s.pdf(d->wi, wo)) << mats[m].label << " eps " << eps;
      }
    }
  }
}
