// BtfMaterial speed (single-threaded): eval straight from a VqBtf (bilinear and nearest texel) and
// from the in-memory data, beside a one-lobe Lafortune eval in the same run (the project's target is
// >= 2x Lafortune's rate), and sampling by twofold binary search (target >= 5 M samples/s).
// The BTF: the 16 x 16-texel GGX pattern of the unit tests (tests/unit/btf_test_data.h), compressed
// with levels = 3, epsilon = 0.02; and the same pattern on the Bonn dome's directions, whose BTF
// material interpolates on triangulations instead of rings. Directions, uv and random numbers are
// drawn before timing.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <memory>
#include <span>
#include <vector>

#include "../unit/btf_test_data.h"
#include "btf/compress/vq_btf.h"
#include "btf/compress/vq_runtime_export.h"
#include "btf/core/rng.h"
#include "btf/material/btf_material.h"
#include "btf/material/lafortune.h"
#include "btf/core/warp.h"
#include "btf_runtime/material.h"

namespace {

struct BtfBenchFixture {
  std::shared_ptr<const btf::BtfData> data =
      std::make_shared<const btf::BtfData>(btf::test::makeGgxBtf(16, 16, false));
  std::shared_ptr<const btf::VqBtf> vq = std::make_shared<const btf::VqBtf>(btf::compressVq(*data, {}));
  btf::BtfMaterial vq_bilinear{vq, btf::BtfTexelFilter::Bilinear};
  btf::BtfMaterial vq_nearest{vq, btf::BtfTexelFilter::Nearest};
  btf::BtfMaterial data_nearest{data, btf::BtfTexelFilter::Nearest};
  // The literal one-lobe fit of bench_eval.cpp's fallback (a glossy lobe, exponent 15); `btf bench
  // decode` (tools/bench/bench_decode.cpp) measures against the same model: change both together.
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
void BM_BtfEvalVqNearest(benchmark::State& state) {
  runBtfEval(state, btfFixture().vq_nearest);
  state.counters["table_MB"] = double(btfFixture().vq->lookupTableBytes()) / 1e6;
}
void BM_BtfEvalDataNearest(benchmark::State& state) { runBtfEval(state, btfFixture().data_nearest); }
void BM_BtfSampleVq(benchmark::State& state) { runBtfSample(state, btfFixture().vq_nearest); }
// The direction and its pdf alone (no eval for the weight): the twofold search's own cost.
void BM_BtfSampleDirectionVq(benchmark::State& state) {
  const btf::BtfMaterial& m = btfFixture().vq_nearest;
  runQueries(state, [&](const BtfBenchFixture::Query& q) { return m.sampleDirection(q.wo, q.uv, q.u); });
}
void BM_BtfSampleData(benchmark::State& state) { runBtfSample(state, btfFixture().data_nearest); }
void BM_BtfSampleLafortune1(benchmark::State& state) { runBtfSample(state, btfFixture().lafortune); }

// The same GGX pattern measured on the Bonn dome's 151 x 151 directions: evaluation and sampling
// on triangulations of the directions (btf_material.h) beside the 81-direction set's rings above
// (BM_BtfEvalVqNearest, BM_BtfSampleVq: same texels, queries and options).
struct DomeBenchFixture {
  std::shared_ptr<const btf::VqBtf> vq = std::make_shared<const btf::VqBtf>(
      btf::compressVq(btf::test::makeGgxBtf(16, 16, false, btf::BtfDirectionSet::uboDome1()), {}));
  btf::BtfMaterial vq_nearest{vq, btf::BtfTexelFilter::Nearest};
};
const DomeBenchFixture& domeFixture() {
  static const DomeBenchFixture f;
  return f;
}
void BM_BtfEvalDomeVqNearest(benchmark::State& state) {
  runBtfEval(state, domeFixture().vq_nearest);
  state.counters["table_MB"] = double(domeFixture().vq->lookupTableBytes()) / 1e6;
}
void BM_BtfSampleDomeVq(benchmark::State& state) { runBtfSample(state, domeFixture().vq_nearest); }


// The engine runtime (runtime/, libbtf::runtime) on the same VqBtf, exported by `btf export
// --runtime`'s writer, beside the library's BM_BtfEvalVqNearest / BM_BtfSampleVq /
// BM_BtfEvalVqBilinear (same queries; the results are the same floats, tests/unit/test_runtime.cpp).
struct RuntimeBenchFixture {
  btfrt::Material nearest, bilinear;
  static btfrt::Material open(btfrt::TexelFilter filter) {
    const std::filesystem::path file = std::filesystem::temp_directory_path() / "libbtf_bench_runtime.btfrt";
    btf::writeVqRuntimeFile(*btfFixture().vq, file);
    btfrt::Material m = btfrt::Material::open(file.string(), filter);
    std::filesystem::remove(file);
    return m;
  }
  RuntimeBenchFixture() : nearest(open(btfrt::TexelFilter::Nearest)), bilinear(open(btfrt::TexelFilter::Bilinear)) {}
};
const RuntimeBenchFixture& runtimeFixture() {
  static const RuntimeBenchFixture f;
  return f;
}
btfrt::Vec3 runtimeVec(const glm::vec3& v) { return {v.x, v.y, v.z}; }
void BM_RuntimeEvalVqNearest(benchmark::State& state) {
  const btfrt::Material& m = runtimeFixture().nearest;
  runQueries(state, [&](const BtfBenchFixture::Query& q) {
    const btfrt::Rgb f = m.eval(runtimeVec(q.wi), runtimeVec(q.wo), q.uv.x, q.uv.y);
    return f.r + f.g + f.b;
  });
}
void BM_RuntimeEvalVqBilinear(benchmark::State& state) {
  const btfrt::Material& m = runtimeFixture().bilinear;
  runQueries(state, [&](const BtfBenchFixture::Query& q) {
    const btfrt::Rgb f = m.eval(runtimeVec(q.wi), runtimeVec(q.wo), q.uv.x, q.uv.y);
    return f.r + f.g + f.b;
  });
}
void BM_RuntimeSampleVq(benchmark::State& state) {
  const btfrt::Material& m = runtimeFixture().nearest;
  runQueries(state, [&](const BtfBenchFixture::Query& q) {
    btfrt::Sample s;
    return m.sample(runtimeVec(q.wo), q.uv.x, q.uv.y, q.u.x, q.u.y, s) ? s.pdf : 0.0f;
  });
}
void BM_RuntimePdfVq(benchmark::State& state) {
  const btfrt::Material& m = runtimeFixture().nearest;
  runQueries(state, [&](const BtfBenchFixture::Query& q) { return m.pdf(runtimeVec(q.wi), runtimeVec(q.wo), q.uv.x, q.uv.y); });
}
void BM_BtfPdfVq(benchmark::State& state) {
  const btf::BtfMaterial& m = btfFixture().vq_nearest;
  runQueries(state, [&](const BtfBenchFixture::Query& q) { return m.pdf(q.wi, q.wo, q.uv); });
}

// Decoding one measured sample (texel, view, light) from the codebooks: no direction mapping and
// no interpolation, the random access that decompression-based renderers make. Its rate depends on
// whether the tables it walks stay in cache, so it runs on the GGX pattern at 4 x 4 to 64 x 64
// texels (argument), whose tables grow with it (counter table_MB, to compare with the L2 cache).
struct DecodeFixture {
  std::shared_ptr<const btf::VqBtf> vq;
  std::vector<btf::BtfSampleIndex> samples;
};
const DecodeFixture& decodeFixture(int size) {
  static std::map<int, DecodeFixture> fixtures;
  auto [it, added] = fixtures.try_emplace(size);
  if (added) {
    it->second.vq = std::make_shared<const btf::VqBtf>(btf::compressVq(btf::test::makeGgxBtf(size, size, false), {}));
    btf::Rng rng(78);
    it->second.samples.resize(1 << 16);
    for (auto& s : it->second.samples) {
      const glm::vec2 a = rng.uniform2D(), b = rng.uniform2D();
      s = {std::min(int(a.x * float(size)), size - 1), std::min(int(a.y * float(size)), size - 1),
           std::min(int(b.x * float(btf::kBtfDirectionCount)), btf::kBtfDirectionCount - 1),
           std::min(int(b.y * float(btf::kBtfDirectionCount)), btf::kBtfDirectionCount - 1)};
    }
  }
  return it->second;
}

void BM_BtfDecodeVqValue(benchmark::State& state) {
  const DecodeFixture& f = decodeFixture(int(state.range(0)));
  const std::size_t mask = f.samples.size() - 1;
  std::size_t i = 0;
  for (auto _ : state) {
    const btf::BtfSampleIndex& s = f.samples[i++ & mask];
    benchmark::DoNotOptimize(f.vq->value(s.x, s.y, s.view, s.light));
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()));
  state.counters["table_MB"] = double(f.vq->lookupTableBytes()) / 1e6;
}

// The same samples through the stream call (VqBtf::values), blocks of 256.
void BM_BtfDecodeVqStream(benchmark::State& state) {
  const DecodeFixture& f = decodeFixture(int(state.range(0)));
  constexpr std::size_t kBlock = 256;
  std::vector<btf::Rgb> out(kBlock);
  std::size_t i = 0;
  for (auto _ : state) {
    f.vq->values(std::span(f.samples.data() + i, kBlock), out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
    i = (i + kBlock) & (f.samples.size() - 1);
  }
  state.SetItemsProcessed(std::int64_t(state.iterations() * kBlock));
  state.counters["table_MB"] = double(f.vq->lookupTableBytes()) / 1e6;
}

BENCHMARK(BM_BtfEvalLafortune1);
BENCHMARK(BM_BtfDecodeVqValue)->Arg(4)->Arg(8)->Arg(16)->Arg(32)->Arg(64);
BENCHMARK(BM_BtfDecodeVqStream)->Arg(4)->Arg(8)->Arg(16)->Arg(32)->Arg(64);
BENCHMARK(BM_BtfEvalVqBilinear);
BENCHMARK(BM_BtfEvalVqNearest);
BENCHMARK(BM_BtfEvalDataNearest);
BENCHMARK(BM_BtfSampleVq);
BENCHMARK(BM_BtfSampleDirectionVq);
BENCHMARK(BM_BtfSampleData);
BENCHMARK(BM_BtfSampleLafortune1);
BENCHMARK(BM_BtfEvalDomeVqNearest);
BENCHMARK(BM_BtfSampleDomeVq);
BENCHMARK(BM_BtfPdfVq);
BENCHMARK(BM_RuntimeEvalVqNearest);
BENCHMARK(BM_RuntimeEvalVqBilinear);
BENCHMARK(BM_RuntimeSampleVq);
BENCHMARK(BM_RuntimePdfVq);

}  // namespace
