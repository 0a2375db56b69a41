// `btf bench compressibility`: a tiny run writes the CSV with one row per (pattern, epsilon) whose
// figures are self-consistent, the chart data (.dat) agreeing with the CSV and the charts when
// gnuplot is installed, and bad options fail with a message naming the problem.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
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

// A .dat file of the command: one block per pattern, opened by "# pattern NAME ...", rows of two
// numbers, blocks separated by blank lines.
struct DatBlock {
  std::string pattern;
  std::vector<std::pair<double, double>> rows;
};

std::vector<DatBlock> readDat(const fs::path& path) {
  std::vector<DatBlock> blocks;
  std::stringstream in(readBytes(path));
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (line.starts_with("# pattern ")) {
      std::stringstream words(line.substr(10));
      blocks.emplace_back();
      words >> blocks.back().pattern;
      continue;
    }
    EXPECT_FALSE(blocks.empty()) << "a row before the first block header: " << line;
    if (blocks.empty()) return blocks;
    std::stringstream numbers(line);
    double a = 0, b = 0;
    std::string rest;
    EXPECT_TRUE(numbers >> a >> b) << line;
    EXPECT_FALSE(numbers >> rest) << "more than two columns: " << line;
    blocks.back().rows.emplace_back(a, b);
  }
  return blocks;
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

  // Nearest-texel CDF: every texel once per pattern, ascending in [0, 1], fraction (i + 1) / 64, and
  // the CSV's median is the midpoint of the two middle order statistics (h = 63 / 2).
  const std::vector<DatBlock> nearest = readDat(out / "compressibility_nearest.dat");
  ASSERT_EQ(nearest.size(), 2u);
  for (std::size_t b = 0; b < nearest.size(); ++b) {
    const DatBlock& block = nearest[b];
    EXPECT_EQ(block.pattern, rows[2 * b][0]);
    ASSERT_EQ(block.rows.size(), 64u) << block.pattern;
    for (std::size_t i = 0; i < block.rows.size(); ++i) {
      EXPECT_GE(block.rows[i].first, 0.0) << block.pattern << " row " << i;
      EXPECT_LE(block.rows[i].first, 1.0) << block.pattern << " row " << i;
      if (i) {
        EXPECT_LE(block.rows[i - 1].first, block.rows[i].first) << block.pattern << " row " << i;
      }
      EXPECT_NEAR(block.rows[i].second, (i + 1) / 64.0, 1e-5) << block.pattern << " row " << i;
    }
    const double median = (block.rows[31].first + block.rows[32].first) / 2;
    EXPECT_NEAR(median, std::stod(rows[2 * b][column("nn_p50")]), 1e-4) << block.pattern;
  }
  // Rank error curve: k = 0..min(64, 256), tail 1 at k = 0, non-increasing, 0 at full rank, and it
  // first drops to each epsilon at the CSV's rank (6 printed digits: compared with a margin).
  const std::vector<DatBlock> rank = readDat(out / "compressibility_rank.dat");
  ASSERT_EQ(rank.size(), 2u);
  for (std::size_t b = 0; b < rank.size(); ++b) {
    const DatBlock& block = rank[b];
    EXPECT_EQ(block.pattern, rows[2 * b][0]);
    ASSERT_EQ(block.rows.size(), 65u) << block.pattern;
    EXPECT_NEAR(block.rows.front().second, 1.0, 1e-6) << block.pattern;
    EXPECT_NEAR(block.rows.back().second, 0.0, 1e-4) << block.pattern;
    for (std::size_t k = 0; k < block.rows.size(); ++k) {
      EXPECT_EQ(block.rows[k].first, double(k)) << block.pattern;
      if (k) {
        EXPECT_LE(block.rows[k].second, block.rows[k - 1].second * (1 + 1e-5)) << block.pattern << " k " << k;
      }
    }
    for (std::size_t e = 0; e < 2; ++e) {
      const std::vector<std::string>& row = rows[2 * b + e];
      const double epsilon = std::stod(row[column("epsilon")]);
      const std::size_t k = std::stoul(row[column("rank")]);
      ASSERT_TRUE(k >= 1 && k < block.rows.size()) << k;
      EXPECT_LE(block.rows[k].second, epsilon * (1 + 1e-5)) << block.pattern << " epsilon " << epsilon;
      EXPECT_GT(block.rows[k - 1].second, epsilon * (1 - 1e-5)) << block.pattern << " epsilon " << epsilon;
      EXPECT_NEAR(block.rows[k].second, std::stod(row[column("rank_rel_error")]), 1e-4) << block.pattern;
    }
  }
  EXPECT_THAT(r.output, HasSubstr("compressibility_nearest.dat"));
  EXPECT_THAT(r.output, HasSubstr("compressibility_rank.dat"));
  if (std::system("command -v gnuplot >/dev/null 2>&1") == 0) {
    for (const char* chart : {"compressibility_nearest", "compressibility_rank"}) {
      const std::string png = readBytes(out / (std::string(chart) + ".png"));
      EXPECT_TRUE(png.starts_with("\x89PNG")) << chart;
      EXPECT_THAT(readBytes(out / (std::string(chart) + ".svg")), HasSubstr("<svg")) << chart;
      EXPECT_THAT(r.output, HasSubstr(std::string(chart) + ".png")) << "listed in the wrote line";
    }
  } else {
    EXPECT_THAT(r.output, HasSubstr("gnuplot not found"));
  }
  for (const fs::path& f : filesIn(out)) EXPECT_EQ(f.string().find(".part"), std::string::npos) << f;
}

// A measured one-view slice beside a synthetic pattern cut to the same view: both analysed on
// their 81 (view, light) pairs, a centred window of --size texels.
TEST(BenchCompressibility, AMeasuredSliceIsAnalysedBesideAPatternAtTheSameView) {
  const fs::path slice = sharedDataDir() / "btf" / "ubo2003_wallpaper_view000";
  ASSERT_TRUE(fs::is_directory(slice)) << slice << " is missing (../shared/data/real must sit beside the checkout)";
  TempDir dir;
  const CommandResult r = runBtf({"bench", "compressibility", "-o", (dir / "out").string(), "--patterns", "fabric",
                                  "--inputs", slice.string(), "--size", "12", "--max-view-theta", "0",
                                  "--directions", "0", "--epsilons", "0.05"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("1 view (theta 0, phi 0)"));
  std::stringstream csv(readBytes(dir / "out" / "compressibility.csv"));
  std::string line;
  std::getline(csv, line);  // header
  std::vector<std::vector<std::string>> rows;
  while (std::getline(csv, line)) rows.push_back(splitCsvLine(line));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0][0], "fabric");
  EXPECT_EQ(rows[1][0], "ubo2003_wallpaper_view000");
  for (const auto& row : rows) {
    EXPECT_EQ(row[2], "144") << "12 x 12 texels";
    EXPECT_EQ(row[3], "81") << "the 81 lights of the one view";
  }
}

// A camera in front of a pattern (noise, jitter, 8-bit codes) takes its near-twins away: the
// median nearest-texel distance grows.
TEST(BenchCompressibility, ACameraInFrontOfAPatternSeparatesItsTexels) {
  TempDir dir;
  auto median = [&](const std::vector<std::string>& extra) {
    std::vector<std::string> args{"bench", "compressibility", "-o", (dir / "out").string(), "--patterns", "fabric",
                                  "--size", "12", "--max-view-theta", "0", "--directions", "0", "--epsilons", "0.05"};
    args.insert(args.end(), extra.begin(), extra.end());
    const CommandResult r = runBtf(args);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    std::stringstream csv(readBytes(dir / "out" / "compressibility.csv"));
    std::string line;
    std::getline(csv, line);
    std::getline(csv, line);
    const std::vector<std::string> row = splitCsvLine(line);
    EXPECT_EQ(row[0], extra.empty() ? "fabric" : "fabric (camera)");
    return std::stod(row[6]);  // nn_p50
  };
  const double clean = median({});
  const double seen = median({"--camera-white", "1", "--camera-jitter", "0.5", "--camera-read-noise", "0.01"});
  EXPECT_GT(seen, 1.5 * clean);
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
      {{"--size", "4", "--patterns", ""}, "no --patterns and no --inputs"},
      {{"--size", "4", "--inputs", (dir / "absent").string()}, "absent"},
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
