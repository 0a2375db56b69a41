// The stream calls sampleDirections / pdfs (binned_sampler.h) against the single queries, bit for
// bit: the DP sampler's AVX2 lanes must give exactly what sampleDirection and pdf give, including
// the awkward queries (pole, grazing, below the horizon, NaN, u at the ends of [0, 1)), which the
// stream call hands to the scalar path. Every test runs with both parameterizations (Incident and
// Half, whose lanes reflect about the half vector and invert its map).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/rng.h"
#include "btf/material/lambert.h"
#include "btf/sampling/dp_cdf_sampler.h"
#include "btf/sampling/parameterization.h"
#include "btf/core/warp.h"
#include "sampler_test_materials.h"

namespace btf {
namespace {

std::uint32_t bits(float v) { return std::bit_cast<std::uint32_t>(v); }

struct Queries {
  std::vector<glm::vec3> wo;
  std::vector<glm::vec2> u;
};

// Random queries plus the edge cases; in all not a multiple of 8 (4,014 for n = 4001), so that the
// last block is partial.
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
      {{0.6f, 0.0f, 0.8f}, {-0.25f, 0.5f}}, {{0.0f, 0.6f, 0.8f}, {0.5f, 1.5f}},
      // Not unit length (the lanes take any finite wo above the horizon): long, and tiny (the
      // rotation's x^2 + y^2 and the normalizations go subnormal).
      {{0.3f, 0.4f, 2.0f}, {0.4f, 0.6f}},  {{1e-20f, 0.0f, 1e-20f}, {0.7f, 0.2f}}};
  for (const auto& [wo, u] : edges) q.wo.push_back(wo), q.u.push_back(u);
  return q;
}

// Streams vs single queries over the queries, their draws and random wi (some below the horizon),
// plus wi where the pdf has edges of its own: the mirror direction of wo (Half: h is the normal
// exactly, the Jacobian 0 and the pdf 0), wo itself, the normal, the horizon, and wi of length
// 3 or 0 (the pdf normalizes nothing; Half's h is a normalized sum).
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
    switch (i % 61) {
      case 1: wi[i] = glm::vec3(-q.wo[i].x, -q.wo[i].y, q.wo[i].z); break;
      case 2: wi[i] = q.wo[i]; break;
      case 3: wi[i] = glm::vec3(0.0f, 0.0f, 1.0f); break;
      case 6: wi[i] = glm::vec3(q.wo[i].y, -q.wo[i].x, 0.0f); break;
      case 7: wi[i] *= 3.0f; break;
      case 8: wi[i] = glm::vec3(0.0f); break;
      default: break;
    }
  }
  EXPECT_GT(drawn, q.wo.size() / 2) << s.name();
  std::vector<float> p(wi.size());
  s.pdfs(wi, wo_for_pdf, p);
  for (std::size_t i = 0; i < wi.size(); ++i) {
    ASSERT_EQ(bits(s.pdf(wi[i], wo_for_pdf[i])), bits(p[i])) << s.name() << " pdf query " << i;
  }
}

constexpr Parameterization kParameterizations[] = {Parameterization::Incident, Parameterization::Half};

TEST(SamplerStreams, DpSamplerLanesGiveTheSingleQueriesBitForBit) {
  const Queries q = makeQueries(4001, 5);
  for (Parameterization parameterization : kParameterizations) {
    for (const test::NamedMaterial& m : test::samplerTestMaterials()) {
      for (float epsilon : {1e-3f, 1e-2f, 0.3f}) {
        // Incident 32 x 64 cells, Half the coarse 32 x 32.
        SamplerOptions o = test::coarseSamplerOptions(parameterization);
        o.cos_theta_bins = 32, o.phi_bins = 64, o.theta_o_bins = 16;
        o.epsilon = epsilon;
        const DpCdfSampler s(m.material, o);
        ASSERT_EQ(s.parameterization(), parameterization);
        std::string trace = m.label + " " + std::string(toString(parameterization));
        trace += s.vectorized() ? " (lanes) eps " : " (loop) eps ";
        trace += std::to_string(epsilon);
        SCOPED_TRACE(trace);
        expectStreamsMatchSingleQueries(s, q);
        // The lanes serve isotropic materials with 16-bit CDFs, in either parameterization; on an
        // AVX2 machine they must be in use.
        if (__builtin_cpu_supports("avx2")) {
          EXPECT_EQ(s.vectorized(), !m.material->isAnisotropic());
        }
      }
    }
  }
}

// The square point (s, t) where pdf() takes a drawn wi: (wi.z, phi_i / 2 pi) for Incident, the
// inverse half-vector map for Half; approximately (the bin frame is the local one only up to
// rounding when wo lies in the xz-plane), which is enough to locate a cell border.
glm::vec2 squarePoint(Parameterization p, const glm::vec3& wi, const glm::vec3& wo) {
  if (p == Parameterization::Half) return halfVectorToSquare(glm::normalize(wi + wo)).st;
  const float t = std::atan2(wi.y, wi.x) / kTwoPi;
  return {wi.z, t < 0.0f ? t + 1.0f : t};
}

// Queries whose draws straddle the grid's cell borders, along s (axis 0: rows) or t (axis 1:
// columns): for each border, the u where the drawn coordinate crosses it (bisection), then the
// 128 floats around it. There the round trip of a draw through wi lands in the neighbouring cell
// now and then, and the lanes must notice (Incident: the draw is within kCellMargin of the border;
// Half: the recomputed row or column differs from the drawn one) and take the scalar pdf; the
// borders inside a segment are the ones where a lane that missed it would get the pdf wrong.
Queries borderQueries(const DpCdfSampler& s, const std::vector<glm::vec3>& wos, int axis) {
  Queries q;
  const int cells = axis == 0 ? s.gridRows() : s.gridColumns();
  for (const glm::vec3& wo : wos)
    for (float other : {0.3f, 0.8f})
      for (int i = 1; i < cells; ++i) {
        const float border = float(i) / float(cells);
        auto u = [&](float v) { return axis == 0 ? glm::vec2(v, other) : glm::vec2(other, v); };
        float lo = 0.0f, hi = 1.0f;
        bool drawn = true;
        for (int step = 0; step < 40 && drawn; ++step) {
          const float mid = 0.5f * (lo + hi);
          int tries = 0;
          const auto d = s.sampleDirection(wo, u(mid), tries);
          drawn = d.has_value();
          if (drawn) (squarePoint(s.parameterization(), d->wi, wo)[axis] < border ? lo : hi) = mid;
        }
        if (!drawn) continue;  // a Half draw below the horizon on the way
        float v = hi;
        for (int k = 0; k < 64; ++k) v = std::nextafter(v, 0.0f);
        for (int k = 0; k < 128 && v < 1.0f; ++k, v = std::nextafter(v, 1.0f)) q.wo.push_back(wo), q.u.push_back(u(v));
      }
  return q;
}

TEST(SamplerStreams, DpSamplerLanesAtCellBordersGiveTheSingleQueriesBitForBit) {
  const std::vector<glm::vec3> wos = {sphericalDirection(0.2f, 0.0f), sphericalDirection(0.7f, 0.0f),
                                      sphericalDirection(1.2f, 0.0f)};
  for (Parameterization parameterization : kParameterizations) {
    for (int material : {0, 2, 4}) {
      const test::NamedMaterial& m = test::samplerTestMaterials()[std::size_t(material)];
      for (float epsilon : {1e-2f, 0.3f}) {
        SamplerOptions o = test::coarseSamplerOptions(parameterization);
        o.cos_theta_bins = 32, o.phi_bins = 64, o.theta_o_bins = 16;
        o.epsilon = epsilon;
        const DpCdfSampler s(m.material, o);
        for (int axis : {0, 1}) {
          SCOPED_TRACE(m.label + " " + std::string(toString(parameterization)) + " eps " + std::to_string(epsilon) +
                       (axis == 0 ? " row borders" : " column borders"));
          const Queries q = borderQueries(s, wos, axis);
          const std::size_t borders = wos.size() * 2 * std::size_t((axis == 0 ? s.gridRows() : s.gridColumns()) - 1);
          EXPECT_GE(q.wo.size(), borders * 128 / 2);  // half the borders at least
          expectStreamsMatchSingleQueries(s, q);
        }
      }
    }
  }
}

TEST(SamplerStreams, WideKeysAndOtherSamplersFallBackToTheLoop) {
  const Queries q = makeQueries(517, 6);
  const auto& m = test::samplerTestMaterials()[2].material;
  for (Parameterization parameterization : kParameterizations) {
    SCOPED_TRACE(std::string(toString(parameterization)));
    SamplerOptions o = test::coarseSamplerOptions(parameterization);
    o.epsilon = 1e-4f;  // below kNarrowEpsilon: float keys
    const DpCdfSampler wide(m, o);
    EXPECT_FALSE(wide.vectorized());
    expectStreamsMatchSingleQueries(wide, q);
    for (SamplerKind kind : {SamplerKind::Tabulated, SamplerKind::Quadtree})
      expectStreamsMatchSingleQueries(*makeSampler(kind, m, test::coarseSamplerOptions(parameterization)), q);
  }
}

TEST(SamplerStreams, AllZeroMaterialGivesNoSamplesAndZeroPdf) {
  const Queries q = makeQueries(100, 7);
  for (Parameterization parameterization : kParameterizations) {
    SCOPED_TRACE(std::string(toString(parameterization)));
    const DpCdfSampler s(std::make_shared<Lambert>(Rgb(0.0f)), test::coarseSamplerOptions(parameterization));
    std::vector<BinnedSampler::DirectionSample> out(q.wo.size(), {glm::vec3(1.0f), 1.0f});
    s.sampleDirections(q.wo, q.u, out);
    for (const auto& d : out) EXPECT_EQ(d.pdf, 0.0f);
    std::vector<float> p(q.wo.size(), 1.0f);
    s.pdfs(q.wo, q.wo, p);
    for (float v : p) EXPECT_EQ(v, 0.0f);
  }
}

TEST(SamplerStreams, SpansOfDifferentSizesAreRejected) {
  for (Parameterization parameterization : kParameterizations) {
    SCOPED_TRACE(std::string(toString(parameterization)));
    const DpCdfSampler s(test::samplerTestMaterials()[0].material, test::coarseSamplerOptions(parameterization));
    std::vector<glm::vec3> wo(4, glm::vec3(0, 0, 1));
    std::vector<glm::vec2> u(3);
    std::vector<BinnedSampler::DirectionSample> out(4);
    EXPECT_THROW(s.sampleDirections(wo, u, out), Error);
    std::vector<float> p(5);
    EXPECT_THROW(s.pdfs(wo, wo, p), Error);
  }
}

}  // namespace
}  // namespace btf
