// Databases of materials in one .btfz with shared codebooks (compress/vq_database.h) through the
// command line: `btf compress IN1 IN2 ... DB.btfz` (with --compare-alone), `btf info` on a
// database, `btf decompress --material`, `btf merge`, and a scene's {"type": "btf", "material"}.
// The inputs are BRDFs (the shared RGL files and published MERL fits) as one-texel BTFs, which
// compress in milliseconds; every failure names what is wrong and leaves no output behind.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <numeric>
#include <string>
#include <vector>

#include "btf/compress/vq_btf.h"
#include "btf/compress/vq_database.h"
#include "btf/io/btf_data.h"
#include "btf/io/btf_images.h"
#include "btf/io/image.h"
#include "cli_test_support.h"

namespace btf::test {
namespace {
using testing::HasSubstr;
namespace fs = std::filesystem;

std::string rgl(const std::string& stem) { return (sharedDataDir() / "rgl_bsdf" / (stem + ".bsdf")).string(); }

// Raw 8-bit RGB bytes of a one-texel BTF: 81 views x 81 lights x 3 (ratio_u8, docs/design-notes.md#measures).
constexpr double kOneTexelRawU8 = 81.0 * 81.0 * 3.0;

std::vector<std::string> namesIn(const nlohmann::json& materials) {
  std::vector<std::string> names;
  for (const auto& m : materials) names.push_back(m.at("name").get<std::string>());
  return names;
}

// `btf compress IN... OUT [extra...]`, asserting success; the JSON report.
nlohmann::json compressOk(std::vector<std::string> inputs, const fs::path& out, const std::vector<std::string>& extra) {
  std::vector<std::string> args{"compress"};
  args.insert(args.end(), inputs.begin(), inputs.end());
  args.push_back(out.string());
  args.insert(args.end(), extra.begin(), extra.end());
  args.push_back("--json");
  const CommandResult r = runBtf(args);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  if (r.exit_code != 0) return {};
  return parseJsonOutput(r);
}

TEST(CliVqDatabase, CompressOfSeveralBrdfsListsThemInOrderWithBoundedErrors) {
  TempDir dir;
  const fs::path db = dir / "db.btfz";
  // Not in alphabetical order: the database keeps the order of the command line.
  const std::vector<std::string> inputs{rgl("vch_golden_yellow_rgb"), "merl-fit:sgd:alum-bronze", rgl("paper_white_rgb"),
                                        rgl("cc_ibiza_sunset_rgb")};
  const std::vector<std::string> names{"vch_golden_yellow_rgb", "alum-bronze-sgd", "paper_white_rgb", "cc_ibiza_sunset_rgb"};
  const nlohmann::json report = compressOk(inputs, db, {"--epsilon", "0.05"});
  ASSERT_FALSE(report.is_null());
  ASSERT_TRUE(fs::is_regular_file(db));
  const double bytes = double(fs::file_size(db));
  EXPECT_EQ(report["output"].get<std::string>(), db.string());
  EXPECT_EQ(report["bytes"].get<double>(), bytes);
  EXPECT_NEAR(report["ratio_u8"].get<double>(), 4 * kOneTexelRawU8 / bytes, 1e-9);
  ASSERT_EQ(report["materials"].size(), 4u);
  EXPECT_EQ(namesIn(report["materials"]), names);
  for (std::size_t i = 0; i < names.size(); ++i) {
    const nlohmann::json& m = report["materials"][i];
    EXPECT_EQ(m["input"].get<std::string>(), inputs[i]);
    EXPECT_EQ(m["texels"], nlohmann::json({1, 1})) << names[i];
    // Lossy but within the tolerance's reach, as if compressed alone.
    EXPECT_GT(m["rel_rmse"].get<double>(), 0.0) << names[i];
    EXPECT_LT(m["rel_rmse"].get<double>(), 0.1) << names[i];
    EXPECT_GT(m["mean_ssim"].get<double>(), 0.9) << names[i];
    EXPECT_FALSE(m.contains("alone_bytes")) << "only with --compare-alone";
  }
  EXPECT_FALSE(report.contains("saving"));

  const CommandResult info = runBtf({"info", db.string(), "--json"});
  ASSERT_EQ(info.exit_code, 0) << info.output;
  const nlohmann::json facts = parseJsonOutput(info);
  EXPECT_EQ(namesIn(facts["materials"]), names);
  EXPECT_EQ(facts["bytes"].get<double>(), bytes);
  EXPECT_EQ(facts["shared_codebook_entries"], report["shared_codebook_entries"]);
  EXPECT_EQ(facts["epsilon"].get<double>(), report["epsilon"].get<double>());
  for (std::size_t i = 0; i < names.size(); ++i)
    EXPECT_EQ(facts["materials"][i]["codebook_entries"], report["materials"][i]["codebook_entries"]) << names[i];

  const CommandResult text = runBtf({"info", db.string()});
  ASSERT_EQ(text.exit_code, 0) << text.output;
  EXPECT_THAT(text.output, HasSubstr("btfz database of 4 materials"));
  for (const std::string& name : names) EXPECT_THAT(text.output, HasSubstr(name));
}

TEST(CliVqDatabase, CompareAloneReportsWhatTheSharedCodebooksSave) {
  TempDir dir;
  const fs::path db = dir / "db.btfz", alone = dir / "alone.btfz";
  const std::vector<std::string> inputs{rgl("paper_white_rgb"), rgl("vch_golden_yellow_rgb"), rgl("cc_ibiza_sunset_rgb"),
                                        "merl-fit:sgd:alum-bronze", "merl-fit:sgd:blue-acrylic"};
  const nlohmann::json report = compressOk(inputs, db, {"--epsilon", "0.05", "--compare-alone", "--no-verify"});
  ASSERT_FALSE(report.is_null());
  const double bytes = double(fs::file_size(db));
  EXPECT_EQ(report["bytes"].get<double>(), bytes);
  ASSERT_EQ(report["materials"].size(), inputs.size());
  std::uint64_t sum = 0;
  for (const auto& m : report["materials"]) {
    ASSERT_TRUE(m.contains("alone_bytes")) << m["name"];
    EXPECT_GT(m["alone_bytes"].get<std::uint64_t>(), 0u);
    EXPECT_FALSE(m.contains("rel_rmse")) << "--no-verify skips the comparison";
    sum += m["alone_bytes"].get<std::uint64_t>();
  }
  EXPECT_EQ(report["alone_bytes"].get<std::uint64_t>(), sum);
  EXPECT_NEAR(report["saving"].get<double>(), double(sum) / bytes, 1e-9);
  EXPECT_GT(report["saving"].get<double>(), 1.0) << "five BRDFs share level-1 and level-2 entries";

  // A material's alone_bytes is (about) the file that compressing it alone writes.
  const nlohmann::json single = compressOk({inputs.back()}, alone, {"--epsilon", "0.05", "--no-verify"});
  ASSERT_FALSE(single.is_null());
  EXPECT_NEAR(report["materials"][4]["alone_bytes"].get<double>(), double(fs::file_size(alone)),
              0.01 * double(fs::file_size(alone)));

  // The text form prints the sum and the factor.
  std::vector<std::string> args{"compress"};
  args.insert(args.end(), inputs.begin(), inputs.end());
  for (const char* a : {"--epsilon", "0.05", "--compare-alone", "--no-verify"}) args.push_back(a);
  args.insert(args.begin() + 1 + std::ptrdiff_t(inputs.size()), (dir / "text.btfz").string());
  const CommandResult text = runBtf(args);
  ASSERT_EQ(text.exit_code, 0) << text.output;
  EXPECT_THAT(text.output, HasSubstr("each compressed alone: " + std::to_string(sum) + " bytes in all"));
  EXPECT_THAT(text.output, HasSubstr("the shared codebooks save a factor "));
}

// Merging is lossless: each material of the merged database decodes to exactly what it decoded to
// in the file it came from (a database of two, and a single-material file).
TEST(CliVqDatabase, MergeIsLosslessAndDecompressMaterialGivesTheSingleFilesBtf) {
  TempDir dir;
  const fs::path pair = dir / "pair.btfz", acrylic = dir / "acrylic.btfz", merged = dir / "merged.btfz",
                 unpacked = dir / "unpacked";
  const std::vector<std::string> options{"--epsilon", "0.05", "--no-verify"};
  ASSERT_FALSE(compressOk({rgl("paper_white_rgb"), "merl-fit:sgd:alum-bronze"}, pair, options).is_null());
  ASSERT_FALSE(compressOk({"merl-fit:sgd:blue-acrylic"}, acrylic, options).is_null());

  const CommandResult m = runBtf({"merge", pair.string(), acrylic.string(), "-o", merged.string()});
  ASSERT_EQ(m.exit_code, 0) << m.output;
  EXPECT_THAT(m.output, HasSubstr("3 materials from 2 files"));

  // Every material, bit for bit (rmse 0 over all entries), against the part it came from.
  const VqDatabase db = VqDatabase::read(merged);
  EXPECT_EQ(db.names(), (std::vector<std::string>{"paper_white_rgb", "alum-bronze-sgd", "blue-acrylic-sgd"}));
  const VqDatabase pair_db = VqDatabase::read(pair);
  struct Origin {
    std::string name;
    VqBtf part;
  };
  const std::vector<Origin> origins{{"paper_white_rgb", pair_db.material("paper_white_rgb")},
                                    {"alum-bronze-sgd", pair_db.material("alum-bronze-sgd")},
                                    {"blue-acrylic-sgd", VqBtf::read(acrylic)}};
  for (const Origin& o : origins) {
    const BtfErrorStats e = compareBtf(o.part, db.material(o.name));
    EXPECT_EQ(e.entries, std::size_t(81 * 81)) << o.name;  // RGB triples
    EXPECT_GT(e.reference_rms, 0.0) << o.name;
    EXPECT_EQ(e.rmse, 0.0) << o.name;
  }

  // A single-material file answers to the name the merge gives its material (its header says
  // NAME " (vq)"), as `btf decompress --material` and a scene's "material" ask for it.
  EXPECT_EQ(compareBtf(VqBtf::read(acrylic), VqBtf::read(acrylic, "blue-acrylic-sgd")).rmse, 0.0);
  EXPECT_THAT(errorOf([&] { VqBtf::read(acrylic, "alum-bronze-sgd"); }), HasSubstr("no material named 'alum-bronze-sgd'"));

  // Through the command line: the folder of the material that came from the single file (whose
  // codebook indices the merge renumbered) is that file's BTF.
  const CommandResult d =
      runBtf({"decompress", merged.string(), unpacked.string(), "--material", "blue-acrylic-sgd", "--format", "exr"});
  ASSERT_EQ(d.exit_code, 0) << d.output;
  // (compareBtf gives the rel_rmse `btf compare FOLDER FILE` reports; in-process it skips that
  // command's SSIM and noise floor, which take seconds on 6561 images.)
  const BtfErrorStats back = compareBtf(VqBtf::read(acrylic), BtfImageFolder::open(unpacked));
  EXPECT_EQ(back.entries, std::size_t(81 * 81));
  EXPECT_EQ(back.rmse, 0.0) << "rel_rmse " << back.rel_rmse;
}

TEST(CliVqDatabase, DecompressOfADatabaseNeedsAKnownMaterialName) {
  TempDir dir;
  const fs::path db = dir / "db.btfz", out = dir / "out";
  ASSERT_FALSE(compressOk({rgl("paper_white_rgb"), "merl-fit:sgd:alum-bronze", "merl-fit:sgd:blue-acrylic"}, db,
                          {"--no-verify"})
                   .is_null());
  const std::string all = "paper_white_rgb, alum-bronze-sgd, blue-acrylic-sgd";
  expectFailure(runBtf({"decompress", db.string(), out.string()}),
                {db.string(), "is a database of 3 materials (" + all + ")", "name the one to read"});
  EXPECT_FALSE(fs::exists(out));
  expectFailure(runBtf({"decompress", db.string(), out.string(), "--material", "alum-bronze"}),
                {db.string(), "no material named 'alum-bronze'", all});
  EXPECT_FALSE(fs::exists(out));
}

TEST(CliVqDatabase, CompareMaterialPicksTheDatabasesMaterial) {
  TempDir dir;
  const fs::path db = dir / "db.btfz", acrylic = dir / "acrylic";
  ASSERT_FALSE(compressOk({"merl-fit:sgd:alum-bronze", "merl-fit:sgd:blue-acrylic"}, db, {"--no-verify"}).is_null());
  const CommandResult d =
      runBtf({"decompress", db.string(), acrylic.string(), "--material", "blue-acrylic-sgd", "--format", "exr"});
  ASSERT_EQ(d.exit_code, 0) << d.output;
  auto relRmse = [&](const std::string& material) {
    const CommandResult r = runBtf({"compare", db.string(), acrylic.string(), "--material", material, "--json"});
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return r.exit_code == 0 ? parseJsonOutput(r).at("rel_rmse").get<double>() : -1.0;
  };
  // The material the folder was decoded from matches it exactly; the other one is another BRDF.
  EXPECT_EQ(relRmse("blue-acrylic-sgd"), 0.0);
  EXPECT_GT(relRmse("alum-bronze-sgd"), 0.1);
  expectFailure(runBtf({"compare", db.string(), acrylic.string()}),
                {db.string(), "is a database of 2 materials", "name the one to read"});
  expectFailure(runBtf({"compare", db.string(), acrylic.string(), "--material", "chrome"}),
                {db.string(), "no material named 'chrome'"});
  expectFailure(runBtf({"compare", acrylic.string(), acrylic.string(), "--material", "chrome"}),
                {"--material names a material of a .btfz database"});
}

TEST(CliVqDatabase, MergeFailuresNameTheProblemAndLeaveNoOutput) {
  TempDir dir;
  const fs::path pair = dir / "pair.btfz", bronze = dir / "bronze.btfz", bronze_coarse = dir / "bronze-coarse.btfz",
                 out = dir / "merged.btfz", previous = dir / "previous.btfz";
  ASSERT_FALSE(compressOk({rgl("paper_white_rgb"), "merl-fit:sgd:alum-bronze"}, pair, {"--epsilon", "0.05", "--no-verify"})
                   .is_null());
  ASSERT_FALSE(compressOk({"merl-fit:sgd:alum-bronze"}, bronze, {"--epsilon", "0.05", "--no-verify"}).is_null());
  ASSERT_FALSE(compressOk({"merl-fit:sgd:alum-bronze"}, bronze_coarse, {"--epsilon", "0.1", "--no-verify"}).is_null());

  // A database and a single file that both hold alum-bronze-sgd.
  expectFailure(runBtf({"merge", pair.string(), bronze.string(), "-o", out.string()}),
                {"two materials are named 'alum-bronze-sgd'"});
  EXPECT_FALSE(fs::exists(out));
  // Different tolerances; a failed merge leaves an existing output as it was (atomic writing).
  std::ofstream(previous, std::ios::binary) << "previous";
  expectFailure(runBtf({"merge", pair.string(), bronze_coarse.string(), "-o", previous.string()}),
                {"cannot merge", "epsilon 0.05", "epsilon 0.1", "recompress with the same options"});
  EXPECT_EQ(readBytes(previous), "previous");
  const fs::path not_btfz = dir / "merged.bin";
  expectFailure(runBtf({"merge", pair.string(), bronze_coarse.string(), "-o", not_btfz.string()}),
                {not_btfz.string(), ".btfz"});
  EXPECT_FALSE(fs::exists(not_btfz));
  expectFailure(runBtf({"merge", pair.string(), rgl("cc_ibiza_sunset_rgb"), "-o", out.string()}),
                {"cc_ibiza_sunset_rgb.bsdf", "is not a .btfz file"});
  EXPECT_FALSE(fs::exists(out));
  for (const fs::path& f : filesIn(dir.path()))
    EXPECT_TRUE(f == pair || f == bronze || f == bronze_coarse || f == previous) << "left behind: " << f;
}

TEST(CliVqDatabase, CompressRefusesTwoInputsOfTheSameName) {
  TempDir dir;
  const fs::path out = dir / "db.btfz";
  // The same file twice, and two files of the same name in different folders.
  fs::create_directories(dir / "copy");
  const fs::path copy = dir / "copy" / "paper_white_rgb.bsdf";
  fs::copy_file(rgl("paper_white_rgb"), copy);
  const std::vector<std::pair<std::string, std::string>> clashes{{rgl("paper_white_rgb"), rgl("paper_white_rgb")},
                                                                 {rgl("paper_white_rgb"), copy.string()}};
  for (const auto& [a, b] : clashes) {
    const CommandResult r = runBtf({"compress", a, "merl-fit:sgd:alum-bronze", b, out.string()});
    expectFailure(r, {a, b, "'paper_white_rgb'", "distinct material names"});
    EXPECT_FALSE(fs::exists(out)) << a << " + " << b;
  }
  // Published fits are named NAME-MODEL: two models of one material do not clash.
  const nlohmann::json ok = compressOk({"merl-fit:sgd:alum-bronze", "merl-fit:abc:alum-bronze"}, out, {"--no-verify"});
  ASSERT_FALSE(ok.is_null());
  EXPECT_EQ(namesIn(ok["materials"]), (std::vector<std::string>{"alum-bronze-sgd", "alum-bronze-abc"}));
}

// A scene's btf material picks one material of a database; a name the database lacks (or none, for
// a database of several) is an error naming the materials there are.
TEST(CliVqDatabase, SceneMaterialSelectsADatabaseMaterial) {
  TempDir dir;
  const fs::path db = dir / "db.btfz";
  ASSERT_FALSE(compressOk({rgl("paper_white_rgb"), "merl-fit:sgd:alum-bronze"}, db, {"--no-verify"}).is_null());
  auto sceneWith = [&](const nlohmann::json& material, const std::string& name) {
    const fs::path path = dir / name;
    std::ofstream(path) << floorScene(material).dump(2);
    return path;
  };
  const fs::path good = sceneWith({{"type", "btf"}, {"file", db.string()}, {"material", "alum-bronze-sgd"}}, "good.json");
  const fs::path image = dir / "good.exr";
  const CommandResult r = runBtf({"render", good.string(), "-o", image.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const Image rendered = readImage(image);
  EXPECT_GT(std::accumulate(rendered.pixels.begin(), rendered.pixels.end(), 0.0), 0.0) << "the lit floor is visible";

  const std::string all = "paper_white_rgb, alum-bronze-sgd";
  const fs::path unknown = sceneWith({{"type", "btf"}, {"file", db.string()}, {"material", "alum-bronze"}}, "unknown.json");
  expectFailure(runBtf({"render", unknown.string(), "-o", (dir / "unknown.exr").string()}),
                {db.string(), "no material named 'alum-bronze'", all});
  EXPECT_FALSE(fs::exists(dir / "unknown.exr"));
  const fs::path unnamed = sceneWith({{"type", "btf"}, {"file", db.string()}}, "unnamed.json");
  expectFailure(runBtf({"render", unnamed.string(), "-o", (dir / "unnamed.exr").string()}),
                {db.string(), "is a database of 2 materials (" + all + ")"});
  EXPECT_FALSE(fs::exists(dir / "unnamed.exr"));
}

}  // namespace
}  // namespace btf::test
