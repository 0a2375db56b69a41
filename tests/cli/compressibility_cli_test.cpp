// `btf bench compressibility`: a tiny run writes the CSV with one row per (pattern, epsilon) whose
// figures are self-consistent, and bad options fail with a message naming the problem.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "cli_test_support.h"

namespace btf::test {
namespace {
using testing::HasSubstr;
namespace fs = std::filesystem;

std::vector<std::string> splitCsvLine(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  std::string cell;
  while (std::getline(in, cell, ',')) cells.push_back(cell);
  return cells;
}

TEST(BenchCompressibility, TinyRunWritesOneRowPerPatternAndEpsilon) {
  TempDir dir;
  const fs::path out = dir / "bench";
  const CommandResult r = runBtf({"bench", "compressibility", "--patterns", "fabric,stones", "--size", "8",
                                  "--directions", "256", "--epsilons", "0.05,0.5", "-o", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::stringstream csv(readBytes(out / "compressibility.csv"));
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  const std::vector<std::string> header = splitCsvLine(line);
  const std::vector<std::string> expected{"pattern", "size", "texels", "directions", "nn_p10", "nn_p25", "nn_p50",
                                          "nn_p75", "nn_p90", "nn_max", "nn_rel_error", "epsilon", "greedy_entries",
                                          "greedy_rel_error", "reuse_factor", "rank", "rank_rel_error",
                                          "ratio_u8_bound", "seconds"};
  ASSERT_EQ(header, expected);
  auto column = [&](const std::string& name) {
    return std::size_t(std::find(header.begin(), header.end(), name) - header.begin());
  };
  std::vector<std::vector<std::string>> rows;
  while (std::getline(csv, line)) rows.push_back(splitCsvLine(line));
  ASSERT_EQ(rows.size(), 4u);
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), header.size()) << line;
    EXPECT_EQ(row[column("texels")], "64");
    EXPECT_EQ(row[column("directions")], "256");
    const double p10 = std::stod(row[column("nn_p10")]), p90 = std::stod(row[column("nn_p90")]);
    EXPECT_LE(p10, p90);
    EXPECT_LE(p90, 1.0);
    const int entries = std::stoi(row[column("greedy_entries")]), rank = std::stoi(row[column("rank")]);
    EXPECT_GE(entries, 1);
    EXPECT_LE(entries, 64);
    EXPECT_NEAR(std::stod(row[column("reuse_factor")]), 64.0 / entries, 1e-3 * 64.0 / entries);
    EXPECT_LE(std::stod(row[column("rank_rel_error")]), std::stod(row[column("epsilon")]));
    EXPECT_GE(rank, 1);
    EXPECT_LE(rank, 64);
    // ratio_u8_bound = T * 6561 * 3 / (2 k (T + 6561)), recomputed here.
    const double bound = 64.0 * 6561 * 3 / (2.0 * rank * (64 + 6561));
    EXPECT_NEAR(std::stod(row[column("ratio_u8_bound")]), bound, 1e-4 * bound);
  }
  EXPECT_EQ(rows[0][0], "fabric");
  EXPECT_EQ(rows[2][0], "stones");
  // A looser tolerance never needs more entries or rank.
  EXPECT_LE(std::stoi(rows[1][column("greedy_entries")]), std::stoi(rows[0][column("greedy_entries")]));
  EXPECT_LE(std::stoi(rows[1][column("rank")]), std::stoi(rows[0][column("rank")]));
  EXPECT_THAT(r.output, HasSubstr("greedy_entries"));
  EXPECT_THAT(r.output, HasSubstr("compressibility.csv"));
}

TEST(BenchCompressibility, BadOptionsFailNamingTheProblem) {
  TempDir dir;
  struct Case {
    std::vector<std::string> args;
    std::string problem;
  };
  const std::vector<Case> cases{
      {{"--size", "4", "--patterns", "velvet"}, "velvet"},
      {{"--size", "4", "--epsilons", "0.02,1.5"}, "(0, 1)"},
      {{"--size", "200"}, "--size"},
      {{"--size", "4", "--directions", "-3"}, "--directions"},
  };
  for (const Case& k : cases) {
    std::vector<std::string> args{"bench", "compressibility", "-o", (dir / "out").string()};
    args.insert(args.end(), k.args.begin(), k.args.end());
    const CommandResult r = runBtf(args);
    EXPECT_NE(r.exit_code, 0) << k.args[0];
    EXPECT_LT(r.exit_code, 128) << "no crash: " << r.output;
    EXPECT_THAT(r.output, HasSubstr(k.problem)) << r.output;
    EXPECT_FALSE(fs::exists(dir / "out" / "compressibility.csv")) << k.args[0];
  }
}

}  // namespace
}  // namespace btf::test
