// Samples per second (sample + pdf of the drawn direction, as a renderer doing MIS calls them) of
// the RGL warp sampler (luminance warp, then VNDF warp; Dupuy & Jakob 2018) per shared RGL file,
// next to evaluations per second, one at a time and through evalMany. Single thread. Views are drawn before timing, cosine-weighted
// over the hemisphere, so each figure averages over incidences.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "btf/core/rng.h"
#include "btf/material/rgl_brdf.h"
#include "btf/core/warp.h"

namespace {

const char* const kFiles[] = {"cc_ibiza_sunset_rgb", "paper_white_rgb", "vch_golden_yellow_rgb"};
constexpr std::size_t kDirections = 4096;

std::unique_ptr<btf::RglBrdf> load(benchmark::State& state) {
  const std::filesystem::path path =
      std::filesystem::path(BTF_SHARED_DATA_DIR) / "rgl_bsdf" / (std::string(kFiles[state.range(0)]) + ".bsdf");
  if (!std::filesystem::exists(path)) {
    state.SkipWithError(("missing " + path.string()).c_str());
    return nullptr;
  }
  state.SetLabel(kFiles[state.range(0)]);
  return std::make_unique<btf::RglBrdf>(path);
}

// Uniform numbers for sample(), drawn before timing so the loops measure the sampler only.
std::vector<glm::vec2> unitSquarePoints(std::uint64_t seed) {
  btf::Rng rng(seed, 0);
  std::vector<glm::vec2> u(kDirections);
  for (auto& x : u) x = rng.uniform2D();
  return u;
}

std::vector<glm::vec3> directions(std::uint64_t seed) {
  btf::Rng rng(seed, 0);
  std::vector<glm::vec3> out(kDirections);
  for (auto& w : out) w = btf::squareToCosineHemisphere(rng.uniform2D());
  return out;
}

void BM_RglSampleAndPdf(benchmark::State& state) {
  const auto material = load(state);
  if (!material) return;
  const std::vector<glm::vec3> views = directions(1);
  const std::vector<glm::vec2> u = unitSquarePoints(2);
  std::size_t i = 0;
  for (auto _ : state) {
    const auto s = material->sample(views[i], {}, u[i]);
    float pdf = 0.0f;
    if (s) pdf = material->pdf(s->wi, views[i]);
    benchmark::DoNotOptimize(pdf);
    i = (i + 1) % kDirections;
  }
  state.counters["samples_per_s"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_RglSampleOnly(benchmark::State& state) {
  const auto material = load(state);
  if (!material) return;
  const std::vector<glm::vec3> views = directions(1);
  const std::vector<glm::vec2> u = unitSquarePoints(2);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(material->sample(views[i], {}, u[i]));
    i = (i + 1) % kDirections;
  }
  state.counters["samples_per_s"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_RglEval(benchmark::State& state) {
  const auto material = load(state);
  if (!material) return;
  const std::vector<glm::vec3> wi = directions(3), wo = directions(4);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(material->eval(wi[i], wo[i]));
    i = (i + 1) % kDirections;
  }
  state.counters["evals_per_s"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
}

// A stream's weights: 256 wi at one wo (a block of draws), one eval at a time against one
// evalMany per block, side by side; wo changes per block, so each block pays wo's set-up once.
constexpr std::size_t kBlock = 256;

// Runs evalBlock(wo, wi, out) on blocks of kBlock wi at one wo, a new block and wo each iteration.
template <typename EvalBlock>
void evalBlocks(benchmark::State& state, const EvalBlock& evalBlock) {
  const auto material = load(state);
  if (!material) return;
  const std::vector<glm::vec3> wi = directions(3), wo = directions(4);
  std::vector<btf::Rgb> out(kBlock);
  std::size_t block = 0;
  for (auto _ : state) {
    const std::span<const glm::vec3> wis(wi.data() + (block * kBlock) % kDirections, kBlock);
    evalBlock(*material, wo[block % kDirections], wis, std::span<btf::Rgb>(out));
    benchmark::DoNotOptimize(out.data());
    ++block;
  }
  state.counters["evals_per_s"] = benchmark::Counter(double(state.iterations() * kBlock), benchmark::Counter::kIsRate);
}

void BM_RglEvalBlockOneByOne(benchmark::State& state) {
  evalBlocks(state, [](const btf::RglBrdf& m, const glm::vec3& wo, std::span<const glm::vec3> wi, std::span<btf::Rgb> out) {
    for (std::size_t k = 0; k < wi.size(); ++k) out[k] = m.eval(wi[k], wo);
  });
}

void BM_RglEvalBlockMany(benchmark::State& state) {
  evalBlocks(state, [](const btf::RglBrdf& m, const glm::vec3& wo, std::span<const glm::vec3> wi, std::span<btf::Rgb> out) {
    m.evalMany(wo, wi, out);
  });
}

}  // namespace

BENCHMARK(BM_RglEvalBlockOneByOne)->DenseRange(0, 2);
BENCHMARK(BM_RglEvalBlockMany)->DenseRange(0, 2);
BENCHMARK(BM_RglSampleAndPdf)->DenseRange(0, 2);
BENCHMARK(BM_RglSampleOnly)->DenseRange(0, 2);
BENCHMARK(BM_RglEval)->DenseRange(0, 2);
