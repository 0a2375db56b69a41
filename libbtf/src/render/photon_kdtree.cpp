#include "btf/render/photon_kdtree.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <limits>
#include <string>

#include <tbb/parallel_invoke.h>

#include "btf/core/error.h"

namespace btf::render {

static_assert(sizeof(PhotonKdTree::Node) == 8, "nodes are packed in 8 bytes");

namespace {

using Node = PhotonKdTree::Node;

constexpr std::uint32_t kLeafTag = 3;
// Below this depth splits are sliding-midpoint; from it on they are median splits. Sliding splits
// may cut off as few as kMinLeafSize points per level, so without a cap a skewed cloud (say,
// photons piling up geometrically towards a point) could nest arbitrarily deep; median splits
// bring any subtree of < 2^32 points down to a leaf within 26 more levels (2^32 / 2^26 = 64),
// which bounds the query stack.
constexpr std::size_t kBalancedDepth = 64;
constexpr std::size_t kMaxDepth = kBalancedDepth + 26;
// Subtrees of at least this many points are built as parallel tasks: smaller ones cost less
// than a task's overhead and the concatenation of its nodes.
constexpr std::uint32_t kParallelGrain = 1u << 15;

struct Item {  // a point with its input index, moved together while partitioning
  glm::vec3 p;
  std::uint32_t index;
};

struct Box {
  glm::vec3 lower, upper;
};

Box boundsOf(const Item* first, const Item* last) {
  Box box{first->p, first->p};
  for (const Item* it = first + 1; it != last; ++it) {
    box.lower = glm::min(box.lower, it->p);
    box.upper = glm::max(box.upper, it->p);
  }
  return box;
}

// The midpoint of a <= b, inside [a, b]: halving before adding cannot overflow, and the clamp
// catches subnormals, whose halves round.
float midpoint(float a, float b) { return std::clamp(0.5f * a + 0.5f * b, a, b); }

Node leafNode(std::uint32_t begin, std::uint32_t count) { return {kLeafTag | (count << 2), begin}; }

Node innerNode(int axis, float split, std::size_t right_offset) {
  return {static_cast<std::uint32_t>(axis) | static_cast<std::uint32_t>(right_offset << 2),
          std::bit_cast<std::uint32_t>(split)};
}

class Builder {
 public:
  Builder(Item* items, bool parallel) : items_(items), parallel_(parallel) {}

  // Appends the nodes of the subtree over items_[begin, end) to `out`; returns its depth.
  std::size_t build(std::uint32_t begin, std::uint32_t end, const Box& box, std::size_t depth,
                    std::vector<Node>& out) const {
    const std::uint32_t n = end - begin;
    if (n <= PhotonKdTree::kMaxLeafSize) {
      out.push_back(leafNode(begin, n));
      return 0;
    }
    const glm::vec3 extent = box.upper - box.lower;
    const int axis = extent.x >= extent.y ? (extent.x >= extent.z ? 0 : 2) : (extent.y >= extent.z ? 1 : 2);
    Item* first = items_ + begin;
    Item* last = items_ + end;
    const auto less = [axis](const Item& a, const Item& b) { return a.p[axis] < b.p[axis]; };
    constexpr std::uint32_t kMin = PhotonKdTree::kMinLeafSize;
    std::uint32_t m;
    if (depth >= kBalancedDepth) {
      m = n / 2;
      std::nth_element(first, first + m, last, less);
    } else {
      const float mid = midpoint(box.lower[axis], box.upper[axis]);
      m = static_cast<std::uint32_t>(
          std::partition(first, last, [axis, mid](const Item& it) { return it.p[axis] < mid; }) - first);
      // Slide the plane: the side that is too small takes the points nearest to it from the other.
      if (m < kMin) {
        std::nth_element(first + m, first + kMin, last, less);
        m = kMin;
      } else if (m > n - kMin) {
        std::nth_element(first, first + (n - kMin), first + m, less);
        m = n - kMin;
      }
    }
    const Box left_box = boundsOf(first, first + m);
    const Box right_box = boundsOf(first + m, last);
    // Anywhere in the gap between the sides is a valid plane; its middle keeps the pruning bound
    // equally tight for queries on either side.
    const float split = midpoint(left_box.upper[axis], right_box.lower[axis]);
    const std::uint32_t mid_index = begin + m;

    if (parallel_ && n >= kParallelGrain) {
      std::vector<Node> left, right;
      std::size_t left_depth = 0, right_depth = 0;
      tbb::parallel_invoke([&] { left_depth = build(begin, mid_index, left_box, depth + 1, left); },
                           [&] { right_depth = build(mid_index, end, right_box, depth + 1, right); });
      out.push_back(innerNode(axis, split, 1 + left.size()));
      out.insert(out.end(), left.begin(), left.end());
      out.insert(out.end(), right.begin(), right.end());
      return 1 + std::max(left_depth, right_depth);
    }
    const std::size_t self = out.size();
    out.push_back({});
    const std::size_t left_depth = build(begin, mid_index, left_box, depth + 1, out);
    out[self] = innerNode(axis, split, out.size() - self);
    const std::size_t right_depth = build(mid_index, end, right_box, depth + 1, out);
    return 1 + std::max(left_depth, right_depth);
  }

 private:
  Item* items_;
  bool parallel_;
};

inline float distance2(const glm::vec3& a, const glm::vec3& b) {
  const glm::vec3 d = a - b;
  return d.x * d.x + d.y * d.y + d.z * d.z;
}

// Squared distance from q to [lower, upper] along one axis.
inline float outside2(float q, float lower, float upper) {
  const float d = q < lower ? lower - q : (q > upper ? q - upper : 0.0f);
  return d * d;
}

// Visits, nearer child first, every leaf whose cell may hold a point within visitor.limit of the
// query; the visitor may lower its limit as it sees points. A cell's bound is the squared distance
// to the box cut out of the root's bounds by the split planes on the way down (incremental
// distance: per axis, the nearest plane crossed), which prunes more than the distance to the last
// plane alone. It is summed in the order and rounding of a point's distance2, so it never exceeds
// the distance2 of a point in the cell: a point exactly at the limit is never pruned.
template <class Visitor>
void traverse(const Node* nodes, const glm::vec3& q, const glm::vec3& lower, const glm::vec3& upper, Visitor& visitor) {
  struct Pending {
    std::uint32_t node;
    float bound;
    float off[3];  // per-axis squared distances to the cell
  };
  Pending stack[kMaxDepth + 1];
  std::size_t top = 0;
  // Arrays rather than glm::vec3, whose operator[] with a run-time axis is a branch on the axis.
  const float qa[3] = {q.x, q.y, q.z};
  float off[3] = {outside2(q.x, lower.x, upper.x), outside2(q.y, lower.y, upper.y), outside2(q.z, lower.z, upper.z)};
  if (!(off[0] + off[1] + off[2] <= visitor.limit)) return;
  std::uint32_t node = 0;
  for (;;) {
    const Node n = nodes[node];
    const std::uint32_t axis = n.bits & 3u;
    if (axis == kLeafTag) {
      visitor(n.value, n.bits >> 2);
      for (;;) {
        if (top == 0) return;
        const Pending& p = stack[--top];
        if (p.bound <= visitor.limit) {
          node = p.node;
          off[0] = p.off[0];
          off[1] = p.off[1];
          off[2] = p.off[2];
          break;
        }
      }
      continue;
    }
    const float diff = qa[axis] - std::bit_cast<float>(n.value);
    const bool left_first = diff < 0.0f;
    const std::uint32_t left = node + 1, right = node + (n.bits >> 2);
    // The far child is written unconditionally and kept if in reach: which side is near is a coin
    // toss that a branch would mispredict.
    Pending& far = stack[top];
    far.node = left_first ? right : left;
    far.off[0] = off[0];
    far.off[1] = off[1];
    far.off[2] = off[2];
    far.off[axis] = diff * diff;
    far.bound = far.off[0] + far.off[1] + far.off[2];
    top += far.bound <= visitor.limit;
    node = left_first ? left : right;
  }
}

// The largest float below x (x >= 0), or -1 below 0: comparing d <= below(x) is d < x.
inline float below(float x) { return x > 0.0f ? std::bit_cast<float>(std::bit_cast<std::uint32_t>(x) - 1) : -1.0f; }

// Sifts x down from heap[i] in the max-heap heap[0, size) (on distance2). heap[size] is a sentinel
// of distance2 -1, so that the larger child is chosen without a bounds test.
inline void siftDown(PhotonKdTree::Neighbor* heap, std::size_t size, std::size_t i, PhotonKdTree::Neighbor x) {
  std::size_t child = 2 * i + 1;
  while (child < size) {
    child += heap[child + 1].distance2 > heap[child].distance2;
    if (!(heap[child].distance2 > x.distance2)) break;
    heap[i] = heap[child];
    i = child;
    child = 2 * i + 1;
  }
  heap[i] = x;
}

// The k nearest: a max-heap of the best so far, whose top bounds the search once it is full.
struct NearestK {
  const glm::vec3* points;
  glm::vec3 query;
  PhotonKdTree::Neighbor* heap;  // capacity + 1 entries, the last the sentinel of siftDown
  std::size_t capacity;
  std::size_t count = 0;
  float limit;  // max_distance2 while filling, then just below the heap's top

  void operator()(std::uint32_t begin, std::uint32_t n) {
    // First the leaf's points within the limit, gathered without branches (once the heap is full,
    // whether a point passes is unpredictable), then the heap, for those few.
    PhotonKdTree::Neighbor fresh[PhotonKdTree::kMaxLeafSize];
    std::size_t m = 0;
    for (std::uint32_t i = begin; i < begin + n; ++i) {
      const float d = distance2(query, points[i]);
      fresh[m] = {i, d};
      m += d <= limit;
    }
    std::size_t j = 0;
    if (count < capacity) {
      j = std::min(m, capacity - count);
      std::copy(fresh, fresh + j, heap + count);
      count += j;
      if (count < capacity) return;
      for (std::size_t i = count / 2; i-- > 0;) siftDown(heap, count, i, heap[i]);
      limit = below(heap[0].distance2);
    }
    for (; j < m; ++j) {
      if (fresh[j].distance2 <= limit) {
        siftDown(heap, count, 0, fresh[j]);
        limit = below(heap[0].distance2);
      }
    }
  }
};

struct WithinRadius {
  const glm::vec3* points;
  glm::vec3 query;
  std::vector<PhotonKdTree::Neighbor>* out;
  float limit;  // radius2

  void operator()(std::uint32_t begin, std::uint32_t n) {
    // Room for the whole leaf, then kept without branches: whether a point is in is a coin toss.
    const std::size_t old = out->size();
    out->resize(old + n);
    PhotonKdTree::Neighbor* found = out->data() + old;
    std::size_t m = 0;
    for (std::uint32_t i = begin; i < begin + n; ++i) {
      const float d = distance2(query, points[i]);
      found[m] = {i, d};
      m += d <= limit;
    }
    out->resize(old + m);
  }
};

// (distance2, index) as one integer in lexicographic order: distances are >= +0, whose float bits
// order as unsigned integers.
inline std::uint64_t sortKey(const PhotonKdTree::Neighbor& n) {
  return (std::uint64_t(std::bit_cast<std::uint32_t>(n.distance2)) << 32) | n.index;
}

constexpr std::size_t kFew = 64;

// Sorts up to kFew neighbours by a bitonic network: its compare-exchanges do not depend on the
// data, so they compile to conditional moves, where std::sort's comparisons are coin tosses that
// the branch predictor loses.
void sortFew(PhotonKdTree::Neighbor* a, std::size_t n) {
  std::uint64_t keys[kFew];
  const std::size_t width = std::bit_ceil(std::max<std::size_t>(n, 2));
  for (std::size_t i = 0; i < n; ++i) keys[i] = sortKey(a[i]);
  std::fill(keys + n, keys + width, ~std::uint64_t(0));
  for (std::size_t size = 2; size <= width; size <<= 1) {
    for (std::size_t stride = size >> 1; stride > 0; stride >>= 1) {
      for (std::size_t block = 0; block < width; block += 2 * stride) {
        for (std::size_t i = block; i < block + stride; ++i) {
          const bool ascending = (i & size) == 0;
          const std::uint64_t x = keys[i], y = keys[i + stride];
          const std::uint64_t lo = x < y ? x : y, hi = x < y ? y : x;
          keys[i] = ascending ? lo : hi;
          keys[i + stride] = ascending ? hi : lo;
        }
      }
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    a[i] = {static_cast<std::uint32_t>(keys[i]), std::bit_cast<float>(static_cast<std::uint32_t>(keys[i] >> 32))};
}

}  // namespace

PhotonKdTree::PhotonKdTree(std::vector<glm::vec3> points, Build build) {
  if (points.size() > std::numeric_limits<std::uint32_t>::max())
    throw Error("PhotonKdTree: " + std::to_string(points.size()) +
                " points are more than the 2^32 - 1 that 32-bit indices address.");
  for (std::size_t i = 0; i < points.size(); ++i) {
    const glm::vec3& p = points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw Error("PhotonKdTree: point " + std::to_string(i) + " of " + std::to_string(points.size()) + " is not finite (" +
                  std::to_string(p.x) + ", " + std::to_string(p.y) + ", " + std::to_string(p.z) +
                  "); photon positions must be finite numbers.");
  }
  if (points.empty()) return;

  const auto n = static_cast<std::uint32_t>(points.size());
  std::vector<Item> items(n);
  for (std::uint32_t i = 0; i < n; ++i) items[i] = {points[i], i};
  const Box box = boundsOf(items.data(), items.data() + n);
  lower_ = box.lower;
  upper_ = box.upper;
  nodes_.reserve(2 * (n / kMinLeafSize) + 1);
  depth_ = Builder(items.data(), build == Build::parallel).build(0, n, box, 0, nodes_);
  assert(depth_ <= kMaxDepth);

  points_ = std::move(points);
  order_.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    points_[i] = items[i].p;
    order_[i] = items[i].index;
  }
}

void PhotonKdTree::knn(const glm::vec3& query, std::size_t k, float max_distance2, std::vector<Neighbor>& out) const {
  out.clear();
  if (nodes_.empty() || k == 0 || !(max_distance2 >= 0.0f)) return;
  const std::size_t capacity = std::min(k, points_.size());
  out.resize(capacity + 1);
  out[capacity] = {0, -1.0f};
  NearestK nearest{points_.data(), query, out.data(), capacity, 0, max_distance2};
  traverse(nodes_.data(), query, lower_, upper_, nearest);
  out.resize(nearest.count);
  if (out.size() <= kFew)
    sortFew(out.data(), out.size());
  else
    std::sort(out.begin(), out.end(), [](const Neighbor& a, const Neighbor& b) { return sortKey(a) < sortKey(b); });
}

void PhotonKdTree::withinRadius(const glm::vec3& query, float radius2, std::vector<Neighbor>& out) const {
  out.clear();
  if (nodes_.empty() || !(radius2 >= 0.0f)) return;
  WithinRadius within{points_.data(), query, &out, radius2};
  traverse(nodes_.data(), query, lower_, upper_, within);
}

std::vector<PhotonKdTree::LeafRange> PhotonKdTree::leaves() const {
  std::vector<LeafRange> result;
  for (const Node& n : nodes_)
    if ((n.bits & 3u) == kLeafTag) result.push_back({n.value, n.bits >> 2});
  return result;
}

}  // namespace btf::render
