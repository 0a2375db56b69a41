// The photon map's kd-B-tree against nanoflann (KDTreeSingleIndexAdaptor) and FLANN
// (KDTreeSingleIndex), single-threaded, on photons spread over the surfaces of a Cornell-box-like
// scene: k = 50 nearest and a fixed radius that finds ~50 on average, 100 k and 1 M photons.
// Every structure has leaves of at most 64 points, as ours. Counters: queries_per_s, and found
// (points per query).
//
// PhotonKdTreeKnn/<structure>/<photons>, PhotonKdTreeRadius/..., PhotonKdTreeBuild/... (one
// thread for all; ours built serially). PhotonKdTreeMeasure runs `btf bench render`'s comparison,
// whose agreement check throws (and so fails the smoke run) if a structure's answers differ.
#include <benchmark/benchmark.h>

#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <vector>

// btf_bench does not link the command line: the comparison and its structures are compiled in from
// their one source, so that this benchmark and `btf bench render` time the same code.
#include "../../tools/bench/bench_photon_search.cpp"

namespace {

using btf::cli::PhotonSearch;

constexpr std::uint64_t kSeed = 1;
constexpr std::size_t kNeighbors = 50;
// Queries cycle through this many points, drawn as the photons are: consecutive queries are
// unrelated, as the gather points of random camera paths.
constexpr std::size_t kQueryCount = 1 << 14;

struct Scene {
  std::vector<glm::vec3> photons, queries;
  float radius2 = 0.0f;
  std::map<std::string, std::unique_ptr<PhotonSearch>> structures;
};

PhotonSearch& structureOf(Scene& scene, const std::string& name) {
  auto& s = scene.structures[name];
  if (!s) s = btf::cli::makePhotonSearch(name, scene.photons);
  return *s;
}

// Built once per size and kept: the set-up of the largest sizes costs far more than a query.
Scene& sceneOf(std::size_t photons) {
  static std::map<std::size_t, Scene> scenes;
  Scene& scene = scenes[photons];
  if (scene.photons.empty()) {
    scene.photons = btf::cli::cornellBoxPoints(photons, kSeed, 0);
    scene.queries = btf::cli::cornellBoxPoints(kQueryCount, kSeed, std::uint64_t(1) << 40);
    // As measurePhotonSearch: the mean of our k-th nearest squared distances.
    PhotonSearch& ours = structureOf(scene, "kd-b-tree");
    double sum = 0.0;
    for (const glm::vec3& q : scene.queries) {
      ours.knn(q, kNeighbors);
      sum += ours.lastKnnDistances2().back();
    }
    scene.radius2 = static_cast<float>(sum / kQueryCount);
  }
  return scene;
}

void setCounters(benchmark::State& state, std::size_t found) {
  state.counters["queries_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["found"] = benchmark::Counter(static_cast<double>(found), benchmark::Counter::kAvgIterations);
}

void knnQueries(benchmark::State& state, const std::string& structure, std::size_t photons) {
  Scene& scene = sceneOf(photons);
  PhotonSearch& search = structureOf(scene, structure);
  std::size_t i = 0, found = 0;
  for (auto _ : state) {
    found += search.knn(scene.queries[i], kNeighbors);
    if (++i == kQueryCount) i = 0;
  }
  setCounters(state, found);
}

void radiusQueries(benchmark::State& state, const std::string& structure, std::size_t photons) {
  Scene& scene = sceneOf(photons);
  PhotonSearch& search = structureOf(scene, structure);
  std::size_t i = 0, found = 0;
  for (auto _ : state) {
    found += search.withinRadius(scene.queries[i], scene.radius2);
    if (++i == kQueryCount) i = 0;
  }
  setCounters(state, found);
}

void build(benchmark::State& state, const std::string& structure, std::size_t photons) {
  const Scene& scene = sceneOf(photons);
  std::unique_ptr<PhotonSearch> built;
  for (auto _ : state) {
    state.PauseTiming();
    built.reset();
    std::vector<glm::vec3> copy = scene.photons;
    state.ResumeTiming();
    built = btf::cli::makePhotonSearch(structure, std::move(copy));
    benchmark::DoNotOptimize(built.get());
  }
  state.counters["photons_per_s"] = benchmark::Counter(static_cast<double>(state.iterations() * photons),
                                                       benchmark::Counter::kIsRate);
}

void measure(benchmark::State& state, std::size_t photons) {
  std::vector<btf::cli::PhotonSearchFigures> figures;
  for (auto _ : state) figures = btf::cli::measurePhotonSearch(photons, 4000, kNeighbors, kSeed);
  for (const auto& f : figures) state.counters[f.structure + "_knn_per_s"] = f.knn_queries_per_s;
}

[[maybe_unused]] const bool kRegistered = [] {
  for (const std::size_t photons : {std::size_t(100000), std::size_t(1000000)}) {
    for (const std::string& structure : btf::cli::photonSearchStructures()) {
      const std::string suffix = "/" + structure + "/" + std::to_string(photons);
      benchmark::RegisterBenchmark(("PhotonKdTreeKnn" + suffix).c_str(), knnQueries, structure, photons);
      benchmark::RegisterBenchmark(("PhotonKdTreeRadius" + suffix).c_str(), radiusQueries, structure, photons);
      benchmark::RegisterBenchmark(("PhotonKdTreeBuild" + suffix).c_str(), build, structure, photons)
          ->Unit(benchmark::kMillisecond);
    }
  }
  benchmark::RegisterBenchmark("PhotonKdTreeMeasure/20000", measure, std::size_t(20000))
      ->Iterations(1)
      ->Unit(benchmark::kMillisecond);
  return true;
}();

}  // namespace
