// Bonn .btf files (btf/io/bonn_btf.h): the reader against files built byte by byte from the
// format's description (support/bonn_btf_bytes.h), the writers by round trips, and the errors of
// bad files.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <fstream>

#include "btf/compress/compressibility.h"
#include "btf/compress/pca.h"
#include "btf/compress/vq_btf.h"
#include "btf/core/btf_direction_set.h"
#include "btf/core/math.h"
#include "btf/io/bonn_btf.h"
#include "btf/material/material.h"
#include "btf/material/registry.h"
#include "btf_test_data.h"
#include "support/bonn_btf_bytes.h"
#include "support/test_support.h"

namespace btf {
namespace {

using test::BonnAngles;
using test::BonnFactorBytes;
using test::BonnFileSpec;
using test::errorOf;
using ::testing::HasSubstr;

constexpr float kDeg = kPi / 180.0f;

// A small scattered set: 3 views, 4 lights each (the third view's second light moved aside when
// `shifted`).
BonnFileSpec smallSampling(bool shifted = false) {
  BonnFileSpec s;
  s.views = {{0, 0}, {30 * kDeg, 0}, {60 * kDeg, 90 * kDeg}};
  const std::vector<BonnAngles> lights = {{0, 0}, {20 * kDeg, 45 * kDeg}, {40 * kDeg, 180 * kDeg}, {70 * kDeg, -90 * kDeg}};
  s.lights = {lights, lights, lights};
  if (shifted) s.lights[2][1] = {25 * kDeg, 50 * kDeg};
  s.width = 3;
  s.height = 2;
  return s;
}

// A deterministic pseudo-random matrix entry.
double entry(std::uint32_t seed, std::size_t i) { return 0.2 + 0.6 * double((seed * 2654435761u + i * 40503u) % 1000) / 1000.0; }

BonnFactorBytes factor(std::uint32_t rows, std::uint32_t columns, std::uint32_t k, std::uint32_t seed, int scalar_bytes = 4) {
  BonnFactorBytes f;
  f.scalar_bytes = scalar_bytes;
  f.rows = rows;
  f.columns = columns;
  f.components = k;
  for (std::uint32_t i = 0; i < k; ++i) f.sigma.push_back(1.0 / (i + 1));
  for (std::size_t i = 0; i < std::size_t(rows) * k; ++i) f.u.push_back(entry(seed, i) / (1 + i % k));
  for (std::size_t i = 0; i < std::size_t(columns) * k; ++i) f.sv.push_back(entry(seed + 7, i));
  return f;
}

// sum_k a[ra * k + j] * b[rb * k + j]
double dot(const std::vector<double>& a, std::size_t ra, const std::vector<double>& b, std::size_t rb, std::size_t k) {
  double s = 0;
  for (std::size_t j = 0; j < k; ++j) s += a[ra * k + j] * b[rb * k + j];
  return s;
}

std::size_t pairOffset(const BonnFileSpec& s, std::size_t view) {
  std::size_t off = 0;
  for (std::size_t v = 0; v < view; ++v) off += s.lights[v].size();
  return off;
}

std::size_t pairCount(const BonnFileSpec& s) { return pairOffset(s, s.views.size()); }

// value(), one entry from the factors, against loadView's matrix product, everywhere.
void expectLookupAgrees(const BonnBtf& btf) {
  std::vector<Rgb> view;
  for (const int v : btf.views().views()) {
    btf.loadView(v, view);
    const int lights = btf.directions().lightCount(v);
    for (int l = 0; l < lights; ++l)
      for (int y = 0; y < btf.height(); ++y)
        for (int x = 0; x < btf.width(); ++x) {
          const Rgb a = view[(std::size_t(l) * std::size_t(btf.height()) + std::size_t(y)) * std::size_t(btf.width()) +
                             std::size_t(x)];
          const Rgb b = btf.value(x, y, v, l);
          for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(a[c], b[c], 1e-5f * std::max(1.0f, std::abs(a[c]))) << "view " << v << " light " << l;
        }
  }
}

BonnBtf writeAndOpen(const test::TempDir& dir, const BonnFileSpec& spec, const std::string& name = "m.btf") {
  test::writeBytes(dir / name, test::bonnFileBytes(spec));
  BonnBtf btf = BonnBtf::open(dir / name);
  expectLookupAgrees(btf);
  return btf;
}

void expectNear(const Rgb& got, double r, double g, double b, double tolerance, const std::string& where) {
  EXPECT_NEAR(got.r, r, tolerance * std::max(1.0, std::abs(r))) << where;
  EXPECT_NEAR(got.g, g, tolerance * std::max(1.0, std::abs(g))) << where;
  EXPECT_NEAR(got.b, b, tolerance * std::max(1.0, std::abs(b))) << where;
}

TEST(BtfDirectionSet, DomeAndUbo2003Sets) {
  const BtfDirectionSet& dome = *BtfDirectionSet::uboDome1();
  EXPECT_EQ(dome.viewCount(), 151);
  EXPECT_EQ(dome.lightCount(0), 151);
  EXPECT_TRUE(dome.sharedLights());
  EXPECT_FALSE(dome.isUbo2003());
  EXPECT_EQ(dome.viewAngles(1).theta_deg, 11.0f);
  EXPECT_EQ(dome.viewAngles(1).phi_deg, 15.0f);
  // The ring of 18 at 52.5 degrees starts at phi 7.5; phi wraps into [-180, 180) as btflib's does.
  EXPECT_EQ(dome.viewAngles(1 + 6 + 12 + 12 + 12 + 18).theta_deg, 52.5f);
  EXPECT_EQ(dome.viewAngles(1 + 6 + 12 + 12 + 12 + 18).phi_deg, 7.5f);
  for (int v = 0; v < dome.viewCount(); ++v) {
    EXPECT_GE(dome.viewAngles(v).phi_deg, -180.0f);
    EXPECT_LT(dome.viewAngles(v).phi_deg, 180.0f);
  }
  EXPECT_TRUE(BtfDirectionSet::ubo2003()->isUbo2003());
  EXPECT_EQ(BtfDirectionSet::ubo2003()->pairCount(), 81u * 81u);
  EXPECT_EQ(dome.describe(), "151 views x 151 lights (Bonn dome 1)");
  // The same directions given in radians and read back compare equal, and map to the shared set.
  std::vector<BtfAngles> again;
  for (int v = 0; v < dome.viewCount(); ++v) {
    const float t = dome.viewAngles(v).theta_deg * kDeg, p = dome.viewAngles(v).phi_deg * kDeg;
    again.push_back({t / kDeg, p / kDeg});
  }
  const auto copy = std::make_shared<const BtfDirectionSet>("", again, again);
  EXPECT_TRUE(*copy == dome);
  EXPECT_EQ(BtfDirectionSet::known(copy), BtfDirectionSet::uboDome1());
}

TEST(BtfDirectionSet, RejectsBadAngles) {
  EXPECT_THAT(errorOf([] { BtfDirectionSet("x", {{95, 0}}, std::vector<BtfAngles>{{0, 0}}); }), HasSubstr("theta must lie in [0, 90)"));
  EXPECT_THAT(errorOf([] { BtfDirectionSet("x", {}, std::vector<BtfAngles>{{0, 0}}); }), HasSubstr("view list is empty"));
  EXPECT_THAT(errorOf([] { BtfDirectionSet("x", {{NAN, 0}}, std::vector<BtfAngles>{{0, 0}}); }), HasSubstr("theta nan"));
}

// A DFMF file, U (pairs x k) and S.V (texels x k), decodes to the product, light by light.
TEST(BonnBtf, DfmfDecodesTheProductOfTheFactors) {
  test::TempDir dir;
  for (const bool texels_first : {false, true})
    for (const int scalar : {2, 4, 8}) {
      BonnFileSpec s = smallSampling();
      const std::uint32_t pairs = std::uint32_t(pairCount(s)), texels = s.width * s.height;
      for (std::uint32_t c = 0; c < 3; ++c)
        s.factors.push_back(texels_first ? factor(texels, pairs, 2 + c, 10 + c, scalar) : factor(pairs, texels, 2 + c, 10 + c, scalar));
      const BonnBtf btf = writeAndOpen(dir, s);
      EXPECT_EQ(btf.width(), 3);
      EXPECT_EQ(btf.height(), 2);
      EXPECT_EQ(btf.directions().viewCount(), 3);
      EXPECT_EQ(btf.header().layout, BonnBtfLayout::Dfmf);
      EXPECT_EQ(btf.header().channel_names, (std::vector<std::string>{"R", "G", "B"}));
      EXPECT_EQ(btf.header().xml, "<measurement/>");
      std::vector<Rgb> out;
      const double tolerance = scalar == 2 ? 3e-3 : 1e-5;
      for (int v = 0; v < 3; ++v) {
        btf.loadView(v, out);
        ASSERT_EQ(out.size(), 4u * texels);
        for (std::size_t l = 0; l < 4; ++l)
          for (std::size_t t = 0; t < texels; ++t) {
            double rgb[3];
            for (std::size_t c = 0; c < 3; ++c) {
              const BonnFactorBytes& f = s.factors[c];
              const std::size_t pair = pairOffset(s, std::size_t(v)) + l;
              rgb[c] = texels_first ? dot(f.sv, pair, f.u, t, f.components) : dot(f.u, pair, f.sv, t, f.components);
            }
            expectNear(out[l * texels + t], rgb[0], rgb[1], rgb[2], tolerance,
                       "view " + std::to_string(v) + " light " + std::to_string(l) + " texel " + std::to_string(t) +
                           " scalar " + std::to_string(scalar));
          }
      }
    }
}

// A DFMF file of one view, one light and one texel whose stored (decorrelated) triple is `stored`.
BonnFileSpec oneEntryFile(std::int32_t model, const std::array<double, 3>& stored) {
  BonnFileSpec s;
  s.views = {{0, 0}};
  s.lights = {{{0, 0}}};
  s.color_model = model;
  for (const double value : stored) {
    BonnFactorBytes f;
    f.rows = f.columns = f.components = 1;
    f.sigma = {1};
    f.u = {1};
    f.sv = {value};
    s.factors.push_back(f);
  }
  return s;
}

// Each colour model decodes a stored triple as btflib's undecorrelate does (written out here).
TEST(BonnBtf, ColourModelsDecodeAsBtflibDoes) {
  test::TempDir dir;
  const double y = -1.5, u = 0.25, w = -0.125;  // the stored triple
  const double eps = 1e-5;
  const auto yuv = [](double a, double b, double c) {
    return std::array<double, 3>{a + 1.13983 * c, a - 0.39465 * b - 0.5806 * c, a + 2.03211 * b};
  };
  struct Case {
    int model;
    std::array<double, 3> expected;
  };
  const double Y = std::exp(y) - eps;
  const std::vector<Case> cases = {
      {0, {0, 0.25, 0}},  // RGB: negative stored values clamp to 0
      {1, {std::max(0.0, yuv(y, u, w)[0]), std::max(0.0, yuv(y, u, w)[1]), std::max(0.0, yuv(y, u, w)[2])}},
      {4, {std::max(0.0, y + u - w), std::max(0.0, y + w), std::max(0.0, y - u - w)}},
      {9, {std::max(0.0, yuv(Y, u, w)[0]), std::max(0.0, yuv(Y, u, w)[1]), std::max(0.0, yuv(Y, u, w)[2])}},
      {10,
       {std::max(0.0, yuv(Y, std::exp(u) * eps, -std::exp(0.125) * eps)[0]),
        std::max(0.0, yuv(Y, std::exp(u) * eps, -std::exp(0.125) * eps)[1]),
        std::max(0.0, yuv(Y, std::exp(u) * eps, -std::exp(0.125) * eps)[2])}},
      {11,
       {std::max(0.0, yuv(Y, u * (Y + eps), w * (Y + eps))[0]), std::max(0.0, yuv(Y, u * (Y + eps), w * (Y + eps))[1]),
        std::max(0.0, yuv(Y, u * (Y + eps), w * (Y + eps))[2])}},
      {12, {std::exp(y) - eps, std::exp(u) - eps, std::exp(w) - eps}},
  };
  for (const Case& c : cases) {
    const BonnBtf btf = writeAndOpen(dir, oneEntryFile(c.model, {y, u, w}));
    std::vector<Rgb> out;
    btf.loadView(0, out);
    expectNear(out[0], c.expected[0], c.expected[1], c.expected[2], 1e-5, "colour model " + std::to_string(c.model));
  }
  // Model 3: v * M + mean, M row-major in the file.
  BonnFileSpec s = oneEntryFile(3, {0.2, 0.4, 0.6});
  const float m[9] = {0.5f, 0.1f, 0.2f, 0.3f, 0.6f, 0.1f, 0.0f, 0.2f, 0.9f};
  std::copy(m, m + 9, s.color_transform);
  s.color_mean[0] = 0.5f;
  s.color_mean[1] = 0.75f;
  s.color_mean[2] = 1.0f;
  std::vector<Rgb> out;
  writeAndOpen(dir, s).loadView(0, out);
  expectNear(out[0], 0.2 * 0.5 + 0.4 * 0.3 + 0.6 * 0.0 + 0.5, 0.2 * 0.1 + 0.4 * 0.6 + 0.6 * 0.2 + 0.75,
             0.2 * 0.2 + 0.4 * 0.1 + 0.6 * 0.9 + 1.0, 1e-6, "colour model 3");
}

// The cosine flag: the stored values are f cos(theta_l); the reader divides it out.
TEST(BonnBtf, CosineFlagIsDividedOut) {
  test::TempDir dir;
  BonnFileSpec s = smallSampling();
  s.cosine_flag = true;
  const std::uint32_t pairs = std::uint32_t(pairCount(s)), texels = s.width * s.height;
  for (std::uint32_t c = 0; c < 3; ++c) s.factors.push_back(factor(pairs, texels, 1, 3 + c));
  const BonnBtf btf = writeAndOpen(dir, s);
  EXPECT_TRUE(btf.header().cosine_flag);
  std::vector<Rgb> out;
  btf.loadView(1, out);
  const std::size_t pair = pairOffset(s, 1) + 3;  // light at theta 70
  const double expected = dot(s.factors[0].u, pair, s.factors[0].sv, 0, 1) / std::cos(70.0 * kPi / 180.0);
  EXPECT_NEAR(out[3 * texels].r, expected, 1e-4 * expected);
}

// FMF in both orientations, with and without the log dynamic-range reduction, extended header
// versions 0 to 2 and the short signatures.
TEST(BonnBtf, FmfDecodesBothOrientations) {
  test::TempDir dir;
  struct Variant {
    std::string signature;
    int header_version;
    std::uint32_t drr;
    bool texels_first;
  };
  for (const Variant& var : {Variant{"!FMF12FCER", 1, 0, false}, Variant{"!FMF12FCER", 2, 1, true},
                             Variant{"!FMF12FCER", 0, 0, true}, Variant{"!FMF06FC", 0, 0, false},
                             Variant{"!FMF06FCR", 0, 0, true}}) {
    BonnFileSpec s = smallSampling();
    s.signature = var.signature;
    s.fmf_header_version = var.header_version;
    s.dynamic_range_reduction = var.drr;
    s.height_map_width = 2;
    s.height_map_height = 3;
    s.rotations = 2;
    const std::uint32_t pairs = std::uint32_t(pairCount(s)), texels = s.width * s.height;
    s.factors.push_back(var.texels_first ? factor(3 * texels, pairs, 3, 21) : factor(3 * pairs, texels, 3, 21));
    const BonnBtf btf = writeAndOpen(dir, s);
    EXPECT_EQ(btf.header().layout, BonnBtfLayout::Fmf);
    std::vector<Rgb> out;
    btf.loadView(2, out);
    const BonnFactorBytes& f = s.factors[0];
    for (std::size_t l = 0; l < 4; ++l)
      for (std::size_t t = 0; t < texels; ++t) {
        double rgb[3];
        for (std::size_t c = 0; c < 3; ++c) {
          const std::size_t pair = pairOffset(s, 2) + l;
          const double v = var.texels_first ? dot(f.sv, pair, f.u, t * 3 + c, 3) : dot(f.u, pair * 3 + c, f.sv, t, 3);
          rgb[c] = var.drr ? std::exp(v) - 1e-5 : v;
        }
        expectNear(out[l * texels + t], rgb[0], rgb[1], rgb[2], 1e-5, var.signature + " light " + std::to_string(l));
      }
  }
}

// PVF: per view, weights x components + mean; both orientations, the current and the legacy
// header; the per-view light lists of a view whose light was moved aside.
TEST(BonnBtf, PvfDecodesPerViewAndKeepsViewDependentLights) {
  test::TempDir dir;
  for (const bool legacy : {false, true})
    for (const bool texels_first : {false, true}) {
      BonnFileSpec s = smallSampling(true);
      s.signature = legacy ? "!PVF06FC" : "!PVF06FCR";
      s.legacy_pvf = legacy;
      const std::uint32_t texels = s.width * s.height;
      for (std::uint32_t v = 0; v < 3; ++v) {
        // rows: dimension (3 x lights, or 3 x texels), columns: weights (texels, or lights)
        BonnFactorBytes f = texels_first ? factor(3 * texels, 4, 2, 30 + v) : factor(3 * 4, texels, 2, 30 + v);
        for (std::uint32_t i = 0; i < f.rows; ++i) f.mean.push_back(0.01 * i);
        s.factors.push_back(f);
      }
      const BonnBtf btf = writeAndOpen(dir, s);
      EXPECT_EQ(btf.header().layout, BonnBtfLayout::Pvf);
      EXPECT_EQ(btf.header().legacy_pvf, legacy);
      EXPECT_FALSE(btf.directions().sharedLights());
      EXPECT_NEAR(btf.directions().lights(2)[1].theta_deg, 25.0f, 1e-4);
      EXPECT_NEAR(btf.directions().lights(1)[1].theta_deg, 20.0f, 1e-4);
      EXPECT_THAT(btf.directions().describe(), HasSubstr("lights per view, view-dependent"));
      std::vector<Rgb> out;
      for (int v = 0; v < 3; ++v) {
        btf.loadView(v, out);
        const BonnFactorBytes& f = s.factors[std::size_t(v)];
        for (std::size_t l = 0; l < 4; ++l)
          for (std::size_t t = 0; t < texels; ++t) {
            double rgb[3];
            for (std::size_t c = 0; c < 3; ++c) {
              const std::size_t d = texels_first ? t * 3 + c : l * 3 + c;
              rgb[c] = (texels_first ? dot(f.u, d, f.sv, l, 2) : dot(f.u, d, f.sv, t, 2)) + f.mean[d];
            }
            expectNear(out[l * texels + t], rgb[0], rgb[1], rgb[2], 1e-5, "PVF view " + std::to_string(v));
          }
      }
    }
}

// Meta-data versions 1 to 4: the fields each adds.
TEST(BonnBtf, ReadsEveryMetaDataVersion) {
  test::TempDir dir;
  for (std::uint32_t version = 1; version <= 4; ++version) {
    BonnFileSpec s = smallSampling();
    s.meta_version = version;
    s.cosine_flag = false;
    const std::uint32_t pairs = std::uint32_t(pairCount(s)), texels = s.width * s.height;
    for (std::uint32_t c = 0; c < 3; ++c) s.factors.push_back(factor(pairs, texels, 1, c));
    const BonnBtf btf = writeAndOpen(dir, s);
    EXPECT_EQ(btf.header().meta_version, version);
    EXPECT_EQ(btf.header().measurement_setup, "set-up");
    EXPECT_EQ(btf.header().xml, version > 2 ? "<measurement/>" : "");
  }
}

// --- writing ----------------------------------------------------------------------------------

// A BTF on a scattered set with every value distinct and positive.
BtfData scatteredBtf(int width, int height, bool view_dependent_lights = false) {
  std::vector<BtfAngles> views = {{0, 0}, {23.5f, 15}, {45, -60}, {67.5f, 172.5f}};
  std::vector<std::vector<BtfAngles>> lights;
  for (std::size_t v = 0; v < views.size(); ++v) {
    std::vector<BtfAngles> list = {{0, 0}, {11, 15}, {30, 105}, {52.5f, -127.5f}, {75, 60}};
    if (view_dependent_lights && v == 2) list[2] = {33, 110};
    lights.push_back(list);
  }
  const auto set = std::make_shared<const BtfDirectionSet>("test set", views, lights);
  BtfData data(width, height, "scattered", BtfViewSet::all(set));
  for (int v = 0; v < set->viewCount(); ++v)
    for (int l = 0; l < set->lightCount(v); ++l)
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
          const float base = 0.05f + 0.9f * float((v * 31 + l * 17 + x * 7 + y * 13) % 23) / 23.0f;
          data.at(x, y, v, l) = Rgb(base, 0.5f * base + 0.1f * float(x), 0.2f + 0.01f * float(l * y));
        }
  return data;
}

TEST(BonnBtfWriter, FullRankRoundTripsInEveryColourModel) {
  test::TempDir dir;
  const BtfData source = scatteredBtf(5, 4);
  for (const int model : {0, 1, 2, 3, 4, 9, 10, 11, 12}) {
    BonnBtfWriteOptions options;
    options.color_model = model;
    options.scalar_bytes = 8;
    options.max_components = 64;  // more than the rank: every component kept
    const BonnBtfWriteReport report = writeBonnBtf(source, dir / "full.btf", options);
    ASSERT_EQ(report.components.size(), 3u);
    const BonnBtf read = BonnBtf::open(dir / "full.btf");
    EXPECT_TRUE(read.directions() == source.directions());
    EXPECT_EQ(read.header().color_model, model);
    const BtfErrorStats e = compareBtf(source, read);
    EXPECT_LT(e.rel_rmse, 1e-5) << "colour model " << model;
  }
}

TEST(BonnBtfWriter, FmfAndHalfScalars) {
  test::TempDir dir;
  const BtfData source = scatteredBtf(5, 4, true);
  for (const int drr : {0, 1}) {
    BonnBtfWriteOptions options;
    options.layout = BonnBtfLayout::Fmf;
    options.dynamic_range_reduction = drr;
    options.scalar_bytes = 2;
    writeBonnBtf(source, dir / "fmf.btf", options);
    const BonnBtf read = BonnBtf::open(dir / "fmf.btf");
    EXPECT_EQ(read.header().signature, "!FMF12FCER");
    EXPECT_FALSE(read.directions().sharedLights());
    EXPECT_LT(compareBtf(source, read).rel_rmse, 5e-3) << "half scalars, drr " << drr;
  }
}

// A rank-r BTF is stored exactly at rank r; the reported error is the error of the stored
// values (for FMF without reduction, the RGB values themselves).
TEST(BonnBtfWriter, TruncationErrorIsTheReportedOne) {
  test::TempDir dir;
  const BtfData source = scatteredBtf(6, 5);
  BonnBtfWriteOptions options;
  options.layout = BonnBtfLayout::Fmf;
  options.scalar_bytes = 8;
  for (const int rank : {1, 2, 4}) {
    options.max_components = rank;
    const BonnBtfWriteReport report = writeBonnBtf(source, dir / "t.btf", options);
    EXPECT_EQ(report.components[0], std::uint32_t(rank));
    const double measured = compareBtf(source, BonnBtf::open(dir / "t.btf")).rel_rmse;
    // Clamping negatives at decoding can only lower the error (float rounding aside).
    EXPECT_LE(measured, report.relative_error[0] * (1 + 1e-4)) << "rank " << rank;
    EXPECT_GT(measured, 0.5 * report.relative_error[0]) << "rank " << rank;
  }
  options.max_components = 30;
  options.relative_error = 0.05;
  const BonnBtfWriteReport report = writeBonnBtf(source, dir / "e.btf", options);
  EXPECT_LE(report.relative_error[0], 0.05);
  EXPECT_LT(report.components[0], 30u);
  EXPECT_LE(compareBtf(source, BonnBtf::open(dir / "e.btf")).rel_rmse, 0.05 + 1e-9);
}

TEST(BonnBtfWriter, SameFileOnAnyThreadCount) {
  test::TempDir dir;
  const BtfData source = scatteredBtf(70, 65);  // more texels than one chunk
  BonnBtfWriteOptions options;
  options.max_components = 6;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    writeBonnBtf(source, dir / "one.btf", options);
  }
  writeBonnBtf(source, dir / "many.btf", options);
  std::ifstream a(dir / "one.btf", std::ios::binary), b(dir / "many.btf", std::ios::binary);
  const std::string x((std::istreambuf_iterator<char>(a)), {}), y((std::istreambuf_iterator<char>(b)), {});
  EXPECT_EQ(x, y);
}

TEST(BonnBtfWriter, PvfRoundTrip) {
  test::TempDir dir;
  const BtfData source = scatteredBtf(5, 4, true);
  writeBonnBtfPvf(source, dir / "p.btf", 64, 8);
  const BonnBtf read = BonnBtf::open(dir / "p.btf");
  EXPECT_EQ(read.header().layout, BonnBtfLayout::Pvf);
  EXPECT_LT(compareBtf(source, read).rel_rmse, 1e-6);
}

TEST(BonnBtfWriter, RefusesWhatTheFormatCannotHold) {
  test::TempDir dir;
  BtfData source = scatteredBtf(3, 2);
  source.at(1, 1, 2, 3) = Rgb(-1.0f, 0.0f, 0.0f);
  EXPECT_THAT(errorOf([&] { writeBonnBtf(source, dir / "x.btf"); }), HasSubstr("view 2, light 3, texel 4"));
  EXPECT_FALSE(std::filesystem::exists(dir / "x.btf"));
  BonnBtfWriteOptions options;
  options.scalar_bytes = 3;
  EXPECT_THAT(errorOf([&] { writeBonnBtf(scatteredBtf(3, 2), dir / "x.btf", options); }), HasSubstr("not 2, 4 or 8"));
  const BtfData partial(2, 2, "partial", BtfViewSet({0, 1}));
  EXPECT_THAT(errorOf([&] { writeBonnBtf(partial, dir / "x.btf"); }), HasSubstr("stores every view"));
}

// PCA and the compressibility analysis work on any set: each view with its own light count.
TEST(AnyDirectionSet, PcaAndCompressibility) {
  const BtfData source = scatteredBtf(6, 5, true);
  const int dimension = 3 * 5;
  const PcaBtf full = compressPca(source, dimension, PcaPrecision::Float);
  EXPECT_LT(compareBtf(source, full).rel_rmse, 1e-5);
  EXPECT_EQ(full.value(2, 3, 2, 4), full.value(2, 3, 2, 4));
  std::vector<Rgb> view;
  full.loadView(2, view);
  EXPECT_NEAR(full.value(2, 3, 2, 4).r, view[4 * 30 + 3 * 6 + 2].r, 1e-6);
  EXPECT_EQ(full.storedBytes(), PcaBtf::storedBytesFor(6, 5, dimension, PcaPrecision::Float, source.views()));
  EXPECT_THAT(errorOf([&] { compressPca(source, dimension + 1); }), HasSubstr("outside 0..15"));
  const PcaBtf small = compressPcaToBytes(source, PcaBtf::storedBytesFor(6, 5, 2, PcaPrecision::Half, source.views()));
  EXPECT_EQ(small.components(), 2);

  CompressibilityOptions options;
  options.epsilons = {0.05};
  const CompressibilityReport report = analyzeCompressibility(source, options);
  EXPECT_EQ(report.texels, 30);
  EXPECT_EQ(report.directions, 4 * 5);
}

// --- bad files --------------------------------------------------------------------------------

BonnFileSpec validDfmf() {
  BonnFileSpec s = smallSampling();
  s.rotations = 1;
  const std::uint32_t pairs = std::uint32_t(pairCount(s)), texels = s.width * s.height;
  for (std::uint32_t c = 0; c < 3; ++c) s.factors.push_back(factor(pairs, texels, 2, c));
  return s;
}

std::string openError(const test::TempDir& dir, const std::vector<unsigned char>& bytes) {
  test::writeBytes(dir / "bad.btf", bytes);
  return errorOf([&] {
    const BonnBtf btf = BonnBtf::open(dir / "bad.btf");
    std::vector<Rgb> out;
    for (const int v : btf.views().views()) btf.loadView(v, out);
  });
}

TEST(BonnBtfErrors, TruncatedInsideEverySection) {
  test::TempDir dir;
  test::BonnFileOffsets o;
  const std::vector<unsigned char> bytes = test::bonnFileBytes(validDfmf(), &o);
  const std::vector<std::pair<std::size_t, std::string>> cuts = {
      {o.meta + 20, "meta-data block is truncated"},     {o.sampling + 10, "bidirectional sampling block is truncated"},
      {o.size + 5, "size block is truncated"},           {o.rotations + 12, "rotations block is truncated"},
      {o.layout + 8, "DFMF colour block is truncated"},  {o.first_factor + 6, "DFMF channel 0 factors is truncated"},
      {o.end - 3, "DFMF channel 2 factors is truncated"}};
  for (const auto& [cut, expected] : cuts) {
    const std::string message = openError(dir, std::vector<unsigned char>(bytes.begin(), bytes.begin() + long(cut)));
    EXPECT_THAT(message, HasSubstr(expected)) << "cut at " << cut;
    EXPECT_THAT(message, HasSubstr("bad.btf")) << "cut at " << cut;
  }
  EXPECT_THAT(openError(dir, std::vector<unsigned char>(bytes.begin(), bytes.begin() + 4)), HasSubstr("Bonn BTF signature"));
}

TEST(BonnBtfErrors, NamesWhatIsWrong) {
  test::TempDir dir;
  {
    BonnFileSpec s = validDfmf();
    s.signature = "!DFMF09FCR";
    EXPECT_THAT(openError(dir, test::bonnFileBytes(s)), HasSubstr("does not start with a Bonn BTF signature"));
  }
  {
    std::vector<unsigned char> bytes = test::bonnFileBytes(validDfmf());
    bytes[10] += 4;  // the meta-data size
    EXPECT_THAT(openError(dir, bytes), HasSubstr("meta-data block declares"));
  }
  {
    BonnFileSpec s = validDfmf();
    s.factors[1].rows += 1;
    s.factors[1].u.resize(std::size_t(s.factors[1].rows) * 2, 0.5);
    EXPECT_THAT(openError(dir, test::bonnFileBytes(s)), HasSubstr("DFMF channel 1 factors are 13 x 6, but the sampling block has 12"));
  }
  {
    BonnFileSpec s = validDfmf();
    s.width = 4;
    EXPECT_THAT(openError(dir, test::bonnFileBytes(s)), HasSubstr("the size block 8 texels"));
  }
  {
    BonnFileSpec s = validDfmf();
    s.factors[2].sv[3] = std::nan("");
    EXPECT_THAT(openError(dir, test::bonnFileBytes(s)), HasSubstr("DFMF channel 2 factors holds a NaN value in S.V"));
  }
  {
    BonnFileSpec s = validDfmf();
    s.factors[0].u[1] = 1e300;
    s.factors[0].scalar_bytes = 8;
    EXPECT_THAT(openError(dir, test::bonnFileBytes(s)), HasSubstr("beyond float range"));
  }
  {
    // log-RGB of 30: e^30 = 1e13, beyond what libbtf holds (core/value_limits.h).
    BonnFileSpec s = validDfmf();
    s.color_model = 12;
    s.factors[0].sv.assign(s.factors[0].sv.size(), 30.0);
    s.factors[0].u.assign(s.factors[0].u.size(), 0.5);
    EXPECT_THAT(openError(dir, test::bonnFileBytes(s)), HasSubstr("beyond 1e10"));
  }
  {
    BonnFileSpec s = validDfmf();
    s.factors[0].scalar_bytes = 3;
    EXPECT_THAT(openError(dir, test::bonnFileBytes(s)), HasSubstr("scalar size 3"));
  }
  {
    BonnFileSpec s = validDfmf();
    s.color_model = 5;
    EXPECT_THAT(openError(dir, test::bonnFileBytes(s)), HasSubstr("multispectral"));
    s.color_model = 7;
    EXPECT_THAT(openError(dir, test::bonnFileBytes(s)), HasSubstr("colour model 7"));
  }
  {
    BonnFileSpec s = validDfmf();
    s.channel_names = {"450", "500", "550", "600"};
    EXPECT_THAT(openError(dir, test::bonnFileBytes(s)), HasSubstr("4 channels"));
  }
  {
    BonnFileSpec s = validDfmf();
    s.views[1].theta_rad = 2.0f;
    EXPECT_THAT(openError(dir, test::bonnFileBytes(s)), HasSubstr("bidirectional sampling block is invalid"));
  }
  {
    std::vector<unsigned char> bytes = test::bonnFileBytes(validDfmf());
    bytes.push_back(0);
    EXPECT_THAT(openError(dir, bytes), HasSubstr("1 bytes follow the last factor"));
  }
  {
    BonnFileSpec s = smallSampling();
    s.signature = "!PVF06FCR";
    for (std::uint32_t v = 0; v < 2; ++v) s.factors.push_back(factor(12, 6, 1, v));
    for (BonnFactorBytes& f : s.factors) f.mean.assign(12, 0.0);
    EXPECT_THAT(openError(dir, test::bonnFileBytes(s)), HasSubstr("2 view slots, but the sampling block has 3 views"));
  }
}

// --- through the registry -----------------------------------------------------------------------

TEST(BonnBtf, OpensThroughTheRegistryByContent) {
  test::TempDir dir;
  writeBonnBtf(scatteredBtf(3, 2), dir / "material.dat");  // not the .btf extension: found by content
  const IdentifiedMaterial id = identifyMaterial((dir / "material.dat").string());
  EXPECT_EQ(id.type->name, "btf");
  EXPECT_THAT(id.description, HasSubstr("Bonn BTF file"));
  const std::shared_ptr<const BtfSource> source = openBtf((dir / "material.dat").string());
  EXPECT_EQ(source->directions().viewCount(), 4);
  EXPECT_EQ(source->entryCount(), 6u * 4 * 5);
  // VQ codes any set whose views have as many lights each (here in bands of elevation).
  const VqBtf vq = compressVq(*source, {});
  EXPECT_TRUE(vq.directions() == source->directions());
  EXPECT_LT(compareBtf(*source, vq).rel_rmse, 0.1);
  // A file on the 81-direction set renders as a material, read in place (no copy of its values).
  writeBonnBtf(test::makeGgxBtf(2, 2, false), dir / "ubo.btf");
  const std::shared_ptr<const Material> material = openMaterial((dir / "ubo.btf").string());
  EXPECT_GT(material->eval(glm::normalize(glm::vec3(0.2f, 0.1f, 1.0f)), glm::vec3(0, 0, 1), {0.3f, 0.3f}).r, 0.0f);
  // A file on any other set renders too, interpolated on triangulations of its directions; at a
  // measured pair it returns the file's value.
  const std::shared_ptr<const Material> scattered = openMaterial((dir / "material.dat").string());
  const BtfDirectionSet& set = source->directions();
  const Rgb at = scattered->eval(set.lightDirections(2)[1], set.view(2), {0.5f / 3.0f, 0.25f});
  const Rgb expected = dynamic_cast<const BtfLookup&>(*source).value(0, 0, 2, 1);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(at[c], expected[c], 1e-4f * std::max(1e-3f, expected[c]));
  // Comparison needs the same set.
  const BtfData other(3, 2);
  EXPECT_THAT(errorOf([&] { compareBtf(other, *source); }), HasSubstr("different direction sets"));
}

}  // namespace
}  // namespace btf
