// Image-folder BTFs: names in any common ordering, exact EXR and quantized PNG round trips, and
// the errors of a broken folder (missing, duplicate, differently sized, corrupt images) naming
// the file; the writer never leaves a half-written folder.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "btf/core/error.h"
#include "btf/core/rng.h"
#include "btf/io/btf_images.h"
#include "btf/io/image.h"
#include "support/raw_image_writer.h"
#include "support/test_support.h"
#include "support/tier.h"

namespace btf {
namespace {
namespace fs = std::filesystem;
using testing::HasSubstr;
using test::errorOf;

constexpr int kW = 4, kH = 3;  // not square, so a swapped x/y shows

// Values in [0, 3): apparent BRDFs above 1 as glossy samples have them.
BtfData randomBtf(std::uint64_t seed) {
  BtfData data(kW, kH, "random");
  Rng rng(seed);
  for (int v = 0; v < kBtfDirectionCount; ++v)
    for (int l = 0; l < kBtfDirectionCount; ++l)
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) data.at(x, y, v, l) = Rgb(3 * rng.uniform(), 3 * rng.uniform(), 3 * rng.uniform());
  return data;
}

// One written folder shared by the tests that only read or damage a copy (writing 6561 files is
// the slow part).
const fs::path& exrFolder() {
  static test::TempDir dir;
  static const fs::path folder = [] {
    const fs::path f = dir / "random-exr";
    writeBtfImageFolder(randomBtf(7), f, BtfImageFormat::Exr);
    return f;
  }();
  return folder;
}

fs::path copyOfExrFolder(const test::TempDir& dir) {
  const fs::path copy = dir / "copy";
  fs::copy(exrFolder(), copy, fs::copy_options::recursive);
  return copy;
}

void expectSameViews(const BtfSource& a, const BtfSource& b) {
  std::vector<Rgb> va, vb;
  for (int v = 0; v < kBtfDirectionCount; ++v) {
    a.loadView(v, va);
    b.loadView(v, vb);
    ASSERT_EQ(va, vb) << "view " << v;
  }
}

TEST(BtfImageNames, AcceptsCommonOrderingsAndSeparators) {
  const int view = *findBtfDirection(30, 60), light = *findBtfDirection(45, 120);
  for (const char* name : {"tv030_pv060_tl045_pl120.png", "tl045_pl120_tv030_pv060.exr",
                           "00012 tl045 pl120 tv030 pv060.png", "TV30-PV60-TL45-PL120.PNG", "tv030pv060tl045pl120.png",
                           "wool_tv030.pv060.tl045.pl120.png", "tv30.0_pv60.0_tl45.0_pl120.0.exr"}) {
    const std::optional<BtfImagePair> pair = parseBtfImageName(name);
    ASSERT_TRUE(pair) << name;
    EXPECT_EQ(pair->view, view) << name;
    EXPECT_EQ(pair->light, light) << name;
  }
  // Any azimuth at the pole.
  EXPECT_EQ(parseBtfImageName("tv000_pv090_tl000_pl000.png")->view, 0);
}

TEST(BtfImageNames, IgnoresOtherFilesAndRejectsBadTags) {
  EXPECT_FALSE(parseBtfImageName("preview.png"));
  EXPECT_FALSE(parseBtfImageName("btf.json"));
  EXPECT_THAT(errorOf([] { parseBtfImageName("tv030_pv060_tl045.png"); }), HasSubstr("'pl' is missing"));
  EXPECT_THAT(errorOf([] { parseBtfImageName("tv030_pv060_tv045_pl120.png"); }), HasSubstr("twice"));
  EXPECT_THAT(errorOf([] { parseBtfImageName("tv031_pv060_tl045_pl120.png"); }),
              HasSubstr("view direction (theta 31, phi 60) is not one of the 81"));
}

TEST(BtfImageNames, WriterNamesParseBackToTheirPair) {
  for (int v = 0; v < kBtfDirectionCount; ++v)
    for (int l = 0; l < kBtfDirectionCount; l += 7) {
      const auto pair = parseBtfImageName(btfImageName(v, l, BtfImageFormat::Png8));
      ASSERT_TRUE(pair);
      EXPECT_EQ(pair->view, v);
      EXPECT_EQ(pair->light, l);
    }
  EXPECT_EQ(btfImageName(*findBtfDirection(30, 60), *findBtfDirection(45, 120), BtfImageFormat::Png8),
            "tv030_pv060_tl045_pl120.png");
}

BTF_SLOW_TEST(BtfImageFolder, ExrRoundTripIsExact) {
  const BtfImageFolder folder = BtfImageFolder::open(exrFolder());
  EXPECT_EQ(folder.width(), kW);
  EXPECT_EQ(folder.height(), kH);
  expectSameViews(randomBtf(7), folder);
}

TEST(BtfImageFolder, WriterLeavesOnlyTheFolderWithImagesAndSidecar) {
  const fs::path parent = exrFolder().parent_path();
  std::size_t siblings = 0;
  for (const auto& entry : fs::directory_iterator(parent)) siblings += entry.path() != exrFolder();
  EXPECT_EQ(siblings, 0u) << "no temporary folder is left beside the output";
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(exrFolder())) files += entry.is_regular_file();
  EXPECT_EQ(files, std::size_t(kBtfDirectionCount * kBtfDirectionCount + 1));
  EXPECT_TRUE(fs::exists(exrFolder() / kBtfSidecarName));
}

class BtfImageFolderPng : public testing::TestWithParam<BtfImageFormat> {};

BTF_SLOW_TEST_P(BtfImageFolderPng, RoundTripIsWithinHalfAQuantizationStep) {
  test::TempDir dir;
  const BtfData original = randomBtf(11);
  writeBtfImageFolder(original, dir / "png", GetParam());
  const BtfImageFolder folder = BtfImageFolder::open(dir / "png");
  float largest = 0;
  std::vector<Rgb> a, b;
  for (int v = 0; v < kBtfDirectionCount; ++v) {
    original.loadView(v, a);
    for (const Rgb& c : a) largest = std::max(largest, c.maxComponent());
  }
  EXPECT_EQ(folder.valueScale(), largest) << "the writer scales the largest value to the largest code";
  // 8-bit PNGs hold sRGB-encoded codes, 16-bit ones linear codes (btf_images.h): the error is half
  // a code step in the encoded domain, plus float rounding (a few ulps).
  const bool srgb = GetParam() == BtfImageFormat::Png8;
  ASSERT_EQ(folder.transfer(), srgb ? BtfTransfer::Srgb : BtfTransfer::Linear);
  const float max_code = srgb ? 255.0f : 65535.0f;
  auto encoded = [&](float value) {
    const float v = value / largest;
    return !srgb ? v : (v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f);
  };
  const float bound = 0.5f / max_code + 2e-6f;
  float worst = 0;
  for (int v = 0; v < kBtfDirectionCount; ++v) {
    original.loadView(v, a);
    folder.loadView(v, b);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i)
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(encoded(a[i][c]) - encoded(b[i][c])));
  }
  EXPECT_LE(worst, bound);
  EXPECT_GT(worst, 0.1f * bound) << "values really went through quantization";
}

INSTANTIATE_TEST_SUITE_P(Formats, BtfImageFolderPng, testing::Values(BtfImageFormat::Png8, BtfImageFormat::Png16),
                         [](const auto& info) { return btfImageFormatName(info.param); });

BTF_SLOW_TEST(BtfImageFolder, SidecarScaleMultipliesPngCodes) {
  test::TempDir dir;
  BtfImageWriteOptions options;
  options.format = BtfImageFormat::Png8;
  options.value_scale = 4.0f;
  writeBtfImageFolder(randomBtf(3), dir / "png", options);
  std::vector<Rgb> scaled, plain;
  BtfImageFolder::open(dir / "png").loadView(5, scaled);
  fs::remove(dir / "png" / kBtfSidecarName);
  BtfImageFolder::open(dir / "png").loadView(5, plain);
  for (std::size_t i = 0; i < scaled.size(); ++i) EXPECT_FLOAT_EQ(scaled[i].g, 4.0f * plain[i].g);

  std::ofstream(dir / "png" / kBtfSidecarName) << R"({"value_scale": -1})";
  EXPECT_THAT(errorOf([&] { BtfImageFolder::open(dir / "png"); }), HasSubstr("value_scale must be a number in ["));
}

BTF_SLOW_TEST(BtfImageFolder, OtherNameOrderingsReadTheSame) {
  test::TempDir dir;
  const fs::path folder = copyOfExrFolder(dir);
  int index = 0;
  for (int v = 0; v < kBtfDirectionCount; ++v)
    for (int l = 0; l < kBtfDirectionCount; ++l) {
      const BtfDirection& dv = btfDirections()[std::size_t(v)];
      const BtfDirection& dl = btfDirections()[std::size_t(l)];
      char name[96];
      // Frame number first, light tags first, spaces, no zero padding, upper-case extension.
      std::snprintf(name, sizeof name, "%05d tl%g pl%g tv%g pv%g.EXR", index++, double(dl.theta_deg),
                    double(dl.phi_deg), double(dv.theta_deg), double(dv.phi_deg));
      fs::rename(folder / btfImageName(v, l, BtfImageFormat::Exr), folder / name);
    }
  expectSameViews(BtfImageFolder::open(exrFolder()), BtfImageFolder::open(folder));
}

TEST(BtfImageFolder, MissingImageIsNamedByItsAngles) {
  test::TempDir dir;
  const fs::path folder = copyOfExrFolder(dir);
  fs::remove(folder / "tv045_pv100_tl060_pl018.exr");
  const std::string message = errorOf([&] { BtfImageFolder::open(folder); });
  EXPECT_THAT(message, HasSubstr(folder.string()));
  EXPECT_THAT(message, HasSubstr("view (theta 45, phi 100) and light (theta 60, phi 18) is missing"));
  EXPECT_THAT(message, HasSubstr("1 of the view's 81 light images are missing"));
}

BTF_SLOW_TEST(BtfImageFolder, DuplicateImageNamesBothFiles) {
  test::TempDir dir;
  const fs::path folder = copyOfExrFolder(dir);
  fs::copy_file(folder / "tv030_pv060_tl045_pl120.exr", folder / "tl045_pl120_tv030_pv060.exr");
  const std::string message = errorOf([&] { BtfImageFolder::open(folder); });
  EXPECT_THAT(message, HasSubstr("two images for view (theta 30, phi 60) and light (theta 45, phi 120)"));
  EXPECT_THAT(message, HasSubstr("tv030_pv060_tl045_pl120.exr"));
  EXPECT_THAT(message, HasSubstr("tl045_pl120_tv030_pv060.exr"));
}

BTF_SLOW_TEST(BtfImageFolder, DifferentlySizedImageNamesFileAndBothSizes) {
  test::TempDir dir;
  const fs::path folder = copyOfExrFolder(dir);
  const fs::path odd = folder / "tv060_pv018_tl015_pl000.exr";
  writeImage(odd, Image(kW + 1, kH + 2, 3, 0.5f));
  const BtfImageFolder btf = BtfImageFolder::open(folder);
  std::vector<Rgb> values;
  EXPECT_NO_THROW(btf.loadView(0, values)) << "other views stay readable";
  const std::string message = errorOf([&] { btf.loadView(*findBtfDirection(60, 18), values); });
  EXPECT_THAT(message, HasSubstr(odd.string()));
  EXPECT_THAT(message, HasSubstr("is 5 x 5 pixels, but the BTF's images are 4 x 3"));
}

TEST(BtfImageFolder, CorruptOrTruncatedImageNamesTheFile) {
  test::TempDir dir;
  const fs::path folder = copyOfExrFolder(dir);
  const fs::path garbage = folder / "tv015_pv000_tl030_pl000.exr";
  std::ofstream(garbage, std::ios::binary | std::ios::trunc) << "this is not an image at all";
  const fs::path truncated = folder / "tv015_pv060_tl030_pl000.exr";
  fs::resize_file(truncated, fs::file_size(truncated) / 2);
  const BtfImageFolder btf = BtfImageFolder::open(folder);
  std::vector<Rgb> values;
  EXPECT_THAT(errorOf([&] { btf.loadView(*findBtfDirection(15, 0), values); }), HasSubstr(garbage.string()));
  EXPECT_THAT(errorOf([&] { btf.loadView(*findBtfDirection(15, 60), values); }), HasSubstr(truncated.string()));
}

BTF_SLOW_TEST(BtfImageFolder, NanOrNegativeExrValueNamesFileAndPixel) {
  test::TempDir dir;
  const fs::path folder = copyOfExrFolder(dir);
  const BtfImageFolder btf = BtfImageFolder::open(folder);
  std::vector<Rgb> values;
  Image image(kW, kH, 3, 0.25f);
  image.at(2, 1, 1) = std::nanf("");
  const fs::path path = folder / "tv075_pv015_tl000_pl000.exr";
  test::writeRawImage(path, image);  // libbtf's writer refuses NaN
  std::string message = errorOf([&] { btf.loadView(*findBtfDirection(75, 15), values); });
  EXPECT_THAT(message, HasSubstr(path.string()));
  EXPECT_THAT(message, HasSubstr("pixel (2, 1) holds NaN"));
  image.at(2, 1, 1) = -0.5f;
  writeImage(path, image);
  EXPECT_THAT(errorOf([&] { btf.loadView(*findBtfDirection(75, 15), values); }), HasSubstr("negative"));
}

BTF_SLOW_TEST(BtfImageFolder, TooFewChannelsIsAnError) {
  test::TempDir dir;
  const fs::path folder = copyOfExrFolder(dir);
  writeImage(folder / "tv000_pv000_tl000_pl000.exr", Image(kW, kH, 1, 0.5f));
  const BtfImageFolder btf = BtfImageFolder::open(folder);
  std::vector<Rgb> values;
  EXPECT_THAT(errorOf([&] { btf.loadView(0, values); }), HasSubstr("has 1 channel(s)"));
}

// A source that fails halfway, as an interrupted generator or an unreadable input would.
class FailingSource final : public BtfSource {
 public:
  int width() const override { return 2; }
  int height() const override { return 2; }
  std::string name() const override { return "failing"; }
  void loadView(int view, std::vector<Rgb>& out) const override {
    if (view == 3) throw Error("failing: view 3 cannot be produced");
    out.assign(std::size_t(kBtfDirectionCount) * 4, Rgb(0.5f));
  }
};

BTF_SLOW_TEST(BtfImageFolder, FailedWriteLeavesNothingAndKeepsTheOldFolder) {
  test::TempDir dir;
  EXPECT_THROW(writeBtfImageFolder(FailingSource(), dir / "new", BtfImageFormat::Exr), Error);
  EXPECT_TRUE(fs::is_empty(dir.path())) << "neither the folder nor a temporary one is left";

  const fs::path folder = copyOfExrFolder(dir);
  EXPECT_THROW(writeBtfImageFolder(FailingSource(), folder, BtfImageFormat::Exr), Error);
  expectSameViews(randomBtf(7), BtfImageFolder::open(folder));
  std::size_t entries = 0;
  for (const auto& entry : fs::directory_iterator(dir.path())) entries += bool(entry.exists());
  EXPECT_EQ(entries, 1u);
}

TEST(BtfImageFolder, WriterRefusesToReplaceAFolderOfOtherFiles) {
  test::TempDir dir;
  fs::create_directory(dir / "photos");
  std::ofstream(dir / "photos" / "holiday.jpg") << "precious";
  EXPECT_THAT(errorOf([&] { writeBtfImageFolder(randomBtf(1), dir / "photos", BtfImageFormat::Exr); }),
              HasSubstr("refusing to replace it"));
  EXPECT_TRUE(fs::exists(dir / "photos" / "holiday.jpg"));
}

TEST(BtfImageFolder, OpenRejectsFoldersWithoutImages) {
  test::TempDir dir;
  EXPECT_THAT(errorOf([&] { BtfImageFolder::open(dir / "absent"); }), HasSubstr("no such folder"));
  EXPECT_THAT(errorOf([&] { BtfImageFolder::open(dir.path()); }), HasSubstr("holds no BTF images"));
}

}  // namespace
}  // namespace btf
