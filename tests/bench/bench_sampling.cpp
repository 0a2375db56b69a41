// Samples per second per core of the tabulated samplers (sampling/binned_sampler.h), on a
// MERL-size TabulatedBrdf (a GGX tabulated into the MERL layout once) and on the analytic GGX.
// Loops per sampler: "direction" = sampleDirection + pdf (the sampler's own cost, what the
// project's 20 M/s target is about), "direction_only" = sampleDirection alone (it returns the pdf
// too, so a caller that takes it from there pays only this), "one_wo" = sample + pdf at a single
// wo (tables cache-resident: the arithmetic alone), "pdf_only" = pdf of a pre-drawn
// (wi, wo) pair (the MIS side of a renderer) and "full" = Material::sample + pdf (adds the eval()
// for the weight, dominated by the table lookup). Single-threaded; wo and u are drawn before timing.
// Counters: bytes of the sampler's tables, the full-CDF bytes of the same grid, and for the
// quadtree the mean acceptance rate; the label is the parameterization in use. The samplers take
// the default options (parameterization Auto) unless the name ends in _incident or _half, which
// fix it: the DP sampler's loops run once per parameterization, to compare the two maps' costs.
#include <benchmark/benchmark.h>

#include <memory>
#include <span>
#include <tuple>
#include <vector>

#include "btf/core/math.h"
#include "btf/core/rng.h"
#include "btf/material/ggx.h"
#include "btf/material/tabulated_brdf.h"
#include "btf/sampling/binned_sampler.h"
#include "btf/sampling/dp_cdf_sampler.h"
#include "btf/core/warp.h"

namespace {

struct SamplingQuery {
  glm::vec3 wo;
  glm::vec2 u;
};

// The MERL table's theta_o resolution (90 bins) with a 64 x 128 incoming grid per bin (Incident;
// Half has the default 128 x 128 cells of the half-vector square).
btf::SamplerOptions merlSizeOptions(float epsilon, btf::Parameterization parameterization) {
  btf::SamplerOptions o;
  o.parameterization = parameterization;
  o.theta_o_bins = 90;
  o.cos_theta_bins = 64;
  o.phi_bins = 128;
  o.epsilon = epsilon;
  return o;
}

struct SamplingFixture {
  std::shared_ptr<const btf::Material> ggx = std::make_shared<btf::Ggx>(btf::Rgb(0.2f), btf::Rgb(0.6f), 0.1f, 0.1f);
  std::shared_ptr<const btf::Material> merl =
      std::make_shared<btf::TabulatedBrdf>(std::make_shared<btf::MerlTable>(btf::tabulate(*ggx)));
  std::vector<SamplingQuery> queries;
  SamplingFixture() {
    btf::Rng rng(7);
    queries.resize(1 << 16);
    for (SamplingQuery& q : queries) q = {btf::squareToCosineHemisphere(rng.uniform2D()), rng.uniform2D()};
  }
};

const SamplingFixture& samplingFixture() {
  static const SamplingFixture f;
  return f;
}

void report(benchmark::State& state, const btf::BinnedSampler& s) {
  const btf::SamplerStats st = s.stats();
  state.SetItemsProcessed(std::int64_t(state.iterations()));
  state.counters["bytes"] = double(st.bytes);
  state.counters["full_cdf_bytes"] = double(st.full_cdf_bytes);
  state.SetLabel(st.parameterization);
  if (s.kind() == btf::SamplerKind::Quadtree) state.counters["acceptance"] = st.acceptance_rate;
}

void runDirection(benchmark::State& state, const btf::BinnedSampler& s) {
  const auto& q = samplingFixture().queries;
  std::size_t i = 0;
  int tries = 0;
  for (auto _ : state) {
    const SamplingQuery& k = q[i++ & (q.size() - 1)];
    const auto d = s.sampleDirection(k.wo, k.u, tries);
    if (d) benchmark::DoNotOptimize(s.pdf(d->wi, k.wo));
  }
  report(state, s);
}

void runDirectionOnly(benchmark::State& state, const btf::BinnedSampler& s) {
  const auto& q = samplingFixture().queries;
  std::size_t i = 0;
  int tries = 0;
  for (auto _ : state) {
    const SamplingQuery& k = q[i++ & (q.size() - 1)];
    benchmark::DoNotOptimize(s.sampleDirection(k.wo, k.u, tries));
  }
  report(state, s);
}

// One wo for all draws (a pixel's many samples at one shading point; the tables it touches stay
// in the L1/L2 cache, so this is the sampler's arithmetic without the cache misses of the random
// wo above).
void runDirectionOneWo(benchmark::State& state, const btf::BinnedSampler& s) {
  const auto& q = samplingFixture().queries;
  const glm::vec3 wo = btf::sphericalDirection(0.6f, 1.0f);
  std::size_t i = 0;
  int tries = 0;
  for (auto _ : state) {
    const SamplingQuery& k = q[i++ & (q.size() - 1)];
    const auto d = s.sampleDirection(wo, k.u, tries);
    if (d) benchmark::DoNotOptimize(s.pdf(d->wi, wo));
  }
  report(state, s);
}

void runPdfOnly(benchmark::State& state, const btf::BinnedSampler& s) {
  // The wi are the sampler's own draws (where a renderer's MIS evaluates the pdf most often);
  // they are drawn before timing.
  const auto& q = samplingFixture().queries;
  std::vector<glm::vec3> wi(q.size(), glm::vec3(0, 0, 1));
  int tries = 0;
  for (std::size_t k = 0; k < q.size(); ++k)
    if (const auto d = s.sampleDirection(q[k].wo, q[k].u, tries)) wi[k] = d->wi;
  std::size_t i = 0;
  for (auto _ : state) {
    const std::size_t k = i++ & (q.size() - 1);
    benchmark::DoNotOptimize(s.pdf(wi[k], q[k].wo));
  }
  report(state, s);
}

void runFull(benchmark::State& state, const btf::BinnedSampler& s) {
  const auto& q = samplingFixture().queries;
  std::size_t i = 0;
  for (auto _ : state) {
    const SamplingQuery& k = q[i++ & (q.size() - 1)];
    const auto d = s.sample(k.wo, {}, k.u);
    if (d) benchmark::DoNotOptimize(s.pdf(d->wi, k.wo));
  }
  report(state, s);
}

// The stream calls (binned_sampler.h): "stream" = sampleDirections then pdfs of the drawn wi,
// "stream_direction" = sampleDirections alone (it returns the pdf), over blocks of 256 queries with
// random wo (a wavefront renderer's batch); items = queries.
constexpr std::size_t kStreamBlock = 256;
void runStream(benchmark::State& state, const btf::BinnedSampler& s, bool with_pdf) {
  const auto& q = samplingFixture().queries;
  std::vector<glm::vec3> wo(q.size());
  std::vector<glm::vec2> u(q.size());
  for (std::size_t k = 0; k < q.size(); ++k) wo[k] = q[k].wo, u[k] = q[k].u;
  std::vector<btf::BinnedSampler::DirectionSample> out(kStreamBlock);
  std::vector<glm::vec3> wi(kStreamBlock);
  std::vector<float> pdf(kStreamBlock);
  std::size_t i = 0;
  for (auto _ : state) {
    const std::span<const glm::vec3> wo_block(wo.data() + i, kStreamBlock);
    s.sampleDirections(wo_block, std::span(u.data() + i, kStreamBlock), out);
    if (with_pdf) {
      for (std::size_t k = 0; k < kStreamBlock; ++k) wi[k] = out[k].wi;
      s.pdfs(wi, wo_block, pdf);
      benchmark::DoNotOptimize(pdf.data());
    }
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
    i = (i + kStreamBlock) & (q.size() - 1);
  }
  report(state, s);
  state.SetItemsProcessed(std::int64_t(state.iterations() * kStreamBlock));
}

// Samplers are built on first use (the MERL-size ones take a second or two each, Auto about twice that).
using P = btf::Parameterization;
const btf::BinnedSampler& sampler(btf::SamplerKind kind, bool merl, float epsilon, P parameterization = P::Auto) {
  static std::vector<std::pair<std::tuple<int, bool, float, int>, std::unique_ptr<btf::BinnedSampler>>> cache;
  const auto key = std::make_tuple(int(kind), merl, epsilon, int(parameterization));
  for (auto& [k, s] : cache)
    if (k == key) return *s;
  cache.emplace_back(key, btf::makeSampler(kind, merl ? samplingFixture().merl : samplingFixture().ggx,
                                           merlSizeOptions(epsilon, parameterization)));
  return *cache.back().second;
}

void BM_Direction(benchmark::State& state, btf::SamplerKind kind, bool merl, float epsilon, P p = P::Auto) {
  runDirection(state, sampler(kind, merl, epsilon, p));
}
void BM_DirectionOnly(benchmark::State& state, btf::SamplerKind kind, bool merl, float epsilon, P p = P::Auto) {
  runDirectionOnly(state, sampler(kind, merl, epsilon, p));
}
void BM_DirectionOneWo(benchmark::State& state, btf::SamplerKind kind, bool merl, float epsilon, P p = P::Auto) {
  runDirectionOneWo(state, sampler(kind, merl, epsilon, p));
}
void BM_PdfOnly(benchmark::State& state, btf::SamplerKind kind, bool merl, float epsilon, P p = P::Auto) {
  runPdfOnly(state, sampler(kind, merl, epsilon, p));
}
void BM_Stream(benchmark::State& state, btf::SamplerKind kind, bool merl, float epsilon, P p = P::Auto) {
  runStream(state, sampler(kind, merl, epsilon, p), true);
}
void BM_StreamDirection(benchmark::State& state, btf::SamplerKind kind, bool merl, float epsilon, P p = P::Auto) {
  runStream(state, sampler(kind, merl, epsilon, p), false);
}
void BM_Full(benchmark::State& state, btf::SamplerKind kind, bool merl, float epsilon, P p = P::Auto) {
  runFull(state, sampler(kind, merl, epsilon, p));
}

using K = btf::SamplerKind;
BENCHMARK_CAPTURE(BM_Direction, merl_tabulated, K::Tabulated, true, 0.0f);
BENCHMARK_CAPTURE(BM_Direction, merl_dp_eps1e-3, K::DpCdf, true, 1e-3f);
BENCHMARK_CAPTURE(BM_Direction, merl_dp_eps1e-2, K::DpCdf, true, 1e-2f);
BENCHMARK_CAPTURE(BM_Direction, merl_quadtree, K::Quadtree, true, 0.0f);
BENCHMARK_CAPTURE(BM_DirectionOnly, merl_tabulated, K::Tabulated, true, 0.0f);
BENCHMARK_CAPTURE(BM_DirectionOnly, merl_dp_eps1e-3, K::DpCdf, true, 1e-3f);
BENCHMARK_CAPTURE(BM_DirectionOneWo, merl_tabulated, K::Tabulated, true, 0.0f);
BENCHMARK_CAPTURE(BM_DirectionOneWo, merl_dp_eps1e-3, K::DpCdf, true, 1e-3f);
BENCHMARK_CAPTURE(BM_PdfOnly, merl_tabulated, K::Tabulated, true, 0.0f);
BENCHMARK_CAPTURE(BM_PdfOnly, merl_dp_eps1e-3, K::DpCdf, true, 1e-3f);
BENCHMARK_CAPTURE(BM_Stream, merl_dp_eps1e-3, K::DpCdf, true, 1e-3f);
BENCHMARK_CAPTURE(BM_Stream, merl_dp_eps1e-2, K::DpCdf, true, 1e-2f);
BENCHMARK_CAPTURE(BM_StreamDirection, merl_dp_eps1e-3, K::DpCdf, true, 1e-3f);
BENCHMARK_CAPTURE(BM_Stream, merl_tabulated, K::Tabulated, true, 0.0f);
BENCHMARK_CAPTURE(BM_Full, merl_tabulated, K::Tabulated, true, 0.0f);
BENCHMARK_CAPTURE(BM_Full, merl_dp_eps1e-3, K::DpCdf, true, 1e-3f);
BENCHMARK_CAPTURE(BM_Full, merl_quadtree, K::Quadtree, true, 0.0f);
// The DP sampler's single queries and stream calls per parameterization (Half: the vector path
// reflects about the half vector and runs pdf()'s path for every draw).
BENCHMARK_CAPTURE(BM_Direction, merl_dp_eps1e-3_incident, K::DpCdf, true, 1e-3f, P::Incident);
BENCHMARK_CAPTURE(BM_Direction, merl_dp_eps1e-3_half, K::DpCdf, true, 1e-3f, P::Half);
BENCHMARK_CAPTURE(BM_DirectionOnly, merl_dp_eps1e-3_incident, K::DpCdf, true, 1e-3f, P::Incident);
BENCHMARK_CAPTURE(BM_DirectionOnly, merl_dp_eps1e-3_half, K::DpCdf, true, 1e-3f, P::Half);
BENCHMARK_CAPTURE(BM_PdfOnly, merl_dp_eps1e-3_incident, K::DpCdf, true, 1e-3f, P::Incident);
BENCHMARK_CAPTURE(BM_PdfOnly, merl_dp_eps1e-3_half, K::DpCdf, true, 1e-3f, P::Half);
BENCHMARK_CAPTURE(BM_Stream, merl_dp_eps1e-3_incident, K::DpCdf, true, 1e-3f, P::Incident);
BENCHMARK_CAPTURE(BM_Stream, merl_dp_eps1e-3_half, K::DpCdf, true, 1e-3f, P::Half);
BENCHMARK_CAPTURE(BM_StreamDirection, merl_dp_eps1e-3_incident, K::DpCdf, true, 1e-3f, P::Incident);
BENCHMARK_CAPTURE(BM_StreamDirection, merl_dp_eps1e-3_half, K::DpCdf, true, 1e-3f, P::Half);
BENCHMARK_CAPTURE(BM_Direction, ggx_dp_eps1e-3, K::DpCdf, false, 1e-3f);
BENCHMARK_CAPTURE(BM_Direction, ggx_quadtree, K::Quadtree, false, 0.0f);
BENCHMARK_CAPTURE(BM_Full, ggx_dp_eps1e-3, K::DpCdf, false, 1e-3f);

// Table size of the DP sampler against the full float CDFs of the same grid, per epsilon (the
// sampler is built once; the timed loop is empty). Counters: bytes_ratio = bytes / full_cdf_bytes,
// vertices per CDF and the largest deviation of a stored CDF from its full CDF.
void BM_Memory(benchmark::State& state, float epsilon) {
  const btf::BinnedSampler& s = sampler(btf::SamplerKind::DpCdf, true, epsilon);
  for (auto _ : state) benchmark::DoNotOptimize(&s);
  const btf::SamplerStats st = s.stats();
  state.counters["bytes"] = double(st.bytes);
  state.counters["bytes_ratio"] = double(st.bytes) / double(st.full_cdf_bytes);
  state.counters["vertices_per_cdf"] = st.mean_elements_per_cdf;
  state.counters["max_deviation"] = static_cast<const btf::DpCdfSampler&>(s).maxCdfDeviation();
}
BENCHMARK_CAPTURE(BM_Memory, merl_dp_eps1e-3, 1e-3f)->Iterations(1);
BENCHMARK_CAPTURE(BM_Memory, merl_dp_eps3e-3, 3e-3f)->Iterations(1);
BENCHMARK_CAPTURE(BM_Memory, merl_dp_eps1e-2, 1e-2f)->Iterations(1);
BENCHMARK_CAPTURE(BM_Memory, merl_dp_eps3e-2, 3e-2f)->Iterations(1);

// The material's own sampler, for scale.
void BM_FullOwnSampler(benchmark::State& state, bool merl) {
  const btf::Material& m = merl ? *samplingFixture().merl : *samplingFixture().ggx;
  const auto& q = samplingFixture().queries;
  std::size_t i = 0;
  for (auto _ : state) {
    const SamplingQuery& k = q[i++ & (q.size() - 1)];
    const auto d = m.sample(k.wo, {}, k.u);
    if (d) benchmark::DoNotOptimize(m.pdf(d->wi, k.wo));
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()));
}
BENCHMARK_CAPTURE(BM_FullOwnSampler, ggx_analytic, false);

}  // namespace
