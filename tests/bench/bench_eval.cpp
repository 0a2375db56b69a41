// Evaluations per second per core of the reflectance lookups that later compressed formats are
// compared against: a MERL table (nearest and interpolated lookup), the same table as an octree
// (lossless and at tolerance 0.02: point location in a tree instead of an array index; the counter
// "bytes" is the tree's size in memory against the array's 34,992,000) and a one-lobe Lafortune
// model. Single-threaded. Direction pairs are drawn before timing, so the loops time eval only.
//
// The Lafortune parameters are the published one-lobe fit of MERL's gold-paint (Ngan et al. 2005),
// read from BTF_SHARED_DATA_DIR/fits/lafortune1_ngan2005_merl.csv; without that file the benchmark
// falls back to literal parameters and labels its output "literal-fallback". The MERL table is
// that model tabulated, so all three benchmarks evaluate the same BRDF.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "btf/compress/octree_table.h"
#include "btf/core/half_diff.h"
#include "btf/core/rng.h"
#include "btf/material/lafortune.h"
#include "btf/material/octree_brdf.h"
#include "btf/material/tabulated_brdf.h"
#include "btf/core/warp.h"

namespace {

struct LafortuneFit {
  btf::Rgb rho_d, rho_s;
  float c_xy, c_z, exponent;
  std::string source;
};

// Columns: index,material,rho_d_r,rho_d_g,rho_d_b,rho_s_r,rho_s_g,rho_s_b,Cxy,Cz,n
std::optional<LafortuneFit> readPublishedFit(const std::filesystem::path& csv, const std::string& material) {
  std::ifstream in(csv);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::stringstream row(line);
    for (std::string field; std::getline(row, field, ',');) fields.push_back(field);
    if (fields.size() != 11 || fields[1] != material) continue;
    auto num = [&](int i) { return std::stof(fields[i]); };
    return LafortuneFit{{num(2), num(3), num(4)}, {num(5), num(6), num(7)}, num(8), num(9), num(10),
                        material + " (Ngan 2005)"};
  }
  return std::nullopt;
}

LafortuneFit benchmarkFit() {
#ifdef BTF_SHARED_DATA_DIR
  if (auto fit = readPublishedFit(std::filesystem::path(BTF_SHARED_DATA_DIR) / "fits/lafortune1_ngan2005_merl.csv",
                                  "gold-paint"))
    return *fit;
#endif
  // Not a published fit: a plain glossy lobe of similar width, so the timings stay comparable.
  return {btf::Rgb(0.2f), btf::Rgb(0.2f), -0.6f, 0.55f, 15.0f, "literal-fallback"};
}

struct Fixture {
  LafortuneFit fit = benchmarkFit();
  btf::Lafortune lafortune{fit.rho_d, {btf::LafortuneLobe{fit.rho_s, {fit.c_xy, fit.c_xy, fit.c_z}, fit.exponent}}};
  std::shared_ptr<const btf::MerlTable> table = std::make_shared<btf::MerlTable>(btf::tabulate(lafortune));
  btf::TabulatedBrdf nearest{table, btf::TableLookup::Nearest};
  btf::TabulatedBrdf interpolated{table, btf::TableLookup::Interpolated};
  std::shared_ptr<const btf::OctreeTable> lossless = std::make_shared<btf::OctreeTable>(btf::OctreeTable::build(*table, 0.0));
  std::shared_ptr<const btf::OctreeTable> lossy = std::make_shared<btf::OctreeTable>(btf::OctreeTable::build(*table, 0.02));
  // 2^16 pairs (1.5 MB): enough that table accesses are spread like a renderer's, few enough to
  // stay in cache themselves. Uniform over the hemisphere, independent wi and wo.
  std::vector<btf::DirectionPair> pairs;

  Fixture() {
    btf::Rng rng(20240601);
    pairs.resize(1 << 16);
    for (auto& p : pairs) {
      p.wi = btf::squareToUniformHemisphere(rng.uniform2D());
      p.wo = btf::squareToUniformHemisphere(rng.uniform2D());
    }
  }
};

const Fixture& fixture() {
  static const Fixture f;
  return f;
}

void runEval(benchmark::State& state, const btf::Material& material) {
  const auto& pairs = fixture().pairs;
  const std::size_t mask = pairs.size() - 1;
  std::size_t i = 0;
  for (auto _ : state) {
    const btf::DirectionPair& p = pairs[i++ & mask];
    benchmark::DoNotOptimize(material.eval(p.wi, p.wo));
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()));
  state.SetLabel(fixture().fit.source);
}

void BM_EvalMerlNearest(benchmark::State& state) { runEval(state, fixture().nearest); }
void BM_EvalMerlInterpolated(benchmark::State& state) { runEval(state, fixture().interpolated); }
void BM_EvalLafortune1(benchmark::State& state) { runEval(state, fixture().lafortune); }
void BM_EvalOctree(benchmark::State& state, bool lossy, btf::TableLookup lookup) {
  const auto& octree = lossy ? fixture().lossy : fixture().lossless;
  runEval(state, btf::OctreeBrdf(octree, lookup));
  state.counters["bytes"] = double(octree->bytes());
}

BENCHMARK(BM_EvalMerlNearest);
BENCHMARK(BM_EvalMerlInterpolated);
BENCHMARK(BM_EvalLafortune1);
BENCHMARK_CAPTURE(BM_EvalOctree, lossless_nearest, false, btf::TableLookup::Nearest);
BENCHMARK_CAPTURE(BM_EvalOctree, lossless_interpolated, false, btf::TableLookup::Interpolated);
BENCHMARK_CAPTURE(BM_EvalOctree, tolerance_0.02_interpolated, true, btf::TableLookup::Interpolated);

}  // namespace

BENCHMARK_MAIN();
