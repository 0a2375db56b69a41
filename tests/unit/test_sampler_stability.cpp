// Where tabulated samplers are pushed to failure, each case with its documented behaviour
// (binned_sampler.h, dp_cdf_sampler.h, quadtree_sampler.h): near-mirror lobes, all-zero slices,
// grazing views, unmeasured table entries, NaN and negative evaluations, epsilon = 0 and huge
// epsilon, thread-count independence. The three chi-square tests here form one family with
// family-wise alpha = 0.01 (Sidak: 1 - 0.99^(1/3) = 3.3e-3 each); 40 x 40 cells, 1e5 draws.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/progress.h"
#include "btf/core/rng.h"
#include "btf/sampling/chi2.h"
#include "btf/sampling/dp_cdf_sampler.h"
#include "btf/sampling/quadtree_sampler.h"
#include "btf/core/warp.h"
#include "btf/sampling/tabulated_sampler.h"
#include "sampler_test_materials.h"

namespace {

using btf::SamplerKind;
constexpr SamplerKind kAllKinds[] = {SamplerKind::Tabulated, SamplerKind::DpCdf, SamplerKind::Quadtree};
const double kSignificance = 1.0 - std::pow(0.99, 1.0 / 3.0);

btf::Chi2Result runChi2(const btf::Material& m, const glm::vec3& wo) {
  btf::Chi2Options o;
  o.sample_count = 100'000;
  o.theta_bins = btf::test::kSamplerChi2ThetaBins;
  o.phi_bins = btf::test::kSamplerChi2PhiBins;
  o.significance = kSignificance;
  return btf::chi2TestMaterial(m, wo, {}, o);
}

// f = albedo / pi where `inside` holds, else 0; optionally NaN or negative somewhere.
class PatchyMaterial final : public btf::Material {
 public:
  enum class Defect { None, NanAndNegative };
  PatchyMaterial(float max_theta_o, Defect defect) : max_cos_(std::cos(max_theta_o)), defect_(defect) {}
  btf::Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const override {
    if (wi.z <= 0 || wo.z <= 0 || wo.z < max_cos_) return {};
    if (defect_ == Defect::NanAndNegative && wi.x > 0.6f) return btf::Rgb(std::nanf(""));
    if (defect_ == Defect::NanAndNegative && wi.y > 0.6f) return btf::Rgb(-1.0f);
    return btf::Rgb(0.5f * btf::kInvPi);
  }
  std::optional<btf::BsdfSample> sample(const glm::vec3&, glm::vec2, glm::vec2) const override { return {}; }
  float pdf(const glm::vec3&, const glm::vec3&, glm::vec2) const override { return 0; }
  std::string name() const override { return "patchy"; }

 private:
  float max_cos_;
  Defect defect_;
};

// E[w^2] / E[w]^2 of the luminance weight f cos / pdf at wo: 1 for a perfect sampler.
double weightSpread(const btf::Material& m, const glm::vec3& wo, int draws) {
  btf::Rng rng(8);
  double sum = 0, sum2 = 0;
  for (int k = 0; k < draws; ++k)
    if (auto s = m.sample(wo, {}, rng.uniform2D())) {
      const double w = s->weight.luminance();
      sum += w, sum2 += w * w;
    }
  return sum2 * draws / (sum * sum);
}

}  // namespace

TEST(SamplerStability, NearMirrorLobeNeedsManyVerticesAndDeepLeavesButNeverLoops) {
  // Behaviour: DP keeps many more vertices per CDF for a near-mirror lobe than for a diffuse one;
  // the quadtree's acceptance stays >= 1/4 (bilinear leaves) and every draw takes at most
  // max_tries + 1 proposals. Both numbers are printed for the record.
  const auto& mats = btf::test::samplerTestMaterials();
  btf::SamplerOptions o = btf::test::coarseSamplerOptions();
  const btf::DpCdfSampler diffuse(mats[0].material, o);
  const btf::DpCdfSampler mirror(mats[4].material, o);
  const auto phong2000 = std::make_shared<btf::Phong>(btf::Rgb(0.0f), btf::Rgb(0.9f), 2000.0f);
  o.max_tries = 4;
  const btf::QuadtreeSampler tree(phong2000, o);
  const btf::QuadtreeSampler ggx_tree(mats[4].material, o);
  const btf::SamplerStats d = diffuse.stats(), m = mirror.stats(), q = tree.stats(), g = ggx_tree.stats();
  std::printf("[ stability ] DP eps 1e-3 vertices per CDF: lambert %.2f, ggx a0.02 %.2f (of %d nodes)\n",
              d.mean_elements_per_cdf, m.mean_elements_per_cdf, o.phi_bins + 1);
  std::printf("[ stability ] quadtree acceptance: phong n2000 mean %.3f min %.3f (%zu leaves); ggx a0.02 mean %.3f "
              "min %.3f (%zu leaves)\n",
              q.acceptance_rate, q.min_acceptance_rate, q.elements, g.acceptance_rate, g.min_acceptance_rate,
              g.elements);
  EXPECT_GT(m.mean_elements_per_cdf, 1.5 * d.mean_elements_per_cdf);
  EXPECT_GE(q.min_acceptance_rate, 0.25);
  EXPECT_GE(g.min_acceptance_rate, 0.25);
  const glm::vec3 wo = btf::sphericalDirection(0.5f, 1.0f);
  btf::Rng rng(4);
  for (int k = 0; k < 20'000; ++k) {
    int tries = 0;
    ASSERT_TRUE(tree.sampleCountingTries(wo, {}, rng.uniform2D(), tries));
    ASSERT_LE(tries, o.max_tries + 1);
  }
  const btf::TabulatedSampler reference(phong2000, btf::test::coarseSamplerOptions());
  std::printf("[ stability ] phong n2000 weight spread E[w^2]/E[w]^2: tabulated %.1f, quadtree %.1f, own %.2f\n",
              weightSpread(reference, wo, 20'000), weightSpread(tree, wo, 20'000), weightSpread(*phong2000, wo, 20'000));
}

TEST(SamplerStability, AllZeroBinsSampleNothingAndHaveZeroPdf) {
  // Zero for theta_o > 30 degrees: those bins are empty, the others are not.
  const auto patchy = std::make_shared<PatchyMaterial>(0.52f, PatchyMaterial::Defect::None);
  const glm::vec3 lit = btf::sphericalDirection(0.2f, 1.0f), dark = btf::sphericalDirection(1.2f, 1.0f);
  const glm::vec3 wi = btf::sphericalDirection(0.4f, 2.0f);
  for (SamplerKind kind : kAllKinds) {
    const auto s = btf::makeSampler(kind, patchy, btf::test::coarseSamplerOptions());
    EXPECT_FALSE(s->sample(dark, {}, {0.3f, 0.6f})) << s->name();
    EXPECT_EQ(s->pdf(wi, dark), 0.0f) << s->name();
    EXPECT_TRUE(s->sample(lit, {}, {0.3f, 0.6f})) << s->name();
    EXPECT_GT(s->pdf(wi, lit), 0.0f) << s->name();
    const btf::SamplerStats st = s->stats();
    EXPECT_GT(st.empty_bins, 0u);
    EXPECT_LT(st.empty_bins, st.bins);
    EXPECT_EQ(st.invalid_evaluations, 0u);
  }
}

TEST(SamplerStability, GrazingViewsStayFiniteAndBelowHorizonGivesNothing) {
  const auto& mats = btf::test::samplerTestMaterials();
  for (SamplerKind kind : kAllKinds) {
    const auto s = btf::makeSampler(kind, mats[2].material, btf::test::coarseSamplerOptions());
    for (float z : {1e-2f, 1e-4f, 1e-7f}) {
      const glm::vec3 wo{std::sqrt(1 - z * z), 0.0f, z};
      btf::Rng rng(2);
      for (int k = 0; k < 1000; ++k) {
        const auto smp = s->sample(wo, {}, rng.uniform2D());
        ASSERT_TRUE(smp) << s->name() << " z " << z;
        ASSERT_TRUE(std::isfinite(smp->pdf) && smp->pdf > 0) << s->name();
        ASSERT_TRUE(smp->weight.isFinite()) << s->name();
      }
    }
    EXPECT_FALSE(s->sample({1, 0, 0}, {}, {0.5f, 0.5f}));
    EXPECT_FALSE(s->sample({0.8f, 0, -0.6f}, {}, {0.5f, 0.5f}));
    EXPECT_EQ(s->pdf({0, 0, 1}, {0.8f, 0, -0.6f}), 0.0f);
    EXPECT_EQ(s->pdf({0.8f, 0, -0.6f}, {0, 0, 1}), 0.0f);
  }
  const auto dp = btf::makeSampler(SamplerKind::DpCdf, mats[2].material, btf::test::coarseSamplerOptions());
  const btf::Chi2Result r = runChi2(*dp, btf::sphericalDirection(1.5621f, 0.0f));  // 89.5 degrees
  EXPECT_TRUE(r.accepted) << r.message;
  std::printf("[ p-value ] %s at 89.5 degrees: p = %.4f\n", dp->name().c_str(), r.p_value);
}

TEST(SamplerStability, UnmeasuredTableEntriesAreHandledByTheTable) {
  // A third of the theta_h rows marked unmeasured (negative): TabulatedBrdf fills them from the
  // nearest measured samples, so the sampler sees only valid values and stays exact.
  const auto& source = dynamic_cast<const btf::TabulatedBrdf&>(*btf::test::samplerTestMaterials()[5].material);
  auto table = std::make_shared<btf::MerlTable>(source.table());
  for (int h = 30; h < 60; ++h)
    for (int d = 0; d < btf::MerlTable::kThetaDiffRes; ++d)
      for (int p = 0; p < btf::MerlTable::kPhiDiffRes; ++p) table->setUnmeasured(btf::MerlTable::index(h, d, p));
  const auto brdf = std::make_shared<btf::TabulatedBrdf>(table);
  const auto s = btf::makeSampler(SamplerKind::DpCdf, brdf, btf::test::coarseSamplerOptions());
  EXPECT_EQ(s->stats().invalid_evaluations, 0u);
  const btf::Chi2Result r = runChi2(*s, btf::sphericalDirection(0.7f, 0.0f));
  EXPECT_TRUE(r.accepted) << r.message;
  std::printf("[ p-value ] %s with unmeasured rows: p = %.4f\n", s->name().c_str(), r.p_value);
}

TEST(SamplerStability, NanAndNegativeEvaluationsCountAsZeroWithOneWarning) {
  std::vector<std::string> warnings;
  btf::setLogHook([&](btf::LogLevel level, std::string_view msg) {
    if (level == btf::LogLevel::Warning) warnings.emplace_back(msg);
  });
  const auto defective = std::make_shared<PatchyMaterial>(2.0f, PatchyMaterial::Defect::NanAndNegative);
  for (SamplerKind kind : kAllKinds) {
    warnings.clear();
    const auto s = btf::makeSampler(kind, defective, btf::test::coarseSamplerOptions());
    const btf::SamplerStats st = s->stats();
    EXPECT_GT(st.invalid_evaluations, 0u) << s->name();
    EXPECT_LT(st.invalid_evaluations, st.evaluations) << s->name();
    ASSERT_EQ(warnings.size(), 1u) << s->name();
    EXPECT_NE(warnings[0].find("NaN, infinite or negative"), std::string::npos) << warnings[0];
    btf::Rng rng(6);
    const glm::vec3 wo = btf::sphericalDirection(0.5f, 0.3f);
    for (int k = 0; k < 2000; ++k) {
      const auto smp = s->sample(wo, {}, rng.uniform2D());
      ASSERT_TRUE(smp);
      ASSERT_TRUE(std::isfinite(smp->pdf) && smp->pdf > 0);
    }
  }
  btf::setLogHook(nullptr);
}

TEST(SamplerStability, ZeroEpsilonMatchesTheReferenceAndHugeEpsilonIsUniformPerCdf) {
  const auto& mats = btf::test::samplerTestMaterials();
  btf::SamplerOptions o = btf::test::coarseSamplerOptions();
  const btf::TabulatedSampler reference(mats[1].material, o);
  o.epsilon = 0.0f;
  const btf::DpCdfSampler exact(mats[1].material, o);
  o.epsilon = 10.0f;
  const btf::DpCdfSampler endpoints(mats[1].material, o);
  btf::Rng rng(12);
  for (int k = 0; k < 5000; ++k) {
    const glm::vec3 wi = btf::squareToUniformHemisphere(rng.uniform2D());
    const glm::vec3 wo = btf::squareToUniformHemisphere(rng.uniform2D());
    ASSERT_NEAR(exact.pdf(wi, wo), reference.pdf(wi, wo), 1e-4f * reference.pdf(wi, wo) + 1e-6f);
    ASSERT_FLOAT_EQ(endpoints.pdf(wi, wo), btf::uniformHemispherePdf(wi));
  }
  const btf::SamplerStats e = endpoints.stats(), x = exact.stats();
  EXPECT_EQ(e.mean_elements_per_cdf, 2.0);
  EXPECT_LE(exact.maxCdfDeviation(), 1e-6);
  std::printf("[ stability ] phong n20 bytes: reference %zu, dp eps0 %zu, dp eps10 %zu\n", reference.stats().bytes,
              x.bytes, e.bytes);
}

TEST(SamplerStability, TablesDoNotDependOnTheThreadCount) {
  const auto& mats = btf::test::samplerTestMaterials();
  const btf::SamplerOptions o = btf::test::coarseSamplerOptions();
  for (SamplerKind kind : kAllKinds) {
    std::unique_ptr<btf::BinnedSampler> one;
    {
      tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
      one = btf::makeSampler(kind, mats[3].material, o);
    }
    const auto many = btf::makeSampler(kind, mats[3].material, o);
    EXPECT_EQ(one->stats().bytes, many->stats().bytes);
    btf::Rng rng(1);
    for (int k = 0; k < 2000; ++k) {
      const glm::vec3 wo = btf::squareToUniformHemisphere(rng.uniform2D());
      const glm::vec2 u = rng.uniform2D();
      const auto a = one->sample(wo, {}, u), b = many->sample(wo, {}, u);
      ASSERT_EQ(a.has_value(), b.has_value());
      if (a) {
        ASSERT_EQ(a->pdf, b->pdf);
      }
    }
  }
}

TEST(SamplerStability, InvalidOptionsAreRejectedWithTheOptionNamed) {
  const auto& mats = btf::test::samplerTestMaterials();
  btf::SamplerOptions o;
  o.epsilon = -1.0f;
  EXPECT_THROW(btf::DpCdfSampler(mats[0].material, o), btf::Error);
  o = {};
  o.threshold = 0.5f;
  try {
    btf::QuadtreeSampler q(mats[0].material, o);
    ADD_FAILURE() << "threshold 0.5 accepted";
  } catch (const btf::Error& e) {
    EXPECT_NE(std::string(e.what()).find("threshold"), std::string::npos) << e.what();
  }
  EXPECT_THROW(btf::TabulatedSampler(nullptr), btf::Error);
}
