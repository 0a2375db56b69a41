// BtfMaterial on direction sets without the 81-direction rings (material/btf_material.h): the
// spherical Delaunay triangulation it interpolates on (core/hemisphere_triangulation.h), eval exact
// at measured directions on the Bonn dome and on scattered view-dependent lights, straight from
// VQ codebooks, and a sampler whose draws follow its pdf exactly (the triangle probabilities of
// the light-then-triangle draw, computed), whose pdf is the sample's bit for bit, and that passes
// the chi-square test (alpha = 0.01 per case, 1,000,000 draws on 20 x 40 cells, fixed seeds; 6 cases:
// the dome's data, its VQ codebooks and scattered lights at two theta_o) on both sets.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "btf/compress/vq_btf.h"
#include "btf/core/hemisphere_triangulation.h"
#include "btf/core/math.h"
#include "btf/core/rng.h"
#include "btf/core/warp.h"
#include "btf/material/btf_material.h"
#include "btf/material/registry.h"
#include "btf/sampling/chi2.h"
#include "btf_test_data.h"
#include "support/test_support.h"
#include "support/tier.h"
#include "synthetic_btf.h"

namespace btf {
namespace {

std::shared_ptr<const BtfData> domeBtf() {
  static const auto data = std::make_shared<const BtfData>(test::makeGgxBtf(3, 3, false, BtfDirectionSet::uboDome1()));
  return data;
}
std::shared_ptr<const VqBtf> domeVq() {
  static const auto vq = std::make_shared<const VqBtf>(compressVq(*domeBtf(), {}));
  return vq;
}
std::shared_ptr<const BtfData> scatteredBtf() {
  static const auto data =
      std::make_shared<const BtfData>(test::makeGgxBtf(2, 2, false, synthetic::scatteredDirectionSet(30, 50)));
  return data;
}

void expectNearRgb(const Rgb& a, const Rgb& b, float rel) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], rel * std::max(1e-3f, std::abs(b[c])));
}

TEST(HemisphereTriangulation, CoversTheHemisphereAndIsExactAtItsDirections) {
  const BtfDirectionSet& dome = *BtfDirectionSet::uboDome1();
  const HemisphereTriangulation tri(dome.lightDirections(0));
  double total = 0;
  for (int t = 0; t < tri.triangleCount(); ++t) total += tri.triangleSolidAngle(t);
  EXPECT_NEAR(total, 2.0 * kPi, 1e-3);
  // Every measured direction interpolates to itself alone.
  for (int l = 0; l < dome.lightCount(0); ++l) {
    const HemisphereTriangulation::Stencil s = tri.stencil(dome.lightDirections(0)[std::size_t(l)]);
    float own = 0;
    for (int k = 0; k < s.count; ++k)
      if (s.index[std::size_t(k)] == l) own += s.weight[std::size_t(k)];
    EXPECT_NEAR(own, 1.0f, 1e-5f) << "light " << l;
  }
  // Weights sum to 1 and reproduce the query on its triangle; every upper direction is located.
  Rng rng(3);
  for (int k = 0; k < 2000; ++k) {
    const glm::vec3 w = sphericalDirection(rng.uniform() * 1.57f, rng.uniform() * kTwoPi);
    ASSERT_GE(tri.locate(w), 0);
    const HemisphereTriangulation::Stencil s = tri.stencil(w);
    float sum = 0;
    for (int j = 0; j < s.count; ++j) sum += s.weight[std::size_t(j)];
    EXPECT_NEAR(sum, 1.0f, 1e-5f);
  }
}

// The sampler's draw (hemisphere_triangulation.h): a direction d with probability f_d W_d / sum,
// then one of its triangles by its share. Summed over the corners, triangle t's probability must
// be its density factor x solid angle x (f_a + f_b + f_c) / sum: what pdf() integrates to.
TEST(HemisphereTriangulation, CornerDrawGivesEachTriangleItsMass) {
  for (const auto& set : {BtfDirectionSet::uboDome1(), synthetic::scatteredDirectionSet(30, 50)}) {
    const HemisphereTriangulation tri(set->lightDirections(0));
    Rng rng(9);
    std::vector<double> f(std::size_t(tri.directionCount()));
    double total = 0, weights = 0, cos_area = 0;
    for (std::size_t d = 0; d < f.size(); ++d) {
      f[d] = rng.uniform() < 0.2 ? 0.0 : rng.uniform();
      total += f[d] * tri.directionWeight(int(d));
      weights += tri.directionWeight(int(d));
    }
    for (int t = 0; t < tri.triangleCount(); ++t) cos_area += std::max(tri.triangleCosTheta(t), 0.0f) * tri.triangleSolidAngle(t);
    EXPECT_NEAR(weights, cos_area, 1e-5 * cos_area);
    std::vector<double> drawn(std::size_t(tri.triangleCount()), 0.0);
    for (int d = 0; d < tri.directionCount(); ++d) {
      const auto triangles = tri.incidentTriangles(d);
      const auto cdf = tri.incidentCdf(d);
      ASSERT_EQ(cdf.size(), triangles.size() + 1);
      for (std::size_t k = 0; k < triangles.size(); ++k)
        drawn[std::size_t(triangles[k])] += f[std::size_t(d)] * tri.directionWeight(d) / total * (cdf[k + 1] - cdf[k]);
    }
    for (int t = 0; t < tri.triangleCount(); ++t) {
      const auto& c = tri.triangleDirections(t);
      const double expected = double(tri.triangleDensityFactor(t)) * tri.triangleSolidAngle(t) *
                              (f[std::size_t(c[0])] + f[std::size_t(c[1])] + f[std::size_t(c[2])]) / total;
      EXPECT_NEAR(drawn[std::size_t(t)], expected, 1e-5 * std::max(expected, 1e-3)) << set->name() << " triangle " << t;
    }
  }
}

// locate and nearest search a grid of candidates: their answers are those of the full scans
// (nearest: the first of the nearest directions; locate: a triangle that holds w, whose
// barycentric weights give w back wherever its corners are measured ones, inside the last ring).
TEST(HemisphereTriangulation, GridSearchesAgreeWithFullScans) {
  const BtfDirectionSet& dome = *BtfDirectionSet::uboDome1();
  const HemisphereTriangulation tri(dome.lightDirections(0));
  Rng rng(10);
  for (int k = 0; k < 20000; ++k) {
    const glm::vec3 w = squareToUniformHemisphere(rng.uniform2D());
    int best = 0;
    for (int d = 1; d < tri.directionCount(); ++d)
      if (glm::dot(dome.lightDirections(0)[std::size_t(d)], w) > glm::dot(dome.lightDirections(0)[std::size_t(best)], w)) best = d;
    ASSERT_EQ(tri.nearest(w), best);
    const int t = tri.locate(w);
    ASSERT_GE(t, 0);
    const HemisphereTriangulation::Stencil s = tri.stencilIn(t, w);
    if (w.z < std::cos(72.0f * kPi / 180.0f)) continue;
    glm::vec3 back(0.0f);
    for (int j = 0; j < s.count; ++j) back += s.weight[std::size_t(j)] * dome.lightDirections(0)[std::size_t(s.index[std::size_t(j)])];
    EXPECT_GT(glm::dot(glm::normalize(back), w), 0.99999f);
  }
}

// locatesIn(t, w) skips the search for w well inside t: it must answer locate(w) == t for every
// t, also for w on or within rounding of an edge (half the draws are pushed to an edge or corner).
TEST(HemisphereTriangulation, LocatesInAgreesWithLocate) {
  for (const BtfDirectionSetPtr& set : {BtfDirectionSet::uboDome1(), synthetic::scatteredDirectionSet(4, 60)}) {
    const HemisphereTriangulation tri(set->lightDirections(0));
    Rng rng(12);
    for (int t = 0; t < tri.triangleCount(); t += 3)
      for (int k = 0; k < 40; ++k) {
        glm::vec2 u = rng.uniform2D();
        if (k % 2 == 1) u[k % 4 == 1 ? 0 : 1] = k % 8 < 4 ? 0.0f : 0x1.fffffep-1f;
        const glm::vec3 w = tri.sampleTriangle(t, u);
        const int located = tri.locate(w);
        for (int other = 0; other < tri.triangleCount(); ++other)
          ASSERT_EQ(tri.locatesIn(other, w), located == other) << "triangle " << other << ", drawn in " << t;
      }
  }
}

TEST(HemisphereTriangulation, TriangleSamplesAreUniformAndInside) {
  const HemisphereTriangulation tri(BtfDirectionSet::uboDome1()->lightDirections(0));
  Rng rng(4);
  for (int t = 0; t < tri.triangleCount(); t += 17) {
    // Inside: located in the triangle they were drawn from.
    for (int k = 0; k < 200; ++k) EXPECT_EQ(tri.locate(tri.sampleTriangle(t, rng.uniform2D())), t);
  }
  // Uniform: the chi-square test of the density 1 / area on one triangle.
  const int t = tri.locate(sphericalDirection(0.6f, 1.0f));
  Chi2Options options;
  options.sample_count = 200'000;
  options.theta_bins = 40;
  options.phi_bins = 80;
  const Chi2Result r = chi2Test([&](glm::vec2 u) { return std::optional<glm::vec3>(tri.sampleTriangle(t, u)); },
                                [&](const glm::vec3& w) { return tri.locate(w) == t ? 1.0 / tri.triangleSolidAngle(t) : 0.0; },
                                options);
  EXPECT_TRUE(r.accepted) << r.message;
}

void expectExactAtMeasuredDirections(const BtfMaterial& material, const BtfLookup& data) {
  const BtfDirectionSet& set = data.lookupViews().directions();
  for (int y = 0; y < data.lookupHeight(); ++y)
    for (int x = 0; x < data.lookupWidth(); ++x)
      for (int v = 0; v < set.viewCount(); v += 7)
        for (int l = 0; l < set.lightCount(v); l += 5) {
          const glm::vec2 uv((float(x) + 0.5f) / float(data.lookupWidth()), (float(y) + 0.5f) / float(data.lookupHeight()));
          expectNearRgb(material.eval(set.lightDirections(v)[std::size_t(l)], set.view(v), uv), data.value(x, y, v, l), 1e-4f);
        }
}

TEST(BtfMaterialAnySet, EvalAtMeasuredDirectionsReturnsTheData) {
  expectExactAtMeasuredDirections(BtfMaterial(domeBtf()), *domeBtf());
  expectExactAtMeasuredDirections(BtfMaterial(scatteredBtf()), *scatteredBtf());
  // From the codebooks of a VQ-compressed dome BTF: its own decoded values.
  expectExactAtMeasuredDirections(BtfMaterial(domeVq()), *domeVq());
}

TEST(BtfMaterialAnySet, InterpolatesBetweenMeasuredDirections) {
  const BtfMaterial material(domeBtf());
  const BtfDirectionSet& dome = *BtfDirectionSet::uboDome1();
  // Between two neighbouring lights of one ring (lights 1 and 2 of ring 1, 60 degrees apart), the
  // value lies between theirs; GGX is smooth there, so it is also near the analytic value.
  const glm::vec3 a = dome.lightDirections(0)[1], b = dome.lightDirections(0)[2];
  const glm::vec3 mid = glm::normalize(a + b);
  const Rgb fa = domeBtf()->at(1, 1, 0, 1), fb = domeBtf()->at(1, 1, 0, 2), fm = material.eval(mid, dome.view(0), {0.5f, 0.5f});
  for (int c = 0; c < 3; ++c) {
    EXPECT_GE(fm[c], std::min(fa[c], fb[c]) - 1e-6f);
    EXPECT_LE(fm[c], std::max(fa[c], fb[c]) + 1e-6f);
  }
  // Beyond the last ring (75 degrees) the value stays that of the last ring's lights, not zero.
  const glm::vec3 grazing = sphericalDirection(88.0f * kPi / 180.0f, 0.3f);
  EXPECT_GT(material.eval(grazing, dome.view(40), {0.5f, 0.5f}).luminance(), 0.0f);
}

TEST(BtfMaterialAnySet, SampleAgreesWithPdfAndWeight) {
  for (const auto& lookup : {std::shared_ptr<const BtfLookup>(domeBtf()), std::shared_ptr<const BtfLookup>(domeVq()),
                             std::shared_ptr<const BtfLookup>(scatteredBtf())}) {
    const BtfMaterial material(lookup);
    Rng rng(5);
    int drawn = 0;
    for (int k = 0; k < 3000; ++k) {
      const glm::vec3 wo = sphericalDirection(rng.uniform() * 1.5f, rng.uniform() * kTwoPi);
      const glm::vec2 uv = rng.uniform2D(), u = rng.uniform2D();
      const auto s = material.sample(wo, uv, u);
      if (!s) continue;
      ++drawn;
      ASSERT_GT(s->wi.z, 0.0f);
      // The density of the draw, bit for bit, and the same draw without the weight.
      EXPECT_EQ(s->pdf, material.pdf(s->wi, wo, uv));
      const auto d = material.sampleDirection(wo, uv, u);
      ASSERT_TRUE(d);
      EXPECT_EQ(d->wi, s->wi);
      EXPECT_EQ(d->pdf, s->pdf);
      // The weight from the draw's own stencil: eval's value.
      const Rgb f = material.eval(s->wi, wo, uv) * (s->wi.z / s->pdf);
      for (int c = 0; c < 3; ++c) EXPECT_EQ(s->weight[c], f[c]);
    }
    EXPECT_GT(drawn, 2990);
  }
}

BTF_STATISTICAL_TEST(BtfMaterialAnySet, SamplerPassesChiSquareOnTheDomeAndScatteredLights) {
  Chi2Options options;
  options.sample_count = 1'000'000;
  options.significance = 0.01;
  for (const auto& lookup : {std::shared_ptr<const BtfLookup>(domeBtf()), std::shared_ptr<const BtfLookup>(domeVq()),
                             std::shared_ptr<const BtfLookup>(scatteredBtf())}) {
    const BtfMaterial material(lookup);
    for (const float theta : {0.2f, 1.0f}) {
      const Chi2Result r = chi2TestMaterial(material, sphericalDirection(theta, 0.7f), {0.6f, 0.3f}, options);
      EXPECT_TRUE(r.accepted) << "theta_o " << theta << ": " << r.message;
    }
  }
}

TEST(BtfMaterialAnySet, OpensThroughTheRegistry) {
  test::TempDir dir;
  compressVq(*domeBtf(), {}).write(dir / "dome.btfz");
  const std::shared_ptr<const Material> material = openMaterial((dir / "dome.btfz").string());
  EXPECT_GT(material->eval(sphericalDirection(0.5f, 1.0f), sphericalDirection(0.3f, 2.0f), {0.5f, 0.5f}).luminance(), 0.0f);
}

}  // namespace
}  // namespace btf
