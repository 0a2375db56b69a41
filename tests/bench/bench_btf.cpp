// BtfMaterial speed (single-threaded): eval straight from a VqBtf (bilinear and nearest texel) and
// from the in-memory data, beside a one-lobe Lafortune eval in the same run (the target is
// >= 2x Lafortune's rate), and sampling by twofold binary search (target >= 5 M samples/s).
// The BTF: the 16 x 16-texel GGX pattern of the unit tests (tests/unit/btf_test_data.h), compressed
// with levels = 3, epsilon = 0.02. Directions, uv and random numbers are drawn before timing.
#include <benchmark/benchmark.h>

#include <memory>
#include <span>
#include <vector>

#include "../unit/btf_test_data.h"
#include "btf/compress/vq_btf.h"
#include "btf/core/rng.h"
#include "btf/material/btf_material.h"
#include "btf/material/lafortune.h"
#include "btf/sampling/warp.h"

namespace {

struct BtfBenchFixture {
  std::shared_ptr<const btf::BtfData> data =
      std::make_shared<const btf::BtfData>(btf::test::makeGgxBtf(16, 16, false));
  std::shared_ptr<const btf::VqBtf> vq = std::make_shared<const btf::VqBtf>(btf::compressVq(*data, {}));
  btf::BtfMaterial vq_bilinear{vq, btf::BtfTexelFilter::Bilinear};
  btf::BtfMaterial vq_nearest{vq, btf::BtfTexelFilter::Nearest};
  btf::BtfMaterial data_nearest{data, btf::BtfTexelFilter::Nearest};
  // The literal one-lobe fit of bench_eval.cpp's fallback (a glossy lobe, exponent 15).
  btf::Lafortune lafortune{btf::Rgb(0.2f), {btf::LafortuneLobe{btf::Rgb(0.2f), {-0.6f, -0.6f, 0.55f}, 15.0f}}};
  struct Query {
    glm::vec3 wi, wo;
    glm::vec2 uv, u;
  };
  std::vector<Query> queries;

  BtfBenchFixture() {
    btf::Rng rng(77);
    queries.resize(1 << 16);
    for (auto& q : queries) {
      q.wi = btf::squareToUniformHemisphere(rng.uniform2D());
      q.wo = btf::squareToUniformHemisphere(rng.uniform2D());
      q.uv = rng.uniform2D();
      q.u = rng.uniform2D();
    }
  }
};

const BtfBenchFixture& btfFixture() {
  static const BtfBenchFixture f;
  return f;
}

// One call per query of the fixture, in order; items = queries.
template <class Call>
void runQueries(benchmark::State& state, Call call) {
  const auto& queries = btfFixture().queries;
  const std::size_t mask = queries.size() - 1;
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(call(queries[i++ & mask]));
  state.SetItemsProcessed(std::int64_t(state.iterations()));
}

void runBtfEval(benchmark::State& state, const btf::Material& material) {
  runQueries(state, [&](const BtfBenchFixture::Query& q) { return material.eval(q.wi, q.wo, q.uv); });
}

void runBtfSample(benchmark::State& state, const btf::Material& material) {
  runQueries(state, [&](const BtfBenchFixture::Query& q) { return material.sample(q.wo, q.uv, q.u); });
}

void BM_BtfEvalLafortune1(benchmark::State& state) { runBtfEval(state, btfFixture().lafortune); }
void BM_BtfEvalVqBilinear(benchmark::State& state) { runBtfEval(state, btfFixture().vq_bilinear); }
void BM_BtfEvalVqNearest(benchmark::State& state) { runBtfEval(state, btfFixture().vq_nearest); }
void BM_BtfEvalDataNearest(benchmark::State& state) { runBtfEval(state, btfFixture().data_nearest); }
void BM_BtfSampleVq(benchmark::State& state) { runBtfSample(state, btfFixture().vq_nearest); }
// The direction and its pdf alone (no eval for the weight): the twofold search's own cost.
void BM_BtfSampleDirectionVq(benchmark::State& state) {
  const btf::BtfMaterial& m = btfFixture().vq_nearest;
  runQueries(state, [&](const BtfBenchFixture::Query& q) { return m.sampleDirection(q.wo, q.uv, q.u); });
}
void BM_BtfSampleData(benchmark::State& state) { runBtfSample(state, btfFixture().data_nearest); }
void BM_BtfSampleLafortune1(benchmark::State& state) { runBtfSample(state, btfFixture().lafortune); }

// Decoding one measured sample (texel, view, light) from the codebooks: no direction mapping and
// no interpolation, the random access that decompression-based renderers make.
void BM_BtfDecodeVqValue(benchmark::State& state) {
  const btf::VqBtf& vq = *btfFixture().vq;
  runQueries(state, [&](const BtfBenchFixture::Query& q) {
    return vq.value(int(q.uv.x * 16.0f), int(q.uv.y * 16.0f), int(q.u.x * float(btf::kBtfDirectionCount)),
                    int(q.u.y * float(btf::kBtfDirectionCount)));
  });
}

// The same samples through the stream call (VqBtf::values, AVX2 lanes), blocks of 256.
void BM_BtfDecodeVqStream(benchmark::State& state) {
  const btf::VqBtf& vq = *btfFixture().vq;
  const auto& queries = btfFixture().queries;
  std::vector<btf::BtfSampleIndex> samples(queries.size());
  for (std::size_t k = 0; k < queries.size(); ++k) {
    const auto& q = queries[k];
    samples[k] = {int(q.uv.x * 16.0f), int(q.uv.y * 16.0f), int(q.u.x * float(btf::kBtfDirectionCount)),
                  int(q.u.y * float(btf::kBtfDirectionCount))};
  }
  constexpr std::size_t kBlock = 256;
  std::vector<btf::Rgb> out(kBlock);
  std::size_t i = 0;
  for (auto _ : state) {
    vq.values(std::span(samples.data() + i, kBlock), out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
    i = (i + kBlock) & (samples.size() - 1);
  }
  state.SetItemsProcessed(std::int64_t(state.iterations() * kBlock));
}

BENCHMARK(BM_BtfEvalLafortune1);
BENCHMARK(BM_BtfDecodeVqValue);
BENCHMARK(BM_BtfDecodeVqStream);
BENCHMARK(BM_BtfEvalVqBilinear);
BENCHMARK(BM_BtfEvalVqNearest);
BENCHMARK(BM_BtfEvalDataNearest);
BENCHMARK(BM_BtfSampleVq);
BENCHMARK(BM_BtfSampleDirectionVq);
BENCHMARK(BM_BtfSampleData);
BENCHMARK(BM_BtfSampleLafortune1);

}  // namespace
