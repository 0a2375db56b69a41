// BTFs that hold only some of the 81 views (core/btf_view_set.h): the view set itself, the
// in-memory BtfData and compareBtf, image folders (EXR, 8-bit sRGB and 16-bit linear PNG, Bonn
// names, the btf.json transfer override, the real one-view Bonn slice), and the consumers: VQ
// (.btfz round trip, header format of complete BTFs unchanged), PCA, the compressibility analysis
// and BtfMaterial (constant in wo beyond the last ring held).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "btf/compress/compressibility.h"
#include "btf/compress/pca.h"
#include "btf/compress/vq_btf.h"
#include "btf/core/btf_view_set.h"
#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/rng.h"
#include "btf/io/btf_data.h"
#include "btf/io/btf_images.h"
#include "btf/io/btf_quality.h"
#include "btf/io/container.h"
#include "btf/io/image.h"
#include "btf/material/btf_material.h"
#include "btf_test_data.h"
#include "support/test_support.h"

namespace btf {
namespace {
namespace fs = std::filesystem;
using testing::HasSubstr;
using test::errorOf;

constexpr int kW = 4, kH = 3;  // not square, so a swapped x/y shows

using test::srgbDecode;
using test::srgbEncode;

// The views of `full` that `views` names, as a partial BtfData (equal values on those views).
BtfData subset(const BtfData& full, const BtfViewSet& views, const std::string& name = "partial") {
  BtfData out(full.width(), full.height(), name, views);
  for (const int v : views.views()) std::copy(full.view(v), full.view(v) + full.viewValueCount(v), out.view(v));
  return out;
}

// Values in [0, 3) on the held views only (the others are never touched).
BtfData randomPartialBtf(const BtfViewSet& views, std::uint64_t seed) {
  BtfData data(kW, kH, "random-partial", views);
  Rng rng(seed);
  for (const int v : views.views())
    for (int l = 0; l < kBtfDirectionCount; ++l)
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) data.at(x, y, v, l) = Rgb(3 * rng.uniform(), 3 * rng.uniform(), 3 * rng.uniform());
  return data;
}

void expectSameHeldViews(const BtfSource& a, const BtfSource& b) {
  ASSERT_EQ(a.views(), b.views());
  std::vector<Rgb> va, vb;
  for (const int v : a.views().views()) {
    a.loadView(v, va);
    b.loadView(v, vb);
    ASSERT_EQ(va, vb) << "view " << v;
  }
}

nlohmann::json readJson(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

// ---------------------------------------------------------------------------------------------
// 1. BtfViewSet

TEST(BtfPartialViewsSet, ConstructionSortsAndRejectsInvalidLists) {
  const BtfViewSet set({40, 0, 7, 3});
  EXPECT_EQ(set.views(), (std::vector<int>{0, 3, 7, 40}));
  EXPECT_EQ(set.count(), 4);
  EXPECT_FALSE(set.complete());
  EXPECT_THAT(errorOf([] { BtfViewSet(std::vector<int>{}); }), HasSubstr("at least one view"));
  EXPECT_THAT(errorOf([] { BtfViewSet({0, 81}); }), HasSubstr("out of range"));
  EXPECT_THAT(errorOf([] { BtfViewSet({-1, 4}); }), HasSubstr("out of range"));
  EXPECT_THAT(errorOf([] { BtfViewSet({5, 3, 5}); }), HasSubstr("listed twice"));
  EXPECT_THROW(BtfViewSet({81}), Error);

  const BtfViewSet all;
  EXPECT_EQ(all.count(), kBtfDirectionCount);
  EXPECT_TRUE(all.complete());
  EXPECT_EQ(all.completeRingsFromPole(), kBtfRingCount);
  EXPECT_EQ(BtfViewSet(all.views()), all);
}

TEST(BtfPartialViewsSet, SlotAndViewRoundTrip) {
  const BtfViewSet set({80, 1, 40, 0, 19});
  for (int s = 0; s < set.count(); ++s) {
    EXPECT_EQ(set.slot(set.view(s)), s);
    EXPECT_TRUE(set.contains(set.view(s)));
  }
  int held = 0;
  for (int v = 0; v < kBtfDirectionCount; ++v) {
    if (set.contains(v)) {
      ++held;
      EXPECT_EQ(set.view(set.slot(v)), v);
    } else {
      EXPECT_EQ(set.slot(v), -1) << v;
    }
  }
  EXPECT_EQ(held, 5);
  EXPECT_FALSE(set.contains(-1));
  EXPECT_FALSE(set.contains(81));
  // Slots follow the ascending order.
  EXPECT_EQ(set.slot(0), 0);
  EXPECT_EQ(set.slot(80), 4);
}

TEST(BtfPartialViewsSet, UpToThetaAndCompleteRings) {
  EXPECT_EQ(BtfViewSet::upToTheta(0), BtfViewSet({0}));
  EXPECT_EQ(BtfViewSet::upToTheta(14.0f), BtfViewSet({0}));
  EXPECT_EQ(BtfViewSet::upToTheta(15).count(), 7);
  const BtfViewSet up30 = BtfViewSet::upToTheta(30);
  EXPECT_EQ(up30.count(), 1 + 6 + 12);
  EXPECT_EQ(up30.completeRingsFromPole(), 3);
  for (int v = 0; v < kBtfDirectionCount; ++v)
    EXPECT_EQ(up30.contains(v), btfDirections()[std::size_t(v)].theta_deg <= 30.0f) << v;
  EXPECT_TRUE(BtfViewSet::upToTheta(75).complete());
  EXPECT_TRUE(BtfViewSet::upToTheta(90).complete());
  EXPECT_EQ(BtfViewSet({0}).completeRingsFromPole(), 1);
  EXPECT_EQ(BtfViewSet({1, 2, 3, 4, 5, 6}).completeRingsFromPole(), 0) << "no pole";
  EXPECT_EQ(BtfViewSet({0, 1, 2}).completeRingsFromPole(), 1) << "ring 1 only partly";
  EXPECT_EQ(BtfViewSet({0, 1, 2, 3, 4, 5, 6, 7}).completeRingsFromPole(), 2);
}

TEST(BtfPartialViewsSet, DescribeTexts) {
  EXPECT_EQ(BtfViewSet().describe(), "all 81 views");
  EXPECT_EQ(BtfViewSet({0}).describe(), "1 view (theta 0, phi 0)");
  EXPECT_EQ(BtfViewSet::upToTheta(30).describe(), "19 views (all up to theta 30)");
  EXPECT_EQ(BtfViewSet::upToTheta(15).describe(), "7 views (all up to theta 15)");
  EXPECT_EQ(BtfViewSet({0, 40}).describe(), "2 views: (theta 0, phi 0), (theta 60, phi 54)");
  EXPECT_EQ(BtfViewSet({2}).describe(), "1 view: (theta 15, phi 60)");
  EXPECT_EQ(BtfViewSet({0, 1, 2, 3, 40, 80}).describe(),
            "6 views: (theta 0, phi 0), (theta 15, phi 0), (theta 15, phi 60), (theta 15, phi 120), ...");
  // Whole rings plus a stray view is not "all up to".
  EXPECT_THAT(BtfViewSet({0, 1, 2, 3, 4, 5, 6, 7}).describe(), HasSubstr("8 views: (theta 0, phi 0)"));
}

TEST(BtfPartialViewsSet, RequireNamesTheDirection) {
  const BtfViewSet set({0, 40});
  EXPECT_NO_THROW(set.require(40, "lookup"));
  EXPECT_NO_THROW(set.require(0, "lookup"));
  const std::string message = errorOf([&] { set.require(1, "lookup"); });
  EXPECT_THAT(message, HasSubstr("lookup: view (theta 15, phi 0) is not in this BTF"));
  EXPECT_THAT(message, HasSubstr("2 views: (theta 0, phi 0), (theta 60, phi 54)"));
  EXPECT_THAT(errorOf([&] { set.require(81, "lookup"); }), HasSubstr("out of range"));
  EXPECT_THAT(errorOf([&] { set.require(-3, "lookup"); }), HasSubstr("out of range"));
  EXPECT_EQ(describeBtfDirection(40), "theta 60, phi 54");
}

// ---------------------------------------------------------------------------------------------
// 2. BtfData and compareBtf

// A distinct value for every entry, so a mix-up of views, lights or texels shows.
Rgb entryValue(int x, int y, int v, int l) {
  return Rgb(float(x + 1) + 0.01f * float(l), float(y + 1) + 0.001f * float(v), 0.5f + 0.1f * float(v % 7));
}

BtfData filledPartial(const BtfViewSet& views, const std::string& name = "partial") {
  BtfData data(kW, kH, name, views);
  for (const int v : views.views())
    for (int l = 0; l < kBtfDirectionCount; ++l)
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) data.at(x, y, v, l) = entryValue(x, y, v, l);
  return data;
}

TEST(BtfPartialViewsData, StoresHeldViewsAndLoadsThemBack) {
  const BtfViewSet views({0, 5, 40});
  const BtfData data = filledPartial(views);
  EXPECT_EQ(data.views(), views);
  EXPECT_EQ(data.lookupViews(), views);
  EXPECT_EQ(data.entryCount(), std::size_t(kW * kH) * 3 * kBtfDirectionCount);
  std::vector<Rgb> out;
  for (const int v : views.views()) {
    data.loadView(v, out);
    ASSERT_EQ(out.size(), std::size_t(kBtfDirectionCount * kW * kH));
    for (int l = 0; l < kBtfDirectionCount; ++l)
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
          const std::size_t i = (std::size_t(l) * kH + std::size_t(y)) * kW + std::size_t(x);
          ASSERT_EQ(out[i], entryValue(x, y, v, l)) << "view " << v << ", light " << l;
          ASSERT_EQ(data.value(x, y, v, l), entryValue(x, y, v, l));
          ASSERT_EQ(data.view(v)[i], entryValue(x, y, v, l));
        }
  }
  const std::string message = errorOf([&] { data.loadView(1, out); });
  EXPECT_THAT(message, HasSubstr("partial"));
  EXPECT_THAT(message, HasSubstr("view (theta 15, phi 0) is not in this BTF"));
  EXPECT_THROW(data.loadView(80, out), Error);

  // The stream lookup checks the views too.
  std::vector<BtfSampleIndex> samples{{1, 2, 40, 7}, {0, 0, 5, 80}};
  std::vector<Rgb> values(samples.size());
  data.values(samples, values);
  EXPECT_EQ(values[0], entryValue(1, 2, 40, 7));
  EXPECT_EQ(values[1], entryValue(0, 0, 5, 80));
  samples[1].view = 7;
  EXPECT_THAT(errorOf([&] { data.values(samples, values); }), HasSubstr("theta 30, phi 0"));
}

TEST(BtfPartialViewsData, CopyOfKeepsViewsValuesAndWhite) {
  BtfData data = filledPartial(BtfViewSet({3, 20, 77}));
  data.setWhite(2.5f);
  const BtfData copy = BtfData::copyOf(data);
  EXPECT_EQ(copy.views(), data.views());
  EXPECT_EQ(copy.white(), std::optional<float>(2.5f));
  expectSameHeldViews(data, copy);
}

TEST(BtfPartialViewsData, CompareBtfRunsOverTheReferenceViews) {
  const BtfViewSet views({0, 5, 40});
  const BtfData reference = filledPartial(views, "reference");
  // A complete test BTF: equal on the reference's views, garbage on the others.
  BtfData test(kW, kH, "complete");
  for (int v = 0; v < kBtfDirectionCount; ++v)
    for (int l = 0; l < kBtfDirectionCount; ++l)
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) test.at(x, y, v, l) = views.contains(v) ? entryValue(x, y, v, l) : Rgb(1000.0f);
  BtfErrorStats s = compareBtf(reference, test);
  EXPECT_EQ(s.rmse, 0.0);
  EXPECT_EQ(s.entries, reference.entryCount());
  // One channel of one entry off by d: rmse = d / sqrt(3 n).
  const float d = 0.75f;
  test.at(2, 1, 40, 33).g += d;
  s = compareBtf(reference, test);
  const double n = double(reference.entryCount()) * 3.0;
  EXPECT_NEAR(s.rmse, double(d) / std::sqrt(n), 1e-6);
  EXPECT_GT(s.reference_rms, 0.0);
  EXPECT_NEAR(s.rel_rmse, s.rmse / s.reference_rms, 1e-12);

  // Partial against partial: fine when the test holds the reference's views (and more).
  const BtfData wider = filledPartial(BtfViewSet({0, 5, 6, 40}), "wider");
  EXPECT_EQ(compareBtf(reference, wider).rmse, 0.0);
}

TEST(BtfPartialViewsData, CompareBtfThrowsWhenTheTestLacksAReferenceView) {
  const BtfData reference = filledPartial(BtfViewSet({0, 5, 40}), "reference");
  const BtfData narrower = filledPartial(BtfViewSet({0, 5}), "narrower");
  std::string message = errorOf([&] { compareBtf(reference, narrower); });
  EXPECT_THAT(message, HasSubstr("cannot compare narrower with reference"));
  EXPECT_THAT(message, HasSubstr("view (theta 60, phi 54) is not in this BTF"));
  // A complete reference against a partial test: the first missing view is named.
  BtfData complete(kW, kH, "complete");
  complete.at(0, 0, 0, 0) = Rgb(1.0f);
  message = errorOf([&] { compareBtf(complete, narrower); });
  EXPECT_THAT(message, HasSubstr("view (theta 15, phi 0) is not in this BTF"));
}

// ---------------------------------------------------------------------------------------------
// 3. Image folders of partial BTFs

const BtfData& imageSource() {
  static const BtfData data = randomPartialBtf(BtfViewSet::upToTheta(15), 21);
  return data;
}

// One written folder per format, shared by the tests that read it or damage a copy.
const fs::path& partialFolder(BtfImageFormat format) {
  static test::TempDir dir;
  static std::map<BtfImageFormat, fs::path> folders;
  auto it = folders.find(format);
  if (it == folders.end()) {
    const fs::path f = dir / ("partial-" + btfImageFormatName(format));
    writeBtfImageFolder(imageSource(), f, format);
    it = folders.emplace(format, f).first;
  }
  return it->second;
}

fs::path copyOfFolder(const fs::path& folder, const test::TempDir& dir) {
  const fs::path copy = dir / "copy";
  fs::copy(folder, copy, fs::copy_options::recursive);
  return copy;
}

std::size_t countFiles(const fs::path& folder) {
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(folder)) files += entry.is_regular_file();
  return files;
}

TEST(BtfPartialViewsImages, ExrRoundTripIsExactAndHoldsOnlyTheViews) {
  const fs::path& path = partialFolder(BtfImageFormat::Exr);
  EXPECT_EQ(countFiles(path), std::size_t(7 * kBtfDirectionCount + 1));
  const BtfImageFolder folder = BtfImageFolder::open(path);
  EXPECT_EQ(folder.width(), kW);
  EXPECT_EQ(folder.height(), kH);
  EXPECT_EQ(folder.views(), BtfViewSet::upToTheta(15));
  EXPECT_FALSE(folder.transfer().has_value());
  EXPECT_FALSE(folder.white().has_value());
  expectSameHeldViews(imageSource(), folder);
  std::vector<Rgb> out;
  EXPECT_THAT(errorOf([&] { folder.loadView(7, out); }), HasSubstr("view (theta 30, phi 0) is not in this BTF"));
  EXPECT_EQ(readJson(path / kBtfSidecarName).at("views"), 7);
}

float largestValue(const BtfSource& source) {
  std::vector<Rgb> values;
  float largest = 0;
  for (const int v : source.views().views()) {
    source.loadView(v, values);
    for (const Rgb& c : values) largest = std::max(largest, c.maxComponent());
  }
  return largest;
}

TEST(BtfPartialViewsImages, Png8RoundTripIsWithinHalfAStepOfTheSrgbCode) {
  const fs::path& path = partialFolder(BtfImageFormat::Png8);
  EXPECT_EQ(countFiles(path), std::size_t(7 * kBtfDirectionCount + 1));
  const BtfImageFolder folder = BtfImageFolder::open(path);
  EXPECT_EQ(folder.views(), imageSource().views());
  ASSERT_TRUE(folder.transfer().has_value());
  EXPECT_EQ(*folder.transfer(), BtfTransfer::Srgb);
  const nlohmann::json sidecar = readJson(path / kBtfSidecarName);
  EXPECT_EQ(sidecar.at("transfer"), "srgb");
  const float scale = folder.valueScale();
  EXPECT_EQ(scale, largestValue(imageSource()));
  EXPECT_EQ(folder.white(), std::optional<float>(scale));
  std::vector<Rgb> a, b;
  double worst = 0, worst_linear = 0;
  for (const int v : folder.views().views()) {
    imageSource().loadView(v, a);
    folder.loadView(v, b);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        worst = std::max(worst, std::abs(srgbEncode(double(a[i][c]) / scale) - srgbEncode(double(b[i][c]) / scale)));
        worst_linear = std::max(worst_linear, std::abs(double(a[i][c]) - b[i][c]) / scale);
      }
  }
  EXPECT_LE(worst, 0.5 / 255 + 1e-5);
  EXPECT_GT(worst, 0.1 / 255) << "values really went through quantization";
  // Bright values are coarser in linear terms than a linear 8-bit code would be: the curve is in use.
  EXPECT_GT(worst_linear, 0.5 / 255 + 1e-4);
}

TEST(BtfPartialViewsImages, Png16RoundTripIsWithinHalfALinearStep) {
  const fs::path& path = partialFolder(BtfImageFormat::Png16);
  const BtfImageFolder folder = BtfImageFolder::open(path);
  EXPECT_EQ(folder.views(), imageSource().views());
  ASSERT_TRUE(folder.transfer().has_value());
  EXPECT_EQ(*folder.transfer(), BtfTransfer::Linear);
  EXPECT_EQ(readJson(path / kBtfSidecarName).at("transfer"), "linear");
  const float scale = folder.valueScale();
  EXPECT_EQ(scale, largestValue(imageSource()));
  std::vector<Rgb> a, b;
  float worst = 0;
  for (const int v : folder.views().views()) {
    imageSource().loadView(v, a);
    folder.loadView(v, b);
    for (std::size_t i = 0; i < a.size(); ++i)
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(a[i][c] - b[i][c]));
  }
  EXPECT_LE(worst, scale * (0.5f / 65535.0f + 1e-6f));
  EXPECT_GT(worst, scale * 0.05f / 65535.0f);
}

TEST(BtfPartialViewsImages, TheMissingImageSuggestedHasTheFoldersOwnExtension) {
  // Issue 16's probe: an EXR folder's error suggested a .png name.
  test::TempDir dir;
  const fs::path folder = copyOfFolder(partialFolder(BtfImageFormat::Exr), dir);
  fs::remove(folder / "tv015_pv060_tl030_pl000.exr");
  const std::string message = test::errorOf([&] { BtfImageFolder::open(folder); });
  EXPECT_THAT(message, HasSubstr("e.g. tv015_pv060_tl030_pl000.exr"));
}

TEST(BtfPartialViewsImages, MissingLightImageOfAHeldViewIsNamed) {
  test::TempDir dir;
  const fs::path folder = copyOfFolder(partialFolder(BtfImageFormat::Png8), dir);
  fs::remove(folder / "tv015_pv060_tl030_pl000.png");
  std::string message;
  try {
    BtfImageFolder::open(folder);
    message = "(no error)";
  } catch (const FileError& e) {
    message = e.what();
  } catch (const Error& e) {
    message = std::string("not a FileError: ") + e.what();
  }
  EXPECT_THAT(message, HasSubstr(folder.string()));
  EXPECT_THAT(message, HasSubstr("view (theta 15, phi 60) and light (theta 30, phi 0) is missing"));
  EXPECT_THAT(message, HasSubstr("1 of the view's 81 light images are missing"));
  // With every light of that view gone, the folder simply does not hold the view.
  const int view = *findBtfDirection(15, 60);
  for (int l = 0; l < kBtfDirectionCount; ++l) fs::remove(folder / btfImageName(view, l, BtfImageFormat::Png8));
  std::vector<int> expected = BtfViewSet::upToTheta(15).views();
  std::erase(expected, view);
  const BtfImageFolder smaller = BtfImageFolder::open(folder);
  EXPECT_EQ(smaller.views(), BtfViewSet(expected));
  std::vector<Rgb> values;
  EXPECT_THROW(smaller.loadView(view, values), Error);
}

TEST(BtfPartialViewsImages, BonnNamesReadTheSame) {
  test::TempDir dir;
  const fs::path folder = copyOfFolder(partialFolder(BtfImageFormat::Png8), dir);
  for (const int v : imageSource().views().views())
    for (int l = 0; l < kBtfDirectionCount; ++l) {
      const BtfDirection& dv = btfDirections()[std::size_t(v)];
      const BtfDirection& dl = btfDirections()[std::size_t(l)];
      char name[96];
      std::snprintf(name, sizeof name, "%05d tl%03d pl%03d tv%03d pv%03d.png", l * kBtfDirectionCount + v,
                    int(std::lround(dl.theta_deg)), int(std::lround(dl.phi_deg)), int(std::lround(dv.theta_deg)),
                    int(std::lround(dv.phi_deg)));
      fs::rename(folder / btfImageName(v, l, BtfImageFormat::Png8), folder / name);
    }
  EXPECT_TRUE(fs::exists(folder / "00000 tl000 pl000 tv000 pv000.png"));
  const BtfImageFolder renamed = BtfImageFolder::open(folder);
  expectSameHeldViews(BtfImageFolder::open(partialFolder(BtfImageFormat::Png8)), renamed);
  EXPECT_EQ(renamed.valueScale(), BtfImageFolder::open(partialFolder(BtfImageFormat::Png8)).valueScale());
}

void rewriteTransfer(const fs::path& folder, const nlohmann::json& transfer) {
  nlohmann::json sidecar = readJson(folder / kBtfSidecarName);
  sidecar["transfer"] = transfer;
  std::ofstream(folder / kBtfSidecarName, std::ios::trunc) << sidecar.dump(2);
}

TEST(BtfPartialViewsImages, SidecarTransferOverridesTheDefault) {
  test::TempDir dir;
  const fs::path folder = copyOfFolder(partialFolder(BtfImageFormat::Png8), dir);
  const BtfImageFolder srgb_folder = BtfImageFolder::open(folder);
  const float scale = srgb_folder.valueScale();
  const int view = *findBtfDirection(15, 120);
  std::vector<Rgb> srgb, linear, plain;
  srgb_folder.loadView(view, srgb);

  // "linear": value = code / 255 * scale, i.e. the sRGB value's code, not decoded.
  rewriteTransfer(folder, "linear");
  const BtfImageFolder linear_folder = BtfImageFolder::open(folder);
  ASSERT_TRUE(linear_folder.transfer().has_value());
  EXPECT_EQ(*linear_folder.transfer(), BtfTransfer::Linear);
  EXPECT_EQ(linear_folder.valueScale(), scale);
  linear_folder.loadView(view, linear);
  ASSERT_EQ(linear.size(), srgb.size());
  int differing = 0;
  for (std::size_t i = 0; i < srgb.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double expected = srgbEncode(double(srgb[i][c]) / scale) * scale;
      const double code = double(linear[i][c]) / scale * 255.0;
      ASSERT_NEAR(code, std::round(code), 1e-3) << "a linear value is a whole code times scale / 255";
      ASSERT_NEAR(linear[i][c], expected, 1e-5 * expected + 1e-7) << "entry " << i << ", channel " << c;
      differing += std::abs(linear[i][c] - srgb[i][c]) > 1e-3f * scale;
    }
  EXPECT_GT(differing, int(srgb.size())) << "the two transfers read different values";

  // An unknown transfer names the key and the value.
  rewriteTransfer(folder, "gamma");
  std::string message = errorOf([&] { BtfImageFolder::open(folder); });
  EXPECT_THAT(message, HasSubstr("transfer"));
  EXPECT_THAT(message, HasSubstr("gamma"));
  EXPECT_THAT(message, HasSubstr(kBtfSidecarName));
  rewriteTransfer(folder, 2.2);
  EXPECT_THAT(errorOf([&] { BtfImageFolder::open(folder); }), HasSubstr("transfer"));

  // No btf.json at all: 8-bit images are sRGB, value_scale 1.
  fs::remove(folder / kBtfSidecarName);
  const BtfImageFolder bare = BtfImageFolder::open(folder);
  ASSERT_TRUE(bare.transfer().has_value());
  EXPECT_EQ(*bare.transfer(), BtfTransfer::Srgb);
  EXPECT_EQ(bare.valueScale(), 1.0f);
  EXPECT_EQ(bare.white(), std::optional<float>(1.0f));
  EXPECT_EQ(bare.views(), BtfViewSet::upToTheta(15));
  bare.loadView(view, plain);
  for (std::size_t i = 0; i < srgb.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      ASSERT_LE(plain[i][c], 1.0f);
      ASSERT_FLOAT_EQ(srgb[i][c], plain[i][c] * scale);
    }
}

TEST(BtfPartialViewsImages, SidecarSrgbAppliesTo16BitImagesToo) {
  test::TempDir dir;
  const fs::path folder = copyOfFolder(partialFolder(BtfImageFormat::Png16), dir);
  const int view = *findBtfDirection(15, 300);
  std::vector<Rgb> linear, srgb;
  const BtfImageFolder linear_folder = BtfImageFolder::open(folder);
  const float scale = linear_folder.valueScale();
  linear_folder.loadView(view, linear);
  rewriteTransfer(folder, "SRGB");  // any case
  const BtfImageFolder srgb_folder = BtfImageFolder::open(folder);
  EXPECT_EQ(*srgb_folder.transfer(), BtfTransfer::Srgb);
  srgb_folder.loadView(view, srgb);
  for (std::size_t i = 0; i < srgb.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double expected = srgbDecode(double(linear[i][c]) / scale) * scale;
      ASSERT_NEAR(srgb[i][c], expected, 1e-5 * expected + 1e-7);
    }
}

TEST(BtfPartialViewsImages, SidecarTransferDoesNotApplyToFloatImages) {
  test::TempDir dir;
  const fs::path folder = copyOfFolder(partialFolder(BtfImageFormat::Exr), dir);
  rewriteTransfer(folder, "srgb");
  const BtfImageFolder exr = BtfImageFolder::open(folder);
  EXPECT_FALSE(exr.transfer().has_value());
  expectSameHeldViews(imageSource(), exr);
}

TEST(BtfPartialViewsImages, QualityMeasuresRunOverTheHeldViews) {
  const BtfImageFolder png = BtfImageFolder::open(partialFolder(BtfImageFormat::Png8));
  const BtfSsimStats ssim = compareBtfSsim(png, imageSource());
  EXPECT_EQ(ssim.images, std::size_t(7 * kBtfDirectionCount));
  EXPECT_EQ(ssim.white, png.valueScale());
  EXPECT_GT(ssim.mean_ssim, 0.99);
  EXPECT_LE(ssim.mean_ssim, 1.0);
  EXPECT_LT(ssim.rel_rmse_display, 0.01);
  const BtfData narrower = subset(imageSource(), BtfViewSet({0, 1, 2}), "narrower");
  EXPECT_THAT(errorOf([&] { compareBtfSsim(png, narrower); }), HasSubstr("view (theta 15, phi 120) is not in this BTF"));
  // Noise floor: residuals of rings 1 .. 5 (80 lights) per texel, held view and channel.
  const BtfNoiseFloor noise = estimateBtfNoiseFloor(imageSource());
  EXPECT_EQ(noise.residuals, std::size_t(kW * kH) * 7 * 80 * 3);
  EXPECT_GT(noise.rel_rmse, 0.1) << "uniform random values are all noise";
}

// ---------------------------------------------------------------------------------------------
// 4. The real Bonn slice: one view (theta 0) of UBO2003 WALLPAPER, 81 sRGB JPEGs

TEST(BtfPartialViewsBonn, RealOneViewSliceReadsAsSrgb) {
  const fs::path path = test::sharedDataDir() / "btf" / "ubo2003_wallpaper_view000";
  ASSERT_TRUE(fs::is_directory(path)) << path << " is missing (../shared/data/real must sit beside the checkout)";
  const BtfImageFolder folder = BtfImageFolder::open(path);
  EXPECT_EQ(folder.width(), 256);
  EXPECT_EQ(folder.height(), 256);
  EXPECT_EQ(folder.views(), BtfViewSet({0}));
  EXPECT_EQ(folder.views().describe(), "1 view (theta 0, phi 0)");
  ASSERT_TRUE(folder.transfer().has_value());
  EXPECT_EQ(*folder.transfer(), BtfTransfer::Srgb);
  EXPECT_EQ(folder.white(), std::optional<float>(1.0f));
  EXPECT_EQ(folder.name(), "ubo2003_wallpaper_view000");

  std::vector<Rgb> values;
  folder.loadView(0, values);
  const std::size_t texels = 256 * 256;
  ASSERT_EQ(values.size(), texels * kBtfDirectionCount);
  float lo = 1e9f, hi = -1e9f;
  for (const Rgb& c : values) {
    lo = std::min(lo, std::min(c.r, std::min(c.g, c.b)));
    hi = std::max(hi, c.maxComponent());
  }
  EXPECT_GE(lo, 0.0f);
  EXPECT_LE(hi, 1.0f);
  EXPECT_GT(hi, 0.05f) << "not a black folder";

  // Every pixel of two images, decoded by OpenImageIO (btf::readImage maps 8-bit code c to c / 255)
  // and through the sRGB curve here, is the value the folder gives.
  for (const int light : {0, *findBtfDirection(60, 54)}) {
    const fs::path& file = folder.imagePath(0, light);
    EXPECT_EQ(file.extension(), ".jpg");
    const Image image = readImage(file);
    ASSERT_EQ(image.width, 256);
    ASSERT_EQ(image.height, 256);
    ASSERT_GE(image.channels, 3);
    double worst = 0;
    for (int y = 0; y < 256; ++y)
      for (int x = 0; x < 256; ++x)
        for (int c = 0; c < 3; ++c) {
          const double code = std::round(double(image.at(x, y, c)) * 255.0);
          const double expected = srgbDecode(code / 255.0);
          const Rgb& ours = values[std::size_t(light) * texels + std::size_t(y) * 256 + std::size_t(x)];
          worst = std::max(worst, std::abs(expected - double(ours[c])));
        }
    EXPECT_LE(worst, 1e-6) << file;
  }
  std::vector<Rgb> other;
  EXPECT_THAT(errorOf([&] { folder.loadView(1, other); }), HasSubstr("view (theta 15, phi 0) is not in this BTF"));
}

// ---------------------------------------------------------------------------------------------
// 5. VQ on partial BTFs

using btf::test::vqLuminanceBound;

// Smooth (GGX over the directions) with a texture (checker times gradient), constant chromaticity
// per texel.
const BtfData& ggxFull() {
  static const BtfData data = test::makeGgxBtf(8, 8, true);
  return data;
}

void expectSameDecodeOfHeldViews(const VqBtf& a, const VqBtf& b) {
  ASSERT_EQ(a.views(), b.views());
  std::vector<Rgb> va, vb;
  for (const int v : a.views().views()) {
    a.loadView(v, va);
    b.loadView(v, vb);
    ASSERT_EQ(va.size(), vb.size());
    for (std::size_t i = 0; i < va.size(); ++i) ASSERT_EQ(va[i], vb[i]) << "view " << v << ", entry " << i;
  }
}

nlohmann::json btfzHeader(const fs::path& path) {
  const std::vector<ContainerSection> sections = readContainer(path);
  const ContainerSection& header = requireSection(sections, "header", path);
  return nlohmann::json::parse(
      std::string(reinterpret_cast<const char*>(header.data.data()), header.data.size()));
}

void checkPartialVq(const BtfData& source, int levels, const fs::path& file, int missing_view) {
  SCOPED_TRACE("views " + source.views().describe() + ", levels " + std::to_string(levels));
  VqOptions options;
  options.levels = levels;
  const VqBtf vq = compressVq(source, options);
  EXPECT_EQ(vq.views(), source.views());
  EXPECT_EQ(vq.lookupViews(), source.views());
  ASSERT_EQ(vq.stats().codebook_entries.size(), std::size_t(levels));
  const BtfErrorStats error = compareBtf(source, vq);
  EXPECT_LE(error.rel_rmse, vqLuminanceBound(options.epsilon, levels) + 3.0 * options.chroma_epsilon);
  EXPECT_LT(error.rel_rmse, 0.1);
  EXPECT_EQ(error.entries, source.entryCount());

  vq.write(file);
  const VqBtf back = VqBtf::read(file);
  EXPECT_EQ(back.views(), source.views());
  EXPECT_EQ(back.options().levels, levels);
  expectSameDecodeOfHeldViews(vq, back);
  const nlohmann::json header = btfzHeader(file);
  ASSERT_TRUE(header.contains("views"));
  EXPECT_EQ(header.at("views").get<std::vector<int>>(), source.views().views());

  // value() and values() agree with loadView on held views; a view not held is an error.
  std::vector<Rgb> view;
  std::vector<BtfSampleIndex> samples;
  std::vector<Rgb> expected;
  for (const int v : source.views().views()) {
    back.loadView(v, view);
    for (int l : {0, 3, 17, 44, 80})
      for (int t : {0, 13, 63}) {
        const int x = t % source.width(), y = t / source.width();
        samples.push_back({x, y, v, l});
        expected.push_back(view[std::size_t(l) * source.texelCount() + std::size_t(t)]);
        ASSERT_EQ(back.value(x, y, v, l), expected.back());
      }
  }
  std::vector<Rgb> out(samples.size());
  back.values(samples, out);
  EXPECT_EQ(out, expected);
  samples[samples.size() / 2].view = missing_view;
  const std::string missing = "view (" + describeBtfDirection(missing_view) + ") is not in this BTF";
  EXPECT_THAT(errorOf([&] { back.values(samples, out); }), HasSubstr(missing));
  EXPECT_THAT(errorOf([&] { vq.values(samples, out); }), HasSubstr(missing));
  EXPECT_THAT(errorOf([&] { back.loadView(missing_view, view); }), HasSubstr(missing));
}

TEST(BtfPartialViewsVq, UpToThetaAtEveryLevelRoundTripsThroughBtfz) {
  const BtfData source = subset(ggxFull(), BtfViewSet::upToTheta(15));
  test::TempDir dir;
  for (int levels = 1; levels <= 3; ++levels) {
    const char* names[] = {"l1.btfz", "l2.btfz", "l3.btfz"};
    checkPartialVq(source, levels, dir / names[levels - 1], *findBtfDirection(30, 0));
  }
}

TEST(BtfPartialViewsVq, ScatteredViewsRoundTripThroughBtfz) {
  const BtfData source = subset(ggxFull(), BtfViewSet({0, 5, 40, 80}));
  test::TempDir dir;
  checkPartialVq(source, 3, dir / "scattered.btfz", 41);
  checkPartialVq(source, 1, dir / "scattered1.btfz", 1);
}

TEST(BtfPartialViewsVq, PartialDecodeMatchesTheCompleteBtfsQuality) {
  // The same texels compressed whole and as a subset: both within the tolerance's bound on the
  // held views, so the subset is not compressed against the wrong views' data.
  const BtfViewSet views({0, 1, 2, 3, 4, 5, 6, 57, 80});
  const BtfData source = subset(ggxFull(), views);
  const VqBtf partial = compressVq(source, {});
  std::vector<Rgb> a, b;
  double err = 0, ref = 0;
  for (const int v : views.views()) {
    source.loadView(v, a);
    partial.loadView(v, b);
    for (std::size_t i = 0; i < a.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        err += (double(b[i][c]) - a[i][c]) * (double(b[i][c]) - a[i][c]);
        ref += double(a[i][c]) * a[i][c];
      }
  }
  EXPECT_LE(std::sqrt(err / ref), vqLuminanceBound(0.02f, 3) + 0.03);
}

TEST(BtfPartialViewsVq, CompleteBtfzHasNoViewsKey) {
  const BtfData complete = test::makeGgxBtf(2, 2, true);
  const VqBtf vq = compressVq(complete, {});
  EXPECT_TRUE(vq.views().complete());
  test::TempDir dir;
  vq.write(dir / "complete.btfz");
  const nlohmann::json header = btfzHeader(dir / "complete.btfz");
  EXPECT_EQ(header.at("format"), "libbtf-vq");
  EXPECT_FALSE(header.contains("views")) << header.dump();
  const VqBtf back = VqBtf::read(dir / "complete.btfz");
  EXPECT_TRUE(back.views().complete());
  std::vector<Rgb> a, b;
  for (int v : {0, 40, 80}) {
    vq.loadView(v, a);
    back.loadView(v, b);
    EXPECT_EQ(a, b);
  }
}

// The .btfz of `vq` with the header's "views" replaced (null: the key removed).
fs::path withHeaderViews(const VqBtf& vq, const test::TempDir& dir, const std::string& name, const nlohmann::json& views) {
  vq.write(dir / "good.btfz");
  auto sections = readContainer(dir / "good.btfz");
  for (auto& s : sections)
    if (s.name == "header") {
      nlohmann::json header = nlohmann::json::parse(std::string(reinterpret_cast<const char*>(s.data.data()), s.data.size()));
      if (views.is_null())
        header.erase("views");
      else
        header["views"] = views;
      const std::string text = header.dump();
      const auto* bytes = reinterpret_cast<const std::byte*>(text.data());
      s.data.assign(bytes, bytes + text.size());
    }
  const fs::path path = dir / (name + ".btfz");
  writeContainer(path, sections);
  return path;
}

TEST(BtfPartialViewsVq, ReaderRejectsInvalidViewsInTheHeader) {
  test::TempDir dir;
  for (int levels = 1; levels <= 3; ++levels) {
    SCOPED_TRACE("levels " + std::to_string(levels));
    VqOptions options;
    options.levels = levels;
    const VqBtf vq = compressVq(subset(ggxFull(), BtfViewSet({0, 40})), options);
    const fs::path repeated = withHeaderViews(vq, dir, "repeated", std::vector<int>{0, 0});
    try {
      VqBtf::read(repeated);
      ADD_FAILURE() << "repeated view accepted";
    } catch (const FileError& e) {
      EXPECT_THAT(e.what(), HasSubstr("views"));
    }
    // A views list of another length than the data: the streams' sizes do not fit it.
    // At level 3 only the header's codebook_entries, checked against the sections, catches a
    // list of a divisor of the real length (the level-3 entries would split evenly at it).
    for (const nlohmann::json& views : {nlohmann::json(std::vector<int>{0}), nlohmann::json(std::vector<int>{0, 40, 41, 42}),
                                        nlohmann::json()}) {
      const fs::path path = withHeaderViews(vq, dir, "count", views);
      try {
        const VqBtf back = VqBtf::read(path);
        std::vector<Rgb> a, b;
        vq.loadView(0, a);
        back.loadView(0, b);
        ADD_FAILURE() << "views " << views.dump() << " accepted for a file of views [0, 40]; view 0 then decodes "
                      << (a == b ? "the same" : "differently") << ", rel_rmse "
                      << compareBtf(subset(ggxFull(), back.views()), back).rel_rmse << " (original "
                      << compareBtf(subset(ggxFull(), vq.views()), vq).rel_rmse << ")";
      } catch (const FileError&) {
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// 6. PCA on partial BTFs

TEST(BtfPartialViewsPca, StoresOnlyTheHeldViews) {
  const BtfData full = test::makeGgxBtf(kW, kH, false);
  const BtfViewSet views = BtfViewSet::upToTheta(15);
  const BtfData source = subset(full, views);
  const PcaBtf pca = compressPca(source, 3);
  EXPECT_EQ(pca.views(), views);
  EXPECT_EQ(pca.lookupViews(), views);
  EXPECT_EQ(pca.components(), 3);
  EXPECT_EQ(pca.storedBytes(), PcaBtf::storedBytesFor(kW, kH, 3, PcaPrecision::Half, views.count()));
  EXPECT_LT(pca.storedBytes(), PcaBtf::storedBytesFor(kW, kH, 3, PcaPrecision::Half));
  EXPECT_LT(pca.storedBytes(), compressPca(full, 3).storedBytes());
  const double error = compareBtf(source, pca).rel_rmse;
  EXPECT_TRUE(std::isfinite(error));
  EXPECT_LT(error, 0.5);
  std::vector<Rgb> out;
  EXPECT_THAT(errorOf([&] { pca.loadView(7, out); }), HasSubstr("view (theta 30, phi 0) is not in this BTF"));
  // value() agrees with loadView on a held view (up to the summation order: loadView is a matrix product).
  pca.loadView(4, out);
  for (int l : {0, 9, 80}) {
    const Rgb a = pca.value(3, 2, 4, l), b = out[(std::size_t(l) * kH + 2) * kW + 3];
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-5f * (1.0f + std::abs(b[c])));
  }

  // At full rank (12 texels: centred rank <= 11) in float the held views come back exactly.
  const PcaBtf exact = compressPca(source, kW * kH - 1, PcaPrecision::Float);
  EXPECT_LT(compareBtf(source, exact).rel_rmse, 1e-5);

  // The budget search counts the held views.
  const PcaBtf budget = compressPcaToBytes(source, pca.storedBytes());
  EXPECT_EQ(budget.components(), 3);
  EXPECT_EQ(pcaComponentsForBudget(kW, kH, pca.storedBytes(), PcaPrecision::Half, views.count()), 3);
}

// ---------------------------------------------------------------------------------------------
// 7. Compressibility on partial BTFs

TEST(BtfPartialViewsCompressibility, AnalyzesThePairsOfTheHeldViews) {
  const BtfViewSet views = BtfViewSet::upToTheta(15);
  const BtfData source = subset(test::makeGgxBtf(kW, kH, false), views);
  CompressibilityOptions options;
  options.directions = 0;
  const CompressibilityReport report = analyzeCompressibility(source, options);
  EXPECT_EQ(report.texels, kW * kH);
  EXPECT_EQ(report.directions, views.count() * kBtfDirectionCount);
  ASSERT_EQ(report.singular_values.size(), std::size_t(kW * kH));
  ASSERT_EQ(report.nearest_distance.size(), std::size_t(kW * kH));

  // The T x D luminance matrix over exactly the held pairs: its energy is the sum of s_i^2, and
  // the nearest-neighbour distances are those of its rows.
  const int T = kW * kH;
  std::vector<std::vector<double>> rows(static_cast<std::size_t>(T));
  std::vector<Rgb> view;
  for (const int v : views.views()) {
    source.loadView(v, view);
    for (int l = 0; l < kBtfDirectionCount; ++l)
      for (int t = 0; t < T; ++t) rows[std::size_t(t)].push_back(view[std::size_t(l) * std::size_t(T) + std::size_t(t)].luminance());
  }
  double energy = 0, singular_energy = 0;
  for (const auto& r : rows)
    for (double x : r) energy += x * x;
  for (double s : report.singular_values) singular_energy += s * s;
  EXPECT_NEAR(singular_energy, energy, 1e-6 * energy);
  for (int t = 0; t < T; ++t) {
    double best = 2;
    const auto& a = rows[std::size_t(t)];
    for (int u = 0; u < T; ++u) {
      if (u == t) continue;
      const auto& b = rows[std::size_t(u)];
      double ab = 0, aa = 0, bb = 0;
      for (std::size_t i = 0; i < a.size(); ++i) ab += a[i] * b[i], aa += a[i] * a[i], bb += b[i] * b[i];
      best = std::min(best, std::sqrt(std::max(0.0, 1.0 - ab * ab / (aa * bb))));
    }
    EXPECT_NEAR(report.nearest_distance[std::size_t(t)], best, 1e-5) << "texel " << t;
  }

  // A sample of the held pairs; more than there are: all of them.
  options.directions = 100;
  EXPECT_EQ(analyzeCompressibility(source, options).directions, 100);
  options.directions = 5000;
  EXPECT_EQ(analyzeCompressibility(source, options).directions, views.count() * kBtfDirectionCount);
  const BtfData scattered = subset(test::makeGgxBtf(kW, kH, false), BtfViewSet({0, 40}));
  options.directions = 0;
  EXPECT_EQ(analyzeCompressibility(scattered, options).directions, 2 * kBtfDirectionCount);
}

// ---------------------------------------------------------------------------------------------
// 8. BtfMaterial on partial BTFs

glm::vec3 direction(float theta_deg, float phi_deg) {
  return sphericalDirection(theta_deg * kPi / 180.0f, phi_deg * kPi / 180.0f);
}

void expectRgbNear(const Rgb& a, const Rgb& b, float rel) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], rel * std::max(1e-3f, std::abs(b[c])));
}

TEST(BtfPartialViewsMaterial, ConstantInWoBeyondTheLastHeldRing) {
  const BtfData full = test::makeGgxBtf(kW, kH, false);
  const auto partial = std::make_shared<const BtfData>(subset(full, BtfViewSet::upToTheta(15)));
  const BtfMaterial material(partial, BtfTexelFilter::Nearest);
  const BtfMaterial complete(std::make_shared<const BtfData>(full), BtfTexelFilter::Nearest);
  const glm::vec2 uv(2.5f / kW, 1.5f / kH);  // texel (2, 1)
  const auto& dirs = btfDirections();
  for (const int l : {0, 10, 25, 60}) {
    const glm::vec3 wi = dirs[std::size_t(l)].w;
    for (const float phi : {0.0f, 30.0f, 60.0f, 137.0f, 290.0f}) {
      const Rgb at15 = material.eval(wi, direction(15.0f, phi), uv);
      const Rgb at50 = material.eval(wi, direction(50.0f, phi), uv);
      expectRgbNear(at50, at15, 1e-4f);
      // Only the azimuth's float rounding differs between these elevations.
      expectRgbNear(material.eval(wi, direction(75.0f, phi), uv), at50, 1e-5f);
      expectRgbNear(material.eval(wi, direction(88.0f, phi), uv), at50, 1e-5f);
      // Within the held rings the partial BTF evaluates as the complete one.
      expectRgbNear(at15, complete.eval(wi, direction(15.0f, phi), uv), 1e-5f);
      expectRgbNear(material.eval(wi, direction(7.5f, phi), uv), complete.eval(wi, direction(7.5f, phi), uv), 1e-5f);
    }
    // At a measured view of ring 1 the data itself.
    expectRgbNear(material.eval(wi, direction(50.0f, 60.0f), uv), full.at(2, 1, *findBtfDirection(15, 60), l), 1e-4f);
    // Halfway between two ring-1 azimuths, their mean.
    expectRgbNear(material.eval(wi, direction(50.0f, 90.0f), uv),
                  0.5f * (full.at(2, 1, *findBtfDirection(15, 60), l) + full.at(2, 1, *findBtfDirection(15, 120), l)), 1e-4f);
  }
  // The test bites: the complete BTF does change between 15 and 50 degrees, and ring 1 with phi.
  const glm::vec3 wi = dirs[25].w;
  EXPECT_GT(std::abs(complete.eval(wi, direction(50.0f, 60.0f), uv).g - complete.eval(wi, direction(15.0f, 60.0f), uv).g),
            1e-3f * complete.eval(wi, direction(15.0f, 60.0f), uv).g);
  EXPECT_NE(material.eval(wi, direction(50.0f, 0.0f), uv), material.eval(wi, direction(50.0f, 180.0f), uv));

  // Sampling and pdf use only held views, and agree.
  Rng rng(5);
  for (int i = 0; i < 50; ++i) {
    const glm::vec3 wo = direction(20.0f + 60.0f * rng.uniform(), 360.0f * rng.uniform());
    const auto s = material.sample(wo, uv, rng.uniform2D());
    if (!s) continue;
    EXPECT_GT(s->pdf, 0.0f);
    EXPECT_NEAR(material.pdf(s->wi, wo, uv), s->pdf, 1e-4f * s->pdf);
  }
}

TEST(BtfPartialViewsMaterial, VqOfPartialViewsIsConstantBeyondTheLastRingToo) {
  const auto vq = std::make_shared<const VqBtf>(compressVq(subset(ggxFull(), BtfViewSet::upToTheta(15)), {}));
  const BtfMaterial material(vq, BtfTexelFilter::Nearest);
  const glm::vec2 uv(0.3f, 0.6f);
  const auto& dirs = btfDirections();
  for (const int l : {0, 12, 50})
    for (const float phi : {0.0f, 45.0f, 200.0f}) {
      const glm::vec3 wi = dirs[std::size_t(l)].w;
      expectRgbNear(material.eval(wi, direction(60.0f, phi), uv), material.eval(wi, direction(15.0f, phi), uv), 1e-4f);
      expectRgbNear(material.eval(wi, direction(80.0f, phi), uv), material.eval(wi, direction(40.0f, phi), uv), 1e-5f);
    }
  // At a measured view and light the decoded entry (texel (2, 4) of 8 x 8).
  const int v = *findBtfDirection(15, 240);
  expectRgbNear(material.eval(dirs[30].w, dirs[std::size_t(v)].w, uv), vq->value(2, 4, v, 30), 1e-4f);
  Rng rng(9);
  for (int i = 0; i < 30; ++i) {
    const glm::vec3 wo = direction(70.0f * rng.uniform(), 360.0f * rng.uniform());
    const auto s = material.sample(wo, uv, rng.uniform2D());
    if (!s) continue;
    EXPECT_NEAR(material.pdf(s->wi, wo, uv), s->pdf, 1e-4f * s->pdf);
  }
}

TEST(BtfPartialViewsMaterial, SingleViewServesEveryWo) {
  const BtfData full = test::makeGgxBtf(kW, kH, false);
  const auto one = std::make_shared<const BtfData>(subset(full, BtfViewSet({0})));
  const BtfMaterial material(one, BtfTexelFilter::Nearest);
  const glm::vec2 uv(0.6f, 0.2f);  // texel (2, 0)
  const auto& dirs = btfDirections();
  for (const int l : {0, 3, 20, 70}) {
    const glm::vec3 wi = dirs[std::size_t(l)].w;
    const Rgb pole = material.eval(wi, glm::vec3(0, 0, 1), uv);
    expectRgbNear(pole, full.at(2, 0, 0, l), 1e-4f);
    for (const float theta : {5.0f, 15.0f, 33.0f, 60.0f, 85.0f})
      for (const float phi : {0.0f, 100.0f, 250.0f}) EXPECT_EQ(material.eval(wi, direction(theta, phi), uv), pole);
  }
  // Between lights it still interpolates over wi.
  expectRgbNear(material.eval(direction(30.0f, 15.0f), direction(45.0f, 10.0f), uv),
                0.5f * (full.at(2, 0, 0, 7) + full.at(2, 0, 0, 8)), 1e-3f);
}

TEST(BtfPartialViewsMaterial, ScatteredViewsAreRejected) {
  const BtfData full = test::makeGgxBtf(2, 2, false);
  for (const BtfViewSet& views : {BtfViewSet({0, 40}), BtfViewSet({0, 1, 2}), BtfViewSet({1, 2, 3, 4, 5, 6}),
                                  BtfViewSet({0, 1, 2, 3, 4, 5, 6, 7})}) {
    const auto data = std::make_shared<const BtfData>(subset(full, views));
    const std::string message = errorOf([&] { BtfMaterial material(data); });
    EXPECT_THAT(message, HasSubstr("whole rings")) << views.describe();
    EXPECT_THAT(message, HasSubstr(views.describe()));
  }
  // Whole rings are accepted, including the complete set.
  for (const float theta : {0.0f, 15.0f, 30.0f, 45.0f, 60.0f, 75.0f})
    EXPECT_NO_THROW(BtfMaterial(std::make_shared<const BtfData>(subset(full, BtfViewSet::upToTheta(theta))))) << theta;
}

}  // namespace
}  // namespace btf
