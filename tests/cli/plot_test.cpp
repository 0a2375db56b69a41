// btf plot: a PNG with the slice and the sphere side by side.
#include <gtest/gtest.h>

#include <cstdio>

#include "btf/io/image.h"
#include "cli_test_support.h"

namespace btf::test {
namespace {

// "wrote <file> (<width>x<height>)"
std::pair<int, int> reportedSize(const std::string& output) {
  int w = 0, h = 0;
  const std::size_t open = output.rfind('(');
  if (open != std::string::npos) std::sscanf(output.c_str() + open, "(%dx%d)", &w, &h);
  return {w, h};
}

TEST(Plot, WritesAPngWithTwoSquarePanelsSideBySide) {
  TempDir dir;
  const auto table = dir / "t.binary";
  ASSERT_EQ(runDatagen({"--preset", "plastic-red", "-o", table.string()}).exit_code, 0);
  std::vector<Image> images;
  for (int size : {128, 256}) {
    const auto png = dir / ("plot" + std::to_string(size) + ".png");
    const CommandResult r = runBtf({"plot", table.string(), "-o", png.string(), "--size", std::to_string(size)});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const Image image = readImage(png);
    EXPECT_EQ(std::make_pair(image.width, image.height), reportedSize(r.output));
    EXPECT_GE(image.width, 2 * size);
    EXPECT_GE(image.height, size);
    EXPECT_EQ(image.channels, 3);
    images.push_back(image);
  }
  // Two panels of `size` side by side plus fixed margins: the width grows by twice the panel growth.
  EXPECT_EQ(images[1].width - images[0].width, 2 * (256 - 128));
  EXPECT_EQ(images[1].height - images[0].height, 256 - 128);
  // Not a blank canvas: the picture spans dark and bright pixels.
  float lo = 1, hi = 0;
  for (float v : images[1].pixels) lo = std::min(lo, v), hi = std::max(hi, v);
  EXPECT_LT(lo, 0.1f);
  EXPECT_GT(hi, 0.9f);
  EXPECT_EQ(filesIn(dir.path()).size(), 3u) << "table and two PNGs, no temporary files";
}

TEST(Plot, RejectsOutputsThatAreNotPng) {
  TempDir dir;
  const auto table = dir / "t.binary";
  ASSERT_EQ(runDatagen({"--preset", "white-diffuse", "--clean", "-o", table.string()}).exit_code, 0);
  const CommandResult r = runBtf({"plot", table.string(), "-o", (dir / "plot.jpg").string()});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_LT(r.exit_code, 128);
  EXPECT_NE(r.output.find("plot.jpg"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "plot.jpg"));
}

}  // namespace
}  // namespace btf::test
