// The photon map's kd-B-tree (render/photon_kdtree.h): agreement of knn and withinRadius with a
// linear scan on clouds that stress sliding-midpoint splits (uniform, flat, duplicated, identical,
// skewed, tiny), the leaf-size and node-size invariants, and a build independent of the thread
// count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "btf/core/error.h"
#include "btf/core/rng.h"
#include "btf/render/photon_kdtree.h"

namespace {

using btf::render::PhotonKdTree;

constexpr float kInf = std::numeric_limits<float>::infinity();

// The tree's own formula, so that brute force and tree agree bit for bit.
float distance2(const glm::vec3& a, const glm::vec3& b) {
  const glm::vec3 d = a - b;
  return d.x * d.x + d.y * d.y + d.z * d.z;
}

std::vector<glm::vec3> uniformCloud(std::size_t n, std::uint64_t seed) {
  btf::Rng rng(seed);
  std::vector<glm::vec3> points(n);
  for (auto& p : points) p = {rng.uniform(), rng.uniform(), rng.uniform()};
  return points;
}

// Points on three axis-aligned planes (exactly flat, as photons on walls) and dense blobs on them.
std::vector<glm::vec3> planeCloud(std::size_t n, std::uint64_t seed) {
  btf::Rng rng(seed);
  std::vector<glm::vec3> points(n);
  for (auto& p : points) {
    const float a = rng.uniform(), b = rng.uniform();
    const std::uint32_t plane = rng.uniformInt(3);
    const bool blob = rng.uniform() < 0.5f;
    const float u = blob ? 0.3f + 0.01f * a : a;
    const float v = blob ? 0.6f + 0.01f * b : b;
    p = plane == 0 ? glm::vec3(0.25f, u, v) : plane == 1 ? glm::vec3(u, 0.7f, v) : glm::vec3(u, v, -2.0f);
  }
  return points;
}

// n points drawn from `distinct` locations.
std::vector<glm::vec3> duplicateCloud(std::size_t n, std::uint32_t distinct, std::uint64_t seed) {
  const std::vector<glm::vec3> sites = uniformCloud(distinct, seed);
  btf::Rng rng(seed, 1);
  std::vector<glm::vec3> points(n);
  for (auto& p : points) p = sites[rng.uniformInt(distinct)];
  return points;
}

// Coordinates piling up geometrically towards 0: each midpoint split cuts off only a few points,
// which is what the depth cap exists for.
std::vector<glm::vec3> skewedCloud(std::size_t n) {
  std::vector<glm::vec3> points(n);
  float x = 1.0f;
  for (std::size_t i = 0; i < n; ++i) {
    points[i] = {x, 0.5f * x, 0.0f};
    x *= 0.97f;
  }
  return points;
}

// Queries inside and around the cloud, on its points (distance 0, duplicates) and far away.
std::vector<glm::vec3> queriesFor(const std::vector<glm::vec3>& cloud, std::size_t n, std::uint64_t seed) {
  btf::Rng rng(seed, 7);
  glm::vec3 lower(kInf), upper(-kInf);
  for (const auto& p : cloud) {
    lower = glm::min(lower, p);
    upper = glm::max(upper, p);
  }
  const glm::vec3 margin = 0.1f * (upper - lower) + 0.01f;
  std::vector<glm::vec3> queries;
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3 u{rng.uniform(), rng.uniform(), rng.uniform()};  // braces: drawn in order
    queries.push_back(lower - margin + u * (upper - lower + 2.0f * margin));
  }
  for (std::size_t i = 0; i < n / 4 && !cloud.empty(); ++i)
    queries.push_back(cloud[rng.uniformInt(static_cast<std::uint32_t>(cloud.size()))]);
  queries.push_back(upper + glm::vec3(100.0f, -50.0f, 3.0f));
  return queries;
}

// Checks knn against a linear scan: the same sorted distances, each neighbour's distance right,
// no index twice.
void expectKnnAgrees(const PhotonKdTree& tree, const glm::vec3& q, std::size_t k, float max_distance2,
                     std::vector<PhotonKdTree::Neighbor>& found, const std::string& context) {
  tree.knn(q, k, max_distance2, found);
  const auto points = tree.points();
  std::vector<float> expected;
  for (const auto& p : points)
    if (const float d = distance2(q, p); d <= max_distance2) expected.push_back(d);
  std::sort(expected.begin(), expected.end());
  expected.resize(std::min(expected.size(), k));

  ASSERT_EQ(found.size(), expected.size()) << context;
  std::vector<std::uint32_t> indices;
  for (std::size_t i = 0; i < found.size(); ++i) {
    ASSERT_LT(found[i].index, points.size()) << context;
    EXPECT_EQ(found[i].distance2, expected[i]) << context << " rank " << i;
    EXPECT_EQ(found[i].distance2, distance2(q, points[found[i].index])) << context << " rank " << i;
    if (i > 0 && found[i].distance2 == found[i - 1].distance2) {
      EXPECT_LT(found[i - 1].index, found[i].index) << context << " rank " << i << ": ties not by index";
    }
    indices.push_back(found[i].index);
  }
  std::sort(indices.begin(), indices.end());
  EXPECT_EQ(std::adjacent_find(indices.begin(), indices.end()), indices.end()) << context << ": an index twice";
}

void expectRadiusAgrees(const PhotonKdTree& tree, const glm::vec3& q, float radius2,
                        std::vector<PhotonKdTree::Neighbor>& found, const std::string& context) {
  tree.withinRadius(q, radius2, found);
  const auto points = tree.points();
  std::vector<std::uint32_t> expected;
  for (std::uint32_t i = 0; i < points.size(); ++i)
    if (distance2(q, points[i]) <= radius2) expected.push_back(i);
  std::vector<std::uint32_t> indices;
  for (const auto& f : found) {
    ASSERT_LT(f.index, points.size()) << context;
    EXPECT_EQ(f.distance2, distance2(q, points[f.index])) << context;
    indices.push_back(f.index);
  }
  std::sort(indices.begin(), indices.end());
  EXPECT_EQ(indices, expected) << context << " radius2 " << radius2;
}

// Every query of the cloud, for several k, bounded and unbounded, and several radii (0 included).
void expectAgreement(const std::vector<glm::vec3>& cloud, const std::string& name, std::size_t queries = 120) {
  const PhotonKdTree tree(cloud);
  ASSERT_EQ(tree.size(), cloud.size()) << name;
  std::vector<PhotonKdTree::Neighbor> found;
  const auto qs = queriesFor(cloud, queries, 11);
  for (std::size_t i = 0; i < qs.size(); ++i) {
    const std::string context = name + " query " + std::to_string(i);
    // 64 and below are sorted by a network, above by std::sort.
    for (const std::size_t k : {std::size_t(1), std::size_t(7), std::size_t(50), std::size_t(64), std::size_t(65),
                                std::size_t(200), cloud.size() + 3}) {
      expectKnnAgrees(tree, qs[i], k, kInf, found, context + " k " + std::to_string(k));
      expectKnnAgrees(tree, qs[i], k, 0.003f, found, context + " bounded k " + std::to_string(k));
      if (::testing::Test::HasFatalFailure()) return;
    }
    for (const float radius2 : {0.0f, 1e-4f, 0.003f, 0.05f}) {
      expectRadiusAgrees(tree, qs[i], radius2, found, context);
      if (::testing::Test::HasFatalFailure()) return;
    }
  }
}

}  // namespace

static_assert(sizeof(PhotonKdTree::Node) == 8);

TEST(PhotonKdTree, KnnAndRadiusAgreeWithLinearScanOnUniformCloud) { expectAgreement(uniformCloud(5000, 1), "uniform"); }

TEST(PhotonKdTree, KnnAndRadiusAgreeWithLinearScanOnPointsOnPlanes) { expectAgreement(planeCloud(6000, 2), "planes"); }

TEST(PhotonKdTree, KnnAndRadiusAgreeWithLinearScanWithManyDuplicates) {
  expectAgreement(duplicateCloud(3000, 40, 3), "duplicates");
}

TEST(PhotonKdTree, KnnAndRadiusAgreeWithLinearScanWhenAllPointsAreIdentical) {
  expectAgreement(std::vector<glm::vec3>(700, glm::vec3(1.0f, -2.0f, 3.5f)), "identical", 20);
}

TEST(PhotonKdTree, KnnAndRadiusAgreeWithLinearScanOnSkewedCloudAndDepthStaysBounded) {
  const auto cloud = skewedCloud(6000);
  expectAgreement(cloud, "skewed", 60);
  const PhotonKdTree tree(cloud);
  // Sliding splits cut off a leaf's worth of points per level here; below depth 64 median splits
  // take over (and the agreement above covers both kinds).
  EXPECT_GT(tree.depth(), 64u);
  EXPECT_LE(tree.depth(), 64u + 26u);
}

TEST(PhotonKdTree, KnnAndRadiusAgreeWithLinearScanOnSubnormalCoordinates) {
  // Split planes halfway between subnormals, whose halves round; squared distances underflow to 0.
  btf::Rng rng(17);
  std::vector<glm::vec3> cloud(3000);
  for (auto& p : cloud)
    p = glm::vec3{static_cast<float>(rng.uniformInt(40)), static_cast<float>(rng.uniformInt(3)), rng.uniform()} * 1e-45f;
  expectAgreement(cloud, "subnormal", 30);
}

TEST(PhotonKdTree, SmallTreesAndKBeyondSize) {
  for (const std::size_t n : {1, 2, 31, 32, 64, 65, 100}) expectAgreement(uniformCloud(n, 4 + n), "n=" + std::to_string(n), 30);

  const PhotonKdTree one(std::vector<glm::vec3>{{0.5f, 0.5f, 0.5f}});
  std::vector<PhotonKdTree::Neighbor> found;
  one.knn({0.0f, 0.0f, 0.0f}, 10, kInf, found);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].index, 0u);
  EXPECT_FLOAT_EQ(found[0].distance2, 0.75f);
  one.knn({0.0f, 0.0f, 0.0f}, 10, 0.7f, found);
  EXPECT_TRUE(found.empty());
  one.knn({0.5f, 0.5f, 0.5f}, 0, kInf, found);
  EXPECT_TRUE(found.empty());
  one.withinRadius({0.5f, 0.5f, 0.5f}, 0.0f, found);
  EXPECT_EQ(found.size(), 1u);
  one.withinRadius({0.5f, 0.5f, 0.5f}, -1.0f, found);
  EXPECT_TRUE(found.empty());
}

TEST(PhotonKdTree, RadiusZeroFindsExactlyTheCoincidentPoints) {
  const auto cloud = duplicateCloud(2000, 25, 5);
  const PhotonKdTree tree(cloud);
  std::vector<PhotonKdTree::Neighbor> found;
  for (std::uint32_t i = 0; i < 40; ++i) {
    const glm::vec3 q = cloud[i];
    tree.withinRadius(q, 0.0f, found);
    const auto expected = static_cast<std::size_t>(std::count(cloud.begin(), cloud.end(), q));
    EXPECT_EQ(found.size(), expected);
    for (const auto& f : found) EXPECT_EQ(tree.points()[f.index], q);
  }
}

TEST(PhotonKdTree, QueryThatIsNotANumberFindsNothing) {
  const PhotonKdTree tree(uniformCloud(1000, 18));
  std::vector<PhotonKdTree::Neighbor> found;
  const glm::vec3 q(0.5f, std::numeric_limits<float>::quiet_NaN(), 0.5f);
  tree.knn(q, 10, kInf, found);
  EXPECT_TRUE(found.empty());
  tree.withinRadius(q, 1.0f, found);
  EXPECT_TRUE(found.empty());
}

TEST(PhotonKdTree, EmptyTreeAnswersNothing) {
  std::vector<PhotonKdTree::Neighbor> found{{1, 2.0f}};
  for (const PhotonKdTree& tree : {PhotonKdTree(), PhotonKdTree(std::vector<glm::vec3>{})}) {
    EXPECT_EQ(tree.size(), 0u);
    EXPECT_TRUE(tree.points().empty());
    EXPECT_TRUE(tree.order().empty());
    EXPECT_EQ(tree.nodeBytes(), 0u);
    EXPECT_TRUE(tree.leaves().empty());
    tree.knn({0.0f, 0.0f, 0.0f}, 5, kInf, found);
    EXPECT_TRUE(found.empty());
    found.push_back({1, 2.0f});
    tree.withinRadius({0.0f, 0.0f, 0.0f}, kInf, found);
    EXPECT_TRUE(found.empty());
  }
}

TEST(PhotonKdTree, RejectsPointsThatAreNotFinite) {
  for (const float bad : {std::numeric_limits<float>::quiet_NaN(), kInf, -kInf}) {
    auto cloud = uniformCloud(100, 6);
    cloud[42].y = bad;
    try {
      PhotonKdTree tree(std::move(cloud));
      ADD_FAILURE() << "accepted a point with coordinate " << bad;
    } catch (const btf::Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("point 42"), std::string::npos) << message;
      EXPECT_NE(message.find("not finite"), std::string::npos) << message;
    }
  }
}

TEST(PhotonKdTree, LeavesAreContiguousRangesWithinTheSizeBounds) {
  for (const auto& cloud : {uniformCloud(20000, 7), planeCloud(20000, 8), duplicateCloud(5000, 3, 9), skewedCloud(5000),
                            std::vector<glm::vec3>(1000, glm::vec3(0.0f))}) {
    const PhotonKdTree tree(cloud);
    const auto leaves = tree.leaves();
    std::uint32_t next = 0;
    for (const auto& leaf : leaves) {
      EXPECT_EQ(leaf.begin, next);
      EXPECT_GE(leaf.count, PhotonKdTree::kMinLeafSize);
      EXPECT_LE(leaf.count, PhotonKdTree::kMaxLeafSize);
      next = leaf.begin + leaf.count;
    }
    EXPECT_EQ(next, cloud.size());
    // A binary tree: one inner node fewer than leaves.
    EXPECT_EQ(tree.nodeCount(), 2 * leaves.size() - 1);
    EXPECT_EQ(tree.nodeBytes(), 8 * tree.nodeCount());
  }
  const PhotonKdTree small(uniformCloud(20, 10));
  ASSERT_EQ(small.leaves().size(), 1u);
  EXPECT_EQ(small.leaves()[0].count, 20u);
}

TEST(PhotonKdTree, OrderIsThePermutationThatReorderedTheInput) {
  const auto cloud = planeCloud(10000, 12);
  const PhotonKdTree tree(cloud);
  const auto order = tree.order();
  ASSERT_EQ(order.size(), cloud.size());
  std::vector<std::uint32_t> sorted(order.begin(), order.end());
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::uint32_t> identity(cloud.size());
  std::iota(identity.begin(), identity.end(), 0u);
  EXPECT_EQ(sorted, identity);
  for (std::size_t i = 0; i < cloud.size(); ++i) ASSERT_EQ(tree.points()[i], cloud[order[i]]) << i;
}

TEST(PhotonKdTree, BuildIsIdenticalForAnyThreadCount) {
  // Large enough for several subtrees to be built as parallel tasks.
  const auto cloud = planeCloud(300000, 13);
  auto buildWith = [&](int threads, PhotonKdTree::Build build) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return PhotonKdTree(cloud, build);
  };
  const PhotonKdTree serial = buildWith(1, PhotonKdTree::Build::serial);
  for (const int threads : {1, 2, 4}) {
    const PhotonKdTree tree = buildWith(threads, PhotonKdTree::Build::parallel);
    ASSERT_TRUE(std::equal(tree.order().begin(), tree.order().end(), serial.order().begin(), serial.order().end()))
        << threads << " threads";
    EXPECT_EQ(tree.nodeCount(), serial.nodeCount());
    EXPECT_EQ(tree.depth(), serial.depth());
    const auto a = tree.leaves(), b = serial.leaves();
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      ASSERT_EQ(a[i].begin, b[i].begin);
      ASSERT_EQ(a[i].count, b[i].count);
    }
    std::vector<PhotonKdTree::Neighbor> x, y;
    for (const auto& q : queriesFor(cloud, 50, 14)) {
      tree.knn(q, 20, kInf, x);
      serial.knn(q, 20, kInf, y);
      ASSERT_EQ(x.size(), y.size());
      for (std::size_t i = 0; i < x.size(); ++i) {
        EXPECT_EQ(x[i].index, y[i].index);
        EXPECT_EQ(x[i].distance2, y[i].distance2);
      }
    }
  }
}

TEST(PhotonKdTree, QueriesReuseTheCapacityOfTheOutputVector) {
  const auto cloud = uniformCloud(5000, 15);
  const PhotonKdTree tree(cloud);
  std::vector<PhotonKdTree::Neighbor> found;
  found.reserve(51);
  const auto* data = found.data();
  for (const auto& q : queriesFor(cloud, 50, 16)) {
    tree.knn(q, 50, kInf, found);
    EXPECT_EQ(found.data(), data);
  }
}
