// Fits of analytic models to tables (fit/analytic_fit.h): the fitter's own formulas agree with the
// Material classes, parameters come back from tables of known models, and a table no model
// represents gets a poor rel_rmse rather than a claim of a good fit.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>

#include <tbb/global_control.h>

#include "support/tier.h"
#include "btf/core/error.h"
#include "btf/fit/analytic_fit.h"
#include "btf/fit/fit_file.h"
#include "btf/fit/merl_fits.h"
#include "btf/material/abc.h"
#include "btf/material/ggx.h"
#include "btf/material/ggx_two_lobes.h"
#include "btf/material/lafortune.h"
#include "btf/material/lambert.h"
#include "btf/material/tabulated_brdf.h"
#include "btf/material/ward.h"
#include "fit/fit_models.h"
#include "merl_fit_reference.h"
#include "support/test_support.h"
#include "fit_expectations.h"

namespace btf {
namespace {

namespace fs = std::filesystem;
using testing::HasSubstr;

glm::vec3 randomUpperDirection(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const float z = 0.05f + 0.95f * u(rng), phi = 6.2831853f * u(rng);
  const float r = std::sqrt(1.0f - z * z);
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// An SGD of the fitted form (analytic_fit.h): rho_d and rho_s per channel, one lobe shape.
AnalyticParameters sgdOf(const Rgb& rho_d, const Rgb& rho_s, const SgdChannel& shape) {
  AnalyticParameters p;
  p.family = ModelFamily::Sgd;
  p.diffuse = rho_d;
  p.specular = rho_s;
  p.sgd_shape = shape;
  return p;
}

void expectClose(const double* model, const Rgb& material, const char* what) {
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(model[c], material[c], 2e-4 * std::max(1.0, double(material[c]))) << what << " channel " << c;
}

// The templated formulas Ceres differentiates are the Material classes' formulas.
TEST(AnalyticFit, FitterFormulasMatchTheMaterials) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const glm::vec3 wi = randomUpperDirection(rng), wo = randomUpperDirection(rng);
    const fit::FitSample s = fit::geometryOf(wi, wo);
    const double alpha = 0.05 + 0.01 * (trial % 40);
    {
      const double p[7] = {0.2, 0.5, 0.7, 0.04, 0.3, 0.9, std::log(alpha)};
      double f[3];
      fit::evalGgx(p, s, f);
      expectClose(f, Ggx(Rgb(0.2f, 0.5f, 0.7f), Rgb(0.04f, 0.3f, 0.9f), float(alpha), float(alpha)).eval(wi, wo), "ggx");
    }
    {
      const double p[7] = {0.2, 0.5, 0.7, 0.04, 0.3, 0.9, std::log(alpha)};
      double f[3];
      fit::evalWard(p, s, f);
      expectClose(f, Ward(Rgb(0.2f, 0.5f, 0.7f), Rgb(0.04f, 0.3f, 0.9f), float(alpha), float(alpha)).eval(wi, wo), "ward");
    }
    {
      const double beta0 = 2.2, beta1 = 2.6, n0 = 40.0, n1 = 3.0;
      const double p[13] = {0.1, 0.2, 0.3, beta0, std::log(n0), 0.3, 0.2, 0.1, beta1, std::log(n1), 0.05, 0.1, 0.15};
      double f[3];
      fit::evalLafortune<3, 2>(p, s, f);
      const auto c = [](double beta) { return glm::vec3(float(std::cos(beta)), float(std::cos(beta)), float(std::sin(beta))); };
      const Lafortune material(Rgb(0.1f, 0.2f, 0.3f), {{Rgb(0.3f, 0.2f, 0.1f), c(beta0), float(n0)},
                                                       {Rgb(0.05f, 0.1f, 0.15f), c(beta1), float(n1)}});
      expectClose(f, material.eval(wi, wo), "lafortune");
    }
    {
      const double p[11] = {0.2, 0.5, 0.7, 0.04, 0.3, 0.9, std::log(alpha), 0.6, 0.5, 0.4, std::log(0.03)};
      double f[3];
      fit::evalGgx2(p, s, f);
      expectClose(f, GgxTwoLobes(Rgb(0.2f, 0.5f, 0.7f), Rgb(0.04f, 0.3f, 0.9f), float(alpha), Rgb(0.6f, 0.5f, 0.4f), 0.03f).eval(wi, wo),
                  "ggx2");
    }
    {
      const double p[9] = {0.02, 0.03, 0.04, std::log(51.7), std::log(37.9), std::log(27.4), std::log(10482.1), 0.8167, 2.2365};
      double f[3];
      fit::evalAbc(p, s, f);
      expectClose(f, Abc(AbcParameters{Rgb(0.02f, 0.03f, 0.04f), Rgb(51.7f, 37.9f, 27.4f), 10482.1, 0.8167, 2.2365}).eval(wi, wo),
                  "abc");
    }
    {
      const double w = 1.3 + 0.005 * (trial % 40);  // the shadowing's width, radians: G1 from 1 down to 0 near grazing
      const double p[12] = {0.05, 0.03, 0.02, std::log(12.5), std::log(7.25), std::log(3.5), std::log(0.2 * alpha), 0.46, 0.06, -0.015,
                            3.1, w};
      double f[3];
      fit::evalSgd(p, s, f);
      const AnalyticParameters sgd = sgdOf(Rgb(0.05f, 0.03f, 0.02f), Rgb(12.5f, 7.25f, 3.5f),
                                           {0, 0, 0.2 * alpha, 0.46, 0.06, -0.015, 1.0, 3.1, std::pow(w, -fit::kSgdFitK), fit::kSgdFitK, 0.0});
      expectClose(f, makeAnalyticMaterial(sgd)->eval(wi, wo), "sgd");
    }
  }
}

AnalyticFit fitTableOf(const Material& truth, const AnalyticFitOptions& options) {
  return fitAnalytic(tabulate(truth), options);
}

// Noiseless tables of known models: the fit finds the parameters within 5% (the project's target)
// and reproduces the table.
BTF_SLOW_TEST(AnalyticFit, RecoversGgxParametersFromItsTable) {
  const Rgb kd(0.3f, 0.2f, 0.1f), f0(0.04f, 0.05f, 0.06f);
  const Ggx truth(kd, f0, 0.15f, 0.15f);
  AnalyticFitOptions options;
  options.objective = FitObjective::Log;
  options.family = ModelFamily::Ggx;
  const AnalyticFit fit = fitTableOf(truth, options);
  test::expectGgxRecovered(fit.parameters, kd, f0, 0.15f, 0.05f);
  EXPECT_LT(fit.report.rel_rmse, 0.01);
  EXPECT_TRUE(fit.report.converged) << fit.report.ceres_report;
}

BTF_SLOW_TEST(AnalyticFit, RecoversWardParametersFromItsTable) {
  const Rgb kd(0.1f, 0.3f, 0.5f), ks(0.2f, 0.15f, 0.1f);
  const Ward truth(kd, ks, 0.1f, 0.1f);
  AnalyticFitOptions options;
  options.objective = FitObjective::Log;
  options.family = ModelFamily::Ward;
  const AnalyticFit fit = fitTableOf(truth, options);
  EXPECT_NEAR(fit.parameters.alpha, 0.1f, 0.005f);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(fit.parameters.diffuse[c], kd[c], 0.05f * kd[c]) << c;
    EXPECT_NEAR(fit.parameters.specular[c], ks[c], 0.05f * ks[c]) << c;
  }
  EXPECT_LT(fit.report.rel_rmse, 0.01);
}

BTF_SLOW_TEST(AnalyticFit, RecoversOneLafortuneLobeFromItsTable) {
  const Rgb kd(0.2f, 0.2f, 0.1f), rho(0.3f, 0.4f, 0.5f);
  const Lafortune truth(kd, {{rho, glm::vec3(-1.0f, -1.0f, 1.0f), 60.0f}});
  AnalyticFitOptions options;
  options.objective = FitObjective::Log;
  options.family = ModelFamily::Lafortune;
  const AnalyticFit fit = fitTableOf(truth, options);
  ASSERT_EQ(fit.parameters.lobes.size(), 1u);
  const LafortuneLobe& lobe = fit.parameters.lobes[0];
  EXPECT_NEAR(lobe.exponent, 60.0f, 3.0f);
  EXPECT_NEAR(lobe.c.z / -lobe.c.x, 1.0f, 0.05f);  // the direction of c; its scale is arbitrary
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(fit.parameters.diffuse[c], kd[c], 0.05f * kd[c]) << c;
    EXPECT_NEAR(lobe.rho[c], rho[c], 0.05f * rho[c]) << c;
  }
  EXPECT_LT(fit.report.rel_rmse, 0.01);
}

// Stability: what measurements do to a table the fit must survive, each with a stated tolerance.
// Multiplicative lognormal noise of sigma 0.1 per cell and channel (three times the generator's
// default): the parameters stay within 5%, and rel_rmse reports the noise instead of hiding it.
BTF_SLOW_TEST(AnalyticFit, RecoversGgxFromANoisyTable) {
  const Rgb kd(0.3f, 0.2f, 0.1f), f0(0.04f);
  MerlTable table = tabulate(Ggx(kd, f0, 0.2f, 0.2f));
  std::mt19937 rng(17);
  std::normal_distribution<double> gauss(0.0, 0.1);
  for (double& v : table.values)
    if (v > 0) v *= std::exp(gauss(rng) - 0.005);  // mean 1
  AnalyticFitOptions options;
  options.objective = FitObjective::Log;
  options.family = ModelFamily::Ggx;
  options.starts = 3;
  const AnalyticFit fit = fitAnalytic(table, options);
  EXPECT_NEAR(fit.parameters.alpha, 0.2f, 0.05f * 0.2f);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(fit.parameters.diffuse[c], kd[c], 0.05f * kd[c]) << c;
  EXPECT_NEAR(fit.parameters.specular[0], 0.04f, 0.05f * 0.04f);
  EXPECT_GT(fit.report.rel_rmse, 0.05);  // the noise, reported
  EXPECT_LT(fit.report.rel_rmse, 0.2);
}

// Four cells in five unmeasured, at random: the fit uses the rest and recovers the model.
BTF_SLOW_TEST(AnalyticFit, RecoversWardFromAMostlyUnmeasuredTable) {
  const Rgb kd(0.2f, 0.3f, 0.4f), ks(0.1f);
  MerlTable table = tabulate(Ward(kd, ks, 0.15f, 0.15f));
  std::mt19937 rng(23);
  for (std::size_t i = 0; i < MerlTable::kEntriesPerChannel; ++i)
    if (rng() % 5 != 0) table.setUnmeasured(i);
  AnalyticFitOptions options;
  options.objective = FitObjective::Log;
  options.family = ModelFamily::Ward;
  options.starts = 3;
  const AnalyticFit fit = fitAnalytic(table, options);
  EXPECT_GT(fit.report.excluded, 4 * fit.report.samples);
  EXPECT_NEAR(fit.parameters.alpha, 0.15f, 0.05f * 0.15f);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(fit.parameters.diffuse[c], kd[c], 0.05f * kd[c]) << c;
  EXPECT_LT(fit.report.rel_rmse, 0.01);
}

// A near-mirror (GGX alpha 0.02, the chrome preset's): its whole highlight lies in the first few
// theta_h cells of the table. The fit still finds it (alpha within 10%: a few cells resolve the
// width coarsely) and says how well it reproduces the table.
BTF_SLOW_TEST(AnalyticFit, RecoversANearMirrorGgx) {
  const Rgb kd(0.01f), f0(0.55f, 0.56f, 0.55f);
  AnalyticFitOptions options;
  options.objective = FitObjective::Log;
  options.family = ModelFamily::Ggx;
  options.starts = 4;
  const AnalyticFit fit = fitTableOf(Ggx(kd, f0, 0.02f, 0.02f), options);
  EXPECT_NEAR(fit.parameters.alpha, 0.02f, 0.1f * 0.02f);
  EXPECT_NEAR(fit.parameters.specular[1], 0.56f, 0.1f * 0.56f);
  EXPECT_LT(fit.report.rel_rmse, 0.05);
}

// The published ABC fit of MERL's blue-acrylic, tabulated: a narrow tall highlight on long tails,
// which no single GGX lobe matches. The robust log objective lets the few peak cells go (its
// rel_rmse, a linear measure, is several times the data); the linear objective minimizes that
// measure and must win on it, and the linear fit must at least match the published SGD fit.
BTF_SLOW_TEST(AnalyticFit, RecoversANarrowHighlightOnLongTailsBestWithTheLinearObjective) {
  const MerlFits fits = MerlFits::load(test::fitsDir());
  const MerlTable table = tabulate(*makeMerlFitMaterial(fits, "blue-acrylic", ModelFamily::Abc));
  AnalyticFitOptions options;
  options.family = ModelFamily::Ggx;
  options.objective = FitObjective::Log;
  options.energy_weight = 0;  // the objectives alone: one GGX lobe cannot also hold this table's albedo
  const AnalyticFit log_fit = fitAnalytic(table, options);
  options.objective = FitObjective::Linear;
  const AnalyticFit linear_fit = fitAnalytic(table, options);
  const double sgd = tableRelRmse(*makeMerlFitMaterial(fits, "blue-acrylic", ModelFamily::Sgd), table);
  EXPECT_LT(linear_fit.report.rel_rmse, 0.5 * log_fit.report.rel_rmse);
  EXPECT_LT(linear_fit.report.rel_rmse, sgd);
  EXPECT_EQ(parseFitObjective("linear"), FitObjective::Linear);
  EXPECT_THROW((void)parseFitObjective("cubic"), Error);
}

// A retro-reflective lobe (c = (1, 1, 1): the lobe points back to the light) is not a GGX
// highlight: the fit must say so by its rel_rmse, not by a claim of convergence alone.
BTF_SLOW_TEST(AnalyticFit, AModelThatCannotRepresentTheTableReportsAPoorFit) {
  const Lafortune retro(Rgb(0.05f), {{Rgb(0.6f), glm::vec3(1.0f, 1.0f, 1.0f), 30.0f}});
  AnalyticFitOptions options;
  options.objective = FitObjective::Log;
  options.family = ModelFamily::Ggx;
  options.starts = 2;
  options.max_iterations = 20;  // enough to see it fail; a converged GGX fits no better
  const AnalyticFit fit = fitTableOf(retro, options);
  EXPECT_GT(fit.report.rel_rmse, 0.3);
  EXPECT_GT(tableRelRmse(*fit.material, tabulate(retro)), 0.3);
}

BTF_SLOW_TEST(AnalyticFit, UnmeasuredCellsAreLeftOut) {
  const Ggx truth(Rgb(0.3f), Rgb(0.04f), 0.2f, 0.2f);
  MerlTable table = tabulate(truth);
  // Every 7th cell: a stride prime to the fitting grid's, so sampled cells are among them.
  for (std::size_t i = 0; i < MerlTable::kEntriesPerChannel; i += 7) table.setUnmeasured(i);
  AnalyticFitOptions options;
  options.family = ModelFamily::Ggx;
  options.objective = FitObjective::Log;
  options.starts = 2;
  const AnalyticFit fit = fitAnalytic(table, options);
  EXPECT_GT(fit.report.excluded, 0u);
  EXPECT_NEAR(fit.parameters.alpha, 0.2f, 0.01f);
  EXPECT_LT(fit.report.rel_rmse, 0.01);
}

// The starts run in parallel; which one wins may not depend on how many threads ran them.
BTF_SLOW_TEST(AnalyticFit, TheSameFitOnOneThreadAndOnSeveral) {
  const MerlTable table = tabulate(Ward(Rgb(0.2f), Rgb(0.1f), 0.2f, 0.2f));
  AnalyticFitOptions options;
  options.objective = FitObjective::Log;
  options.family = ModelFamily::Ward;
  options.starts = 3;
  options.max_iterations = 3;
  AnalyticParameters one, several;
  {
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 1);
    one = fitAnalytic(table, options).parameters;
  }
  {
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 3);
    several = fitAnalytic(table, options).parameters;
  }
  EXPECT_EQ(one.alpha, several.alpha);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(one.diffuse[c], several.diffuse[c]);
    EXPECT_EQ(one.specular[c], several.specular[c]);
  }
}

// The energy term. The published ABC fit of gold-metallic-paint, tabulated: a sharp flake sparkle
// over a broad base, which one GGX lobe cannot match. The log objective alone trades the shape for
// energy (its albedo ends far above the data's); with the energy term the fit's albedo stays within
// the report's 10% at theta_o 0, 30 and 60 degrees, and the report says how far it is.
BTF_SLOW_TEST(AnalyticFit, TheEnergyTermHoldsTheAlbedoOfAMetallicPaint) {
  const MerlFits fits = MerlFits::load(test::fitsDir());
  const MerlTable table = tabulate(*makeMerlFitMaterial(fits, "gold-metallic-paint", ModelFamily::Abc));
  AnalyticFitOptions options;
  options.family = ModelFamily::Ggx;
  options.objective = FitObjective::Log;
  options.starts = 3;
  const AnalyticFit held = fitAnalytic(table, options);
  ASSERT_EQ(held.report.albedo.size(), kAlbedoCheckAnglesDeg.size());
  double worst_held = 0;
  for (const AlbedoCheck& a : held.report.albedo) worst_held = std::max(worst_held, a.rel_error);
  EXPECT_LE(worst_held, kFitAlbedoTolerance);
  options.energy_weight = 0;
  const AnalyticFit free = fitAnalytic(table, options);
  double worst_free = 0;
  for (const AlbedoCheck& a : free.report.albedo) worst_free = std::max(worst_free, a.rel_error);
  EXPECT_GT(worst_free, 2 * worst_held);
}

// ABC is fittable: the published ABC fit of alum-bronze, tabulated, gives its parameters back, so
// `btf fit --model abc` compares with the literature on the literature's own model.
BTF_SLOW_TEST(AnalyticFit, RecoversThePublishedAbcFitFromItsTable) {
  const MerlFits fits = MerlFits::load(test::fitsDir());
  const MerlTable table = tabulate(*makeMerlFitMaterial(fits, "alum-bronze", ModelFamily::Abc));
  AnalyticFitOptions options;
  options.objective = FitObjective::Log;
  options.family = ModelFamily::Abc;
  options.starts = 2;
  const AnalyticFit fit = fitAnalytic(table, options);
  const AbcFit* published = fits.findAbc("alum-bronze");
  ASSERT_NE(published, nullptr);
  EXPECT_LT(fit.report.rel_rmse, 0.01);
  EXPECT_NEAR(fit.parameters.abc_c, published->parameters.c, 0.02 * published->parameters.c);
  EXPECT_NEAR(fit.parameters.abc_b, published->parameters.b, 0.02 * published->parameters.b);
  EXPECT_NEAR(fit.parameters.abc_ior, published->parameters.ior, 0.02 * published->parameters.ior);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(fit.parameters.specular[c], published->parameters.a[c], 0.02f * published->parameters.a[c]) << c;
}

// SGD is fittable in its fitted form (one lobe shape for all channels, the shadowing's k and theta0
// fixed, kap 1: analytic_fit.h): a table of such an SGD gives its parameters back.
BTF_SLOW_TEST(AnalyticFit, RecoversAnSgdOfTheFittedFormFromItsTable) {
  const AnalyticParameters truth =
      sgdOf(Rgb(0.06f, 0.04f, 0.02f), Rgb(8.0f, 5.0f, 3.0f), {0, 0, 0.02, 0.45, 0.08, 0.01, 1.0, 2.0, std::pow(1.4, -25.0), 25.0, 0.0});
  const MerlTable table = tabulate(*makeAnalyticMaterial(truth));
  AnalyticFitOptions options;
  options.family = ModelFamily::Sgd;
  options.starts = 2;
  const AnalyticFit fit = fitAnalytic(table, options);
  EXPECT_LT(fit.report.rel_rmse, 0.01);
  const SgdChannel& g = fit.parameters.sgd_shape;
  EXPECT_NEAR(g.alpha, 0.02, 0.002);
  EXPECT_NEAR(g.p, 0.45, 0.05);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(fit.parameters.diffuse[c], truth.diffuse[c], 0.005f) << c;
  EXPECT_TRUE(fit.report.warnings.empty());
  // Without shadowing (lambda 0) a width whose c overflows exp still gives a finite SGD.
  const AnalyticParameters unshadowed =
      sgdOf(Rgb(0.06f, 0.04f, 0.02f), Rgb(8.0f), {0, 0, 0.02, 0.45, 0.08, 0.01, 1.0, 0.0, std::pow(0.5, -25.0), 25.0, 0.0});
  const Rgb f = makeAnalyticMaterial(unshadowed)->eval(glm::normalize(glm::vec3(0.9f, 0.0f, 0.2f)), glm::vec3(0, 0, 1));
  EXPECT_TRUE(f.isFinite());
  EXPECT_GT(f.r, 0.0f);
}

TEST(AnalyticFit, WarningsNameWhatIsWrong) {
  AnalyticFitReport r;
  r.converged = true;
  r.rel_rmse = 0.3;
  r.albedo = {albedoCheck(0, Rgb(0.5f), Rgb(0.52f)), albedoCheck(30, Rgb(0.5f), Rgb(0.5f)), albedoCheck(60, Rgb(0.5f), Rgb(0.5f))};
  EXPECT_TRUE(fitWarnings(r).empty());
  r.albedo[2] = albedoCheck(60, Rgb(0.5f), Rgb(1.2f));
  r.rel_rmse = 4.0;
  r.converged = false;
  const std::vector<std::string> w = fitWarnings(r);
  ASSERT_EQ(w.size(), 3u);
  EXPECT_THAT(w[0], HasSubstr("did not converge"));
  EXPECT_THAT(w[1], HasSubstr("rel_rmse 4 is above 0.5"));
  EXPECT_THAT(w[2], HasSubstr("albedo at theta_o 60 deg is 1.2000, the data's 0.5000 (+140%"));
  // A fit explaining less than half of the signal warns, and so does a parameter at a bound.
  AnalyticFitReport half;
  half.converged = true;
  half.rel_rmse = 0.51;
  EXPECT_TRUE(isDegenerateFit(half));
  ASSERT_EQ(fitWarnings(half).size(), 1u);
  EXPECT_THAT(fitWarnings(half)[0], HasSubstr("rel_rmse 0.51 is above 0.5"));
  half.rel_rmse = 0.49;
  EXPECT_FALSE(isDegenerateFit(half));
  EXPECT_TRUE(fitWarnings(half).empty());
  half.at_bound = {"B 1e+08, its upper bound"};
  EXPECT_TRUE(isDegenerateFit(half));
  ASSERT_EQ(fitWarnings(half).size(), 1u);
  EXPECT_THAT(fitWarnings(half)[0], HasSubstr("degenerate fit: B 1e+08, its upper bound"));
}

TEST(AnalyticFit, BadOptionsAndEmptyTablesAreErrors) {
  MerlTable empty;
  for (std::size_t i = 0; i < MerlTable::kEntriesPerChannel; ++i) empty.setUnmeasured(i);
  AnalyticFitOptions options;
  options.family = ModelFamily::Ggx;
  options.objective = FitObjective::Log;
  try {
    (void)fitAnalytic(empty, options);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("measured cells"));
  }
  const MerlTable table = tabulate(Ggx(Rgb(0.3f), Rgb(0.04f), 0.2f, 0.2f));
  options.lobes = 2;
  EXPECT_THROW((void)fitAnalytic(table, options), Error);  // lobes are for lafortune only
  options.family = ModelFamily::Lafortune;
  options.lobes = 4;
  EXPECT_THROW((void)fitAnalytic(table, options), Error);
  EXPECT_THROW((void)parseModelFamily("phong", kFittableFamilies), Error);
  try {  // a black table: nothing to fit
    (void)fitAnalytic(tabulate(Lambert(Rgb(0.0f))), AnalyticFitOptions{});
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_THAT(e.what(), HasSubstr("reflects nothing"));
  }
  EXPECT_EQ(parseModelFamily("ward", kFittableFamilies), ModelFamily::Ward);
}

// The fit file keeps every parameter exactly (floats through JSON doubles) for each model.
TEST(AnalyticFitFile, RoundTripsEveryModel) {
  test::TempDir dir;
  AnalyticFit fit;
  fit.report.rel_rmse = 0.25;
  std::vector<AnalyticParameters> models(5);
  models[0] = {ModelFamily::Ggx, Rgb(0.1f, 0.2f, 0.3f), Rgb(0.04f, 0.5f, 1.0f), 0.123456f, {}};
  models[1] = {ModelFamily::Ward, Rgb(0.3f, 0.2f, 0.1f), Rgb(0.7f, 0.01f, 0.02f), 0.0345f, {}};
  models[2] = {ModelFamily::Lafortune, Rgb(0.05f), Rgb(), 0.0f,
               {{Rgb(0.3f, 0.2f, 0.1f), glm::vec3(-0.7f, -0.7f, 0.71f), 37.5f}, {Rgb(0.0f, 0.0f, 0.2f), glm::vec3(0.9f, 0.9f, 0.4f), 3.25f}}};
  models[3] = {ModelFamily::Ggx2, Rgb(0.1f, 0.2f, 0.3f), Rgb(0.04f, 0.5f, 1.0f), 0.31f, {}, Rgb(0.9f, 0.8f, 0.7f), 0.0123f};
  models[4] = {ModelFamily::Abc, Rgb(0.02f, 0.03f, 0.04f), Rgb(51.7f, 37.9f, 27.4f), 0.0f, {}, {}, 0.0f, 10482.1, 0.8167, 2.2365};
  models.push_back(sgdOf(Rgb(0.05f, 0.03f, 0.02f), Rgb(12.5f, 7.25f, 3.5f), {0, 0, 0.0123, 0.459, 0.0605, -0.0155, 1.0, 3.12, 1.71e-5, 25.0, 0.0}));
  for (const AnalyticParameters& p : models) {
    fit.parameters = p;
    const fs::path path = dir / (std::string(modelFamilyName(p.family)) + ".json");
    writeFitFile(path, fit, "source.binary");
    const AnalyticParameters back = readFitFile(path);
    EXPECT_EQ(back.family, p.family);
    const glm::vec3 wi = glm::normalize(glm::vec3(0.2f, 0.1f, 1.0f)), wo = glm::normalize(glm::vec3(-0.3f, 0.0f, 1.0f));
    const Rgb a = makeAnalyticMaterial(p)->eval(wi, wo), b = makeAnalyticMaterial(back)->eval(wi, wo);
    EXPECT_EQ(a.r, b.r);
    EXPECT_EQ(a.g, b.g);
    EXPECT_EQ(a.b, b.b);
    ASSERT_EQ(back.lobes.size(), p.lobes.size());
    for (std::size_t i = 0; i < p.lobes.size(); ++i) EXPECT_EQ(back.lobes[i].exponent, p.lobes[i].exponent);
  }
}

TEST(AnalyticFitFile, ErrorsNameTheFileAndTheKey) {
  test::TempDir dir;
  const auto expectError = [&](const std::string& text, const std::string& part) {
    const fs::path path = dir / "bad.json";
    std::ofstream(path) << text;
    try {
      (void)readFitFile(path);
      ADD_FAILURE() << "no error for " << text;
    } catch (const FileError& e) {
      EXPECT_THAT(e.what(), HasSubstr(path.string()));
      EXPECT_THAT(e.what(), HasSubstr(part)) << text;
    }
  };
  const std::string head = R"({"format": "libbtf-fit", "version": 1, )";
  expectError("{", "malformed JSON");
  expectError(R"({"format": "scene", "version": 1})", "/format");
  expectError(R"({"format": "libbtf-fit", "version": 2})", "/version: 2");
  expectError(head + R"("model": "phong", "parameters": {}})", "unknown model 'phong' (expected lafortune, ggx, ward, ggx2, abc or sgd)");
  expectError(head + R"("model": "ggx", "parameters": {"diffuse": [0.1, 0.1, 0.1], "f0": [0, 0, 0]}})", "missing \"alpha\"");
  expectError(head + R"("model": "ggx", "parameters": {"diffuse": [0.1, 0.1, 0.1], "f0": [0, 0, 0], "alpha": -1}})",
              "/parameters/alpha");
  expectError(head + R"("model": "ward", "parameters": {"diffuse": [0.1, 0.1], "specular": [0, 0, 0], "alpha": 1}})",
              "/parameters/diffuse: expected [r, g, b]");
  expectError(head + R"("model": "ggx", "parameters": {"diffuse": [0.1, 0.1, 0.1], "f0": [0, 0, 0], "alpha": 1, "beta": 2}})",
              "unknown key \"beta\"");
  expectError(head + R"("model": "lafortune", "parameters": {"diffuse": [0.1, 0.1, 0.1], "lobes": []}})", "one or more lobes");
  expectError(head + R"("model": "lafortune", "parameters": {"diffuse": [0.1, 0.1, 0.1],
              "lobes": [{"rho": [0.1, 0.1, 0.1], "c": [0, 0, 0], "exponent": 2}]}})", "/parameters:");
  expectError(head + R"("model": "lafortune", "parameters": {"diffuse": [0.1, 0.1, 0.1],
              "lobes": [{"rho": [0.1, 0.1, 0.1], "c": [1, 1, 1e400], "exponent": 2}]}})", "malformed JSON");
  EXPECT_THROW((void)readFitFile(dir / "missing.json"), FileError);
}

// A near-mirror (GGX, alpha 0.003: its peak within the first few theta_h cells): a fit that gives
// up the lobe must say so, and the default fit must not end degenerate without saying so. ABC
// alone either follows the peak (rel_rmse <= 0.5, no parameter at a bound) or warns naming why;
// the default (ABC with its SGD fallback) ends with a fit that is not degenerate, or, where SGD
// degenerates too, with warnings and its fallback line.
TEST(AnalyticFit, MirrorLikeTableNeverFitsSilentlyDegenerate) {
  const MerlTable table = tabulate(Ggx(Rgb(0.0f), Rgb(0.55f, 0.56f, 0.55f), 0.003f, 0.003f));
  AnalyticFitOptions abc;
  abc.starts = 2;
  abc.fallback.reset();
  const AnalyticFit alone = fitAnalytic(table, abc);
  if (isDegenerateFit(alone.report)) {
    EXPECT_FALSE(alone.report.warnings.empty());
  }
  AnalyticFitOptions defaults;
  defaults.starts = 2;
  const AnalyticFit fit = fitAnalytic(table, defaults);
  std::printf("abc alone: rel_rmse %.4f, at_bound %zu; default %s rel_rmse %.4f, %s\n", alone.report.rel_rmse,
              alone.report.at_bound.size(), modelFamilyName(fit.parameters.family), fit.report.rel_rmse, fit.report.fallback.c_str());
  for (const std::string& w : alone.report.warnings) std::printf("  abc warning: %s\n", w.c_str());
  for (const std::string& w : fit.report.warnings) std::printf("  default warning: %s\n", w.c_str());
  if (isDegenerateFit(alone.report)) {
    EXPECT_THAT(fit.report.fallback, HasSubstr("abc's fit was degenerate"));
  }
  EXPECT_LE(fit.report.rel_rmse, alone.report.rel_rmse);
  EXPECT_FALSE(isDegenerateFit(fit.report)) << fit.report.fallback;
}

// A table no half-vector lobe can follow (a Lafortune retroreflector, its lobe about wi = wo):
// ABC alone is degenerate, the default fits SGD too and says so, keeps the closer fit, and a kept
// fit that is still degenerate carries its warnings: never a silent degenerate fit.
TEST(AnalyticFit, DefaultFallsBackAndWarnsWhereAbcDegenerates) {
  const MerlTable table = tabulate(Lafortune(Rgb(0.05f), {LafortuneLobe{Rgb(0.8f), glm::vec3(1.0f), 8.0f}}));
  AnalyticFitOptions abc;
  // One start of few iterations and no energy term (whose raises repeat each fit): the
  // retroreflection is out of every half-vector lobe's reach however long the solver runs, and
  // the fallback's logic is what is under test.
  abc.starts = 1;
  abc.max_iterations = 25;
  abc.energy_weight = 0;
  abc.fallback.reset();
  const AnalyticFit alone = fitAnalytic(table, abc);
  ASSERT_TRUE(isDegenerateFit(alone.report)) << alone.report.rel_rmse;
  EXPECT_FALSE(alone.report.warnings.empty());
  EXPECT_TRUE(alone.report.fallback.empty());
  AnalyticFitOptions defaults;
  defaults.starts = abc.starts;
  defaults.max_iterations = abc.max_iterations;
  defaults.energy_weight = abc.energy_weight;
  const AnalyticFit fit = fitAnalytic(table, defaults);
  EXPECT_THAT(fit.report.fallback, HasSubstr("abc's fit was degenerate"));
  EXPECT_THAT(fit.report.fallback, HasSubstr("sgd fitted too"));
  EXPECT_LE(fit.report.rel_rmse, alone.report.rel_rmse);
  if (isDegenerateFit(fit.report)) {
    EXPECT_FALSE(fit.report.warnings.empty());
  }
}

}  // namespace
}  // namespace btf
