// `btf compress`, `btf decompress`, `btf info` on BTFs and `btf bench compression`: the reported
// figures are those of the written file (recomputed here independently), decompression gives back
// what the file decodes to, and bad inputs fail clearly without leaving an output behind.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

#include "btf/compress/vq_btf.h"
#include "btf/io/btf_images.h"
#include "btf/io/btf_quality.h"
#include "cli_test_support.h"

namespace btf::test {
namespace {
using testing::HasSubstr;
using testing::Not;
namespace fs = std::filesystem;

TEST(CompressCli, FolderRoundTripReportsTheFilesOwnErrorAndRatio) {
  TempDir dir;
  const fs::path folder = dir / "stones", packed = dir / "stones.btfz", unpacked = dir / "unpacked";
  ASSERT_EQ(runDatagen({"btf", "--pattern", "stones", "--size", "8", "--seed", "3", "--format", "exr", "-o",
                        folder.string()}).exit_code, 0);
  const CommandResult c = runBtf({"compress", folder.string(), packed.string(), "--epsilon", "0.05", "--json"});
  ASSERT_EQ(c.exit_code, 0) << c.output;
  const nlohmann::json report = parseJsonOutput(c);
  const BtfImageFolder source = BtfImageFolder::open(folder);
  const VqBtf vq = VqBtf::read(packed);
  const double bytes = double(fs::file_size(packed));
  EXPECT_EQ(report["bytes"].get<double>(), bytes);
  EXPECT_NEAR(report["ratio_u8"].get<double>(), 8.0 * 8 * 81 * 81 * 3 / bytes, 1e-9);
  EXPECT_NEAR(report["ratio_f32"].get<double>(), 4.0 * report["ratio_u8"].get<double>(), 1e-9);
  const BtfErrorStats e = compareBtf(source, vq);
  EXPECT_NEAR(report["rel_rmse"].get<double>(), e.rel_rmse, 1e-12);
  EXPECT_GT(e.rel_rmse, 0.0) << "a lossy setting loses something";
  EXPECT_NEAR(report["mean_ssim"].get<double>(), compareBtfSsim(source, vq).mean_ssim, 1e-12);

  const CommandResult info = runBtf({"info", packed.string(), "--json"});
  ASSERT_EQ(info.exit_code, 0) << info.output;
  const nlohmann::json facts = parseJsonOutput(info);
  EXPECT_EQ(facts["bytes"].get<double>(), bytes);
  EXPECT_EQ(facts["codebook_entries"], report["codebook_entries"]);
  EXPECT_EQ(facts["texels"], nlohmann::json({8, 8}));

  const CommandResult d = runBtf({"decompress", packed.string(), unpacked.string(), "--format", "exr"});
  ASSERT_EQ(d.exit_code, 0) << d.output;
  const BtfErrorStats back = compareBtf(vq, BtfImageFolder::open(unpacked));
  EXPECT_LE(back.rel_rmse, 1e-6) << "the folder holds what the file decodes to";
}

// --energy-floor reaches the compressor: it is recorded in the file and the report, a higher
// floor (more absolute tolerance for dark vectors) stores fewer bytes, and a negative one is refused.
TEST(CompressCli, EnergyFloorReachesTheFile) {
  TempDir dir;
  const fs::path folder = dir / "fabric";
  ASSERT_EQ(runDatagen({"btf", "--pattern", "fabric", "--size", "8", "--seed", "2", "--format", "exr", "-o",
                        folder.string()}).exit_code, 0);
  double bytes[2] = {0, 0};
  const char* floors[2] = {"0", "3"};
  for (int i = 0; i < 2; ++i) {
    const fs::path packed = dir / ("floor" + std::string(floors[i]) + ".btfz");
    const CommandResult c = runBtf({"compress", folder.string(), packed.string(), "--epsilon", "0.1", "--energy-floor",
                                    floors[i], "--no-verify", "--json"});
    ASSERT_EQ(c.exit_code, 0) << c.output;
    EXPECT_EQ(parseJsonOutput(c)["energy_floor"].get<double>(), std::stod(floors[i]));
    EXPECT_EQ(VqBtf::read(packed).options().energy_floor, float(std::stod(floors[i])));
    bytes[i] = double(fs::file_size(packed));
  }
  EXPECT_LT(bytes[1], bytes[0]);
  const fs::path refused = dir / "refused.btfz";
  const CommandResult bad = runBtf({"compress", folder.string(), refused.string(), "--energy-floor", "-1"});
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_THAT(bad.output, HasSubstr("--energy-floor"));
  EXPECT_FALSE(fs::exists(refused));
}

// --no-level3-exceptions reaches the library and the report: a print through the camera (noisy
// near-twin texels) has derived level-3 entries by default and none with the flag.
TEST(CompressCli, NoLevel3ExceptionsReachesTheReportAndTheFile) {
  TempDir dir;
  const fs::path folder = dir / "print";
  ASSERT_EQ(runDatagen({"btf", "--pattern", "print", "--camera", "--size", "16", "--seed", "1", "-o", folder.string()}).exit_code,
            0);
  for (const bool exceptions : {true, false}) {
    const fs::path packed = dir / (exceptions ? "derived.btfz" : "whole.btfz");
    std::vector<std::string> args = {"compress", folder.string(), packed.string(), "--epsilon", "0.2", "--chroma-epsilon",
                                     "0.25", "--no-verify", "--json"};
    if (!exceptions) args.push_back("--no-level3-exceptions");
    const CommandResult c = runBtf(args);
    ASSERT_EQ(c.exit_code, 0) << c.output;
    EXPECT_EQ(parseJsonOutput(c)["level3_exceptions"].get<bool>(), exceptions);
    const CommandResult info = runBtf({"info", packed.string()});
    ASSERT_EQ(info.exit_code, 0) << info.output;
    if (exceptions) {
      EXPECT_THAT(info.output, HasSubstr("level3/parent"));
    } else {
      EXPECT_THAT(info.output, Not(HasSubstr("level3/parent")));
    }
  }
}

// --level1-cut reaches the library and the report: the file then carries level-1 bases (16 x 16
// texels: enough for ring 1's), and without it none, as files were before.
TEST(CompressCli, Level1CutReachesTheReportAndTheFile) {
  TempDir dir;
  const fs::path folder = dir / "fabric";
  ASSERT_EQ(runDatagen({"btf", "--pattern", "fabric", "--size", "16", "--seed", "2", "--format", "exr", "-o",
                        folder.string()}).exit_code, 0);
  for (const bool cut : {false, true}) {
    const fs::path packed = dir / (cut ? "cut.btfz" : "plain.btfz");
    // The check of the written file against the images is not what this test is about.
    std::vector<std::string> args = {"compress", folder.string(), packed.string(), "--epsilon", "0.1", "--levels", "1",
                                     "--no-verify", "--json"};
    if (cut) args.push_back("--level1-cut");
    const CommandResult c = runBtf(args);
    ASSERT_EQ(c.exit_code, 0) << c.output;
    EXPECT_EQ(parseJsonOutput(c)["level1_cut"].get<bool>(), cut);
    const CommandResult info = runBtf({"info", packed.string()});
    ASSERT_EQ(info.exit_code, 0) << info.output;
    if (cut) {
      EXPECT_THAT(info.output, HasSubstr("level1/basis1"));
    } else {
      EXPECT_THAT(info.output, Not(HasSubstr("level1/basis")));
    }
  }
}

// The real measured slice (one view, Bonn naming, 8-bit sRGB JPEG) through info, compress and
// decompress: the partial view set survives every step, and the perceptual figures are those of
// the written file.
TEST(CompressCli, AOneViewMeasuredSliceGoesThroughEveryVerb) {
  const fs::path slice = sharedDataDir() / "btf" / "ubo2003_wallpaper_view000";
  ASSERT_TRUE(fs::is_directory(slice)) << slice << " is missing (../shared/data/real must sit beside the checkout)";
  TempDir dir;
  const fs::path packed = dir / "slice.btfz", unpacked = dir / "unpacked";
  const CommandResult info = runBtf({"info", slice.string(), "--json"});
  ASSERT_EQ(info.exit_code, 0) << info.output;
  const nlohmann::json facts = parseJsonOutput(info);
  EXPECT_EQ(facts["views"], nlohmann::json({0}));
  EXPECT_EQ(facts["images"].get<int>(), 81);
  EXPECT_EQ(facts["transfer"].get<std::string>(), "srgb");
  EXPECT_THAT(runBtf({"info", slice.string()}).output, HasSubstr("1 view (theta 0, phi 0) x 81 lights"));

  const CommandResult c = runBtf({"compress", slice.string(), packed.string(), "--epsilon", "0.3", "--levels", "2",
                                  "--chroma-epsilon", "0.3", "--json"});
  ASSERT_EQ(c.exit_code, 0) << c.output;
  const nlohmann::json report = parseJsonOutput(c);
  EXPECT_EQ(report["views"], nlohmann::json({0}));
  EXPECT_NEAR(report["ratio_u8"].get<double>(), 256.0 * 256 * 81 * 3 / double(fs::file_size(packed)), 1e-9);
  const BtfImageFolder source = BtfImageFolder::open(slice);
  const VqBtf vq = VqBtf::read(packed);
  EXPECT_EQ(vq.views(), source.views());
  const BtfSsimStats ssim = compareBtfSsim(source, vq);
  EXPECT_NEAR(report["mean_ssim"].get<double>(), ssim.mean_ssim, 1e-12);
  EXPECT_NEAR(report["rel_rmse_display"].get<double>(), ssim.rel_rmse_display, 1e-12);
  EXPECT_EQ(report["ssim_white"].get<double>(), 1.0) << "an 8-bit folder's white is its largest code";
  EXPECT_GT(ssim.mean_ssim, 0.3);
  EXPECT_LT(ssim.mean_ssim, 0.99) << "epsilon 0.3 loses visible detail";
  EXPECT_NEAR(report["noise_rel_rmse"].get<double>(), estimateBtfNoiseFloor(source).rel_rmse, 1e-12);

  const CommandResult d = runBtf({"decompress", packed.string(), unpacked.string(), "--format", "png8"});
  ASSERT_EQ(d.exit_code, 0) << d.output;
  const BtfImageFolder back = BtfImageFolder::open(unpacked);
  EXPECT_EQ(back.views(), source.views());
  EXPECT_LE(compareBtf(vq, back).rel_rmse, 0.02) << "8-bit sRGB quantization only";
}

TEST(CompressCli, ABrdfFileIsCompressedAsAOneTexelBtf) {
  TempDir dir;
  const fs::path brdf = dir / "plastic.binary", packed = dir / "plastic.btfz";
  ASSERT_EQ(runDatagen({"--preset", "plastic-red", "--clean", "-o", brdf.string()}).exit_code, 0);
  const CommandResult c = runBtf({"compress", brdf.string(), packed.string(), "--json"});
  ASSERT_EQ(c.exit_code, 0) << c.output;
  const nlohmann::json report = parseJsonOutput(c);
  EXPECT_EQ(report["texels"], nlohmann::json({1, 1}));
  EXPECT_THAT(report["input_kind"].get<std::string>(), HasSubstr("one-texel"));
  EXPECT_LT(report["bytes"].get<double>(), 81.0 * 81 * 12) << "smaller than the raw float data";
}

TEST(CompressCli, BadInputsFailNamingTheFileAndLeaveNoOutput) {
  TempDir dir;
  const fs::path brdf = dir / "white.binary", packed = dir / "white.btfz";
  ASSERT_EQ(runDatagen({"--preset", "white-diffuse", "--clean", "-o", brdf.string()}).exit_code, 0);
  ASSERT_EQ(runBtf({"compress", brdf.string(), packed.string()}).exit_code, 0);
  const std::string bytes = readBytes(packed);
  const fs::path truncated = dir / "truncated.btfz", flipped = dir / "flipped.btfz";
  std::ofstream(truncated, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size() / 2));
  std::string changed = bytes;
  changed[changed.size() - 3] = char(changed[changed.size() - 3] ^ 0x40);
  std::ofstream(flipped, std::ios::binary).write(changed.data(), std::streamsize(changed.size()));

  struct Case {
    std::vector<std::string> args;
    std::string named, problem;
    fs::path must_not_exist;
  };
  const std::vector<Case> cases{
      {{"compress", (dir / "missing").string(), (dir / "a.btfz").string()}, "missing", "no such", dir / "a.btfz"},
      {{"compress", brdf.string(), (dir / "b.bin").string()}, "b.bin", ".btfz", dir / "b.bin"},
      {{"compress", packed.string(), (dir / "c.btfz").string()}, "white.btfz", "already compressed", dir / "c.btfz"},
      {{"info", truncated.string()}, "truncated.btfz", "truncated", {}},
      {{"info", flipped.string()}, "flipped.btfz", "checksum", {}},
      {{"decompress", truncated.string(), (dir / "out").string()}, "truncated.btfz", "truncated", dir / "out"},
      {{"decompress", brdf.string(), (dir / "out2").string()}, "white.binary", ".btfz", dir / "out2"},
  };
  for (const Case& k : cases) {
    const CommandResult r = runBtf(k.args);
    EXPECT_NE(r.exit_code, 0) << k.args[0] << ' ' << k.args[1];
    EXPECT_THAT(r.output, HasSubstr(k.named)) << r.output;
    EXPECT_THAT(r.output, HasSubstr(k.problem)) << r.output;
    EXPECT_LT(r.exit_code, 128) << "no crash: " << r.output;
    if (!k.must_not_exist.empty()) {
      EXPECT_FALSE(fs::exists(k.must_not_exist)) << k.must_not_exist;
    }
  }
}

TEST(BenchDecode, ReportsTheFilesRatesBesideLafortuneAndRefusesBadInput) {
  TempDir dir;
  const fs::path brdf = dir / "plastic.binary", packed = dir / "plastic.btfz";
  ASSERT_EQ(runDatagen({"--preset", "plastic-red", "--clean", "-o", brdf.string()}).exit_code, 0);
  ASSERT_EQ(runBtf({"compress", brdf.string(), packed.string()}).exit_code, 0);
  auto bench = [&](const std::string& seed) {
    const CommandResult r = runBtf({"bench", "decode", packed.string(), "--samples", "1000", "--repeats", "2", "--seed",
                                    seed, "--json"});
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return parseJsonOutput(r);
  };
  const nlohmann::json a = bench("1"), b = bench("1"), c = bench("2");
  EXPECT_EQ(a["texels"], nlohmann::json({1, 1}));
  EXPECT_EQ(a["views"], 81);
  EXPECT_EQ(a["samples"], 768) << "whole blocks of 256";
  EXPECT_DOUBLE_EQ(a["table_MB"].get<double>(), double(VqBtf::read(packed).lookupTableBytes()) / 1e6);
  for (const char* rate : {"value_per_s", "values_per_s", "lafortune_per_s"}) EXPECT_GT(a[rate].get<double>(), 0.0) << rate;
  EXPECT_DOUBLE_EQ(a["values_vs_lafortune"].get<double>(), a["values_per_s"].get<double>() / a["lafortune_per_s"].get<double>());
  // The checksum sums the decoded samples, which follow the seed alone: the same seed decodes the
  // same values, another seed others.
  EXPECT_EQ(a["checksum"], b["checksum"]);
  EXPECT_NE(a["checksum"], c["checksum"]);

  struct Case {
    std::vector<std::string> args;
    std::string named, problem;
  };
  const std::vector<Case> cases{
      {{"bench", "decode", (dir / "missing.btfz").string()}, "missing.btfz", "no such"},
      {{"bench", "decode", brdf.string()}, "plastic.binary", "not a libbtf container"},
      {{"bench", "decode", packed.string(), "--samples", "100"}, "--samples", "256"},
      {{"bench", "decode", packed.string(), "--samples", "100000000"}, "--samples", "33554432"},
      {{"bench", "decode", packed.string(), "--repeats", "0"}, "--repeats", "1"},
  };
  for (const Case& k : cases) {
    const CommandResult r = runBtf(k.args);
    EXPECT_NE(r.exit_code, 0) << k.args[2];
    EXPECT_LT(r.exit_code, 128) << "no crash: " << r.output;
    EXPECT_THAT(r.output, HasSubstr(k.named)) << r.output;
    EXPECT_THAT(r.output, HasSubstr(k.problem)) << r.output;
  }
}

TEST(BenchCompression, QuickRunWritesBothCsvFilesWithVqAndPcaRows) {
  TempDir dir;
  const fs::path out = dir / "bench";
  const CommandResult r = runBtf({"bench", "compression", "--quick", "-o", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string csv = readBytes(out / "compression.csv");
  EXPECT_THAT(csv, HasSubstr("method,material,texels,epsilon,levels,components,bytes,ratio_u8,ratio_f32,rel_rmse,psnr_db,"
                             "compression_s,evals_per_s,chroma_epsilon,mean_ssim,rel_rmse_display,noise_rel_rmse\n"));
  EXPECT_THAT(csv, HasSubstr("\nvq,fabric,64,0.04,"));
  // The chroma tolerance follows epsilon (--chroma-scale 0.5); mean_ssim, rel_rmse_display and
  // noise_rel_rmse follow it.
  EXPECT_THAT(csv, testing::ContainsRegex(",0\\.02,[-0-9.e]+,[-0-9.e]+,[-0-9.e]+\n"));
  EXPECT_THAT(csv, HasSubstr("\npca,fabric,64,"));
  const std::string brdfs = readBytes(out / "brdf_compression.csv");
  EXPECT_THAT(brdfs, HasSubstr("plastic-red,"));
  EXPECT_THAT(r.output, HasSubstr("Bagher"));
}

}  // namespace
}  // namespace btf::test
