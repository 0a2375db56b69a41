#include "bench_photon_search.h"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <limits>
#include <numbers>
#include <string>
#include <utility>

#include <flann/flann.hpp>
#include <nanoflann.hpp>

#include "btf/core/error.h"
#include "btf/core/rng.h"
#include "btf/render/photon_kdtree.h"

namespace btf::cli {

namespace {

using render::PhotonKdTree;

// The sphere of the scene: standing on the floor, left of the middle.
constexpr glm::vec3 kSphereCenter{0.35f, 0.25f, 0.4f};
constexpr float kSphereRadius = 0.25f;

class KdBTreeSearch final : public PhotonSearch {
 public:
  explicit KdBTreeSearch(std::vector<glm::vec3> photons) : tree_(std::move(photons), PhotonKdTree::Build::serial) {}

  std::size_t knn(const glm::vec3& query, std::size_t k) override {
    tree_.knn(query, k, std::numeric_limits<float>::infinity(), found_);
    return found_.size();
  }
  std::vector<float> lastKnnDistances2() const override {
    std::vector<float> d;
    for (const auto& f : found_) d.push_back(f.distance2);
    return d;
  }
  std::size_t withinRadius(const glm::vec3& query, float radius2) override {
    tree_.withinRadius(query, radius2, found_);
    return found_.size();
  }
  std::size_t bytes() const override { return tree_.nodeBytes() + tree_.order().size_bytes(); }

 private:
  PhotonKdTree tree_;
  std::vector<PhotonKdTree::Neighbor> found_;
};

// nanoflann 1.4.3 reads points through a dataset adaptor.
struct PointCloudAdaptor {
  const std::vector<glm::vec3>* points;
  std::size_t kdtree_get_point_count() const { return points->size(); }
  float kdtree_get_pt(std::uint32_t i, std::size_t dim) const { return (*points)[i][static_cast<int>(dim)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

class NanoflannSearch final : public PhotonSearch {
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, PointCloudAdaptor>,
                                                   PointCloudAdaptor, 3, std::uint32_t>;

 public:
  explicit NanoflannSearch(std::vector<glm::vec3> photons)
      : photons_(std::move(photons)),
        adaptor_{&photons_},
        tree_(3, adaptor_, nanoflann::KDTreeSingleIndexAdaptorParams(PhotonKdTree::kMaxLeafSize)),
        bytes_(tree_.usedMemory(tree_)) {}

  std::size_t knn(const glm::vec3& query, std::size_t k) override {
    indices_.resize(k);
    distances2_.resize(k);
    found_ = tree_.knnSearch(&query.x, k, indices_.data(), distances2_.data());
    return found_;
  }
  std::vector<float> lastKnnDistances2() const override {
    return {distances2_.begin(), distances2_.begin() + static_cast<std::ptrdiff_t>(found_)};
  }
  std::size_t withinRadius(const glm::vec3& query, float radius2) override {
    // L2_Simple_Adaptor's distances are squared, so is the radius; unsorted, as ours.
    return tree_.radiusSearch(&query.x, radius2, pairs_, nanoflann::SearchParams(32, 0.0f, false));
  }
  std::size_t bytes() const override { return bytes_; }

 private:
  std::vector<glm::vec3> photons_;
  PointCloudAdaptor adaptor_;
  Tree tree_;
  std::size_t bytes_;
  std::vector<std::uint32_t> indices_;
  std::vector<float> distances2_;
  std::size_t found_ = 0;
  std::vector<std::pair<std::uint32_t, float>> pairs_;
};

class FlannSearch final : public PhotonSearch {
  using Index = flann::KDTreeSingleIndex<flann::L2_Simple<float>>;

 public:
  explicit FlannSearch(std::vector<glm::vec3> photons)
      : photons_(std::move(photons)),
        index_(flann::Matrix<float>(&photons_[0].x, photons_.size(), 3),
               flann::KDTreeSingleIndexParams(static_cast<int>(PhotonKdTree::kMaxLeafSize), true)) {
    index_.buildIndex();
  }

  // findNeighbors with a reused result set is what FLANN's own knnSearch does per query row
  // (single-threaded, k below its heap threshold), without the matrices around it.
  std::size_t knn(const glm::vec3& query, std::size_t k) override {
    if (!knn_result_ || knn_capacity_ != k) {
      knn_result_ = std::make_unique<flann::KNNSimpleResultSet<float>>(k);
      knn_capacity_ = k;
    }
    knn_result_->clear();
    index_.findNeighbors(*knn_result_, &query.x, params_);
    return knn_result_->size();
  }
  std::vector<float> lastKnnDistances2() const override {
    const std::size_t n = knn_result_->size();
    std::vector<std::size_t> indices(n);
    std::vector<float> distances2(n);
    knn_result_->copy(indices.data(), distances2.data(), n);
    return distances2;
  }
  std::size_t withinRadius(const glm::vec3& query, float radius2) override {
    // The radius is fixed at a result set's construction, which reserves memory: one per radius.
    if (!radius_result_ || radius_result_->worstDist() != radius2)
      radius_result_ = std::make_unique<flann::RadiusResultSet<float>>(radius2);
    radius_result_->clear();
    index_.findNeighbors(*radius_result_, &query.x, params_);
    return radius_result_->size();
  }
  std::size_t bytes() const override { return static_cast<std::size_t>(index_.usedMemory()); }

 private:
  std::vector<glm::vec3> photons_;
  Index index_;
  flann::SearchParams params_{flann::FLANN_CHECKS_UNLIMITED, 0.0f, false};
  std::unique_ptr<flann::KNNSimpleResultSet<float>> knn_result_;
  std::size_t knn_capacity_ = 0;
  std::unique_ptr<flann::RadiusResultSet<float>> radius_result_;
};

// The calling thread's CPU time: the figures are per core, and on a shared machine wall time would
// also count the time other processes hold the core.
double threadSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double perSecond(std::size_t count, double seconds) { return static_cast<double>(count) / std::max(seconds, 1e-9); }

}  // namespace

std::vector<glm::vec3> cornellBoxPoints(std::size_t n, std::uint64_t seed, std::uint64_t first_stream) {
  constexpr float kSphereArea = 4.0f * std::numbers::pi_v<float> * kSphereRadius * kSphereRadius;
  constexpr float kTotalArea = 5.0f + kSphereArea;
  std::vector<glm::vec3> points(n);
  for (std::size_t i = 0; i < n; ++i) {
    Rng rng(seed, first_stream + i);
    const float pick = rng.uniform() * kTotalArea;
    const float u = rng.uniform(), v = rng.uniform();
    if (pick < 5.0f) {
      switch (static_cast<int>(pick)) {
        case 0: points[i] = {0.0f, u, v}; break;  // left wall
        case 1: points[i] = {1.0f, u, v}; break;  // right wall
        case 2: points[i] = {u, 0.0f, v}; break;  // floor
        case 3: points[i] = {u, 1.0f, v}; break;  // ceiling
        default: points[i] = {u, v, 0.0f}; break;  // back wall
      }
    } else {
      const float z = 1.0f - 2.0f * u;
      const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
      const float phi = 2.0f * std::numbers::pi_v<float> * v;
      points[i] = kSphereCenter + kSphereRadius * glm::vec3(r * std::cos(phi), r * std::sin(phi), z);
    }
  }
  return points;
}

const std::vector<std::string>& photonSearchStructures() {
  static const std::vector<std::string> names{"kd-b-tree", "nanoflann", "flann"};
  return names;
}

std::unique_ptr<PhotonSearch> makePhotonSearch(std::string_view structure, std::vector<glm::vec3> photons) {
  if (photons.empty()) throw Error("photon search: there are no photons to build a search structure over.");
  if (structure == "kd-b-tree") return std::make_unique<KdBTreeSearch>(std::move(photons));
  if (structure == "nanoflann") return std::make_unique<NanoflannSearch>(std::move(photons));
  if (structure == "flann") return std::make_unique<FlannSearch>(std::move(photons));
  throw Error("photon search: unknown structure '" + std::string(structure) +
              "' (known: kd-b-tree, nanoflann, flann).");
}

std::vector<PhotonSearchFigures> measurePhotonSearch(std::size_t photons, std::size_t queries, std::size_t k,
                                                     std::uint64_t seed) {
  if (photons == 0 || queries == 0 || k == 0)
    throw Error("photon search: the comparison needs at least one photon, one query and k >= 1.");
  const std::vector<glm::vec3> points = cornellBoxPoints(photons, seed, 0);
  const std::vector<glm::vec3> query_points = cornellBoxPoints(queries, seed, std::uint64_t(1) << 40);

  std::vector<std::unique_ptr<PhotonSearch>> structures;
  std::vector<PhotonSearchFigures> figures;
  for (const std::string& name : photonSearchStructures()) {
    std::vector<glm::vec3> copy = points;
    const double start = threadSeconds();
    structures.push_back(makePhotonSearch(name, std::move(copy)));
    figures.push_back({name, threadSeconds() - start, 0.0, 0.0, 0.0, structures.back()->bytes()});
  }

  // Our answers are the reference; the check runs untimed and warms every structure's memory.
  PhotonSearch& ours = *structures[0];
  std::vector<std::vector<float>> reference(queries);
  double radius2_sum = 0.0;
  for (std::size_t q = 0; q < queries; ++q) {
    ours.knn(query_points[q], k);
    reference[q] = ours.lastKnnDistances2();
    radius2_sum += reference[q].back();
  }
  const auto radius2 = static_cast<float>(radius2_sum / static_cast<double>(queries));
  for (std::size_t s = 1; s < structures.size(); ++s) {
    for (std::size_t q = 0; q < queries; ++q) {
      structures[s]->knn(query_points[q], k);
      const std::vector<float> theirs = structures[s]->lastKnnDistances2();
      bool same = theirs.size() == reference[q].size();
      for (std::size_t i = 0; same && i < theirs.size(); ++i)
        same = std::abs(theirs[i] - reference[q][i]) <= 1e-5f * reference[q][i] + 1e-12f;
      if (!same)
        throw Error("photon search: " + figures[s].structure + " disagrees with kd-b-tree on the " + std::to_string(k) +
                    " nearest of query " + std::to_string(q) + "; the speeds would not compare equal work.");
    }
  }

  // Rounds over the structures in turn, each keeping its fastest pass: a burst of load from
  // elsewhere then slows one pass, not one structure.
  constexpr int kRounds = 3;
  for (int round = 0; round < kRounds; ++round) {
    for (std::size_t s = 0; s < structures.size(); ++s) {
      PhotonSearch& search = *structures[s];
      std::size_t found = 0;
      double start = threadSeconds();
      for (const glm::vec3& q : query_points) found += search.knn(q, k);
      figures[s].knn_queries_per_s =
          std::max(figures[s].knn_queries_per_s, perSecond(queries, threadSeconds() - start));
      if (found == 0) throw Error("photon search: " + figures[s].structure + " found no neighbours.");

      found = 0;
      start = threadSeconds();
      for (const glm::vec3& q : query_points) found += search.withinRadius(q, radius2);
      figures[s].radius_queries_per_s =
          std::max(figures[s].radius_queries_per_s, perSecond(queries, threadSeconds() - start));
      figures[s].mean_found_radius = static_cast<double>(found) / static_cast<double>(queries);
    }
  }
  // nanoflann and FLANN leave out points exactly at the radius, which on float data are rare.
  for (std::size_t s = 1; s < figures.size(); ++s)
    if (std::abs(figures[s].mean_found_radius - figures[0].mean_found_radius) > 1e-3 * figures[0].mean_found_radius)
      throw Error("photon search: " + figures[s].structure + " finds " + std::to_string(figures[s].mean_found_radius) +
                  " points per radius query, kd-b-tree " + std::to_string(figures[0].mean_found_radius) + ".");
  return figures;
}

}  // namespace btf::cli
