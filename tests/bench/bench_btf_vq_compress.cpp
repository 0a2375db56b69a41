// Multi-level VQ compression time (compress/vq_btf.h) of a synthetic fabric BTF, 16 x 16 texels,
// epsilon 0.02, 3 levels, all threads; the BTF is rendered into memory before timing. Counters:
// texels per second, ratio_u8 and the level-1 codebook size. Compression time grows about linearly
// with the texel count; larger sizes take minutes, so they are measured with the CLI instead:
//   btf-datagen btf --pattern fabric --size 128 --seed 1 --format png16 -o DIR
//   btf compress DIR out.btfz --epsilon 0.02 --json
#include <benchmark/benchmark.h>

#include <memory>

#include "btf/compress/vq_btf.h"
#include "btf_patterns.h"

namespace {

void BM_VqCompressSyntheticFabric(benchmark::State& state) {
  const int size = int(state.range(0));
  const auto generated = btf::synthetic::makeSyntheticBtf(btf::synthetic::BtfPattern::Fabric, size, size, 1);
  const btf::BtfData data = btf::BtfData::copyOf(*generated);
  btf::VqOptions options;
  options.epsilon = 0.02f;
  options.levels = 3;
  btf::VqStats stats;
  for (auto _ : state) {
    const btf::VqBtf vq = btf::compressVq(data, options);
    stats = vq.stats();
    benchmark::DoNotOptimize(stats.compressed_bytes);
  }
  state.counters["texels_per_s"] =
      benchmark::Counter(double(size) * size * double(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["ratio_u8"] = stats.ratio_u8;
  state.counters["level1_entries"] = double(stats.codebook_entries.empty() ? 0 : stats.codebook_entries[0]);
}
BENCHMARK(BM_VqCompressSyntheticFabric)->Arg(16)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
