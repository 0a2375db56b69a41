// btf compare A B: the measures on images with known closed-form differences, the heat map, and
// errors that name the file and the problem.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "btf/compress/vq_btf.h"
#include "btf/io/btf_images.h"
#include "btf/io/btf_quality.h"
#include "btf/io/image.h"
#include "cli_test_support.h"
#include "support/raw_image_writer.h"

namespace btf::test {
namespace {

// 4 x 3 RGB; the reference is 2 in the left half and 0 in the right half, the test 0.5 above
// everywhere. Exact in float, so the measures have closed forms:
//   relmse   = (0.25 / (4 + 0.01) + 0.25 / (0 + 0.01)) / 2
//   rel_rmse = sqrt(0.25) / sqrt(4 / 2)
//   psnr_db  = 10 log10(2^2 / 0.25)
//   max_abs  = 0.5
Image reference() {
  Image image(4, 3, 3, 0.0f);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 2; ++x)
      for (int c = 0; c < 3; ++c) image.at(x, y, c) = 2.0f;
  return image;
}
Image shifted() {
  Image image = reference();
  for (float& v : image.pixels) v += 0.5f;
  return image;
}

struct Files {
  TempDir dir;
  std::string test = (dir / "render.exr").string();
  std::string ref = (dir / "reference.exr").string();
  Files() {
    writeImage(test, shifted());
    writeImage(ref, reference());
  }
};

}  // namespace

TEST(Compare, IdenticalImagesHaveZeroErrorAndInfinitePsnr) {
  Files f;
  const CommandResult r = runBtf({"compare", f.ref, f.ref, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = parseJsonOutput(r);
  EXPECT_EQ(j["relmse"].get<double>(), 0.0);
  EXPECT_EQ(j["rel_rmse"].get<double>(), 0.0);
  EXPECT_EQ(j["max_abs"].get<double>(), 0.0);
  EXPECT_EQ(j["psnr_db"], "inf");  // JSON has no infinity
  EXPECT_EQ(j["width"], 4);
  EXPECT_EQ(j["height"], 3);
  const CommandResult text = runBtf({"compare", f.ref, f.ref});
  ASSERT_EQ(text.exit_code, 0) << text.output;
  EXPECT_NE(text.output.find("psnr_db  inf"), std::string::npos) << text.output;
}

TEST(Compare, KnownDifferenceGivesTheClosedFormMeasures) {
  Files f;
  const CommandResult r = runBtf({"compare", f.test, f.ref, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = parseJsonOutput(r);
  EXPECT_NEAR(j["relmse"].get<double>(), (0.25 / 4.01 + 0.25 / 0.01) / 2.0, 1e-12);
  EXPECT_NEAR(j["rel_rmse"].get<double>(), 0.5 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(j["psnr_db"].get<double>(), 10.0 * std::log10(16.0), 1e-12);
  EXPECT_EQ(j["max_abs"].get<double>(), 0.5);
  EXPECT_FALSE(j.contains("heat_map"));
  // The text form prints the same four measures.
  const CommandResult text = runBtf({"compare", f.test, f.ref});
  ASSERT_EQ(text.exit_code, 0) << text.output;
  for (const char* line : {"relmse   12.5312", "rel_rmse 0.353553", "psnr_db  12.0412", "max_abs  0.5"})
    EXPECT_NE(text.output.find(line), std::string::npos) << line << "\n" << text.output;
}

TEST(Compare, WritesAHeatMapOfTheInputSizeWithALegend) {
  Files f;
  const std::string heat = (f.dir / "diff.png").string();
  const CommandResult r = runBtf({"compare", f.test, f.ref, "-o", heat, "--scale", "0.25"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("wrote " + heat), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("dark purple = 0"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("yellow >= 0.25"), std::string::npos) << r.output;
  const Image image = readImage(heat);
  EXPECT_EQ(image.width, 4);
  EXPECT_EQ(image.height, 3);
  EXPECT_GE(image.channels, 3);
  // Left half: error 0.5 / 2.01 ~ 0.249, just below the top; right half: 50, at the top (yellow:
  // red and green high, blue low).
  EXPECT_GT(image.at(3, 1, 0), 0.95f);
  EXPECT_LT(image.at(3, 1, 2), 0.2f);
  const CommandResult json = runBtf({"compare", f.test, f.ref, "-o", heat, "--json"});
  ASSERT_EQ(json.exit_code, 0) << json.output;
  EXPECT_EQ(parseJsonOutput(json)["heat_map"]["scale"].get<double>(), 0.5);  // the default
}

TEST(Compare, MissingFileIsAnErrorNamingIt) {
  Files f;
  const std::string missing = (f.dir / "nope.exr").string();
  const CommandResult r = runBtf({"compare", missing, f.ref});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_LT(r.exit_code, 128) << r.output;
  EXPECT_NE(r.output.find(missing), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("no such file"), std::string::npos) << r.output;
}

TEST(Compare, SizeMismatchIsAnErrorNamingBothSizes) {
  Files f;
  const std::string small = (f.dir / "small.exr").string();
  writeImage(small, Image(2, 3, 3, 1.0f));
  const CommandResult r = runBtf({"compare", small, f.ref});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_LT(r.exit_code, 128) << r.output;
  EXPECT_NE(r.output.find(small + " is 2x3"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(f.ref + " is 4x3"), std::string::npos) << r.output;
}

TEST(Compare, NanPixelIsAnErrorNamingTheFileAndThePixel) {
  Files f;
  Image bad = shifted();
  bad.at(1, 2, 0) = std::numeric_limits<float>::quiet_NaN();
  const std::string nan_file = (f.dir / "nan.exr").string();
  writeRawImage(nan_file, bad);
  const CommandResult r = runBtf({"compare", f.test, nan_file});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_LT(r.exit_code, 128) << r.output;
  EXPECT_NE(r.output.find(nan_file + ": pixel (1, 2) channel 0 is NaN"), std::string::npos) << r.output;
}

TEST(Compare, OutputIntoAMissingFolderFailsAndLeavesNothing) {
  Files f;
  const std::filesystem::path folder = f.dir / "no" / "such";
  const CommandResult r = runBtf({"compare", f.test, f.ref, "-o", (folder / "diff.png").string()});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_LT(r.exit_code, 128) << r.output;
  EXPECT_NE(r.output.find("does not exist"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(f.dir / "no"));
  EXPECT_EQ(filesIn(f.dir.path()).size(), 2u);  // the two inputs, nothing else
  // A bad scale is refused by the parser.
  const CommandResult scale = runBtf({"compare", f.test, f.ref, "--scale", "0"});
  EXPECT_NE(scale.exit_code, 0);
  EXPECT_LT(scale.exit_code, 128) << scale.output;
}

namespace {

// Two BTFs (a generated folder and its VQ-compressed form): the figures are the library's, and an
// image against a BTF is refused.
TEST(Compare, TwoBtfsGiveTheLibrarysMeasures) {
  TempDir dir;
  const std::filesystem::path folder = dir / "stones", packed = dir / "stones.btfz";
  ASSERT_EQ(runDatagen({"btf", "--pattern", "stones", "--size", "6", "--seed", "2", "--format", "exr", "-o",
                        folder.string()}).exit_code, 0);
  ASSERT_EQ(runBtf({"compress", folder.string(), packed.string(), "--epsilon", "0.1", "--no-verify"}).exit_code, 0);
  const CommandResult r = runBtf({"compare", packed.string(), folder.string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json out = parseJsonOutput(r);
  // In memory: the two measures below then read the 6,561 images once.
  const BtfData reference_btf = BtfData::copyOf(BtfImageFolder::open(folder));
  const VqBtf test = VqBtf::read(packed);
  EXPECT_NEAR(out["rel_rmse"].get<double>(), compareBtf(reference_btf, test).rel_rmse, 1e-12);
  const BtfSsimStats ssim = compareBtfSsim(reference_btf, test);
  EXPECT_NEAR(out["mean_ssim"].get<double>(), ssim.mean_ssim, 1e-12);
  EXPECT_NEAR(out["rel_rmse_display"].get<double>(), ssim.rel_rmse_display, 1e-12);
  EXPECT_GT(out["rel_rmse"].get<double>(), 0.0);
  EXPECT_LT(out["mean_ssim"].get<double>(), 1.0);

  writeImage(dir / "image.exr", reference());
  const CommandResult mixed = runBtf({"compare", (dir / "image.exr").string(), folder.string()});
  EXPECT_EQ(mixed.exit_code, 1) << mixed.output;
  EXPECT_NE(mixed.output.find("both be images or both be BTFs"), std::string::npos) << mixed.output;
}

}  // namespace
}  // namespace btf::test
