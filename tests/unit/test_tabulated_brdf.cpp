// TabulatedBrdf: a tabulated copy of each analytic model matches it within the table's
// interpolation error; the policies for holes and the horizon; reciprocity; sample/pdf agreement;
// tabulate() independent of the thread count.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "btf/core/half_diff.h"
#include "btf/core/math.h"
#include "btf/core/rng.h"
#include "btf/material/albedo.h"
#include "btf/material/ggx.h"
#include "btf/material/lafortune.h"
#include "btf/material/lambert.h"
#include "btf/material/phong.h"
#include "btf/material/tabulated_brdf.h"
#include "btf/material/ward.h"
#include "btf/core/warp.h"

namespace btf {
namespace {

// --- Accuracy against the analytic models -----------------------------------------------------

// Accuracy bounds on rel_rmse (RMSE of f cos(theta_i) over RMS of the reference's) per lookup, over
// direction pairs within 80 degrees of the normal.
//
// Why these bounds: trilinear interpolation of a smooth function errs by about (1/8) spacing^2 |f''|
// per axis. The lobes vary fastest in theta_h; for a lobe of width w there, f''/f ~ 1/w^2, and the
// sqrt mapping makes the theta_h spacing at theta_h = w equal to pi sqrt(w pi/2) / 90 rad, so the
// relative error scales as (spacing/w)^2 / 8 ~ 1/(90^2 w): interpolated bound = 6e-4 / w (a margin
// over the largest constant the models reach). Nearest lookup errs to first order,
// ~(spacing / w) / 2 ~ 1/sqrt(w): nearest bound = 0.025 / sqrt(w) (again with a margin).
// Widths w in theta_h: alpha for GGX and Ward; sqrt(2/n)/2 for cos^n lobes about the mirror
// direction (half the lobe's angular width, as theta_h moves half as fast as the mirror angle).
// Lambert is constant: any error beyond float rounding would be a lookup bug.
//
// Beyond 80 degrees the last theta_d cell (89 to 90 degrees) cannot resolve grazing Fresnel and
// masking, and cells below the horizon are unmeasured, so the rel_rmse over the full hemisphere is
// dominated by a few grazing pairs. It is reported and held
// below full_bound; Ward's f grows as 1/sqrt(cos theta_o) towards the horizon, which no table
// resolves, so it has no full-hemisphere bound.
struct AnalyticCase {
  std::string name;
  std::function<std::unique_ptr<Material>()> make;
  float lobe_width;  // w in theta_h (rad); 0 for a constant BRDF
  double full_bound;  // on the full hemisphere; 0: none (see above)
  double interpolatedBound() const { return lobe_width > 0 ? 6e-4 / lobe_width : 1e-5; }
  double nearestBound() const { return lobe_width > 0 ? 0.025 / std::sqrt(lobe_width) : 1e-5; }
};

float cosinePowerWidth(float n) { return std::sqrt(2.0f / n) / 2; }

std::vector<AnalyticCase> analyticCases() {
  const Rgb kd(0.3f, 0.2f, 0.1f), ks(0.4f, 0.5f, 0.6f);
  return {
      {"Lambert", [] { return std::make_unique<Lambert>(Rgb(0.8f, 0.5f, 0.2f)); }, 0, 1e-5},
      {"Phong20", [=] { return std::make_unique<Phong>(kd, ks, 20.0f); }, cosinePowerWidth(20), 0.15},
      {"Lafortune1", [=] { return std::make_unique<Lafortune>(kd, std::vector{LafortuneLobe{ks, {-0.6f, -0.6f, 0.55f}, 14.3f}}); },
       cosinePowerWidth(14.3f), 0.15},
      {"GgxAlpha0p1", [=] { return std::make_unique<Ggx>(kd, Rgb(0.9f, 0.6f, 0.3f), 0.1f, 0.1f); }, 0.1f, 0.15},
      {"GgxAlpha0p3", [=] { return std::make_unique<Ggx>(kd, Rgb(0.9f, 0.6f, 0.3f), 0.3f, 0.3f); }, 0.3f, 0.15},
      {"WardAlpha0p15", [=] { return std::make_unique<Ward>(kd, ks, 0.15f, 0.15f); }, 0.15f, 0},
  };
}

// One model and its table, built once per test (ctest runs each test in its own process).
struct Tabulated {
  std::unique_ptr<Material> analytic;
  std::shared_ptr<const MerlTable> table;
  explicit Tabulated(const AnalyticCase& c) : analytic(c.make()), table(std::make_shared<MerlTable>(tabulate(*analytic))) {}
};

// rel_rmse of f cos(theta_i), all channels, over pairs where wo is uniform on the hemisphere and wi
// is either uniform (half the pairs: the whole domain) or drawn by the model's own sampler (the
// other half: the lobes, where rendering looks and interpolation is hardest). 200,000 pairs drawn;
// those with a direction beyond max_theta from the normal are skipped. Across seeds the result
// varies by a few percent of itself.
double relRmseCosWeighted(const Material& reference, const Material& tabulated, float max_theta) {
  constexpr int kPairs = 200'000;
  const float min_cos = std::cos(max_theta);
  Rng rng(99);
  double err2 = 0, ref2 = 0;
  for (int n = 0; n < kPairs; ++n) {
    const glm::vec3 wo = squareToUniformHemisphere(rng.uniform2D());
    glm::vec3 wi = squareToUniformHemisphere(rng.uniform2D());
    if (n % 2 == 1) {
      const auto s = reference.sample(wo, {}, rng.uniform2D());
      if (!s) continue;
      wi = s->wi;
    }
    if (wi.z < min_cos || wo.z < min_cos) continue;
    const Rgb a = reference.eval(wi, wo) * wi.z, b = tabulated.eval(wi, wo) * wi.z;
    for (int c = 0; c < 3; ++c) {
      err2 += double(b[c] - a[c]) * (b[c] - a[c]);
      ref2 += double(a[c]) * a[c];
    }
  }
  return std::sqrt(err2 / ref2);
}

class TabulatedAnalytic : public ::testing::TestWithParam<AnalyticCase> {};

TEST_P(TabulatedAnalytic, LookupsMatchAnalyticWithinInterpolationError) {
  const AnalyticCase& c = GetParam();
  const Tabulated t(c);
  const TabulatedBrdf interpolated(t.table, TableLookup::Interpolated), nearest(t.table, TableLookup::Nearest);
  const float k80 = 80.0f * kPi / 180.0f;
  const double interpolated80 = relRmseCosWeighted(*t.analytic, interpolated, k80);
  const double nearest80 = relRmseCosWeighted(*t.analytic, nearest, k80);
  const double interpolated_full = relRmseCosWeighted(*t.analytic, interpolated, kHalfPi);
  std::printf("%s: rel_rmse within 80 deg: interpolated %.3g (bound %.3g), nearest %.3g (bound %.3g); "
              "full hemisphere interpolated %.3g\n",
              c.name.c_str(), interpolated80, c.interpolatedBound(), nearest80, c.nearestBound(), interpolated_full);
  RecordProperty("rel_rmse_interpolated_80deg", std::to_string(interpolated80));
  RecordProperty("rel_rmse_nearest_80deg", std::to_string(nearest80));
  RecordProperty("rel_rmse_interpolated_full", std::to_string(interpolated_full));
  EXPECT_LT(interpolated80, c.interpolatedBound());
  EXPECT_LT(nearest80, c.nearestBound());
  if (c.full_bound > 0) {
    EXPECT_LT(interpolated_full, c.full_bound);
  }
}

TEST_P(TabulatedAnalytic, AlbedoWithin2PercentOfAnalytic) {
  const Tabulated t(GetParam());
  const TabulatedBrdf tabulated(t.table, TableLookup::Interpolated);
  for (const float degrees : {0.0f, 30.0f, 60.0f}) {
    const float theta_o = degrees * kPi / 180.0f;
    const Rgb expected = integrateAlbedoHalfVector(*t.analytic, theta_o);
    const Rgb actual = integrateAlbedoHalfVector(tabulated, theta_o);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(actual[c], expected[c], 0.02f * expected[c]) << "theta_o " << degrees << " channel " << c;
  }
}

TEST_P(TabulatedAnalytic, TabulatedEvalIsReciprocal) {
  const Tabulated t(GetParam());
  const TabulatedBrdf interpolated(t.table, TableLookup::Interpolated), nearest(t.table, TableLookup::Nearest);
  Rng rng(5);
  int nearest_mismatches = 0;
  constexpr int kPairs = 20'000;
  for (int n = 0; n < kPairs; ++n) {
    const glm::vec3 wi = squareToUniformHemisphere(rng.uniform2D()), wo = squareToUniformHemisphere(rng.uniform2D());
    const Rgb a = interpolated.eval(wi, wo), b = interpolated.eval(wo, wi);
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(a[c], b[c], 1e-4f * a[c] + 1e-7f);
    nearest_mismatches += !(nearest.eval(wi, wo) == nearest.eval(wo, wi));
  }
  // Nearest lookup rounds; swapping wi and wo changes the coordinates by float rounding only, so
  // a different cell is picked only for pairs within ~1e-5 cells of a rounding boundary.
  EXPECT_LE(nearest_mismatches, kPairs / 1000);
}

INSTANTIATE_TEST_SUITE_P(Models, TabulatedAnalytic, ::testing::ValuesIn(analyticCases()),
                         [](const auto& info) { return info.param.name; });

// --- Policies ----------------------------------------------------------------------------------

MerlTable constantTable(const Rgb& f) {
  MerlTable table;
  for (std::size_t c = 0; c < MerlTable::kEntriesPerChannel; ++c) table.setReflectance(c, f);
  return table;
}

glm::vec3 randomUpper(Rng& rng) { return squareToUniformHemisphere(rng.uniform2D()); }

TEST(TabulatedBrdfPolicy, HolesInALambertTableStillGiveTheLambertValue) {
  const Rgb f(0.25f, 0.15f, 0.05f);
  auto table = std::make_shared<MerlTable>(constantTable(f));
  Rng rng(17);
  for (std::size_t c = 0; c < MerlTable::kEntriesPerChannel; ++c)
    if (rng.uniform() < 0.3f) table->setUnmeasured(c);
  for (int k = 0; k < MerlTable::kPhiDiffRes; ++k) table->setUnmeasured(MerlTable::index(10, 40, k));  // a row
  for (int j = 0; j < MerlTable::kThetaDiffRes; ++j)  // a whole theta_h slab
    for (int k = 0; k < MerlTable::kPhiDiffRes; ++k) table->setUnmeasured(MerlTable::index(20, j, k));
  for (const TableLookup lookup : {TableLookup::Interpolated, TableLookup::Nearest}) {
    const TabulatedBrdf brdf(table, lookup);
    for (int n = 0; n < 20000; ++n) {
      const Rgb value = brdf.eval(randomUpper(rng), randomUpper(rng));
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(value[c], f[c], 1e-5f * f[c]);
    }
  }
}

TEST(TabulatedBrdfPolicy, AllUnmeasuredTableEvaluatesToZeroNeverNaN) {
  auto table = std::make_shared<MerlTable>();
  for (std::size_t c = 0; c < MerlTable::kEntriesPerChannel; ++c) table->setUnmeasured(c);
  Rng rng(18);
  for (const TableLookup lookup : {TableLookup::Interpolated, TableLookup::Nearest}) {
    const TabulatedBrdf brdf(table, lookup);
    for (int n = 0; n < 10000; ++n) ASSERT_EQ(brdf.eval(randomUpper(rng), randomUpper(rng)), Rgb(0.0f));
  }
}

// Cell values encode their own indices, so a lookup reveals which cell it read.
MerlTable indexEncodingTable() {
  MerlTable table;
  for (int i = 0; i < MerlTable::kThetaHalfRes; ++i)
    for (int j = 0; j < MerlTable::kThetaDiffRes; ++j)
      for (int k = 0; k < MerlTable::kPhiDiffRes; ++k)
        table.setReflectance(MerlTable::index(i, j, k), Rgb(float(i + 1), float(j + 1), float(k + 1)));
  return table;
}

// Evaluates at continuous table coordinates (integers are the sample angles).
Rgb evalAt(const Material& m, double u_h, double u_d, double u_p, float phi_h) {
  HalfDiff hd;
  hd.theta_h = float((u_h / 90) * (u_h / 90) * kHalfPi);
  hd.theta_d = float(u_d * kPi / 180);
  hd.phi_d = float(u_p * kPi / 180);
  hd.phi_h = phi_h;
  const DirectionPair p = fromHalfDiff(hd);
  return m.eval(p.wi, p.wo);
}
Rgb evalAtCell(const Material& m, int i, int j, int k, float phi_h) { return evalAt(m, i, j, k, phi_h); }

TEST(TabulatedBrdfPolicy, LookupsAtSampleAnglesReadThatSample) {
  auto table = std::make_shared<MerlTable>(indexEncodingTable());
  const TabulatedBrdf nearest(table, TableLookup::Nearest), interpolated(table, TableLookup::Interpolated);
  Rng rng(19);
  for (int n = 0; n < 2000; ++n) {
    // theta_h + theta_d below 80 degrees keeps both directions above the horizon.
    // theta_h = 0 and theta_d = 0 are left out: there h or d is the pole and phi_h or phi_d is
    // undefined (an isotropic BRDF does not depend on phi_d there).
    const int i = 1 + int(rng.uniformInt(59)), j = 1 + int(rng.uniformInt(39)), k = int(rng.uniformInt(180));
    const float phi_h = kTwoPi * rng.uniform();
    const Rgb expected(float(i + 1), float(j + 1), float(k + 1));
    EXPECT_EQ(evalAtCell(nearest, i, j, k, phi_h), expected) << i << " " << j << " " << k;
    const Rgb value = evalAtCell(interpolated, i, j, k, phi_h);
    // Interpolation reads neighbours too, with weights of the order of the coordinate rounding.
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(value[c], expected[c], 0.01f) << i << " " << j << " " << k;
  }
}

// MERL's reader truncates: anywhere inside [i, i+1) x [j, j+1) x [k, k+1) it reads sample (i, j, k),
// where nearest lookup reads the closest sample (the upper one past the middle).
TEST(TabulatedBrdfPolicy, TruncatedLookupReadsTheSampleBelowLikeMerlsReader) {
  auto table = std::make_shared<MerlTable>(indexEncodingTable());
  const TabulatedBrdf truncated(table, TableLookup::Truncated), nearest(table, TableLookup::Nearest);
  Rng rng(23);
  for (int n = 0; n < 2000; ++n) {
    const int i = 1 + int(rng.uniformInt(59)), j = 1 + int(rng.uniformInt(39)), k = int(rng.uniformInt(179));
    // Fractions inside the cell, away from its edges by more than the coordinates' float rounding.
    const double fh = 0.6 + 0.3 * rng.uniform(), fd = 0.6 + 0.3 * rng.uniform(), fp = 0.6 + 0.3 * rng.uniform();
    const float phi_h = kTwoPi * rng.uniform();
    EXPECT_EQ(evalAt(truncated, i + fh, j + fd, k + fp, phi_h), Rgb(float(i + 1), float(j + 1), float(k + 1)))
        << i << " " << j << " " << k;
    EXPECT_EQ(evalAt(nearest, i + fh, j + fd, k + fp, phi_h), Rgb(float(i + 2), float(j + 2), float(k + 2)));
  }
  EXPECT_EQ(truncated.name(), "tabulated(lookup=truncated)");
}

TEST(TabulatedBrdfPolicy, NearestSkipsHolesAlongPhiThenThetaDiffThenThetaHalf) {
  auto table = std::make_shared<MerlTable>(indexEncodingTable());
  table->setUnmeasured(MerlTable::index(30, 20, 50));  // a hole: phi_d neighbours 49 and 51 tie
  for (int k = 0; k < MerlTable::kPhiDiffRes; ++k) table->setUnmeasured(MerlTable::index(30, 25, k));  // a row
  for (int j = 0; j < MerlTable::kThetaDiffRes; ++j)
    for (int k = 0; k < MerlTable::kPhiDiffRes; ++k) table->setUnmeasured(MerlTable::index(40, j, k));  // a slab
  const TabulatedBrdf nearest(table, TableLookup::Nearest);
  EXPECT_EQ(evalAtCell(nearest, 30, 20, 50, 0.3f), Rgb(31, 21, 50));  // ties go to the lower index
  EXPECT_EQ(evalAtCell(nearest, 30, 25, 70, 0.3f), Rgb(31, 25, 71));  // row below in theta_d
  EXPECT_EQ(evalAtCell(nearest, 40, 10, 70, 0.3f), Rgb(40, 11, 71));  // slab below in theta_h
  // Halfway between the hole (phi_d 50) and its measured neighbour (51, stored as 52), interpolation
  // gives the neighbour's value: the hole's weight goes to the measured corners, it is not a 0.
  const TabulatedBrdf interpolated(table, TableLookup::Interpolated);
  const Rgb blended = evalAt(interpolated, 30, 20, 50.5, 0.3f);
  EXPECT_NEAR(blended.b, 52.0f, 1e-3f);
  EXPECT_NEAR(blended.r, 31.0f, 1e-3f);
}

TEST(TabulatedBrdfPolicy, BelowTheHorizonIsZero) {
  const TabulatedBrdf brdf(std::make_shared<MerlTable>(constantTable(Rgb(0.1f))));
  Rng rng(20);
  for (int n = 0; n < 1000; ++n) {
    const glm::vec3 up = randomUpper(rng);
    glm::vec3 down = randomUpper(rng);
    down.z = -down.z;
    EXPECT_EQ(brdf.eval(up, down), Rgb(0.0f));
    EXPECT_EQ(brdf.eval(down, up), Rgb(0.0f));
  }
  EXPECT_EQ(brdf.eval({1, 0, 0}, {0, 0, 1}), Rgb(0.0f));  // exactly at the horizon
  EXPECT_EQ(brdf.eval({0, 0, 1}, {0, 0, 1}), Rgb(0.1f));
}

TEST(TabulatedBrdfPolicy, TabulateMarksCellsBelowTheHorizonUnmeasured) {
  const MerlTable table = tabulate(Lambert(Rgb(0.5f)));
  int below = 0;
  for (int i = 0; i < MerlTable::kThetaHalfRes; i += 7)
    for (int j = 0; j < MerlTable::kThetaDiffRes; j += 3)
      for (int k = 0; k < MerlTable::kPhiDiffRes; k += 11) {
        HalfDiff hd;
        hd.theta_h = float(MerlTable::thetaHalfOf(i));
        hd.theta_d = float(MerlTable::thetaDiffOf(j));
        hd.phi_d = float(MerlTable::phiDiffOf(k));
        const DirectionPair p = fromHalfDiff(hd);
        const bool visible = p.wi.z > 0 && p.wo.z > 0;
        below += !visible;
        EXPECT_EQ(table.isMeasured(MerlTable::index(i, j, k)), visible) << i << " " << j << " " << k;
      }
  EXPECT_GT(below, 0);
}

TEST(TabulatedBrdfSampling, SampleAndPdfAgree) {
  const TabulatedBrdf brdf(std::make_shared<MerlTable>(indexEncodingTable()));
  Rng rng(21);
  for (int n = 0; n < 20000; ++n) {
    const glm::vec3 wo = randomUpper(rng);
    const auto s = brdf.sample(wo, {}, rng.uniform2D());
    if (!s) continue;
    EXPECT_EQ(s->pdf, brdf.pdf(s->wi, wo));
    EXPECT_GT(s->wi.z, 0);
    const Rgb expected = brdf.eval(s->wi, wo) * (s->wi.z / s->pdf);
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(s->weight[c], expected[c], 1e-5f * expected[c]);
  }
  EXPECT_FALSE(brdf.sample({0, 0, -1}, {}, {0.3f, 0.7f}).has_value());
  EXPECT_EQ(brdf.pdf({0, 0, 1}, {0, 0, -1}), 0.0f);
  EXPECT_EQ(brdf.pdf({0, 0, -1}, {0, 0, 1}), 0.0f);
}

TEST(TabulatedBrdfSampling, PdfIntegratesToOne) {
  // Uniform-hemisphere Monte Carlo of int pdf dw: each term is 2 cos(theta) with cos uniform, so
  // with N = 10^5 the estimator's standard deviation is 2 / sqrt(12 N) = 0.18%; the bound is 5.5 of
  // those (a correct pdf fails with probability < 1e-7).
  const TabulatedBrdf brdf(std::make_shared<MerlTable>(constantTable(Rgb(0.1f))));
  Rng rng(22);
  constexpr int kN = 100'000;
  const glm::vec3 wo = sphericalDirection(0.8f, 1.0f);
  double sum = 0;
  for (int n = 0; n < kN; ++n) sum += brdf.pdf(randomUpper(rng), wo) / uniformHemispherePdf({0, 0, 1});
  EXPECT_NEAR(sum / kN, 1.0, 0.01);
}

// A smooth material that is deliberately not reciprocal: f grows with the light's elevation only.
class LightElevationWeighted final : public Material {
 public:
  Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 = {}) const override {
    if (wi.z <= 0 || wo.z <= 0) return {};
    return Rgb((0.2f + 0.6f * wi.z) * kInvPi);
  }
  std::optional<BsdfSample> sample(const glm::vec3&, glm::vec2, glm::vec2) const override { return std::nullopt; }
  float pdf(const glm::vec3&, const glm::vec3&, glm::vec2 = {}) const override { return 0; }
  std::string name() const override { return "light-elevation-weighted"; }
};

TEST(Tabulate, StoresTheReciprocalMeanOfANonReciprocalMaterial) {
  const LightElevationWeighted material;
  ASSERT_FALSE(material.isReciprocal());
  const TabulatedBrdf table(std::make_shared<const MerlTable>(tabulate(material)));
  Rng rng(11);
  double worst = 0;
  for (int n = 0; n < 2000; ++n) {
    const glm::vec3 wi = sphericalDirection(rng.uniform() * 1.3f, rng.uniform() * kTwoPi);
    const glm::vec3 wo = sphericalDirection(rng.uniform() * 1.3f, rng.uniform() * kTwoPi);
    const float mean = 0.5f * (material.eval(wi, wo).r + material.eval(wo, wi).r);
    worst = std::max(worst, double(std::abs(table.eval(wi, wo).r - mean) / mean));
  }
  // f is linear in cos(theta_i), so the only error left is the table's interpolation of it.
  EXPECT_LT(worst, 0.01) << "one order alone would differ by up to "
                         << (0.2 + 0.6 * 1.0) / (0.2 + 0.6 * std::cos(1.3)) - 1;
}

TEST(Tabulate, ResultDoesNotDependOnTheThreadCount) {
  const Ggx ggx(Rgb(0.2f), Rgb(0.9f, 0.6f, 0.3f), 0.2f, 0.2f);
  MerlTable one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = tabulate(ggx);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = tabulate(ggx);
  }
  EXPECT_EQ(std::memcmp(one.values.data(), two.values.data(), one.values.size() * sizeof(double)), 0);
}

}  // namespace
}  // namespace btf
