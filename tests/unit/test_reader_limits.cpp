// Regression tests of what the readers' mutation probe and fuzz targets (tests/fuzz) found: image
// headers claiming huge sizes refused before any pixel is allocated, image-folder sidecars and
// image headers read strictly, and values that overflow once interpolated refused by name.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "btf/core/error.h"
#include "btf/io/btf_images.h"
#include "btf/io/image.h"
#include "support/test_support.h"

namespace btf {
namespace {
namespace fs = std::filesystem;
using testing::HasSubstr;
using test::errorOf;

std::string bytesOf(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}
void writeBytes(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
}

// Restores the process-wide limits whatever a test set.
class ImageSizeLimitsTest : public testing::Test {
 protected:
  void TearDown() override { setImageSizeLimits(ImageSizeLimits{}); }
  test::TempDir dir_;
};

TEST_F(ImageSizeLimitsTest, AnImageBeyondTheLimitsIsRefusedAndOneWithinIsRead) {
  const fs::path path = dir_ / "eight.png";  // checked by libbtf (an EXR is refused by OpenEXR first)
  writeImage(path, Image(8, 6, 3, 0.5f));
  setImageSizeLimits({4, 1000});
  EXPECT_THAT(errorOf([&] { (void)readImage(path); }), HasSubstr("beyond the limit of 4 per side"));
  setImageSizeLimits({100, 40});
  EXPECT_THAT(errorOf([&] { (void)readImage(path); }), HasSubstr("beyond the limit of 40 pixels"));
  setImageSizeLimits({8, 48});
  EXPECT_EQ(readImage(path).pixels.size(), 8u * 6u * 3u);
  EXPECT_THROW(setImageSizeLimits({0, 10}), Error);
}

// readPixels decodes the first tile before it allocates the image; a tiled EXR (written here with
// OpenImageIO, as libbtf writes scanlines only) must still arrive whole, edge tiles included.
TEST(ImageReading, ATiledExrIsReadWhole) {
  test::TempDir dir;
  const fs::path path = dir / "tiled.exr";
  const int width = 40, height = 23, channels = 3;
  std::vector<float> values(std::size_t(width) * height * channels);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = float(i) * 0.25f;
  {
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::FLOAT);
    spec.tile_width = spec.tile_height = 16;
    ASSERT_TRUE(out->open(path.string(), spec)) << out->geterror();
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, values.data())) << out->geterror();
    ASSERT_TRUE(out->close());
  }
  const Image image = readImage(path);
  ASSERT_EQ(image.width, width);
  ASSERT_EQ(image.height, height);
  ASSERT_EQ(image.channels, channels);
  EXPECT_EQ(image.pixels, values);
}

// Radiance HDR is one of the formats libbtf reads (environment maps): written by writeImage (RGBE),
// read back within RGBE's precision (8-bit mantissas with a shared exponent: 2^-8 of the largest
// channel), values across 8 orders of magnitude.
TEST(ImageReading, ARadianceHdrRoundTripsWithinRgbePrecision) {
  test::TempDir dir;
  const fs::path path = dir / "sky.hdr";
  Image image(7, 5, 3);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = std::pow(10.0f, float(i % 9) - 4.0f) * (1.0f + 0.1f * float(i % 3));
  writeImage(path, image);
  const Image back = readImage(path);
  ASSERT_EQ(back.width, 7);
  ASSERT_EQ(back.height, 5);
  ASSERT_EQ(back.channels, 3);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 7; ++x) {
      float largest = 0;
      for (int c = 0; c < 3; ++c) largest = std::max(largest, image.at(x, y, c));
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(back.at(x, y, c), image.at(x, y, c), largest / 128.0f) << x << "," << y << "," << c;
    }
}

// The probe's case: an EXR of a BTF folder whose header claims 5,963,780 x 4 pixels. OpenEXR's
// own header check (the same limit) refuses it before it allocates its tables.
TEST_F(ImageSizeLimitsTest, AnExrHeaderClaimingMillionsOfColumnsIsRefused) {
  const fs::path path = dir_ / "wide.exr";
  writeImage(path, Image(2, 2, 3, 0.5f));
  std::string bytes = bytesOf(path);
  const std::string key("dataWindow\0box2i\0", 17);
  const std::size_t at = bytes.find(key);
  ASSERT_NE(at, std::string::npos);
  const std::int32_t x_max = 5963779;  // box2i: xMin yMin xMax yMax after the 4-byte size
  std::memcpy(bytes.data() + at + key.size() + 4 + 8, &x_max, 4);
  writeBytes(path, bytes);
  const std::string message = errorOf([&] { (void)readImage(path); });
  EXPECT_THAT(message, HasSubstr(path.string()));
  EXPECT_THAT(message, testing::AnyOf(HasSubstr("maximum"), HasSubstr("beyond the limit")));
}

BtfData smallBtf() {
  BtfData data(2, 3, "small", BtfViewSet({0}));
  for (int l = 0; l < kBtfDirectionCount; ++l)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 2; ++x) data.at(x, y, 0, l) = Rgb(0.1f * float(1 + x + y), 0.2f, 0.3f);
  return data;
}

// decodeExrInCallingThreads sets OpenImageIO's exr_threads to -1, and leaves it as the environment
// set it when OPENIMAGEIO_OPTIONS names it; an EXR then reads back exactly as before.
TEST(ImageReading, DecodeExrInCallingThreadsDefersToTheEnvironment) {
  test::TempDir dir;
  Image image(19, 7, 3);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = float(i % 97) * 0.25f;
  writeImage(dir / "a.exr", image);
  int before = 0;
  ASSERT_TRUE(OIIO::getattribute("exr_threads", before));
  const char* env = std::getenv("OPENIMAGEIO_OPTIONS");
  const std::string saved = env ? env : "";

  ::setenv("OPENIMAGEIO_OPTIONS", "exr_threads=3", 1);
  OIIO::attribute("exr_threads", 3);
  decodeExrInCallingThreads();
  int threads = 0;
  ASSERT_TRUE(OIIO::getattribute("exr_threads", threads));
  EXPECT_EQ(threads, 3);

  ::unsetenv("OPENIMAGEIO_OPTIONS");
  decodeExrInCallingThreads();
  ASSERT_TRUE(OIIO::getattribute("exr_threads", threads));
  EXPECT_EQ(threads, -1);
  EXPECT_EQ(readImage(dir / "a.exr").pixels, image.pixels);

  OIIO::attribute("exr_threads", before);
  if (env) ::setenv("OPENIMAGEIO_OPTIONS", saved.c_str(), 1);
}

TEST(BtfSidecarStrict, TheWritersFactsMustBeWellFormedAndMatchTheImages) {
  test::TempDir dir;
  const fs::path folder = dir / "btf";
  writeBtfImageFolder(smallBtf(), folder, BtfImageFormat::Exr);
  const fs::path sidecar = folder / kBtfSidecarName;
  for (const char* bad : {R"({"width": 9223372036854775808})", R"({"width": true})", R"({"width": "nan"})",
                          R"({"height": 0})", R"({"views": 82})", R"({"width": 2.5})", R"({"format": 7})"}) {
    writeBytes(sidecar, bad);
    const std::string message = errorOf([&] { (void)BtfImageFolder::open(folder); });
    EXPECT_THAT(message, HasSubstr(sidecar.string())) << bad;
    EXPECT_THAT(message, testing::AnyOf(HasSubstr("whole number"), HasSubstr("must be a string"))) << bad;
  }
  writeBytes(sidecar, R"({"width": 3, "height": 3})");
  EXPECT_THAT(errorOf([&] { (void)BtfImageFolder::open(folder); }), HasSubstr("records 3 x 3 texels, but the images are 2 x 3"));
  writeBytes(sidecar, R"({"width": 2, "height": 3, "views": 1, "format": "exr", "source": "small", "note": "kept"})");
  EXPECT_EQ(BtfImageFolder::open(folder).width(), 2);
}

// `btf info` checks every image's header: an empty image, one of 10 bytes and one replaced by
// "{}" exited 0 before.
TEST(BtfImageHeaders, EveryImageIsCheckedWithoutReadingPixels) {
  test::TempDir dir;
  const fs::path folder = dir / "btf";
  writeBtfImageFolder(smallBtf(), folder, BtfImageFormat::Exr);
  EXPECT_NO_THROW(BtfImageFolder::open(folder).checkImageHeaders());
  const fs::path image = folder / btfImageName(0, 40, BtfImageFormat::Exr);
  const std::string good = bytesOf(image);
  for (const std::string& bad : {std::string(), good.substr(0, 10), std::string("{}")}) {
    writeBytes(image, bad);
    const BtfImageFolder btf = BtfImageFolder::open(folder);
    EXPECT_THAT(errorOf([&] { btf.checkImageHeaders(); }), HasSubstr(image.string())) << bad.size() << " bytes";
  }
  writeImage(image, Image(3, 3, 3, 0.1f));
  EXPECT_THAT(errorOf([&] { BtfImageFolder::open(folder).checkImageHeaders(); }), HasSubstr("is 3 x 3 pixels"));
}

}  // namespace
}  // namespace btf
