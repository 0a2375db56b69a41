// Time to render one view of a 256 x 256 synthetic BTF (81 lights, i.e. 5.3 million entries with a
// view ray and 81 shadow rays per texel): what streaming a generated BTF into a compressor costs.
// Stones at views of theta 0, 45 and 75 degrees (longer rays at grazing angles), the other patterns
// at 45 degrees. Uses all threads.
#include <benchmark/benchmark.h>

#include <memory>
#include <vector>

#include "btf_patterns.h"

namespace {

void BM_SyntheticBtfView256(benchmark::State& state) {
  const auto pattern = btf::synthetic::BtfPattern(state.range(0));
  const int view = int(state.range(1));
  const auto btf = btf::synthetic::makeSyntheticBtf(pattern, 256, 256, 1);
  std::vector<btf::Rgb> values;
  for (auto _ : state) {
    btf->loadView(view, values);
    benchmark::DoNotOptimize(values.data());
  }
  state.SetLabel(btf::synthetic::btfPatternName(pattern) + " view theta " +
                 std::to_string(int(btf::btfDirections()[std::size_t(view)].theta_deg)));
  state.counters["entries_per_s"] =
      benchmark::Counter(double(values.size()) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_SyntheticBtfView256)
    ->Args({1, 0})
    ->Args({1, btf::btfDirectionIndex(3, 0)})
    ->Args({1, btf::btfDirectionIndex(5, 0)})
    ->Args({0, btf::btfDirectionIndex(3, 0)})
    ->Args({2, btf::btfDirectionIndex(3, 0)})
    ->Args({3, btf::btfDirectionIndex(3, 0)})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Building the 256 x 256 microgeometry (height field and material map, 1024 x 1024 samples).
void BM_SyntheticMicrogeometry256(benchmark::State& state) {
  const auto pattern = btf::synthetic::BtfPattern(state.range(0));
  for (auto _ : state) {
    auto g = btf::synthetic::makePatternMicrogeometry(pattern, 256, 256, 1);
    benchmark::DoNotOptimize(g.heights.data());
  }
  state.SetLabel(btf::synthetic::btfPatternName(pattern));
}
BENCHMARK(BM_SyntheticMicrogeometry256)->DenseRange(0, 3)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
