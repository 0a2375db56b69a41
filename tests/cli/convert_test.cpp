// btf convert: MERL -> EXR stack -> MERL within float precision; the stack is readable as such;
// MERL -> octree -> MERL bit for bit at tolerance 0 and within the tolerance otherwise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "btf/io/image.h"
#include "btf/io/merl.h"
#include "cli_test_support.h"

namespace btf::test {
namespace {

TEST(Convert, MerlToExrToMerlRoundTripsWithinFloatPrecision) {
  TempDir dir;
  const auto original = dir / "original.binary", stack = dir / "stack.exr", back = dir / "back.binary";
  ASSERT_EQ(runDatagen({"--preset", "glossy-blue-plastic", "--holes", "0.05", "-o", original.string()}).exit_code, 0);
  CommandResult r = runBtf({"convert", original.string(), stack.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = runBtf({"convert", stack.string(), back.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;

  const MerlTable a = readMerl(original), b = readMerl(back);
  // One rounding to a 32-bit float (2^-24 relative) and back: allow two ulps.
  constexpr double kFloatPrecision = 2.0 * 0x1p-24;
  std::size_t unmeasured_a = 0, unmeasured_b = 0;
  double worst = 0;
  for (std::size_t k = 0; k < a.values.size(); ++k) {
    const double x = a.values[k], y = b.values[k];
    worst = std::max(worst, std::abs(x - y) / std::max(std::abs(x), 1e-300));
  }
  for (std::size_t i = 0; i < MerlTable::kEntriesPerChannel; ++i) {
    unmeasured_a += !a.isMeasured(i);
    unmeasured_b += !b.isMeasured(i);
  }
  EXPECT_LE(worst, kFloatPrecision);
  EXPECT_GT(unmeasured_a, 0u);
  EXPECT_EQ(unmeasured_a, unmeasured_b) << "unmeasured samples stay unmeasured";
}

TEST(Convert, StackHasOneLabelledSlicePerThetaHalfAndInfoReadsIt) {
  TempDir dir;
  const auto table = dir / "t.binary", stack = dir / "t.exr";
  ASSERT_EQ(runDatagen({"--preset", "plastic-red", "-o", table.string()}).exit_code, 0);
  ASSERT_EQ(runBtf({"convert", table.string(), stack.string()}).exit_code, 0);
  const std::vector<StackLayer> layers = readImageStack(stack);
  ASSERT_EQ(layers.size(), std::size_t(MerlTable::kThetaHalfRes));
  const MerlTable merl = readMerl(table);
  for (int th : {0, 17, 89}) {
    const StackLayer& layer = layers[th];
    EXPECT_EQ(layer.image.width, MerlTable::kPhiDiffRes);
    EXPECT_EQ(layer.image.height, MerlTable::kThetaDiffRes);
    EXPECT_EQ(layer.image.channels, 3);
    EXPECT_TRUE(layer.attributes.count("btf:layout")) << "the header names the layout";
    // A pixel holds f in 1/sr of the cell (phi_d = x, theta_d = y).
    const std::size_t i = MerlTable::index(th, 40, 100);
    EXPECT_NEAR(layer.image.at(100, 40, 1), merl.raw(1, i) * MerlTable::kChannelScale[1],
                1e-6 * std::abs(merl.raw(1, i) * MerlTable::kChannelScale[1]));
  }
  const CommandResult from_binary = runBtf({"info", table.string(), "--json"});
  const CommandResult from_stack = runBtf({"info", stack.string(), "--json"});
  ASSERT_EQ(from_stack.exit_code, 0) << from_stack.output;
  const auto a = parseJsonOutput(from_binary), b = parseJsonOutput(from_stack);
  EXPECT_EQ(a["unmeasured"]["count"], b["unmeasured"]["count"]);
  for (std::size_t k = 0; k < a["albedo"].size(); ++k)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(a["albedo"][k]["rgb"][c].get<double>(), b["albedo"][k]["rgb"][c].get<double>(), 1e-5);
}

TEST(Convert, MerlToOctreeIsLosslessAtToleranceZeroAndWithinItOtherwise) {
  TempDir dir;
  const auto original = dir / "original.binary";
  ASSERT_EQ(runDatagen({"--preset", "glossy-blue-plastic", "--holes", "0.05", "-o", original.string()}).exit_code, 0);
  const MerlTable a = readMerl(original);
  for (const char* tolerance : {"0", "0.02"}) {
    SCOPED_TRACE(tolerance);
    const auto octree = dir / (std::string("t") + tolerance + ".octree"), back = dir / (std::string("t") + tolerance + ".binary");
    CommandResult r = runBtf({"convert", original.string(), octree.string(), "--tolerance", tolerance});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("leaves"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("rel_rmse"), std::string::npos) << r.output;
    r = runBtf({"convert", octree.string(), back.string()});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const MerlTable b = readMerl(back);
    if (std::string(tolerance) == "0") {
      EXPECT_EQ(std::memcmp(a.values.data(), b.values.data(), a.values.size() * sizeof(double)), 0);
      continue;
    }
    double worst = 0;
    for (std::size_t k = 0; k < a.values.size(); ++k)
      if (a.isMeasured(k % MerlTable::kEntriesPerChannel))
        worst = std::max(worst, std::abs(a.values[k] - b.values[k]) / std::abs(b.values[k]));
      else
        ASSERT_EQ(a.values[k], b.values[k]);
    EXPECT_LE(worst, 0.02 * (1 + 1e-12));
    // The octree is a material like any other.
    r = runBtf({"eval", octree.string(), "--theta-i", "30", "--theta-o", "30", "--phi-i", "180"});
    EXPECT_EQ(r.exit_code, 0) << r.output;
    r = runBtf({"info", octree.string(), "--json"});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_GT(parseJsonOutput(r)["octree"]["leaves"].get<long>(), 0);
  }
  // --tolerance is for octree outputs only.
  const CommandResult r = runBtf({"convert", original.string(), (dir / "x.exr").string(), "--tolerance", "0.1"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--tolerance applies to an .octree output only"), std::string::npos) << r.output;
}

TEST(Convert, RefusesToConvertToTheSameFormat) {
  TempDir dir;
  const auto table = dir / "t.binary";
  ASSERT_EQ(runDatagen({"--preset", "white-diffuse", "--clean", "-o", table.string()}).exit_code, 0);
  const CommandResult r = runBtf({"convert", table.string(), (dir / "copy.binary").string()});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_LT(r.exit_code, 128);
  EXPECT_NE(r.output.find("copy.binary"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "copy.binary"));
}

}  // namespace
}  // namespace btf::test
