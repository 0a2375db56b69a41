// The octree-bound sampler (sampling/octree_bound_sampler.h) against the quadtree rejection sampler
// (sampling/quadtree_sampler.h, default options) on the same octree material: a MERL-layout table
// at tolerance 0.02 with interpolated lookups, of a GGX plastic and of the glossy RGL file
// cc_ibiza_sunset_rgb (when the shared data is there). Loops, single-threaded, wo and u drawn
// before timing:
//   direction  the proposal and its pdf (octree exact mode; quadtree sampleDirection + pdf);
//   full       Material::sample (adds the eval of the octree for the weight) + pdf;
//   rejection  octree rejection mode, up to 64 proposals, each with one eval of the octree.
// Counters: bytes of the sampler's own tables, build_s (wall seconds to build it, all cores; the
// octree itself is built before), acceptance (octree: accepted / proposals measured
// in the loop; quadtree: its mean per-bin rate) and rel_variance, the variance per sample of the
// luminance of f cos / pdf over the mean squared (one draw per query, 65,536 queries): with
// items/s it gives the efficiency 1 / (variance * time) of the exact-mode samplers.
#include <benchmark/benchmark.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "btf/compress/octree_table.h"
#include "btf/core/math.h"
#include "btf/core/rng.h"
#include "btf/material/ggx.h"
#include "btf/material/octree_brdf.h"
#include "btf/material/rgl_brdf.h"
#include "btf/material/tabulated_brdf.h"
#include "btf/sampling/octree_bound_sampler.h"
#include "btf/sampling/quadtree_sampler.h"
#include "btf/core/warp.h"

namespace {

struct Query {
  glm::vec3 wo;
  glm::vec2 u;
};

struct Samplers {
  double octree_build_s = 0, quadtree_build_s = 0;
  std::shared_ptr<const btf::OctreeBrdf> material;
  std::unique_ptr<btf::OctreeBoundSampler> octree;
  std::unique_ptr<btf::QuadtreeSampler> quadtree;
};

const std::vector<Query>& queries() {
  static const std::vector<Query> q = [] {
    btf::Rng rng(7);
    std::vector<Query> v(1 << 16);
    for (Query& k : v) k = {btf::squareToCosineHemisphere(rng.uniform2D()), rng.uniform2D()};
    return v;
  }();
  return q;
}

std::shared_ptr<const btf::Material> source(const std::string& name) {
  if (name == "ggx_plastic") return std::make_shared<btf::Ggx>(btf::Rgb(0.2f), btf::Rgb(0.05f), 0.1f, 0.1f);
  const std::filesystem::path file = std::filesystem::path(BTF_SHARED_DATA_DIR) / "rgl_bsdf" / (name + ".bsdf");
  if (!std::filesystem::exists(file)) return nullptr;
  return std::make_shared<btf::RglBrdf>(file);
}

const Samplers* samplers(const std::string& name) {
  static std::map<std::string, Samplers> built;
  if (const auto it = built.find(name); it != built.end()) return it->second.material ? &it->second : nullptr;
  Samplers& s = built[name];
  const auto m = source(name);
  if (!m) return nullptr;
  const btf::MerlTable table = btf::tabulate(*m);
  s.material = std::make_shared<btf::OctreeBrdf>(std::make_shared<btf::OctreeTable>(btf::OctreeTable::build(table, 0.02)));
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  s.octree = std::make_unique<btf::OctreeBoundSampler>(s.material);
  const auto t1 = Clock::now();
  s.quadtree = std::make_unique<btf::QuadtreeSampler>(s.material);
  const auto t2 = Clock::now();
  s.octree_build_s = std::chrono::duration<double>(t1 - t0).count();
  s.quadtree_build_s = std::chrono::duration<double>(t2 - t1).count();
  return &s;
}

// Relative variance per sample of luminance(f cos / pdf), a missing draw counting 0.
template <class Sample>
double relVariance(Sample&& sample) {
  double sum = 0, sq = 0;
  for (const Query& k : queries()) {
    const auto s = sample(k);
    const double w = s ? double(s->weight.luminance()) : 0.0;
    sum += w, sq += w * w;
  }
  const double n = double(queries().size()), mean = sum / n;
  return (sq / n - mean * mean) / (mean * mean);
}

void BM_OctreeBound(benchmark::State& state, const std::string& name, const std::string& loop) {
  const Samplers* s = samplers(name);
  if (!s) return state.SkipWithError("shared data not found");
  const auto& q = queries();
  std::size_t i = 0;
  std::uint64_t accepted = 0, proposals = 0;
  btf::Rng rng(3);
  for (auto _ : state) {
    const Query& k = q[i++ & (q.size() - 1)];
    if (loop == "direction") {
      benchmark::DoNotOptimize(s->octree->sampleDirection(k.wo, k.u));
    } else if (loop == "full") {
      const auto d = s->octree->sample(k.wo, {}, k.u);
      if (d) benchmark::DoNotOptimize(s->octree->pdf(d->wi, k.wo));
    } else {
      int tries = 0;
      accepted += s->octree->sampleByRejection(k.wo, rng, 64, tries).has_value();
      proposals += std::uint64_t(tries);
    }
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()));
  state.counters["bytes"] = double(s->octree->bytes());
  state.counters["build_s"] = s->octree_build_s;
  if (loop == "rejection") state.counters["acceptance"] = proposals ? double(accepted) / double(proposals) : 0.0;
  if (loop == "full")
    state.counters["rel_variance"] = relVariance([&](const Query& k) { return s->octree->sample(k.wo, {}, k.u); });
}

void BM_Quadtree(benchmark::State& state, const std::string& name, const std::string& loop) {
  const Samplers* s = samplers(name);
  if (!s) return state.SkipWithError("shared data not found");
  const auto& q = queries();
  std::size_t i = 0;
  int tries = 0;
  for (auto _ : state) {
    const Query& k = q[i++ & (q.size() - 1)];
    if (loop == "direction") {
      const auto d = s->quadtree->sampleDirection(k.wo, k.u, tries);
      if (d) benchmark::DoNotOptimize(s->quadtree->pdf(d->wi, k.wo));
    } else {
      const auto d = s->quadtree->sample(k.wo, {}, k.u);
      if (d) benchmark::DoNotOptimize(s->quadtree->pdf(d->wi, k.wo));
    }
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()));
  const btf::SamplerStats st = s->quadtree->stats();
  state.counters["bytes"] = double(st.bytes);
  state.counters["build_s"] = s->quadtree_build_s;
  state.counters["acceptance"] = st.acceptance_rate;
  if (loop == "full")
    state.counters["rel_variance"] = relVariance([&](const Query& k) { return s->quadtree->sample(k.wo, {}, k.u); });
}

BENCHMARK_CAPTURE(BM_OctreeBound, ggx_plastic_direction, std::string("ggx_plastic"), std::string("direction"));
BENCHMARK_CAPTURE(BM_OctreeBound, ggx_plastic_full, std::string("ggx_plastic"), std::string("full"));
BENCHMARK_CAPTURE(BM_OctreeBound, ggx_plastic_rejection, std::string("ggx_plastic"), std::string("rejection"));
BENCHMARK_CAPTURE(BM_Quadtree, ggx_plastic_direction, std::string("ggx_plastic"), std::string("direction"));
BENCHMARK_CAPTURE(BM_Quadtree, ggx_plastic_full, std::string("ggx_plastic"), std::string("full"));
BENCHMARK_CAPTURE(BM_OctreeBound, cc_ibiza_sunset_direction, std::string("cc_ibiza_sunset_rgb"), std::string("direction"));
BENCHMARK_CAPTURE(BM_OctreeBound, cc_ibiza_sunset_full, std::string("cc_ibiza_sunset_rgb"), std::string("full"));
BENCHMARK_CAPTURE(BM_OctreeBound, cc_ibiza_sunset_rejection, std::string("cc_ibiza_sunset_rgb"), std::string("rejection"));
BENCHMARK_CAPTURE(BM_Quadtree, cc_ibiza_sunset_direction, std::string("cc_ibiza_sunset_rgb"), std::string("direction"));
BENCHMARK_CAPTURE(BM_Quadtree, cc_ibiza_sunset_full, std::string("cc_ibiza_sunset_rgb"), std::string("full"));

}  // namespace
