// btf info / eval / convert / plot on the shared RGL measured materials (.bsdf).
#include <gtest/gtest.h>

#include <string>

#include "btf/io/image.h"
#include "btf/io/merl.h"
#include "cli_test_support.h"

namespace btf::test {
namespace {

std::filesystem::path rglFile(const std::string& stem) { return sharedDataDir() / "rgl_bsdf" / (stem + ".bsdf"); }

TEST(RglCli, InfoListsFieldsDescriptionResolutionAndAlbedo) {
  const CommandResult r = runBtf({"info", rglFile("paper_white_rgb").string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = parseJsonOutput(r);
  EXPECT_EQ(j["description"], "White A4 paper (160 gsm)");
  EXPECT_EQ(j["resolution"], 32);
  bool found_rgb = false;
  for (const auto& f : j["fields"])
    if (f["name"] == "rgb") {
      found_rgb = true;
      EXPECT_EQ(f["dtype"], "f32");
      EXPECT_EQ(f["shape"], nlohmann::json({1, 8, 3, 32, 32}));
    }
  EXPECT_TRUE(found_rgb);
  ASSERT_EQ(j["albedo"].size(), 4u);
  for (const auto& a : j["albedo"])
    for (int c = 0; c < 3; ++c) {
      EXPECT_GT(a["rgb"][c].get<float>(), 0.5f);  // white paper
      EXPECT_LE(a["rgb"][c].get<float>(), 1.0f);
    }
  const CommandResult text = runBtf({"info", rglFile("paper_white_rgb").string()});
  EXPECT_NE(text.output.find("luminance    f32    (1, 8, 32, 32)"), std::string::npos) << text.output;
}

TEST(RglCli, ConvertTabulatesIntoTheMerlLayoutAndPlotWorksForBoth) {
  TempDir dir;
  const auto binary = dir / "golden.binary";
  const CommandResult c = runBtf({"convert", rglFile("vch_golden_yellow_rgb").string(), binary.string()});
  ASSERT_EQ(c.exit_code, 0) << c.output;
  // The table holds the RGL material's values: compare one direction pair through `btf eval`
  // (interpolated table lookup vs the RGL parameterization; 10% covers the table's interpolation).
  const std::vector<std::string> angles = {"--theta-i", "40", "--phi-i", "180", "--theta-o", "35", "--json"};
  auto evalOf = [&](const std::filesystem::path& file) {
    std::vector<std::string> args = {"eval", file.string()};
    args.insert(args.end(), angles.begin(), angles.end());
    const CommandResult r = runBtf(args);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return parseJsonOutput(r)["f"];
  };
  const nlohmann::json f_rgl = evalOf(rglFile("vch_golden_yellow_rgb")), f_table = evalOf(binary);
  for (int ch = 0; ch < 3; ++ch)
    EXPECT_NEAR(f_table[ch].get<float>(), f_rgl[ch].get<float>(), 0.1f * f_rgl[ch].get<float>()) << ch;
  EXPECT_GT(f_rgl[0].get<float>(), 1.0f);  // near the specular peak of a glossy film

  for (const auto& in : {rglFile("vch_golden_yellow_rgb"), binary}) {
    const auto png = dir / (in.stem().string() + in.extension().string().substr(1) + ".png");
    const CommandResult p = runBtf({"plot", in.string(), "-o", png.string(), "--size", "128"});
    ASSERT_EQ(p.exit_code, 0) << p.output;
    const Image image = readImage(png);
    EXPECT_GT(image.width, 2 * 128);
  }
}

// A table lookup is a property of the MERL layout; an RGL file has its own parameterization, so
// the option is refused rather than silently ignored.
TEST(RglCli, LookupOptionIsRefusedForRglFiles) {
  const std::string file = rglFile("paper_white_rgb").string();
  for (const std::string cmd : {"eval", "info"}) {
    const CommandResult r = runBtf({cmd, file, "--lookup", "nearest"});
    EXPECT_NE(r.exit_code, 0) << cmd;
    EXPECT_LT(r.exit_code, 128) << cmd;
    EXPECT_NE(r.output.find("--lookup does not apply to " + file), std::string::npos) << cmd << ": " << r.output;
  }
  const CommandResult ok = runBtf({"eval", file, "--theta-i", "20", "--json"});
  ASSERT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_EQ(parseJsonOutput(ok)["lookup"], "rgl parameterization");
}

TEST(RglCli, ErrorsNameTheFileAndProblem) {
  TempDir dir;
  const auto bad = dir / "bad.bsdf";
  std::string bytes = readBytes(rglFile("paper_white_rgb"));
  bytes.resize(5000);
  std::ofstream(bad, std::ios::binary) << bytes;
  for (const std::string cmd : {"info", "plot", "convert"}) {
    std::vector<std::string> args = {cmd, bad.string()};
    if (cmd == "plot") args.insert(args.end(), {"-o", (dir / "x.png").string()});
    if (cmd == "convert") args.push_back((dir / "x.binary").string());
    const CommandResult r = runBtf(args);
    EXPECT_NE(r.exit_code, 0) << cmd;
    EXPECT_NE(r.output.find(bad.string() + ": truncated"), std::string::npos) << cmd << ": " << r.output;
  }
  const CommandResult w = runBtf({"convert", rglFile("paper_white_rgb").string(), (dir / "out.bsdf").string()});
  EXPECT_NE(w.exit_code, 0);
  EXPECT_NE(w.output.find("cannot write .bsdf"), std::string::npos) << w.output;
}

}  // namespace
}  // namespace btf::test
