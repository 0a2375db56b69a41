// The downloaded-dataset layouts on the command line: btf-datagen writes a BTF on the 81, the Bonn
// dome's 151 and a scattered set, as a UTIA folder or a Bonn .btf; `btf info` reads a .btf's
// headers alone; `btf convert` moves a BTF between layouts and `btf compare` measures the trip; a
// damaged .btf fails naming the file and the section, and leaves no output.
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "btf/io/image.h"
#include "cli_test_support.h"

namespace btf::test {
namespace {
namespace fs = std::filesystem;
using testing::HasSubstr;

TEST(BonnCli, DatagenWritesEverySetAndInfoReadsTheHeaders) {
  TempDir dir;
  const CommandResult dome = runDatagen({"btf", "--pattern", "stones", "--size", "4", "--directions", "dome", "--layout",
                                         "dfmf", "--components", "8", "-o", (dir / "dome.btf").string()});
  ASSERT_EQ(dome.exit_code, 0) << dome.output;
  const CommandResult info = runBtf({"info", (dir / "dome.btf").string(), "--json"});
  ASSERT_EQ(info.exit_code, 0) << info.output;
  const nlohmann::json facts = parseJsonOutput(info);
  EXPECT_EQ(facts["signature"], "!DFMF08FCR");
  EXPECT_EQ(facts["views"], 151);
  EXPECT_EQ(facts["lights_per_view_max"], 151);
  EXPECT_EQ(facts["directions"], "151 views x 151 lights (Bonn dome 1)");
  EXPECT_EQ(facts["texels"], nlohmann::json({4, 4}));
  EXPECT_EQ(facts["factors"].size(), 3u);
  EXPECT_EQ(facts["factors"][0]["components"], 8);
  EXPECT_EQ(facts["bytes"], fs::file_size(dir / "dome.btf"));

  const CommandResult scattered = runDatagen({"btf", "--size", "4", "--directions", "scattered", "--layout", "pvf",
                                              "--components", "4", "-o", (dir / "scattered.btf").string()});
  ASSERT_EQ(scattered.exit_code, 0) << scattered.output;
  EXPECT_THAT(runBtf({"info", (dir / "scattered.btf").string()}).output, HasSubstr("view-dependent"));

  // A folder layout holds the 81 directions only.
  expectFailure(runDatagen({"btf", "--size", "4", "--directions", "dome", "-o", (dir / "folder").string()}),
                {"holds the 81 UBO2003 directions"});
  EXPECT_FALSE(fs::exists(dir / "folder"));
}

TEST(BonnCli, ConvertBetweenLayoutsAndCompare) {
  TempDir dir;
  const fs::path folder = dir / "fabric";
  ASSERT_EQ(runDatagen({"btf", "--size", "4", "--format", "exr", "-o", folder.string()}).exit_code, 0);
  // Full rank (16 texels), float factors: the trip through the SVD is exact to rounding.
  const CommandResult to_bonn = runBtf({"convert", folder.string(), (dir / "fabric.btf").string(), "--components", "16",
                                        "--relative-error", "1e-9", "--scalar", "4", "--layout", "fmf"});
  ASSERT_EQ(to_bonn.exit_code, 0) << to_bonn.output;
  EXPECT_THAT(to_bonn.output, HasSubstr("Bonn BTF (FMF"));
  const CommandResult compared = runBtf({"compare", (dir / "fabric.btf").string(), folder.string(), "--json"});
  ASSERT_EQ(compared.exit_code, 0) << compared.output;
  EXPECT_LT(parseJsonOutput(compared)["rel_rmse"].get<double>(), 1e-4);
  // On to the UTIA layout and back to the reference.
  const CommandResult to_utia = runBtf({"convert", (dir / "fabric.btf").string(), (dir / "utia").string(), "--layout", "utia"});
  ASSERT_EQ(to_utia.exit_code, 0) << to_utia.output;
  EXPECT_TRUE(fs::exists(dir / "utia" / "tv000_pv000" / "tl000_pl000_tv000_pv000.exr"));
  EXPECT_LT(parseJsonOutput(runBtf({"compare", (dir / "utia").string(), folder.string(), "--json"}))["rel_rmse"].get<double>(),
            1e-4);
  // A .btf compresses like any BTF on the 81 set.
  const CommandResult compressed = runBtf({"compress", (dir / "fabric.btf").string(), (dir / "fabric.btfz").string()});
  EXPECT_EQ(compressed.exit_code, 0) << compressed.output;
  expectFailure(runBtf({"convert", folder.string(), (dir / "x.btf").string(), "--layout", "utia"}), {"folder layout"});
  EXPECT_FALSE(fs::exists(dir / "x.btf"));
}

TEST(BonnCli, DamagedFilesFailNamingTheSection) {
  TempDir dir;
  ASSERT_EQ(runDatagen({"btf", "--size", "4", "--directions", "dome", "--layout", "dfmf", "--components", "4", "-o",
                        (dir / "dome.btf").string()})
                .exit_code,
            0);
  const std::string bytes = readBytes(dir / "dome.btf");
  {
    std::ofstream cut(dir / "cut.btf", std::ios::binary);
    cut.write(bytes.data(), std::streamsize(bytes.size() - 100));
  }
  expectFailure(runBtf({"info", (dir / "cut.btf").string()}), {"cut.btf", "DFMF channel 2 factors is truncated"});
  expectFailure(runBtf({"convert", (dir / "cut.btf").string(), (dir / "out.btf").string()}), {"cut.btf", "truncated"});
  EXPECT_FALSE(fs::exists(dir / "out.btf"));
  // The dome's file compresses by VQ (larger than this tiny file: allowed), and decompresses to a
  // .btf on the same set.
  const CommandResult compressed =
      runBtf({"compress", (dir / "dome.btf").string(), (dir / "dome.btfz").string(), "--form", "vq", "--allow-larger"});
  EXPECT_EQ(compressed.exit_code, 0) << compressed.output;
  EXPECT_THAT(compressed.output, HasSubstr("all 151 views (Bonn dome 1) x 151 lights"));
  EXPECT_THAT(runBtf({"info", (dir / "dome.btfz").string()}).output,
              HasSubstr("light rings of level 1: 10 rings of 1, 6, 12, 12, 12, 18, 18, 24, 24, 24 lights"));
  const CommandResult back = runBtf({"decompress", (dir / "dome.btfz").string(), (dir / "back.btf").string()});
  EXPECT_EQ(back.exit_code, 0) << back.output;
  const CommandResult info = runBtf({"info", (dir / "back.btf").string()});
  EXPECT_THAT(info.output, HasSubstr("151 views x 151 lights (Bonn dome 1)"));
}

// A Bonn file is already factorised: what `btf compress` writes is never larger than it. The small
// dome file's codebooks would be (refused, nothing written); auto measures both forms and keeps
// the factor form, which meets epsilon; the Bonn writer keeps the components the data needs.
TEST(BonnCli, CompressNeverWritesMoreThanTheBonnInput) {
  TempDir dir;
  const fs::path btf = dir / "dome.btf";
  ASSERT_EQ(runDatagen({"btf", "--size", "8", "--directions", "dome", "--layout", "dfmf", "--components", "8", "-o",
                        btf.string()})
                .exit_code,
            0);
  const std::uint64_t input_bytes = fs::file_size(btf);
  expectFailure(runBtf({"compress", btf.string(), (dir / "vq.btfz").string(), "--form", "vq", "--no-verify"}),
                {"vq.btfz", "not written", "more than the", "--allow-larger"});
  EXPECT_FALSE(fs::exists(dir / "vq.btfz"));
  for (const auto& entry : fs::directory_iterator(dir.path()))
    EXPECT_EQ(entry.path().string().find("pending"), std::string::npos) << entry.path();

  const CommandResult c = runBtf({"compress", btf.string(), (dir / "auto.btfz").string(), "--epsilon", "0.02", "--json"});
  ASSERT_EQ(c.exit_code, 0) << c.output;
  const nlohmann::json report = parseJsonOutput(c);
  EXPECT_EQ(report["form"], "factor log-luminance");
  EXPECT_EQ(report["from_source_factors"], true);
  EXPECT_EQ(report["form_choice"]["trials"].size(), 3u);
  EXPECT_LE(report["bytes"].get<std::uint64_t>(), input_bytes);
  EXPECT_EQ(report["bytes"].get<std::uint64_t>(), fs::file_size(dir / "auto.btfz"));
  EXPECT_LE(report["rel_rmse"].get<double>(), 0.02) << "measured against the file's own decode";
  EXPECT_GT(report["peak_memory_bytes"].get<std::uint64_t>(), 1u << 20);
  const CommandResult compared = runBtf({"compare", (dir / "auto.btfz").string(), btf.string(), "--json"});
  ASSERT_EQ(compared.exit_code, 0) << compared.output;
  EXPECT_NEAR(parseJsonOutput(compared)["rel_rmse"].get<double>(), report["rel_rmse"].get<double>(), 1e-9);
  EXPECT_THAT(runBtf({"info", (dir / "auto.btfz").string()}).output,
              HasSubstr("btfz (quantized factors, log-luminance), 8 x 8 texels x all 151 views (Bonn dome 1)"));

  const CommandResult back = runBtf({"decompress", (dir / "auto.btfz").string(), (dir / "back.btf").string()});
  ASSERT_EQ(back.exit_code, 0) << back.output;
  EXPECT_THAT(back.output, HasSubstr("truncation error"));
}

// A BTF on the dome renders as a scene material, read from its .btf and from its .btfz.
TEST(BonnCli, DomeBtfRendersFromTheFileAndItsCompressedForm) {
  TempDir dir;
  ASSERT_EQ(runDatagen({"btf", "--size", "4", "--directions", "dome", "--layout", "dfmf", "--components", "8", "-o",
                        (dir / "dome.btf").string()})
                .exit_code,
            0);
  ASSERT_EQ(runBtf({"compress", (dir / "dome.btf").string(), (dir / "dome.btfz").string(), "--no-verify"}).exit_code, 0);
  double sums[2] = {0, 0};
  int i = 0;
  for (const char* file : {"dome.btf", "dome.btfz"}) {
    const nlohmann::json scene = floorScene({{"type", "btf"}, {"file", (dir / file).string()}});
    const fs::path path = dir / (std::string(file) + ".json"), image = dir / (std::string(file) + ".exr");
    std::ofstream(path) << scene.dump(2);
    const CommandResult r = runBtf({"render", path.string(), "-o", image.string()});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const Image rendered = readImage(image);
    for (float p : rendered.pixels) sums[i] += double(p);
    ++i;
  }
  EXPECT_GT(sums[0], 0.0) << "the lit floor is visible";
  // The compressed form renders the same picture within the codec's error and the noise of 4 spp.
  EXPECT_NEAR(sums[1], sums[0], 0.1 * sums[0]);
}

// Camera data (noise, misregistration, 8-bit codes) is far from low-rank: a crop factorised anew
// misses epsilon 0.02 with every component a sketch holds, while the file's own factors, re-coded,
// meet it. The choice measures that candidate on the whole file, so the factor form is found.
TEST(BonnCli, NoisyDfmfKeepsItsOwnFactorsWhereACropMisses) {
  TempDir dir;
  const fs::path btf = dir / "print.btf";
  ASSERT_EQ(runDatagen({"btf", "--pattern", "print", "--camera", "--size", "33", "--directions", "dome", "--layout",
                        "dfmf", "-o", btf.string()})
                .exit_code,
            0);
  const CommandResult c = runBtf({"compress", btf.string(), (dir / "p.btfz").string(), "--form", "factor", "--epsilon",
                                  "0.02", "--json"});
  ASSERT_EQ(c.exit_code, 0) << c.output;
  const nlohmann::json report = parseJsonOutput(c);
  EXPECT_EQ(report["form"], "factor log-luminance");
  EXPECT_LE(report["rel_rmse"].get<double>(), 0.02);
  EXPECT_LE(report["bytes"].get<std::uint64_t>(), fs::file_size(btf));
  bool whole = false;
  for (const auto& t : report["form_choice"]["trials"])
    if (t["form"] == "factor log-luminance") {
      whole = t["whole"].get<bool>();
      EXPECT_NEAR(t["sample_rel_rmse"].get<double>(), report["rel_rmse"].get<double>(), 1e-6)
          << "the trial is the file written";
      EXPECT_EQ(t["projected_bytes"].get<double>(), double(report["bytes"].get<std::uint64_t>()));
    }
  EXPECT_TRUE(whole) << c.output;
}

// `btf bench bonn --quick`: one side, a row per method, each figure consistent with the others.
TEST(BonnCli, BenchBonnSetsTheBtfzBesideTheDfmfAtEqualBytes) {
  TempDir dir;
  const fs::path out = dir / "bench";
  const CommandResult r = runBtf({"bench", "bonn", "--quick", "-o", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::istringstream csv(readBytes(out / "bonn.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "side,texels,pairs,input_bytes,generate_s,method,epsilon,form,components,bytes,ratio_input,rel_rmse,"
                  "mean_ssim,seconds,peak_memory_mib");
  std::map<std::string, std::vector<std::string>> rows;
  while (std::getline(csv, line)) {
    std::vector<std::string> cells;
    std::istringstream in(line);
    for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 15u) << line;
    rows[cells[5]] = cells;
  }
  ASSERT_EQ(rows.count("btfz"), 1u) << r.output;
  ASSERT_EQ(rows.count("dfmf-equal-bytes"), 1u) << r.output;
  const auto& z = rows["btfz"];
  const auto& d = rows["dfmf-equal-bytes"];
  EXPECT_EQ(z[0], "12");
  EXPECT_EQ(z[2], "22801") << "the dome's 151 x 151 pairs";
  const double input = std::stod(z[3]), bytes = std::stod(z[9]);
  EXPECT_GT(bytes, 0);
  EXPECT_NEAR(std::stod(z[10]), input / bytes, 1e-4 * input / bytes);
  if (z[7].starts_with("factor")) {
    EXPECT_LE(std::stod(z[11]), 0.05 * 1.0001) << "the factor form meets --epsilon";
  }
  EXPECT_GT(std::stod(z[14]), 1.0) << "btf compress reports its peak memory";
  // The baseline: the largest component count whose DFMF fits in the .btfz's bytes. One more
  // component per factorisation costs 3 x (1 + pairs + texels) half floats (the generated input keeps
  // all 64 in each, so a .btfz below the input's bytes leaves room for one more).
  const int k = std::stoi(d[8]);
  if (k > 0 && bytes < input) {
    const double dfmf_bytes = std::stod(d[9]), step = 3.0 * (1 + 22801 + 144) * 2;
    EXPECT_LE(dfmf_bytes, bytes);
    EXPECT_GT(dfmf_bytes + step, bytes) << "k + 1 components would have fitted";
    EXPECT_GT(std::stod(d[11]), 0.0);
  }
  EXPECT_FALSE(fs::exists(out / "work")) << "the generated inputs are removed";
  EXPECT_THAT(r.output, HasSubstr("dfmf-equal-bytes"));
}

}  // namespace
}  // namespace btf::test
