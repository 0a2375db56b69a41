// btf sample (chi-square picture of one sampler at one wo) and btf bench sampling --quick.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "btf/io/image.h"
#include "cli_test_support.h"

namespace btf::test {
namespace {

// One small table shared by the tests of this file (datagen takes a moment).
const std::filesystem::path& plasticTable() {
  static TempDir dir;
  static const std::filesystem::path table = [] {
    const auto path = dir / "plastic-red.binary";
    const CommandResult r = runDatagen({"--preset", "plastic-red", "--clean", "-o", path.string()});
    if (r.exit_code != 0) throw std::runtime_error(r.output);
    return path;
  }();
  return table;
}

TEST(Sample, CorrectSamplerPassesTheChiSquareTestAndWritesThePicture) {
  TempDir dir;
  const auto png = dir / "dp.png";
  // A correct sampler passes at alpha = 0.01 with N = 50000 draws; seed fixed, so the result is
  // reproducible (p-values of a correct sampler are uniform, so 1 seed in 100 would fail).
  const CommandResult r = runBtf({"sample", plasticTable().string(), "--theta-o", "40", "--sampler", "dp-cdf",
                                  "-n", "50000", "--seed", "3", "-o", png.string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = parseJsonOutput(r);
  EXPECT_GE(j["chi2_p"].get<double>(), 0.01) << r.output;
  EXPECT_TRUE(j["accepted"].get<bool>());
  EXPECT_EQ(j["alpha"].get<double>(), 0.01);
  EXPECT_GT(j["chi2_dof"].get<int>(), 10);
  EXPECT_GT(j["samples_per_s"].get<double>(), 0.0);
  const Image image = readImage(png);
  EXPECT_GT(image.width, 2 * image.height) << "three panels side by side";
  EXPECT_EQ(filesIn(dir.path()).size(), 1u) << "the PNG only, no temporary files";
}

TEST(Sample, OctreeBoundSamplesAnOctreeAndRefusesOtherTables) {
  TempDir dir;
  const auto octree = dir / "plastic.octree";
  CommandResult r = runBtf({"convert", plasticTable().string(), octree.string(), "--tolerance", "0.02"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // alpha = 0.01, N = 50,000 draws, seed fixed.
  r = runBtf({"sample", octree.string(), "--theta-o", "55", "--sampler", "octree-bound", "-n", "50000", "--seed", "2",
              "-o", (dir / "o.png").string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(parseJsonOutput(r)["accepted"].get<bool>()) << r.output;
  r = runBtf({"sample", plasticTable().string(), "--theta-o", "55", "--sampler", "octree-bound", "-o",
              (dir / "t.png").string()});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("octree-bound"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("not one"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "t.png"));
}

TEST(Sample, TextOutputNamesStatisticDofAndPValue) {
  TempDir dir;
  const CommandResult r = runBtf({"sample", plasticTable().string(), "--theta-o", "10", "--sampler", "cosine", "-n",
                                  "20000", "-o", (dir / "c.png").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("chi2 statistic"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("dof"), std::string::npos);
  EXPECT_NE(r.output.find("p-value"), std::string::npos);
  EXPECT_NE(r.output.find("samples/s"), std::string::npos);
}

TEST(Sample, RejectsBadSamplerMissingFileAndThetaOutOfRange) {
  TempDir dir;
  const auto png = (dir / "x.png").string();
  const std::string table = plasticTable().string();
  const CommandResult bad_sampler = runBtf({"sample", table, "--theta-o", "30", "--sampler", "magic", "-o", png});
  EXPECT_NE(bad_sampler.exit_code, 0);
  EXPECT_NE(bad_sampler.output.find("magic"), std::string::npos) << bad_sampler.output;
  EXPECT_NE(bad_sampler.output.find("dp-cdf"), std::string::npos) << "lists the known samplers";

  const CommandResult missing = runBtf({"sample", (dir / "none.binary").string(), "--theta-o", "30", "-o", png});
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.output.find("none.binary"), std::string::npos) << missing.output;

  for (const char* theta : {"90", "-5", "120"}) {
    const CommandResult r = runBtf({"sample", table, "--theta-o", theta, "-o", png});
    EXPECT_NE(r.exit_code, 0) << theta;
    EXPECT_NE(r.output.find("theta-o"), std::string::npos) << r.output;
  }
  EXPECT_TRUE(filesIn(dir.path()).empty()) << "no output on errors";
}

std::vector<std::vector<std::string>> readCsv(const std::filesystem::path& path) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::stringstream s(line);
    std::string f;
    while (std::getline(s, f, ',')) fields.push_back(f);
    if (!line.empty() && line.back() == ',') fields.emplace_back();
    rows.push_back(fields);
  }
  return rows;
}

TEST(BenchSampling, QuickRunWritesTheCsvWithEverySamplerAndCharts) {
  TempDir dir;
  const auto out = dir / "bench";
  const CommandResult r = runBtf({"bench", "sampling", "--quick", "-o", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto rows = readCsv(out / "sampling.csv");
  ASSERT_GE(rows.size(), 2u);
  const std::vector<std::string> columns = {"material", "sampler", "parameter", "bytes", "samples_per_s",
                                            "chi2_statistic", "chi2_p", "variance", "seconds", "efficiency",
                                            "rel_error_vs_reference", "per_sample_variance", "full_cdf_bytes",
                                            "acceptance_rate", "stream_samples_per_s", "theta_o_deg",
                                            "parameterization", "fcos_rel_variance", "efficiency_vs_own",
                                            "stream_efficiency_vs_own", "stream_with_eval_per_s",
                                            "ceiling_vs_own", "stream_ceiling_vs_own",
                                            "proportional_variance_vs_own", "eval_env_ns",
                                            "draw_budget_ns_2x", "ns_per_draw"};
  EXPECT_EQ(rows[0], columns);
  // DP-CDF against the warp at equal memory, per view.
  const auto warp = readCsv(out / "warp_comparison.csv");
  ASSERT_GE(warp.size(), 2u);
  EXPECT_EQ(warp[0][0], "material");
  EXPECT_EQ(warp[0][6], "efficiency_vs_warp");
  std::map<std::string, int> per_sampler, per_view;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].size(), columns.size()) << i;
    ++per_sampler[rows[i][1]];
    EXPECT_GT(std::stod(rows[i][4]), 0.0) << "samples_per_s of " << rows[i][1];
    EXPECT_GT(std::stod(rows[i][9]), 0.0) << "efficiency of " << rows[i][1];
  }
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const std::string& sampler = rows[i][1];
    // The reference is a quadrature of the same material: every unbiased sampler's estimate lies
    // near it (5000 draws; 20% is many standard errors for all but the uniform warp).
    if (sampler != "uniform") {
      EXPECT_LT(std::stod(rows[i][10]), 0.2) << "rel_error_vs_reference of " << sampler;
    }
    EXPECT_GT(std::stod(rows[i][11]), 0.0) << "per_sample_variance of " << sampler;
    const bool tables = sampler == "tabulated" || sampler == "dp-cdf" || sampler == "quadtree";
    EXPECT_EQ(rows[i][12].empty(), !tables) << "full_cdf_bytes of " << sampler;
    EXPECT_EQ(rows[i][13].empty(), sampler != "quadtree") << "acceptance_rate of " << sampler;
    // The Dupuy-Jakob warp has stream rates too (its draws one by one), and its bytes are the .bsdf's.
    const bool streams = tables || sampler == "dj-warp";
    EXPECT_EQ(rows[i][14].empty(), !streams) << "stream_samples_per_s of " << sampler;
    EXPECT_EQ(rows[i][20].empty(), !streams) << "stream_with_eval_per_s of " << sampler;
    if (sampler == "dj-warp") {
      EXPECT_GT(std::stod(rows[i][3]), 100000.0) << "bytes of dj-warp";
    }
    if (tables) {
      EXPECT_GT(std::stod(rows[i][14]), 0.0) << "stream_samples_per_s of " << sampler;
      EXPECT_TRUE(rows[i][16] == "incident" || rows[i][16] == "half") << "parameterization of " << sampler;
      EXPECT_GT(std::stod(rows[i][19]), 0.0) << "stream_efficiency_vs_own of " << sampler;
      EXPECT_GT(std::stod(rows[i][20]), 0.0) << "stream_with_eval_per_s of " << sampler;
    } else {
      EXPECT_TRUE(rows[i][16].empty()) << "parameterization of " << sampler;
    }
    // Every row is related to the own sampler's at its view (the own sampler's own ratio is 1).
    EXPECT_GT(std::stod(rows[i][18]), 0.0) << "efficiency_vs_own of " << sampler;
    if (sampler == "material") {
      EXPECT_DOUBLE_EQ(std::stod(rows[i][18]), 1.0);
      // The ceilings belong to the own sampler's rows alone.
      EXPECT_GT(std::stod(rows[i][21]), 0.0) << "ceiling_vs_own";
      EXPECT_GT(std::stod(rows[i][22]), 0.0) << "stream_ceiling_vs_own";
      EXPECT_GT(std::stod(rows[i][23]), 0.0) << "proportional_variance_vs_own";
      // The draw budget for twice the own efficiency follows from the ceiling and the eval's time:
      // a zero-cost draw reaches the ceiling, so the budget is eval_env_ns (ceiling / 2 - 1).
      const double eval_env_ns = std::stod(rows[i][24]), budget = std::stod(rows[i][25]);
      EXPECT_GT(eval_env_ns, 0.0) << "eval_env_ns";
      // (The CSV's 6 significant digits: a tolerance relative to the larger of the two terms.)
      EXPECT_NEAR(budget, eval_env_ns * (std::stod(rows[i][21]) / 2.0 - 1.0), 1e-4 * (std::abs(budget) + eval_env_ns))
          << "draw_budget_ns_2x";
    } else {
      EXPECT_TRUE(rows[i][21].empty() && rows[i][22].empty() && rows[i][23].empty() && rows[i][24].empty() &&
                  rows[i][25].empty())
          << "ceilings of " << sampler;
    }
    // ns_per_draw is the estimate's seconds over its draws, in ns: the same factor on every row.
    EXPECT_GT(std::stod(rows[i][26]), 0.0) << "ns_per_draw of " << sampler;
    EXPECT_NEAR(std::stod(rows[i][8]) / std::stod(rows[i][26]), std::stod(rows[1][8]) / std::stod(rows[1][26]),
                1e-4 * std::stod(rows[1][8]) / std::stod(rows[1][26]))
        << "seconds / ns_per_draw of " << sampler;
    EXPECT_GE(std::stod(rows[i][17]), 0.0) << "fcos_rel_variance of " << sampler;
    ++per_view[rows[i][15]];
    if (sampler == "quadtree") {
      EXPECT_GE(std::stod(rows[i][13]), 0.25) << "bilinear leaves accept at least a quarter";
      EXPECT_LE(std::stod(rows[i][13]), 1.0);
    }
  }
  for (const char* sampler : {"uniform", "cosine", "material", "tabulated", "dp-cdf", "quadtree"})
    EXPECT_GE(per_sampler[sampler], 1) << sampler;
  // The printed conclusions: the quadtree's standing against DP-CDF and the memory target.
  EXPECT_NE(r.output.find("Quadtree beats DP-CDF"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Quadtree loses to DP-CDF"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("DP-CDF memory target"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("(quadrature"), std::string::npos) << r.output;
  EXPECT_GE(per_sampler["dp-cdf"], 2) << "a sweep of epsilon";
  // The default views, each with the same rows.
  EXPECT_EQ(per_view.size(), 4u);
  for (const auto& [view, count] : per_view) EXPECT_EQ(count, per_view.begin()->second) << view;
  EXPECT_NE(r.output.find("Against the material's own sampler"), std::string::npos) << r.output;
  if (std::system("command -v gnuplot >/dev/null 2>&1") == 0) {
    for (const char* chart : {"sampling_memory_vs_error", "sampling_speed_vs_error", "sampling_efficiency"})
      for (const char* ext : {".png", ".svg"}) EXPECT_TRUE(std::filesystem::exists(out / (std::string(chart) + ext))) << chart << ext;
    // Per material with an own sampler: efficiency and variance against it over theta_o.
    std::set<std::string> efficiency, variance;
    for (const auto& f : filesIn(out)) {
      const std::string name = f.filename().string();
      if (name.rfind("sampling_vs_own_", 0) == 0 && f.extension() == ".png") efficiency.insert(name.substr(16));
      if (name.rfind("sampling_variance_vs_own_", 0) == 0 && f.extension() == ".png") variance.insert(name.substr(25));
    }
    EXPECT_FALSE(efficiency.empty());
    EXPECT_EQ(efficiency, variance);
  }
  for (const auto& f : filesIn(out)) EXPECT_EQ(f.string().find(".part"), std::string::npos) << f;
}

TEST(BenchSampling, UnknownMaterialIsAnError) {
  TempDir dir;
  const CommandResult r = runBtf({"bench", "sampling", "--quick", "--materials", "no-such-thing", "-o",
                                  (dir / "b").string()});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("no-such-thing"), std::string::npos) << r.output;
}

TEST(BenchSampling, SweepsTheGivenEpsilonsAndThresholdsAndRejectsBadOnes) {
  TempDir dir;
  const auto out = dir / "b";
  const CommandResult r = runBtf({"bench", "sampling", "--quick", "--epsilons", "0.02,0.005", "--thresholds", "3",
                                  "--theta-o", "30", "--parameterizations", "half", "-o", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::vector<double> epsilons, thresholds;
  for (const auto& row : readCsv(out / "sampling.csv")) {
    if (row.size() > 2 && row[1] == "dp-cdf") epsilons.push_back(std::stod(row[2]));
    if (row.size() > 2 && row[1] == "quadtree") thresholds.push_back(std::stod(row[2]));
  }
  EXPECT_EQ(epsilons, (std::vector<double>{0.02, 0.005}));
  EXPECT_EQ(thresholds, (std::vector<double>{3.0}));
  for (const auto& row : readCsv(out / "sampling.csv"))
    if (row.size() > 16 && (row[1] == "dp-cdf" || row[1] == "quadtree" || row[1] == "tabulated")) {
      EXPECT_EQ(row[16], "half");
    }
  for (const char* bad : {"--epsilons=-0.1", "--thresholds=0.5", "--theta-o=95", "--parameterizations=diagonal"}) {
    const CommandResult e = runBtf({"bench", "sampling", "--quick", bad, "-o", (dir / "c").string()});
    EXPECT_NE(e.exit_code, 0) << bad;
    const std::string option(bad, std::string(bad).find('='));  // the message names the option
    EXPECT_NE(e.output.find(option), std::string::npos) << e.output;
  }
}

TEST(BenchSampling, MeasuresOnlyTheNamedTableSamplersAtTheGivenGrid) {
  TempDir dir;
  // The tabulated half-vector table at two grids: its bytes grow with the square of the half-vector
  // bins, so twice the bins must give about four times the bytes.
  std::vector<double> bytes;
  for (const char* bins : {"16", "32"}) {
    const auto out = dir / (std::string("g") + bins);
    const CommandResult r = runBtf({"bench", "sampling", "--quick", "--samplers", "tabulated", "--theta-o", "30",
                                    "--parameterizations", "half", "--theta-o-bins", "4", "--half-vector-bins", bins,
                                    "-o", out.string()});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    std::set<std::string> samplers;
    const auto rows = readCsv(out / "sampling.csv");
    for (std::size_t i = 1; i < rows.size(); ++i) {
      samplers.insert(rows[i][1]);
      if (rows[i][1] == "tabulated") bytes.push_back(std::stod(rows[i][3]));
    }
    EXPECT_EQ(samplers, (std::set<std::string>{"uniform", "cosine", "material", "tabulated"}));
  }
  ASSERT_EQ(bytes.size(), 2u);
  EXPECT_GT(bytes[1] / bytes[0], 3.0);
  EXPECT_LT(bytes[1] / bytes[0], 5.0);
  for (const char* bad : {"--samplers=uniform", "--samplers=octree", "--theta-o-bins=-1", "--half-vector-bins=1",
                          "--half-vector-bins=5000"}) {
    const CommandResult e = runBtf({"bench", "sampling", "--quick", bad, "-o", (dir / "c").string()});
    EXPECT_NE(e.exit_code, 0) << bad;
    const std::string option(bad, std::string(bad).find('='));
    EXPECT_NE(e.output.find(option), std::string::npos) << e.output;
  }
}

}  // namespace
}  // namespace btf::test
