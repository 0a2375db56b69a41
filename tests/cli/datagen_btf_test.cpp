// `btf-datagen btf`: the written image folder reads back as the generator's own BTF (exactly in
// EXR, within quantization in PNG), and bad arguments fail clearly before any work.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "btf/io/btf_images.h"
#include "btf_patterns.h"
#include "cli_test_support.h"

namespace btf::test {
namespace {
using testing::HasSubstr;

TEST(DatagenBtf, ExrFolderReadsBackAsTheGeneratorsBtf) {
  TempDir dir;
  const auto out = dir / "leather";
  const CommandResult result = runDatagen({"btf", "--pattern", "leather", "--size", "16", "--seed", "4", "--format",
                                           "exr", "-o", out.string(), "--json"});
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json summary = parseJsonOutput(result);
  EXPECT_EQ(summary["images"].get<int>(), 6561);
  EXPECT_GT(summary["bytes"].get<double>(), 0.0);
  const BtfImageFolder folder = BtfImageFolder::open(out);
  const auto generated = synthetic::makeSyntheticBtf(synthetic::BtfPattern::Leather, 16, 16, 4);
  const BtfErrorStats stats = compareBtf(*generated, folder);
  EXPECT_EQ(stats.rmse, 0.0) << "EXR holds the values exactly";
  EXPECT_EQ(filesIn(dir.path()).size(), 1u) << "no temporary folder is left beside the output";
}

TEST(DatagenBtf, PngFolderIsWithinQuantizationOfTheGeneratorsBtf) {
  TempDir dir;
  const auto out = dir / "fabric";
  const CommandResult result = runDatagen({"btf", "--pattern", "fabric", "--size", "16", "--seed", "2", "-o", out.string()});
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_THAT(result.output, HasSubstr("wrote"));
  const BtfImageFolder folder = BtfImageFolder::open(out);
  const auto generated = synthetic::makeSyntheticBtf(synthetic::BtfPattern::Fabric, 16, 16, 2);
  const BtfErrorStats stats = compareBtf(*generated, folder);
  // Rounding to the nearest of 255 codes: the error is uniform within half a step, rms step/sqrt(12).
  const double step = folder.valueScale() / 255.0;
  EXPECT_GT(stats.rmse, 0.0);
  EXPECT_LE(stats.rmse, 1.1 * step / std::sqrt(12.0));
  EXPECT_NEAR(folder.valueScale(), stats.reference_max, 1e-6 * stats.reference_max)
      << "the largest value gets the largest code";
}

TEST(DatagenBtf, BadArgumentsFailWithClearMessages) {
  TempDir dir;
  const std::string out = (dir / "x").string();
  struct Case {
    std::vector<std::string> args;
    std::string message;
  };
  const std::vector<Case> cases{
      {{"btf", "--pattern", "wood", "-o", out}, "wood"},
      {{"btf", "--size", "0", "-o", out}, "--size"},
      {{"btf", "--format", "jpg", "-o", out}, "jpg"},
      {{"btf", "--pattern", "paint"}, "--output"},
      {{"btf", "--size", "8", "-o", (dir / "no" / "such" / "x").string()}, "does not exist"},
  };
  for (const Case& c : cases) {
    const CommandResult result = runDatagen(c.args);
    EXPECT_NE(result.exit_code, 0) << c.message << ": " << result.output;
    EXPECT_THAT(result.output, HasSubstr(c.message));
  }
  EXPECT_TRUE(filesIn(dir.path()).empty()) << "a failed run writes nothing";
}

TEST(DatagenBtf, RefusesToReplaceAFolderOfOtherFiles) {
  TempDir dir;
  std::filesystem::create_directory(dir / "mine");
  std::ofstream(dir / "mine" / "notes.txt") << "keep me";
  const CommandResult result = runDatagen({"btf", "--size", "4", "-o", (dir / "mine").string()});
  EXPECT_NE(result.exit_code, 0);
  EXPECT_THAT(result.output, HasSubstr("refusing to replace it"));
  EXPECT_TRUE(std::filesystem::exists(dir / "mine" / "notes.txt"));
}

}  // namespace
}  // namespace btf::test
