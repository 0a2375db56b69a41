// The fitted models (Sgd, Abc, and Lafortune with Ngan's fits) on the published MERL parameters:
// agreement with an independent evaluation of SOURCES.md's formulas for every material, exact
// importance sampling (chi-square), sample/pdf/eval agreement, reciprocity and energy.
//
// Statistical tests use fixed seeds, so each outcome is deterministic; counts and levels are stated
// per test.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "support/tier.h"
#include "btf/core/error.h"
#include "btf/core/half_diff.h"
#include "btf/core/math.h"
#include "btf/core/rng.h"
#include "btf/fit/merl_fits.h"
#include "btf/material/albedo.h"
#include "btf/sampling/chi2.h"
#include "btf/core/warp.h"
#include "unit/merl_fit_reference.h"

namespace btf::test {
namespace {

const MerlFits& fits() {
  static const MerlFits loaded = MerlFits::load(fitsDir());
  return loaded;
}

// Direction pairs both above the horizon: half the pairs near the specular peak (theta_h below
// 0.05 rad, where sharp fits are large), half anywhere (theta_h, theta_d up to 89 degrees).
std::vector<DirectionPair> testDirections(int count, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<DirectionPair> pairs;
  while (int(pairs.size()) < count) {
    const glm::vec2 u = rng.uniform2D(), v = rng.uniform2D();
    const bool near_peak = pairs.size() % 2 == 0;
    HalfDiff hd;
    hd.theta_h = near_peak ? 0.05f * u.x * u.x : glm::radians(89.0f) * u.x;
    hd.phi_h = kTwoPi * u.y;
    hd.theta_d = glm::radians(89.0f) * v.x;
    hd.phi_d = kTwoPi * v.y;
    const DirectionPair p = fromHalfDiff(hd);
    if (p.wi.z > 1e-3f && p.wo.z > 1e-3f) pairs.push_back(p);
  }
  return pairs;
}

using Reference = double (*)(const CsvRecord&, int, const glm::dvec3&, const glm::dvec3&);

// Compares the library's material with the reference formula at `count` direction pairs for every
// row of a fit table; counts the values the library clamped (reference < 0).
void expectMatchesReference(const std::string& file, ModelFamily model, Reference reference, bool clamps_at_zero,
                            int& clamped) {
  int compared = 0;
  clamped = 0;
  for (const CsvRecord& row : readCsvRecords(fitsDir() / file)) {
    const std::string name = row.at("material");
    const auto material = makeMerlFitMaterial(fits(), name, model);
    for (const DirectionPair& p : testDirections(60, 7)) {
      const Rgb f = material->eval(p.wi, p.wo);
      for (int c = 0; c < 3; ++c) {
        double expected = reference(row, c, glm::dvec3(p.wi), glm::dvec3(p.wo));
        if (clamps_at_zero && expected < 0) {
          expected = 0;
          ++clamped;
        }
        // float output of a double computation on float inputs: 1e-4 relative, plus an absolute
        // floor far below any visible reflectance for values that underflow towards 0. Lafortune
        // computes in float, so x^n carries about 4 n float epsilons (n reaches 7690 in Ngan's table).
        const double exponent = model == ModelFamily::Lafortune ? num(row, "n") : 0.0;
        const double tolerance = 1e-4 + 4.0 * exponent * 0x1p-23;
        ++compared;
        ASSERT_NEAR(f[c], expected, tolerance * std::abs(expected) + 1e-12)
            << modelFamilyName(model) << " " << name << " channel " << c << " wi (" << p.wi.x << "," << p.wi.y << ","
            << p.wi.z << ") wo (" << p.wo.x << "," << p.wo.y << "," << p.wo.z << ")";
      }
    }
  }
  EXPECT_GT(compared, 0);
}

}  // namespace

TEST(FitModels, SgdReproducesThePublishedParametersFormula) {
  int clamped = 0;
  expectMatchesReference(kSgdFitsFile, ModelFamily::Sgd, referenceSgd, true, clamped);
  // F < 0 near cos_d = 1 for the fits with f1 > f0 (blue-fabric, white-fabric2, white-paint), but
  // their diffuse term keeps f > 0 (smallest value 0.0077 1/sr, blue-fabric red at normal view),
  // so the library's clamp at 0 is a guard that the published fits never reach.
  EXPECT_EQ(clamped, 0);
}

TEST(FitModels, AbcReproducesThePublishedParametersFormula) {
  int clamped = 0;
  expectMatchesReference(kAbcFitsFile, ModelFamily::Abc, referenceAbc, false, clamped);
}

TEST(FitModels, LafortuneReproducesThePublishedParametersFormula) {
  // Rows of Ngan's table, including the 14 materials outside the MERL 100.
  int clamped = 0;
  expectMatchesReference(kLafortuneFitsFile, ModelFamily::Lafortune, referenceLafortune, false, clamped);
}

// Materials for the sampling tests: sharp metals (chrome; specular-orange-phenolic has SGD
// alpha 1.6e-5 in blue), a metallic paint, a diffuse fabric with SGD's negative Fresnel, and the
// most diffuse MERL material by ABC (pink-felt: B = 55, C = 0.34).
const std::vector<std::string> kSamplingMaterials = {"chrome", "specular-orange-phenolic", "gold-metallic-paint",
                                                     "blue-fabric", "pink-felt"};

class FitSampling : public ::testing::TestWithParam<std::tuple<std::string, ModelFamily>> {};

BTF_STATISTICAL_TEST_P(FitSampling, SamplerPassesChi2) {
  // 500,000 draws per view (normal, 40 deg, 80 deg), 20 x 40 cells, significance 0.01, seed 1.
  const auto& [name, model] = GetParam();
  const auto material = makeMerlFitMaterial(fits(), name, model);
  Chi2Options options;
  options.sample_count = 500'000;
  for (float deg : {0.0f, 40.0f, 80.0f}) {
    const Chi2Result r = chi2TestMaterial(*material, sphericalDirection(glm::radians(deg), 0.3f), {}, options);
    RecordProperty("p_value_" + std::to_string(int(deg)) + "deg", std::to_string(r.p_value));
    EXPECT_TRUE(r.accepted) << name << " theta_o " << deg << ": " << r.message << " (500,000 draws, alpha = 0.01)";
  }
}

TEST_P(FitSampling, SampleAgreesWithPdfAndEval) {
  const auto& [name, model] = GetParam();
  const auto material = makeMerlFitMaterial(fits(), name, model);
  Rng rng(3);
  int returned = 0;
  for (int n = 0; n < 2000; ++n) {
    const glm::vec3 wo = squareToCosineHemisphere(rng.uniform2D());
    const auto s = material->sample(wo, {}, rng.uniform2D());
    if (!s) continue;
    ++returned;
    ASSERT_GT(s->wi.z, 0.0f);
    const float pdf = material->pdf(s->wi, wo);
    ASSERT_NEAR(s->pdf, pdf, 1e-5f * pdf);
    const Rgb expected = material->eval(s->wi, wo) * (s->wi.z / pdf);
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(s->weight[c], expected[c], 1e-5f * expected[c] + 1e-12f);
  }
  // Lost draws are half vectors reflected below the horizon; the broadest ABC lobes (blue-fabric:
  // B = 3.1e6, C = 0.14, normals nearly uniform) lose about half, the rest far fewer.
  EXPECT_GT(returned, 800) << "at least 40% of draws return a direction";
}

TEST_P(FitSampling, IsReciprocalToTheBit) {
  const auto& [name, model] = GetParam();
  const auto material = makeMerlFitMaterial(fits(), name, model);
  for (const DirectionPair& p : testDirections(500, 11)) EXPECT_EQ(material->eval(p.wi, p.wo), material->eval(p.wo, p.wi));
}

INSTANTIATE_TEST_SUITE_P(Fits, FitSampling,
                         ::testing::Combine(::testing::ValuesIn(kSamplingMaterials),
                                            ::testing::Values(ModelFamily::Sgd, ModelFamily::Abc)),
                         [](const auto& info) {
                           std::string s = std::get<0>(info.param) + "_" + modelFamilyName(std::get<1>(info.param));
                           for (char& c : s) if (c == '-') c = '_';
                           return s;
                         });

TEST(FitModels, AlbedoAtMostOneUpTo60DegreesForEveryFit) {
  // Every fit of every material at theta_o = 0, 30, 60 deg (half-vector quadrature, 128 x 256).
  // Beyond 60 deg this does not hold for some SGD fits (next test), so it is not claimed there.
  for (const std::string& name : fits().names())
    for (ModelFamily model : fits().modelsFor(name)) {
      const auto material = makeMerlFitMaterial(fits(), name, model);
      for (float deg : {0.0f, 30.0f, 60.0f}) {
        const Rgb a = integrateAlbedoHalfVector(*material, glm::radians(deg), 128, 256);
        EXPECT_LE(a.maxComponent(), 1.0f) << modelFamilyName(model) << " " << name << " at " << deg << " deg";
        EXPECT_GE(a.minComponent(), 0.0f);
      }
    }
}

TEST(FitModels, SomePublishedSgdFitsExceedAlbedoOneAtGrazing) {
  // Documented, not hidden: the SGD fit of white-paint has rho_s = 4.1 in red, and its red albedo
  // passes 1 at 75 deg and grows towards grazing. Fits of measured data are only checked where
  // the measurements were, and MERL has little grazing data.
  const auto material = makeMerlFitMaterial(fits(), "white-paint", ModelFamily::Sgd);
  EXPECT_LT(integrateAlbedoHalfVector(*material, glm::radians(30.0f)).r, 1.0f);
  EXPECT_GT(integrateAlbedoHalfVector(*material, glm::radians(75.0f)).r, 1.0f);
}

TEST(FitModels, RejectInvalidParameters) {
  SgdParameters sgd;
  sgd.channel[1].alpha = 0;
  EXPECT_THROW((void)Sgd(sgd), Error);
  sgd.channel[1].alpha = 0.1;
  sgd.channel[2].c = std::nan("");
  EXPECT_THROW((void)Sgd(sgd), Error);
  AbcParameters abc;
  abc.b = -1;
  EXPECT_THROW((void)Abc(abc), Error);
  abc.b = 10;
  abc.ior = 0.5;
  EXPECT_THROW((void)Abc(abc), Error);
}

}  // namespace btf::test
