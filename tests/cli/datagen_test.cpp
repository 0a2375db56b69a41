// btf-datagen: presets, valid output, determinism from the seed, option errors.
#include <gtest/gtest.h>

#include <set>

#include "btf/io/merl.h"
#include "cli_test_support.h"

namespace btf::test {
namespace {

TEST(Datagen, ListsAtLeastEightPresetsWithPhysicalAlbedos) {
  const CommandResult result = runDatagen({"--list-presets", "--json"});
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json list = parseJsonOutput(result);
  ASSERT_GE(list.size(), 8u);
  std::set<std::string> names;
  for (const auto& preset : list) {
    names.insert(preset["name"].get<std::string>());
    EXPECT_FALSE(preset["description"].get<std::string>().empty());
    for (const auto& a : preset["albedo_normal"]) {
      EXPECT_GT(a.get<double>(), 0.0) << preset["name"];
      EXPECT_LE(a.get<double>(), 1.0) << preset["name"];
    }
  }
  EXPECT_EQ(names.size(), list.size()) << "preset names must be unique";
  // The text listing names every preset too.
  const CommandResult text = runDatagen({"--list-presets"});
  for (const std::string& name : names) EXPECT_NE(text.output.find(name), std::string::npos) << name;
}

class DatagenPreset : public testing::TestWithParam<std::string> {};

TEST_P(DatagenPreset, WritesAReadableMerlTable) {
  TempDir dir;
  const auto out = dir / "table.binary";
  const CommandResult result = runDatagen({"--preset", GetParam(), "-o", out.string(), "--json"});
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const MerlTable table = readMerl(out);  // throws on a malformed file
  std::size_t measured = 0, positive = 0;
  for (std::size_t i = 0; i < MerlTable::kEntriesPerChannel; ++i) {
    if (!table.isMeasured(i)) continue;
    ++measured;
    positive += table.reflectance(i).maxComponent() > 0;
  }
  EXPECT_GT(positive, measured / 2) << "most measured samples reflect something";
  const nlohmann::json summary = parseJsonOutput(result);
  EXPECT_EQ(summary["unmeasured"]["count"].get<std::size_t>(), MerlTable::kEntriesPerChannel - measured);
  EXPECT_EQ(filesIn(dir.path()).size(), 1u) << "no temporary file is left beside the output";
}

INSTANTIATE_TEST_SUITE_P(Presets, DatagenPreset,
                         testing::Values("white-diffuse", "satin-paint", "glossy-blue-plastic", "chrome"),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (char& c : name) if (c == '-') c = '_';
                           return name;
                         });

TEST(Datagen, SameSeedGivesIdenticalBytesAndAnotherSeedDiffers) {
  TempDir dir;
  const std::vector<std::string> common = {"--preset", "plastic-red", "--noise", "0.05", "--holes", "0.01"};
  auto run = [&](const std::string& seed, const std::string& name) {
    std::vector<std::string> args = common;
    args.insert(args.end(), {"--seed", seed, "-o", (dir / name).string()});
    const CommandResult r = runDatagen(args);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return readBytes(dir / name);
  };
  const std::string a = run("7", "a.binary"), b = run("7", "b.binary"), c = run("8", "c.binary");
  ASSERT_FALSE(a.empty());
  EXPECT_TRUE(a == b) << "the same seed must reproduce the file byte for byte";
  EXPECT_FALSE(a == c) << "another seed must give other noise and holes";
}

TEST(Datagen, HolesDropTheRequestedFractionOfMeasurableCells) {
  TempDir dir;
  ASSERT_EQ(runDatagen({"--preset", "matte-clay", "--clean", "-o", (dir / "clean.binary").string()}).exit_code, 0);
  ASSERT_EQ(runDatagen({"--preset", "matte-clay", "--holes", "0.1", "--grazing-gap", "0", "-o", (dir / "holes.binary").string()}).exit_code, 0);
  auto unmeasured = [](const MerlTable& t) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < MerlTable::kEntriesPerChannel; ++i) n += !t.isMeasured(i);
    return n;
  };
  const std::size_t clean = unmeasured(readMerl(dir / "clean.binary"));
  const std::size_t holes = unmeasured(readMerl(dir / "holes.binary"));
  // The clean table lacks only cells below the horizon; --holes 0.1 drops 10% of the others.
  const double measurable = double(MerlTable::kEntriesPerChannel - clean);
  EXPECT_NEAR(double(holes - clean), 0.1 * measurable, 0.005 * measurable);
}

TEST(Datagen, RejectsBadOptionsWithoutWritingAnything) {
  TempDir dir;
  struct Case {
    std::vector<std::string> args;
    std::string expected;  // a phrase of the message
  };
  const std::vector<Case> cases = {
      {{"--preset", "no-such-material", "-o", (dir / "x.binary").string()}, "no-such-material"},
      {{"--preset", "chrome", "-o", (dir / "x.exr").string()}, "x.exr"},
      {{"--preset", "chrome", "-o", (dir / "missing-folder" / "x.binary").string()}, "missing-folder"},
      {{"--preset", "chrome", "-o", dir.path().string()}, dir.path().string()},
      {{"--preset", "chrome", "--clean", "--noise", "0.1", "-o", (dir / "x.binary").string()}, "--noise"},
      {{"--preset", "chrome", "--noise", "-1", "-o", (dir / "x.binary").string()}, "--noise"},
      {{"--preset", "chrome"}, "-o"},
  };
  for (const Case& c : cases) {
    const CommandResult r = runDatagen(c.args);
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_LT(r.exit_code, 128) << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << r.output;
  }
  EXPECT_TRUE(filesIn(dir.path()).empty());
}

}  // namespace
}  // namespace btf::test
