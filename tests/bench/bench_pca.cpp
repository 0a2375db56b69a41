// The per-view PCA baseline (compress/pca.h) on a 32 x 32 analytic BTF (GGX over Lambert, albedo
// and roughness varying per texel; tests/unit/synthetic_btf_data.h): compression time per k, with
// rel_rmse, psnr_db and ratio_u8 as counters, and single-entry decode rate.
#include <benchmark/benchmark.h>

#include <vector>

#include "../unit/synthetic_btf_data.h"
#include "btf/compress/pca.h"
#include "btf/core/rng.h"

namespace {

const btf::BtfData& btf32() {
  static const btf::BtfData data = btf::test::makeAnalyticBtf(32, 32, true, "analytic-32");
  return data;
}

void BM_PcaCompress(benchmark::State& state) {
  const btf::BtfData& data = btf32();
  const int k = int(state.range(0));
  const auto precision = state.range(1) == 0 ? btf::PcaPrecision::Half : btf::PcaPrecision::Float;
  std::uint64_t bytes = 0;
  for (auto _ : state) {
    const btf::PcaBtf pca = btf::compressPca(data, k, precision);
    bytes = pca.storedBytes();
    benchmark::DoNotOptimize(bytes);
  }
  const btf::PcaBtf pca = btf::compressPca(data, k, precision);
  const btf::BtfErrorStats error = btf::compareBtf(data, pca);
  state.counters["rel_rmse"] = error.rel_rmse;
  state.counters["psnr_db"] = error.psnr_db;
  state.counters["ratio_u8"] = double(data.entryCount() * 3) / double(bytes);
  state.counters["explained"] = pca.explainedVariance();
}
BENCHMARK(BM_PcaCompress)
    ->ArgsProduct({{0, 1, 2, 4, 8, 16, 32}, {0}})
    ->Args({8, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_PcaValue(benchmark::State& state) {
  const btf::PcaBtf pca = btf::compressPca(btf32(), int(state.range(0)));
  struct Entry {
    int x, y, view, light;
  };
  btf::Rng rng(3);
  std::vector<Entry> entries(4096);
  for (auto& e : entries)
    e = {int(rng.uniformInt(32)), int(rng.uniformInt(32)), int(rng.uniformInt(81)), int(rng.uniformInt(81))};
  std::size_t i = 0;
  for (auto _ : state) {
    const Entry& e = entries[i++ & 4095];
    benchmark::DoNotOptimize(pca.value(e.x, e.y, e.view, e.light));
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()));
}
BENCHMARK(BM_PcaValue)->Arg(4)->Arg(16);

}  // namespace
