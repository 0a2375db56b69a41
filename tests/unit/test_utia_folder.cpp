// UTIA-layout image folders (btf/io/btf_images.h): a subfolder per view, EXR images in CIE XYZ
// (D65) read as linear Rec.709, the database's list of shifted lights, and the errors of a broken
// folder naming the file.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "btf/compress/vq_btf.h"
#include "btf/core/btf_directions.h"
#include "btf/io/btf_images.h"
#include "btf/io/image.h"
#include "support/test_support.h"
#include "support/tier.h"

namespace btf {
namespace {
namespace fs = std::filesystem;
using test::errorOf;
using testing::HasSubstr;

constexpr int kUtiaW = 3, kUtiaH = 2;

BtfData utiaSource() {
  BtfData data(kUtiaW, kUtiaH, "utia-source");
  for (int v = 0; v < kBtfDirectionCount; ++v)
    for (int l = 0; l < kBtfDirectionCount; ++l)
      for (int y = 0; y < kUtiaH; ++y)
        for (int x = 0; x < kUtiaW; ++x)
          data.at(x, y, v, l) = Rgb(0.1f + 0.01f * float(l % 13), 0.2f + 0.005f * float(v % 7), 0.05f * float(1 + x + y));
  return data;
}

// One written UTIA folder shared by the tests that read or damage a copy.
const fs::path& utiaFolder() {
  static test::TempDir dir;
  static const fs::path folder = [] {
    const fs::path f = dir / "utia";
    BtfImageWriteOptions options;
    options.layout = BtfImageLayout::Utia;
    writeBtfImageFolder(utiaSource(), f, options);
    return f;
  }();
  return folder;
}

fs::path copyOfUtiaFolder(const test::TempDir& dir, bool with_sidecar = true) {
  const fs::path copy = dir / "copy";
  fs::copy(utiaFolder(), copy, fs::copy_options::recursive);
  if (!with_sidecar) fs::remove(copy / kBtfSidecarName);
  return copy;
}

TEST(UtiaFolder, WriterMakesTheDatabaseLayout) {
  EXPECT_EQ(btfImagePath(*findBtfDirection(30, 60), *findBtfDirection(45, 120), BtfImageFormat::Png8, BtfImageLayout::Utia),
            "tv030_pv060/tl045_pl120_tv030_pv060.png");
  EXPECT_TRUE(fs::exists(utiaFolder() / "tv000_pv000" / "tl000_pl000_tv000_pv000.exr"));
  EXPECT_TRUE(fs::exists(utiaFolder() / "tv075_pv345" / "tl075_pl345_tv075_pv345.exr"));
  std::size_t views = 0;
  for (const auto& entry : fs::directory_iterator(utiaFolder())) views += entry.is_directory();
  EXPECT_EQ(views, 81u);
}

// The images hold XYZ: read one back raw and check it against the standard matrix, then the
// folder as a BTF against its source.
TEST(UtiaFolder, ExrImagesHoldXyzAndReadBackAsRgb) {
  const Image raw = readImage(utiaFolder() / "tv015_pv060" / "tl030_pl030_tv015_pv060.exr");
  const Rgb rgb = utiaSource().at(2, 1, *findBtfDirection(15, 60), *findBtfDirection(30, 30));
  const double x = 0.4124564 * rgb.r + 0.3575761 * rgb.g + 0.1804375 * rgb.b;
  const double y = 0.2126729 * rgb.r + 0.7151522 * rgb.g + 0.0721750 * rgb.b;
  const double z = 0.0193339 * rgb.r + 0.1191920 * rgb.g + 0.9503041 * rgb.b;
  EXPECT_NEAR(raw.pixels[raw.offset(2, 1, 0)], x, 1e-6);
  EXPECT_NEAR(raw.pixels[raw.offset(2, 1, 1)], y, 1e-6);
  EXPECT_NEAR(raw.pixels[raw.offset(2, 1, 2)], z, 1e-6);

  // Without btf.json, as the database ships it: the layout alone says XYZ.
  test::TempDir dir;
  const BtfImageFolder folder = BtfImageFolder::open(copyOfUtiaFolder(dir, false));
  EXPECT_EQ(folder.layout(), BtfImageLayout::Utia);
  EXPECT_EQ(folder.colorSpace(), BtfColorSpace::Xyz);
  EXPECT_LT(compareBtf(utiaSource(), folder).rel_rmse, 1e-6);
}

TEST(UtiaFolder, ShiftedLightsFromTheDirectionList) {
  test::TempDir dir;
  const fs::path folder = copyOfUtiaFolder(dir);
  {
    std::ofstream list(folder / "directions.txt");
    list << "# number theta phi theta_lS phi_lS\n";
    for (int k = 0; k < kBtfDirectionCount; ++k) {
      const BtfDirection& d = btfDirections()[std::size_t(k)];
      list << k + 1 << " " << d.theta_deg << " " << d.phi_deg << " " << (k == 0 ? 8.0f : d.theta_deg + 4.0f) << " "
           << d.phi_deg << "\n";
    }
    std::ofstream sidecar(folder / kBtfSidecarName);
    sidecar << R"({"direction_list": "directions.txt"})";
  }
  const BtfImageFolder btf = BtfImageFolder::open(folder);
  const BtfDirectionSet& set = btf.directions();
  EXPECT_FALSE(set.sharedLights());
  EXPECT_TRUE(set.indexedAsUbo2003());
  EXPECT_EQ(set.lights(0)[0].theta_deg, 8.0f);                             // the pole's light, moved aside
  EXPECT_EQ(set.lights(0)[1].theta_deg, 15.0f);                            // other lights where named
  EXPECT_EQ(set.lights(*findBtfDirection(45, 20))[std::size_t(*findBtfDirection(45, 20))].theta_deg, 49.0f);
  EXPECT_THAT(set.describe(), HasSubstr("view-dependent"));
  // The codecs index lights by their nominal place: they take it.
  EXPECT_NO_THROW(btf.views().requireUbo2003("VQ compression"));

  std::ofstream(folder / "directions.txt") << "1 0 0 5 0\n";
  EXPECT_THAT(errorOf([&] { BtfImageFolder::open(folder); }), HasSubstr("lists 1 directions"));
}

TEST(UtiaFolder, BrokenFoldersNameTheFile) {
  test::TempDir dir;
  const fs::path folder = copyOfUtiaFolder(dir);
  fs::remove(folder / "tv045_pv100" / "tl060_pl018_tv045_pv100.exr");
  const std::string missing = errorOf([&] { BtfImageFolder::open(folder); });
  EXPECT_THAT(missing, HasSubstr("view (theta 45, phi 100) and light (theta 60, phi 18) is missing"));
  EXPECT_THAT(missing, HasSubstr("tv045_pv100/tl060_pl018_tv045_pv100"));

  writeImage(folder / "tv045_pv100" / "tl060_pl018_tv045_pv100.exr", Image(kUtiaW + 1, kUtiaH, 3, 0.5f));
  const BtfImageFolder btf = BtfImageFolder::open(folder);
  std::vector<Rgb> values;
  const std::string odd = errorOf([&] { btf.loadView(*findBtfDirection(45, 100), values); });
  EXPECT_THAT(odd, HasSubstr("tl060_pl018_tv045_pv100.exr"));
  EXPECT_THAT(odd, HasSubstr("is 4 x 2 pixels, but the BTF's images are 3 x 2"));

  fs::copy_file(folder / "tv015_pv000" / "tl000_pl000_tv015_pv000.exr", folder / "tv000_pv000" / "tl000_pl000_tv015_pv000.exr");
  EXPECT_THAT(errorOf([&] { BtfImageFolder::open(folder); }), HasSubstr("lies in the folder of view (theta 0, phi 0)"));
}

}  // namespace
}  // namespace btf
