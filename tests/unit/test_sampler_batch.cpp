// The stream calls sampleDirections / pdfs (binned_sampler.h) against the single queries, bit for
// bit: the DP sampler's AVX2 lanes must give exactly what sampleDirection and pdf give, including
// the awkward queries (pole, grazing, below the horizon, NaN, u at the ends of [0, 1)), which the
// stream call hands to the scalar path.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "btf/core/error.h"
#include "btf/core/rng.h"
#include "btf/material/lambert.h"
#include "btf/sampling/dp_cdf_sampler.h"
#include "btf/sampling/warp.h"
#include "sampler_test_materials.h"

namespace btf {
namespace {

std::uint32_t bits(float v) { return std::bit_cast<std::uint32_t>(v); }

struct Queries {
  std::vector<glm::vec3> wo;
  std::vector<glm::vec2> u;
};

// Random queries plus the edge cases; n not a multiple of 8, so that the last block is partial.
Queries makeQueries(std::size_t n, std::uint64_t seed) {
  Rng rng(seed);
  Queries q;
  for (std::size_t i = 0; i < n; ++i) {
    glm::vec3 wo = squareToUniformHemisphere(rng.uniform2D());
    if (i % 7 == 3) wo = squareToCosineHemisphere(rng.uniform2D());
    q.wo.push_back(wo);
    q.u.push_back(rng.uniform2D());
  }
  const float nan = std::numeric_limits<float>::quiet_NaN(), below_one = std::nextafter(1.0f, 0.0f);
  const glm::vec3 grazing = glm::normalize(glm::vec3(1.0f, 0.3f, 1e-4f));
  const std::vector<std::pair<glm::vec3, glm::vec2>> edges = {
      {{0, 0, 1}, {0.5f, 0.5f}},       {grazing, {0.3f, 0.9f}},           {{0, 0, -1}, {0.5f, 0.5f}},
      {{1, 0, 0}, {0.2f, 0.2f}},       {{0.6f, 0.0f, 0.8f}, {0.0f, 0.0f}}, {{0.6f, 0.0f, 0.8f}, {below_one, below_one}},
      {{nan, 0, 1}, {0.5f, 0.5f}},     {{0, 0, 1}, {nan, 0.5f}},           {{0.6f, 0.0f, 0.8f}, {1.0f, 0.5f}},
      {{0.6f, 0.0f, 0.8f}, {-0.25f, 0.5f}}, {{0.0f, 0.6f, 0.8f}, {0.5f, 1.5f}}};
  for (const auto& [wo, u] : edges) q.wo.push_back(wo), q.u.push_back(u);
  return q;
}

// Streams vs single queries over the queries, their draws and random wi (some below the horizon).
void expectStreamsMatchSingleQueries(const BinnedSampler& s, const Queries& q) {
  std::vector<BinnedSampler::DirectionSample> out(q.wo.size());
  s.sampleDirections(q.wo, q.u, out);
  std::vector<glm::vec3> wi(q.wo.size()), wo_for_pdf = q.wo;
  Rng rng(99);
  std::size_t drawn = 0;
  for (std::size_t i = 0; i < q.wo.size(); ++i) {
    int tries = 0;
    const auto d = s.sampleDirection(q.wo[i], q.u[i], tries);
    ASSERT_EQ(d.has_value(), out[i].pdf > 0.0f) << s.name() << " query " << i;
    if (d) {
      ++drawn;
      ASSERT_EQ(bits(d->wi.x), bits(out[i].wi.x)) << s.name() << " query " << i;
      ASSERT_EQ(bits(d->wi.y), bits(out[i].wi.y)) << s.name() << " query " << i;
      ASSERT_EQ(bits(d->wi.z), bits(out[i].wi.z)) << s.name() << " query " << i;
      ASSERT_EQ(bits(d->pdf), bits(out[i].pdf)) << s.name() << " query " << i;
      wi[i] = d->wi;
    } else {
      ASSERT_EQ(out[i].wi, glm::vec3(0.0f));
      wi[i] = squareToUniformSphere(rng.uniform2D());
    }
    if (i % 5 == 4) wi[i] = squareToUniformSphere(rng.uniform2D());
  }
  EXPECT_GT(drawn, q.wo.size() / 2) << s.name();
  std::vector<float> p(wi.size());
  s.pdfs(wi, wo_for_pdf, p);
  for (std::size_t i = 0; i < wi.size(); ++i) {
    ASSERT_EQ(bits(s.pdf(wi[i], wo_for_pdf[i])), bits(p[i])) << s.name() << " pdf query " << i;
  }
}

TEST(SamplerStreams, DpSamplerLanesGiveTheSingleQueriesBitForBit) {
  const Queries q = makeQueries(4003, 5);
  for (const test::NamedMaterial& m : test::samplerTestMaterials()) {
    for (float epsilon : {1e-3f, 1e-2f, 0.3f}) {
      SamplerOptions o = test::coarseSamplerOptions();
      o.cos_theta_bins = 32, o.phi_bins = 64, o.theta_o_bins = 16;
      o.epsilon = epsilon;
      const DpCdfSampler s(m.material, o);
      std::string trace = m.label;
      trace += s.vectorized() ? " (lanes) eps " : " (loop) eps ";
      trace += std::to_string(epsilon);
      SCOPED_TRACE(trace);
      expectStreamsMatchSingleQueries(s, q);
      // The lanes serve isotropic materials with 16-bit CDFs; on an AVX2 machine they must be in use.
      if (__builtin_cpu_supports("avx2")) {
        EXPECT_EQ(s.vectorized(), !m.material->isAnisotropic());
      }
    }
  }
}

TEST(SamplerStreams, WideKeysAndOtherSamplersFallBackToTheLoop) {
  const Queries q = makeQueries(517, 6);
  const auto& m = test::samplerTestMaterials()[2].material;
  SamplerOptions o = test::coarseSamplerOptions();
  o.epsilon = 1e-4f;  // below kNarrowEpsilon: float keys
  const DpCdfSampler wide(m, o);
  EXPECT_FALSE(wide.vectorized());
  expectStreamsMatchSingleQueries(wide, q);
  for (SamplerKind kind : {SamplerKind::Tabulated, SamplerKind::Quadtree})
    expectStreamsMatchSingleQueries(*makeSampler(kind, m, test::coarseSamplerOptions()), q);
}

TEST(SamplerStreams, AllZeroMaterialGivesNoSamplesAndZeroPdf) {
  const DpCdfSampler s(std::make_shared<Lambert>(Rgb(0.0f)), test::coarseSamplerOptions());
  const Queries q = makeQueries(100, 7);
  std::vector<BinnedSampler::DirectionSample> out(q.wo.size(), {glm::vec3(1.0f), 1.0f});
  s.sampleDirections(q.wo, q.u, out);
  for (const auto& d : out) EXPECT_EQ(d.pdf, 0.0f);
  std::vector<float> p(q.wo.size(), 1.0f);
  s.pdfs(q.wo, q.wo, p);
  for (float v : p) EXPECT_EQ(v, 0.0f);
}

TEST(SamplerStreams, SpansOfDifferentSizesAreRejected) {
  const DpCdfSampler s(test::samplerTestMaterials()[0].material, test::coarseSamplerOptions());
  std::vector<glm::vec3> wo(4, glm::vec3(0, 0, 1));
  std::vector<glm::vec2> u(3);
  std::vector<BinnedSampler::DirectionSample> out(4);
  EXPECT_THROW(s.sampleDirections(wo, u, out), Error);
  std::vector<float> p(5);
  EXPECT_THROW(s.pdfs(wo, wo, p), Error);
}

}  // namespace
}  // namespace btf
