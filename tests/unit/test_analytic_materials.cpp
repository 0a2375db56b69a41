// The analytic models (Lambert, Phong, Lafortune, GGX, Ward): exact importance sampling, agreement
// of sample/pdf/eval, reciprocity, energy conservation and argument validation.
//
// Statistical tests use fixed seeds, so each outcome is deterministic (a chance rejection at
// alpha = 0.01 would fail every run, never flake); the counts and levels are stated per test.
#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "support/tier.h"
#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/rng.h"
#include "btf/material/albedo.h"
#include "btf/material/ggx.h"
#include "btf/material/lafortune.h"
#include "btf/material/lambert.h"
#include "btf/material/phong.h"
#include "btf/material/ward.h"
#include "btf/sampling/chi2.h"
#include "btf/core/warp.h"

namespace {

using btf::Rgb;

struct MaterialCase {
  std::string label;
  std::function<std::unique_ptr<btf::Material>()> make;
  bool anisotropic;
};

void PrintTo(const MaterialCase& c, std::ostream* os) { *os << c.label; }

// One-lobe Lafortune fits of Ngan et al. 2005 (see ../shared/data/real/fits/), as published.
btf::Lafortune nganFit(Rgb rho_d, Rgb rho_s, float cxy, float cz, float n) {
  return btf::Lafortune(rho_d, {btf::LafortuneLobe{rho_s, {cxy, cxy, cz}, n}});
}

std::vector<MaterialCase> materialCases() {
  return {
      {"lambert", [] { return std::make_unique<btf::Lambert>(Rgb(0.8f, 0.5f, 0.2f)); }, false},
      {"phong_glossy", [] { return std::make_unique<btf::Phong>(Rgb(0.3f), Rgb(0.6f, 0.5f, 0.4f), 10.0f); }, false},
      {"phong_near_mirror", [] { return std::make_unique<btf::Phong>(Rgb(0.1f), Rgb(0.85f), 5000.0f); }, false},
      {"lafortune_ngan_gold_metallic_paint",
       [] {
         return std::make_unique<btf::Lafortune>(
             nganFit({0.0601f, 0.0298f, 0.00487f}, {0.475f, 0.27f, 0.0681f}, -0.596f, 0.537f, 12.8f));
       },
       false},
      {"lafortune_ngan_alum_bronze",
       [] {
         return std::make_unique<btf::Lafortune>(
             nganFit({0.0923f, 0.0625f, 0.0311f}, {0.322f, 0.193f, 0.105f}, -0.579f, 0.574f, 630.0f));
       },
       false},
      {"lafortune_two_lobes_anisotropic",
       [] {
         return std::make_unique<btf::Lafortune>(
             Rgb(0.2f), std::vector<btf::LafortuneLobe>{{Rgb(0.3f), {-1.0f, -0.6f, 0.9f}, 40.0f},
                                                        {Rgb(0.2f), {0.5f, 0.5f, 0.6f}, 5.0f}});
       },
       true},
      {"ggx_plastic", [] { return std::make_unique<btf::Ggx>(Rgb(0.5f, 0.1f, 0.1f), Rgb(0.04f), 0.3f, 0.3f); }, false},
      {"ggx_anisotropic_metal",
       [] { return std::make_unique<btf::Ggx>(Rgb(0.0f), Rgb(0.9f, 0.7f, 0.5f), 0.05f, 0.4f); }, true},
      {"ggx_near_mirror", [] { return std::make_unique<btf::Ggx>(Rgb(0.2f), Rgb(0.95f), 0.02f, 0.02f); }, false},
      {"ward_isotropic", [] { return std::make_unique<btf::Ward>(Rgb(0.3f), Rgb(0.4f), 0.2f, 0.2f); }, false},
      {"ward_anisotropic", [] { return std::make_unique<btf::Ward>(Rgb(0.2f), Rgb(0.5f), 0.05f, 0.3f); }, true},
      {"ward_near_mirror", [] { return std::make_unique<btf::Ward>(Rgb(0.1f), Rgb(0.8f), 0.02f, 0.02f); }, false},
  };
}

// Views: normal, oblique at an azimuth where anisotropy matters, and grazing at 85 degrees.
std::vector<glm::vec3> viewDirections() {
  return {btf::sphericalDirection(0.0f, 0.0f), btf::sphericalDirection(glm::radians(40.0f), 0.7f),
          btf::sphericalDirection(glm::radians(85.0f), 2.1f)};
}

float relativeDifference(float a, float b) { return std::abs(a - b) / std::max({std::abs(a), std::abs(b), 1e-20f}); }

// The parameterized tests stay in this anonymous namespace with their fixture: a test class
// outside it deriving from a fixture inside it is a -Wsubobject-linkage warning once the unity
// build includes this file into another.
class AnalyticMaterial : public ::testing::TestWithParam<MaterialCase> {};

BTF_STATISTICAL_TEST_P(AnalyticMaterial, SamplerPassesChi2) {
  // 500,000 draws per view, 20 x 40 cells, significance 0.01, seed 1.
  const auto material = GetParam().make();
  btf::Chi2Options options;
  options.sample_count = 500'000;
  for (const glm::vec3& wo : viewDirections()) {
    const btf::Chi2Result r = btf::chi2TestMaterial(*material, wo, {}, options);
    EXPECT_TRUE(r.accepted) << "wo.z " << wo.z << ": " << r.message << " (500,000 draws, alpha = 0.01)";
  }
}

TEST_P(AnalyticMaterial, SampleAgreesWithPdfAndEval) {
  const auto material = GetParam().make();
  for (const glm::vec3& wo : viewDirections()) {
    btf::Rng rng(7, 0);
    int drawn = 0;
    for (int i = 0; i < 20'000; ++i) {
      const auto s = material->sample(wo, {}, rng.uniform2D());
      if (!s) continue;
      ++drawn;
      ASSERT_GT(s->wi.z, 0.0f);
      ASSERT_NEAR(glm::length(s->wi), 1.0f, 1e-5f);
      const float pdf = material->pdf(s->wi, wo);
      ASSERT_GT(s->pdf, 0.0f);
      ASSERT_LE(relativeDifference(s->pdf, pdf), 1e-5f) << "wo.z " << wo.z << " draw " << i;
      const Rgb expected = material->eval(s->wi, wo) * (s->wi.z / pdf);
      for (int c = 0; c < 3; ++c)
        ASSERT_LE(relativeDifference(s->weight[c], expected[c]), 1e-5f) << "wo.z " << wo.z << " draw " << i;
    }
    EXPECT_GT(drawn, 10'000) << "wo.z " << wo.z;
  }
}

TEST_P(AnalyticMaterial, IsReciprocal) {
  const auto material = GetParam().make();
  btf::Rng rng(11, 0);
  for (int i = 0; i < 20'000; ++i) {
    const glm::vec3 a = btf::squareToUniformHemisphere(rng.uniform2D());
    const glm::vec3 b = btf::squareToUniformHemisphere(rng.uniform2D());
    const Rgb ab = material->eval(a, b), ba = material->eval(b, a);
    for (int c = 0; c < 3; ++c) {
      ASSERT_TRUE(std::isfinite(ab[c]));
      // Values far below float precision of the peak (near-mirror tails) compare absolutely.
      if (std::max(ab[c], ba[c]) < 1e-30f) continue;
      ASSERT_LE(relativeDifference(ab[c], ba[c]), 1e-5f) << "pair " << i << " channel " << c;
    }
  }
}

TEST_P(AnalyticMaterial, ConservesEnergy) {
  // Directional albedo by Monte Carlo, 200,000 draws per view: must not exceed 1 by more than 4
  // standard errors (the estimate's own uncertainty; seed fixed).
  const auto material = GetParam().make();
  for (const glm::vec3& wo : viewDirections()) {
    const btf::AlbedoEstimate albedo = btf::estimateAlbedo(*material, wo, 200'000, 3);
    for (int c = 0; c < 3; ++c)
      EXPECT_LE(albedo.value[c], 1.0f + 4.0f * albedo.standard_error[c])
          << "wo.z " << wo.z << " channel " << c << " (200,000 draws, margin 4 standard errors)";
  }
}

TEST_P(AnalyticMaterial, ReflectsNothingBelowTheHorizon) {
  const auto material = GetParam().make();
  const glm::vec3 up{0.0f, 0.6f, 0.8f}, down{0.0f, 0.6f, -0.8f};
  EXPECT_TRUE(material->eval(down, up).isBlack());
  EXPECT_TRUE(material->eval(up, down).isBlack());
  EXPECT_EQ(material->pdf(down, up), 0.0f);
  EXPECT_FALSE(material->sample(down, {}, {0.3f, 0.6f}).has_value());
}

TEST_P(AnalyticMaterial, ReportsAnisotropyAndANameWithItsParameters) {
  const auto material = GetParam().make();
  EXPECT_EQ(material->isAnisotropic(), GetParam().anisotropic);
  EXPECT_NE(material->name().find('('), std::string::npos) << material->name();
}

INSTANTIATE_TEST_SUITE_P(Models, AnalyticMaterial, ::testing::ValuesIn(materialCases()),
                         [](const auto& info) { return info.param.label; });

}  // namespace

// The energy-conservation claims at their limits: albedos summing to 1, smooth and rough, and the
// grazing views where Fresnel and the Ward normalization are strongest. 100,000 draws per view,
// margin 4 standard errors, seed 5.
BTF_STATISTICAL_TEST(AnalyticMaterialLimits, ConserveEnergyAtFullAlbedo) {
  std::vector<std::unique_ptr<btf::Material>> materials;
  materials.push_back(std::make_unique<btf::Phong>(Rgb(0.5f), Rgb(0.5f), 1.0f));
  materials.push_back(std::make_unique<btf::Phong>(Rgb(0.0f), Rgb(1.0f), 300.0f));
  materials.push_back(std::make_unique<btf::Lafortune>(
      Rgb(0.4f), std::vector<btf::LafortuneLobe>{{Rgb(0.6f), {-1.0f, -0.5f, 1.0f}, 20.0f}}));
  for (const float alpha : {0.02f, 0.2f, 1.0f})
    for (const float f0 : {0.0f, 0.04f, 1.0f}) {
      materials.push_back(std::make_unique<btf::Ggx>(Rgb(1.0f), Rgb(f0), alpha, alpha));
      materials.push_back(std::make_unique<btf::Ggx>(Rgb(1.0f), Rgb(f0), alpha, 0.5f * alpha));
    }
  for (const float alpha : {0.02f, 0.2f, 0.6f}) materials.push_back(std::make_unique<btf::Ward>(Rgb(0.0f), Rgb(1.0f), alpha, alpha));
  for (const auto& m : materials)
    for (const float degrees : {0.0f, 30.0f, 60.0f, 75.0f, 85.0f, 89.0f}) {
      const glm::vec3 wo = btf::sphericalDirection(glm::radians(degrees), 0.4f);
      const btf::AlbedoEstimate albedo = btf::estimateAlbedo(*m, wo, 100'000, 5);
      EXPECT_LE(albedo.value.maxComponent(), 1.0f + 4.0f * albedo.standard_error.maxComponent())
          << m->name() << " at " << degrees << " degrees: albedo " << albedo.value.maxComponent() << " +- "
          << albedo.standard_error.maxComponent() << " (100,000 draws, margin 4 standard errors)";
    }
}

TEST(AnalyticMaterialValidation, RejectsInvalidParametersWithAClearMessage) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(btf::Lambert(Rgb(-0.1f, 0.5f, 0.5f)), btf::Error);
  EXPECT_THROW(btf::Lambert(Rgb(nan)), btf::Error);
  EXPECT_THROW(btf::Phong(Rgb(0.5f), Rgb(0.5f), -1.0f), btf::Error);
  EXPECT_THROW(btf::Phong(Rgb(0.5f), Rgb(-0.5f), 10.0f), btf::Error);
  EXPECT_THROW(btf::Lafortune(Rgb(0.5f), {{Rgb(0.3f), {-1, -1, 1}, -2.0f}}), btf::Error);
  EXPECT_THROW(btf::Lafortune(Rgb(0.5f), {{Rgb(0.3f), {0, 0, 0}, 2.0f}}), btf::Error);
  EXPECT_THROW(btf::Lafortune(Rgb(0.5f), {{Rgb(nan), {-1, -1, 1}, 2.0f}}), btf::Error);
  EXPECT_THROW(btf::Ggx(Rgb(0.5f), Rgb(0.04f), 0.0f, 0.1f), btf::Error);
  EXPECT_THROW(btf::Ggx(Rgb(0.5f), Rgb(0.04f), 0.1f, -0.1f), btf::Error);
  EXPECT_THROW(btf::Ggx(Rgb(0.5f), Rgb(1.5f), 0.1f, 0.1f), btf::Error);
  EXPECT_THROW(btf::Ward(Rgb(0.5f), Rgb(0.4f), nan, 0.1f), btf::Error);
  EXPECT_THROW(btf::Ward(Rgb(-0.5f), Rgb(0.4f), 0.1f, 0.1f), btf::Error);
  try {
    btf::Ggx(Rgb(0.5f), Rgb(0.04f), 0.0f, 0.1f);
  } catch (const btf::Error& e) {
    EXPECT_STREQ(e.what(), "ggx: alpha_x must be finite and > 0, got 0");
  }
}
