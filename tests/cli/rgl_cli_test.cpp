// btf info / eval / convert / plot on the shared RGL measured materials (.bsdf).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
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
}

// `btf convert X out.bsdf`: a MERL table written by virtual acquisition, read back by every verb.
TEST(RglCli, ConvertWritesATableAsAnRglFileThatTheVerbsRead) {
  TempDir dir;
  const auto table = dir / "plastic.binary", out = dir / "plastic.bsdf";
  ASSERT_EQ(runDatagen({"--preset", "rough-gold", "-o", table.string()}).exit_code, 0);
  const CommandResult c = runBtf({"convert", table.string(), out.string()});
  ASSERT_EQ(c.exit_code, 0) << c.output;
  for (const char* part : {"theta_i     8 values (deg): 0.0", "32 x 32 luminance/RGB per incidence, 128 x 128 VNDF",
                           "rel_rmse", "largest albedo error"})
    EXPECT_NE(c.output.find(part), std::string::npos) << part << ": " << c.output;
  const CommandResult info = runBtf({"info", out.string(), "--json"});
  ASSERT_EQ(info.exit_code, 0) << info.output;
  const nlohmann::json j = parseJsonOutput(info);
  EXPECT_EQ(j["description"], "virtual acquisition (libbtf) of plastic.binary");
  // The written file's albedo and the table's agree (rough gold: no lobe finer than the format).
  const nlohmann::json t = parseJsonOutput(runBtf({"info", table.string(), "--json"}));
  ASSERT_EQ(j["albedo"].size(), t["albedo"].size());
  for (std::size_t k = 0; k < j["albedo"].size(); ++k)
    for (int ch = 0; ch < 3; ++ch)
      EXPECT_NEAR(j["albedo"][k]["rgb"][ch].get<float>(), t["albedo"][k]["rgb"][ch].get<float>(),
                  0.02f * t["albedo"][k]["rgb"][ch].get<float>() + 1e-3f)
          << k << " " << ch;
  // Options: other resolutions, and an RGL file rewritten on its own parameterization.
  const CommandResult fine = runBtf({"convert", table.string(), (dir / "fine.bsdf").string(), "--theta-i", "12",
                                     "--resolution", "16", "--description", "gold, 12 angles"});
  ASSERT_EQ(fine.exit_code, 0) << fine.output;
  EXPECT_EQ(parseJsonOutput(runBtf({"info", (dir / "fine.bsdf").string(), "--json"}))["resolution"], 16);
  // The default file holds spectra (pbrt-v4); --rgb-only leaves them out (Mitsuba 3's RGB variants
  // refuse a file with 'wavelengths'). Field names are in the header, so the bytes say which.
  const auto holds = [](const std::filesystem::path& p, const std::string& name) {
    std::ifstream in(p, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return bytes.find(name) != std::string::npos;
  };
  EXPECT_NE(c.output.find("RGB and spectra 360-830 nm"), std::string::npos) << c.output;
  EXPECT_TRUE(holds(out, "wavelengths") && holds(out, "spectra"));
  const CommandResult rgb_only = runBtf({"convert", table.string(), (dir / "rgb.bsdf").string(), "--rgb-only"});
  ASSERT_EQ(rgb_only.exit_code, 0) << rgb_only.output;
  EXPECT_NE(rgb_only.output.find("RGB only: Mitsuba 3 RGB variants"), std::string::npos) << rgb_only.output;
  EXPECT_FALSE(holds(dir / "rgb.bsdf", "wavelengths") || holds(dir / "rgb.bsdf", "spectra"));
  EXPECT_TRUE(holds(dir / "rgb.bsdf", "rgb"));
  expectFailure(runBtf({"convert", table.string(), (dir / "x.binary").string(), "--rgb-only"}), {"x.binary"});
  const CommandResult again = runBtf({"convert", rglFile("paper_white_rgb").string(), (dir / "paper.bsdf").string()});
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("theta_i     8 values (deg): 0.0 27.7 39.9"), std::string::npos) << again.output;
}

TEST(RglCli, ConvertTakesABtfTexelOrItsMeanAndRefusesABtfWithoutOne) {
  TempDir dir;
  const auto folder = dir / "fabric";
  ASSERT_EQ(runDatagen({"btf", "--pattern", "fabric", "--size", "4", "--format", "exr", "-o", folder.string()}).exit_code, 0);
  const auto out = dir / "fabric.bsdf";
  expectFailure(runBtf({"convert", folder.string(), out.string()}), {folder.string(), "--texel X,Y", "--texel mean"});
  EXPECT_FALSE(std::filesystem::exists(out));
  expectFailure(runBtf({"convert", folder.string(), out.string(), "--texel", "9,9"}), {folder.string(), "outside"});
  expectFailure(runBtf({"convert", folder.string(), out.string(), "--texel", "one"}), {"--texel takes X,Y"});
  const CommandResult mean = runBtf({"convert", folder.string(), out.string(), "--texel", "mean"});
  ASSERT_EQ(mean.exit_code, 0) << mean.output;
  EXPECT_NE(mean.output.find("mean over its 16 texels, averaged over phi_h"), std::string::npos) << mean.output;
  const CommandResult texel = runBtf({"convert", folder.string(), (dir / "t.bsdf").string(), "--texel", "1,2"});
  ASSERT_EQ(texel.exit_code, 0) << texel.output;
  EXPECT_EQ(runBtf({"info", (dir / "t.bsdf").string()}).exit_code, 0);
}

TEST(RglCli, ConvertToRglRefusesBadOptionsAndLeavesNoPartialFile) {
  TempDir dir;
  const std::string paper = rglFile("paper_white_rgb").string();
  expectFailure(runBtf({"convert", paper, (dir / "a.bsdf").string(), "--resolution", "2"}),
                {"resolution must be in [4, 256], not 2"});
  expectFailure(runBtf({"convert", paper, (dir / "a.bsdf").string(), "--theta-i", "500"}), {"must be in [2, 90], not 500"});
  expectFailure(runBtf({"convert", paper, (dir / "a.bsdf").string(), "--texel", "0,0"}), {paper, "--texel is for BTFs"});
  expectFailure(runBtf({"convert", paper, (dir / "a.binary").string(), "--theta-i", "8"}), {"apply to an RGL output"});
  expectFailure(runBtf({"convert", paper, (dir / "missing" / "a.bsdf").string()}), {"a.bsdf"});
  EXPECT_TRUE(filesIn(dir.path()).empty());
}

}  // namespace
}  // namespace btf::test
