// Every subcommand on every kind of bad input: a non-zero exit (not a crash), one message naming
// the file and the problem, and no output file (complete or partial) left behind.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <limits>

#include "btf/io/image.h"
#include "btf/io/merl.h"
#include "cli_test_support.h"
#include "support/raw_image_writer.h"

namespace btf::test {
namespace {
namespace fs = std::filesystem;

struct BadInput {
  std::string kind;
  std::string file_name;
  std::string problem;  // a word the message must contain
};

const std::vector<BadInput> kBadInputs = {
    {"missing", "missing.binary", "no such file"},
    {"empty", "empty.binary", "empty"},
    {"truncated", "truncated.binary", "truncated"},
    {"wrong_dims", "dims.binary", "dims"},
    {"nan", "nan.binary", "NaN"},
    {"directory", "folder.binary", "directory"},
    {"unknown_extension", "table.txt", "extension"},
    {"exr_empty", "empty.exr", "empty"},
    {"exr_truncated", "truncated.exr", "truncated"},
    {"exr_not_a_stack", "single.exr", "parts"},
    {"exr_nan", "nan.exr", "non-finite"},
};

// gtest prints parameters in test listings (and ctest names): the kind says it all.
void PrintTo(const BadInput& bad, std::ostream* os) { *os << bad.kind; }

// A MERL-layout file: header dims, then `count` doubles of value 1 with an optional NaN.
void writeRawMerl(const fs::path& path, std::array<std::int32_t, 3> dims, std::size_t count, bool with_nan) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(dims.data()), sizeof dims);
  std::vector<double> values(count, 1.0);
  if (with_nan) values[count / 2] = std::numeric_limits<double>::quiet_NaN();
  out.write(reinterpret_cast<const char*>(values.data()), std::streamsize(values.size() * sizeof(double)));
}

std::vector<StackLayer> constantStack(float value) {
  std::vector<StackLayer> layers(MerlTable::kThetaHalfRes);
  for (int th = 0; th < MerlTable::kThetaHalfRes; ++th) {
    layers[th].name = "theta_h_" + std::to_string(th);
    layers[th].attributes["btf:theta_h_index"] = th;
    layers[th].image = Image(MerlTable::kPhiDiffRes, MerlTable::kThetaDiffRes, 3, value);
  }
  return layers;
}

void truncateCopy(const fs::path& from, const fs::path& to, double fraction) {
  const std::string bytes = readBytes(from);
  std::ofstream(to, std::ios::binary).write(bytes.data(), std::streamsize(double(bytes.size()) * fraction));
}

// Creates the bad input of one kind in `dir` and returns its path.
fs::path makeBadInput(const BadInput& bad, const fs::path& dir) {
  const fs::path path = dir / bad.file_name;
  const std::size_t entries = 3 * MerlTable::kEntriesPerChannel;
  if (bad.kind == "empty" || bad.kind == "exr_empty") std::ofstream(path, std::ios::binary);
  if (bad.kind == "truncated") writeRawMerl(path, {90, 90, 180}, 1000, false);
  if (bad.kind == "wrong_dims") writeRawMerl(path, {90, 180, 90}, entries, false);  // right size, wrong dims
  if (bad.kind == "nan") writeRawMerl(path, {90, 90, 180}, entries, true);
  if (bad.kind == "directory") fs::create_directory(path);
  // Neither the content nor the extension of any format (a MERL table named .txt is read by its
  // content: ContentBeforeExtension below).
  if (bad.kind == "unknown_extension") std::ofstream(path) << "theta_h theta_d phi_d r g b\n";
  if (bad.kind == "exr_truncated") {
    writeImageStack(dir / "whole.exr", constantStack(0.25f));
    truncateCopy(dir / "whole.exr", path, 0.5);
    fs::remove(dir / "whole.exr");
  }
  if (bad.kind == "exr_not_a_stack") writeImage(path, Image(16, 8, 3, 0.5f));
  if (bad.kind == "exr_nan") {
    std::vector<StackLayer> layers = constantStack(0.25f);
    layers[45].image.at(7, 3, 1) = std::numeric_limits<float>::quiet_NaN();
    writeRawImageStack(path, layers);
  }
  return path;
}

// The command line of each subcommand reading `input` and, where it writes, writing into `out_dir`.
std::vector<std::string> commandLine(const std::string& command, const fs::path& input, const fs::path& out_dir) {
  if (command == "info") return {"info", input.string()};
  if (command == "eval") return {"eval", input.string(), "--theta-i", "30", "--theta-o", "30", "--phi-o", "180"};
  if (command == "plot") return {"plot", input.string(), "-o", (out_dir / "plot.png").string()};
  const bool from_exr = input.extension() == ".exr";
  return {"convert", input.string(), (out_dir / (from_exr ? "out.binary" : "out.exr")).string()};
}

using Case = std::tuple<std::string, BadInput>;

class BadInputTest : public testing::TestWithParam<Case> {};

TEST_P(BadInputTest, FailsCleanlyNamingFileAndProblem) {
  const auto& [command, bad] = GetParam();
  TempDir in_dir, out_dir;
  const fs::path input = makeBadInput(bad, in_dir.path());
  const CommandResult r = runBtf(commandLine(command, input, out_dir.path()));
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_LT(r.exit_code, 128) << "crashed: " << r.output;
  EXPECT_NE(r.output.find("error"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(input.string()), std::string::npos) << "message must name the file: " << r.output;
  EXPECT_NE(r.output.find(bad.problem), std::string::npos) << "message must name the problem: " << r.output;
  EXPECT_TRUE(filesIn(out_dir.path()).empty()) << "no output, not even a partial one";
}

INSTANTIATE_TEST_SUITE_P(AllCommands, BadInputTest,
                         testing::Combine(testing::Values("info", "eval", "convert", "plot"), testing::ValuesIn(kBadInputs)),
                         [](const testing::TestParamInfo<Case>& info) {
                           return std::get<0>(info.param) + "_" + std::get<1>(info.param).kind;
                         });

// A file is recognised by its content before its extension: a MERL table named .txt is one.
TEST(BadInput, ContentBeforeExtension) {
  TempDir dir;
  const fs::path table = dir / "table.txt";
  writeRawMerl(table, {90, 90, 180}, 3 * MerlTable::kEntriesPerChannel, false);
  const CommandResult r = runBtf({"info", table.string()});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("MERL binary"), std::string::npos) << r.output;
}

// Unwritable destinations: the input is fine, the output cannot be created.
TEST(BadOutput, MissingFolderOrDirectoryAsOutputLeavesNothing) {
  TempDir dir;
  const fs::path table = dir / "t.binary";
  ASSERT_EQ(runDatagen({"--preset", "white-diffuse", "--clean", "-o", table.string()}).exit_code, 0);
  fs::create_directory(dir / "taken.exr");
  const std::vector<std::vector<std::string>> commands = {
      {"convert", table.string(), (dir / "no-folder" / "out.exr").string()},
      {"convert", table.string(), (dir / "taken.exr").string()},
      {"plot", table.string(), "-o", (dir / "no-folder" / "plot.png").string()},
  };
  for (const auto& args : commands) {
    const CommandResult r = runBtf(args);
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_LT(r.exit_code, 128) << r.output;
    EXPECT_NE(r.output.find(args.back() == (dir / "taken.exr").string() ? "directory" : "no-folder"), std::string::npos)
        << r.output;
  }
  EXPECT_EQ(filesIn(dir.path()).size(), 2u) << "only the table and the pre-existing folder";
}

TEST(BadOutput, UnknownSubcommandOrMissingArgumentIsAUsageError) {
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{{"frobnicate"}, {"info"}, {}}) {
    const CommandResult r = runBtf(args);
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_LT(r.exit_code, 128) << r.output;
  }
  for (const char* sub : {"info", "eval", "convert", "plot"}) {
    const CommandResult help = runBtf({sub, "--help"});
    EXPECT_EQ(help.exit_code, 0) << sub;
    EXPECT_NE(help.output.find(sub), std::string::npos) << help.output;
  }
}

}  // namespace
}  // namespace btf::test
