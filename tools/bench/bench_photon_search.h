// The photon map's search structure against nanoflann and FLANN (`btf bench render`): the same
// photons, the same queries, the same k, answers checked against ours so that the speeds compare
// equal work. tests/bench/bench_photon_kdtree.cpp drives the same pieces under Google Benchmark.
#pragma once

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace btf::cli {

struct PhotonSearchFigures {
  std::string structure;         // "kd-b-tree" (ours), "nanoflann", "flann"
  // Times are the calling thread's CPU time; every structure is built and queried on one thread
  // (ours built serially), queries as the best of a few passes.
  double build_seconds;
  double knn_queries_per_s;      // k nearest, unbounded
  double radius_queries_per_s;   // fixed radius
  double mean_found_radius;      // points found per radius query
  std::size_t bytes;             // the index beyond the point coordinates: nodes and permutation
};

// `photons` points on the surfaces of a Cornell-box-like scene and `queries` points drawn the same
// way (deterministic from `seed`); per structure, k nearest and a fixed radius chosen so that ~k
// points are found on average (the mean of our k-th nearest squared distances). Throws btf::Error
// if a structure's k nearest distances differ from ours beyond float rounding, or its mean radius
// count differs from ours beyond points exactly at the radius.
std::vector<PhotonSearchFigures> measurePhotonSearch(std::size_t photons, std::size_t queries, std::size_t k,
                                                     std::uint64_t seed);

// The pieces measurePhotonSearch is made of, shared with the Google Benchmark.

// n points, uniform by area on the five walls of the unit box [0, 1]^3 (open towards +z) and on a
// sphere standing on its floor; point i is a pure function of (seed, first_stream + i).
std::vector<glm::vec3> cornellBoxPoints(std::size_t n, std::uint64_t seed, std::uint64_t first_stream);

// One search structure behind the two queries compared. Queries keep their results inside, so
// the timed calls do exactly what the structure's own API does and nothing more.
class PhotonSearch {
 public:
  virtual ~PhotonSearch() = default;
  // The k nearest; returns how many were found.
  virtual std::size_t knn(const glm::vec3& query, std::size_t k) = 0;
  // The squared distances of the last knn, ascending.
  virtual std::vector<float> lastKnnDistances2() const = 0;
  // Returns how many points lie within the radius (ours counts distance2 <= radius2, nanoflann and
  // FLANN distance2 < radius2).
  virtual std::size_t withinRadius(const glm::vec3& query, float radius2) = 0;
  virtual std::size_t bytes() const = 0;
};

// The structures by name, in the order of the figures.
const std::vector<std::string>& photonSearchStructures();
// Builds `structure` over the photons (all leaves as ours: at most PhotonKdTree::kMaxLeafSize
// points); throws btf::Error for an unknown name.
std::unique_ptr<PhotonSearch> makePhotonSearch(std::string_view structure, std::vector<glm::vec3> photons);

}  // namespace btf::cli
