// The photon map's search structure: a kd-B-tree over 3D points (kd-tree whose leaves are buckets
// of points), built by sliding-midpoint splits.
//
// Why this shape: photon gathering asks for tens of neighbours, so the search reads a few dozen
// points around the query anyway, and reading them as whole leaves is cheap: the points of a leaf
// lie contiguously in memory (the tree reorders them), a scan streams one run of cache lines
// instead of chasing an index per point, and it needs no branch per point. Sliding-midpoint splits
// adapt to photons lying on surfaces (2D sets in 3D), where median splits make long thin cells
// that prune badly.
#pragma once

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace btf::render {

class PhotonKdTree {
 public:
  // Leaves hold between kMinLeafSize and kMaxLeafSize points (fewer only when the whole tree
  // does): a node of more than kMaxLeafSize points is split, and the split plane slides so that
  // neither side gets fewer than kMinLeafSize. A 64-point leaf is 768 bytes of coordinates (twelve
  // cache lines), comparable to the neighbourhood of a k = 50 query.
  static constexpr std::uint32_t kMinLeafSize = 32;
  static constexpr std::uint32_t kMaxLeafSize = 64;

  struct Neighbor {
    std::uint32_t index;  // position in points() (tree order); order()[index] is the input index
    float distance2;
  };

  // Whether the build may use TBB's threads. The tree is the same either way (each subtree is a
  // pure function of its points); `serial` is for per-core timings.
  enum class Build { parallel, serial };

  // One node in 8 bytes, depth-first: the left child of an inner node follows it, the right one is
  // `offset` nodes further on (relative, so subtrees built apart are concatenated unchanged).
  // bits & 3 is the split axis (0..2), or 3 for a leaf; bits >> 2 is the right child's offset
  // (inner) or the point count (leaf). `value` is the split coordinate's float bits (inner; points
  // of the left subtree are <= it, of the right one >= it) or the first point (leaf).
  struct Node {
    std::uint32_t bits;
    std::uint32_t value;
  };

  struct LeafRange {
    std::uint32_t begin, count;
  };

  PhotonKdTree() = default;
  // Takes ownership of the points and reorders them. Throws btf::Error for a point that is not
  // finite (NaN or infinite) and for more than 2^32 - 1 points.
  explicit PhotonKdTree(std::vector<glm::vec3> points, Build build = Build::parallel);

  std::size_t size() const { return points_.size(); }
  // The points in tree order.
  std::span<const glm::vec3> points() const { return points_; }
  // order()[i] = index in the constructor's input of points()[i].
  std::span<const std::uint32_t> order() const { return order_; }

  // The k nearest points with distance2 <= max_distance2, sorted by ascending distance2 (equal
  // ones by index), into out (cleared first). Allocates nothing once out has capacity k + 1.
  void knn(const glm::vec3& query, std::size_t k, float max_distance2, std::vector<Neighbor>& out) const;
  // Every point with distance2 <= radius2, in no particular order, into out (cleared first).
  // Allocates nothing once out has capacity for the points found plus kMaxLeafSize.
  void withinRadius(const glm::vec3& query, float radius2, std::vector<Neighbor>& out) const;

  // Memory of the node array (the points and order() come on top: 16 bytes per point).
  std::size_t nodeBytes() const { return nodes_.size() * sizeof(Node); }
  std::size_t nodeCount() const { return nodes_.size(); }
  // Levels below the root of the deepest leaf (0 for a single leaf); bounded by construction, so
  // that queries can use a fixed traversal stack.
  std::size_t depth() const { return depth_; }
  // The leaves in depth-first order, which is also the order of their point ranges.
  std::vector<LeafRange> leaves() const;

 private:
  std::vector<glm::vec3> points_;
  std::vector<std::uint32_t> order_;
  std::vector<Node> nodes_;
  glm::vec3 lower_{0.0f}, upper_{0.0f};  // bounds of all points, where every query's pruning starts
  std::size_t depth_ = 0;
};

}  // namespace btf::render
